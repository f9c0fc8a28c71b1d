// Backlog: the daemon down for 12 hours while the scanner goes on. The demo's `small` scene
// (knocked target and step event inside the outage); a few epochs processed live, the daemon
// stopped, 48 scans (15 min apart) with their meteo sidecars written into the ingest folder,
// the daemon started again. Prints how long it takes to catch up, and checks from the daemon's
// log and database that the epochs were processed, and the alarm events written, in
// acquisition order. The series starts yesterday at 00:00 UTC, so its scans are rendered
// afresh each day (--scans keeps them for reruns). Nothing is asserted; an order broken is
// printed as such (and the exit code is 1).
// Usage: bench_backlog [--waiting N] [--live N] [--scans DIR]   (defaults: 48, 4)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <regex>
#include <string>

#include "bench/bench_support.hpp"
#include "bench/daemon_bench.hpp"
#include "core/utc_time.hpp"
#include "demo/daemon_process.hpp"

using namespace tlsmon;
using namespace tlsmon::bench;

int main(int argc, char** argv) {
    int waiting = 48, live = 4;
    std::string scans_dir;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--waiting"))
            waiting = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--live"))
            live = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--scans"))
            scans_dir = argv[i + 1];
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (waiting < 1 || live < 1) {
        std::fprintf(stderr, "--waiting and --live must be at least 1\n");
        return 2;
    }
    try {
        BenchDir tmp;
        const int total = live + waiting;
        // Yesterday from 00:00 UTC: the reference at night, when the pier is near its rest (as
        // in `tlsmon demo`); the daemon's system.stale then stays raised, the newest scan being
        // hours old by the wall clock.
        const std::int64_t now = now_utc();
        const std::int64_t start = now - now % 86400 - 86400;
        ScanSeries scans(scans_dir.empty() ? tmp / "scans" : fs::path(scans_dir), "small", total,
                         start);
        const double render_s = scans.render(0, total, 2);
        std::printf(
            "backlog: %d epochs live, then %d waiting (%.1f h outage) of the demo's "
            "'small' scene; rendered in %.0f s (0 when reused)\n",
            live, waiting, waiting * scans.site().cadence_seconds / 3600.0, render_s);

        const fs::path dir = tmp / "run";
        const fs::path config = write_daemon_folder(dir, scans);
        const fs::path log = dir / "daemon.log";
        DatabaseView db(dir / "tlsmon.sqlite");
        int expected = 0;
        {
            DaemonChild daemon(TLSMON_BINARY, config, log);
            for (int k = 0; k < live; ++k) {
                if (scans.feed(k, dir / "ingest")) ++expected;
                wait_for([&] { return db.processed() >= expected || !daemon.running(); }, 300,
                         "live epoch " + std::to_string(k));
                require_running(daemon, log);
            }
            std::printf("  live epochs processed; daemon stopped, exit %d\n", daemon.stop());
        }
        for (int k = live; k < total; ++k) {
            if (scans.feed(k, dir / "ingest")) ++expected;
        }
        const auto log_offset = fs::file_size(log);

        const auto t0 = std::chrono::steady_clock::now();
        DaemonChild daemon(TLSMON_BINARY, config, log);
        double first_s = -1;
        wait_for(
            [&] {
                const int n = db.processed();
                if (first_s < 0 && n > expected - waiting) first_s = seconds_since(t0);
                return n >= expected || !daemon.running();
            },
            60.0 * waiting, "the backlog");
        require_running(daemon, log);
        const double catch_up = seconds_since(t0);
        const ProcSample proc = sample_process(daemon.pid());
        std::printf(
            "  caught up %d waiting scans in %.1f s from the daemon's start (%.2f s per "
            "epoch; first done after %.1f s); %.0f h of acquisitions per minute\n",
            waiting, catch_up, catch_up / waiting, first_s,
            waiting * scans.site().cadence_seconds / 3600.0 / (catch_up / 60.0));
        print_sample("after", db.processed(), proc);
        const int code = daemon.stop();

        // The processing order: the daemon's "epoch ID done|rejected" lines after the restart.
        SQLite::Database& d = db.open();
        std::map<long, std::int64_t> acquired;
        SQLite::Statement epochs(d, "SELECT id, acquired FROM epochs ORDER BY id");
        std::vector<std::int64_t> by_id;
        while (epochs.executeStep()) {
            acquired[epochs.getColumn(0).getInt64()] = epochs.getColumn(1).getInt64();
            by_id.push_back(epochs.getColumn(1).getInt64());
        }
        const std::string text = read_text(log).substr(log_offset);
        const std::regex line(R"(epoch (\d+) (done|rejected))");
        std::vector<std::int64_t> order;
        for (std::sregex_iterator it(text.begin(), text.end(), line), end; it != end; ++it) {
            order.push_back(acquired.at(std::stol((*it)[1].str())));
        }
        const auto in_order = [](const std::vector<std::int64_t>& v) {
            return std::is_sorted(v.begin(), v.end());
        };
        std::printf("  processing order (daemon log): %zu epochs after the restart, %s\n",
                    order.size(),
                    in_order(order) ? "in acquisition order" : "NOT in acquisition order");
        std::printf("  epoch ids (discovery order): %s\n",
                    in_order(by_id) ? "in acquisition order" : "not in acquisition order");

        // The alarm events as written (row id) against their epochs' acquisition.
        SQLite::Statement events(
            d,
            "SELECT a.id, a.time, r.name, a.kind, a.level, e.acquired FROM alarm_events a "
            "JOIN alarm_rules r ON r.id = a.rule_id LEFT JOIN epochs e ON e.id = a.epoch_id "
            "ORDER BY a.id");
        std::vector<std::int64_t> event_order;
        while (events.executeStep()) {
            const std::int64_t at =
                events.getColumn(5).isNull() ? -1 : events.getColumn(5).getInt64();
            std::printf(
                "    alarm event %lld: %s %s %s, epoch acquired %s (event time %s)\n",
                static_cast<long long>(events.getColumn(0).getInt64()),
                events.getColumn(2).getString().c_str(), events.getColumn(3).getString().c_str(),
                events.getColumn(4).getString().c_str(), at < 0 ? "-" : sim::format_utc(at).c_str(),
                sim::format_utc(events.getColumn(1).getInt64()).c_str());
            if (at >= 0) event_order.push_back(at);
        }
        std::printf("  alarm events: %zu with an epoch, %s\n", event_order.size(),
                    in_order(event_order) ? "written in acquisition order"
                                          : "NOT written in acquisition order");
        std::printf("  daemon stopped, exit %d\n", code);
        return code == 0 && in_order(order) && in_order(event_order) ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_backlog: %s\n", e.what());
        return 1;
    }
}
