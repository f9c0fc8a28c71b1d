// Per-epoch time budget by stage for full-size scans through a real daemon: for each preset
// (default `pier` and `hochmosel`, the demo's scenes), two epochs rendered once (or taken from
// --scans DIR/<preset>, where an earlier run left them), the first fed as the reference, then
// the second. Prints, for each epoch, the times the daemon stored (read, analyse, total, and
// each stage of epoch_stages), the wall time from the file's arrival (rename) to its commit
// (the watcher's stable wait, the commit and the alarm rules included), and the daemon's peak
// resident memory (VmHWM). Targets (issue 14): a `pier` epoch within 60 s, peak RSS within
// 2 GB. Nothing is asserted.
// Usage: bench_epoch_budget [--scans DIR] [preset...]
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "bench/daemon_bench.hpp"
#include "demo/daemon_process.hpp"

using namespace tlsmon;
using namespace tlsmon::bench;

namespace {

void print_epoch(SQLite::Database& d, long id, double arrival_to_commit_s) {
    SQLite::Statement e(d,
                        "SELECT status, reason, point_count, read_ms, analyse_ms, total_ms "
                        "FROM epochs WHERE id = ?");
    e.bind(1, static_cast<std::int64_t>(id));
    if (!e.executeStep()) return;
    const auto ms = [&](int col) {
        return e.getColumn(col).isNull() ? -1.0 : e.getColumn(col).getDouble();
    };
    std::printf(
        "    epoch %ld %s, %lld points: read %.0f ms, analyse %.0f ms (the stages below), "
        "total %.0f ms; arrival to commit %.1f s%s%s\n",
        id, e.getColumn(0).getString().c_str(),
        static_cast<long long>(e.getColumn(2).isNull() ? 0 : e.getColumn(2).getInt64()), ms(3),
        ms(4), ms(5), arrival_to_commit_s, e.getColumn(1).getString().empty() ? "" : "; ",
        e.getColumn(1).getString().substr(0, 120).c_str());
    SQLite::Statement s(
        d,
        "SELECT stage, ms, rejected, note FROM epoch_stages WHERE epoch_id = ? ORDER BY position");
    s.bind(1, static_cast<std::int64_t>(id));
    while (s.executeStep()) {
        std::printf("      stage %-14s %8.0f ms  %s%s\n", s.getColumn(0).getString().c_str(),
                    s.getColumn(1).getDouble(), s.getColumn(3).getString().substr(0, 80).c_str(),
                    s.getColumn(2).getString().empty()
                        ? ""
                        : (" rejected: " + s.getColumn(2).getString().substr(0, 80)).c_str());
    }
}

int run(const std::string& preset, const fs::path& scans_dir) {
    BenchDir tmp;
    ScanSeries scans(scans_dir, preset, 96, kSeriesStart);
    const double render_s = scans.render(0, 2, 2);
    std::printf("%s: scans of %.0f MB rendered in %.0f s (0 when reused)\n", preset.c_str(),
                scans.scan_bytes(1) / 1e6, render_s);
    const fs::path dir = tmp / "run";
    const fs::path config = write_daemon_folder(dir, scans);
    DatabaseView db(dir / "tlsmon.sqlite");
    DaemonChild daemon(TLSMON_BINARY, config, dir / "daemon.log");
    wait_for([&] { return fs::exists(dir / "tlsmon.sqlite"); }, 60, "the database");
    std::this_thread::sleep_for(std::chrono::seconds(1));
    print_sample("start", 0, sample_process(daemon.pid()));
    for (int k = 0; k < 2; ++k) {
        if (!scans.feed(k, dir / "ingest")) {
            std::printf("    epoch %d: the scene has no scan here\n", k);
            continue;
        }
        const auto t0 = std::chrono::steady_clock::now();  // the scan has appeared (renamed)
        wait_for([&] { return db.processed() > k || !daemon.running(); }, 1800,
                 preset + " epoch " + std::to_string(k));
        require_running(daemon, dir / "daemon.log");
        const double wall = seconds_since(t0);
        std::printf("  %s:\n", k == 0 ? "reference epoch" : "second epoch");
        SQLite::Database& d = db.open();
        print_epoch(d, d.execAndGet("SELECT max(id) FROM epochs").getInt64(), wall);
        print_sample("after", k + 1, sample_process(daemon.pid()));
    }
    const int code = daemon.stop(120);
    std::printf("  daemon stopped, exit %d\n", code);
    return code;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scans_dir;
    std::vector<std::string> presets;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--scans") && i + 1 < argc) {
            scans_dir = argv[++i];
        } else {
            presets.emplace_back(argv[i]);
        }
    }
    if (presets.empty()) presets = {"pier", "hochmosel"};
    int rc = 0;
    try {
        BenchDir tmp;
        for (const std::string& p : presets) {
            const fs::path folder = (scans_dir.empty() ? tmp / "scans" : fs::path(scans_dir)) / p;
            rc |= run(p, folder) == 0 ? 0 : 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_epoch_budget: %s\n", e.what());
        return 1;
    }
    return rc;
}
