// Soak: N accelerated epochs of the demo's `small` scene through a real daemon (`tlsmon run`).
// The scans are rendered first (or taken from --scans DIR, where an earlier run left them),
// then fed into the ingest folder in acquisition order as fast as the daemon takes them (at
// most two waiting), so the daemon never idles on the feeder. Prints the throughput, the
// daemon's resident memory and open file descriptors at the start, every --every epochs and
// at the end (they must stay flat), and the database size. Nothing is asserted.
// Usage: bench_soak [--epochs N] [--every K] [--scans DIR] [--render-threads T]
//        (defaults: 500 epochs, every 50, scans rendered into a temporary folder, 2 threads)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "bench/bench_support.hpp"
#include "bench/daemon_bench.hpp"
#include "demo/daemon_process.hpp"

using namespace tlsmon;
using namespace tlsmon::bench;

int main(int argc, char** argv) {
    int epochs = 500, every = 50;
    unsigned render_threads = 2;
    std::string scans_dir;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--epochs"))
            epochs = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--every"))
            every = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--scans"))
            scans_dir = argv[i + 1];
        else if (!std::strcmp(argv[i], "--render-threads"))
            render_threads = static_cast<unsigned>(std::atoi(argv[i + 1]));
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (epochs < 2 || every < 1) {
        std::fprintf(stderr, "--epochs must be at least 2 and --every at least 1\n");
        return 2;
    }
    try {
        BenchDir tmp;
        // The scene of 500 epochs (its events at 125 and 250) whatever --epochs: a shorter run
        // is the start of the same series, and renders kept in --scans serve a longer one.
        ScanSeries scans(scans_dir.empty() ? tmp / "scans" : fs::path(scans_dir), "small",
                         std::max(epochs, 500), kSeriesStart);
        std::printf("soak: %d epochs of the demo's 'small' scene (0.05°, five spheres)\n", epochs);
        const double render_s = scans.render(0, epochs, render_threads);
        std::printf("  rendered in %.0f s (0 when reused); scan size %.1f MB\n", render_s,
                    scans.scan_bytes(1) / 1e6);

        const fs::path dir = tmp / "run";
        const fs::path config = write_daemon_folder(dir, scans);
        DatabaseView db(dir / "tlsmon.sqlite");
        DaemonChild daemon(TLSMON_BINARY, config, dir / "daemon.log");
        wait_for([&] { return fs::exists(dir / "tlsmon.sqlite"); }, 60, "the database");
        std::this_thread::sleep_for(std::chrono::seconds(1));
        print_sample("start", 0, sample_process(daemon.pid()));

        const auto t0 = std::chrono::steady_clock::now();
        int fed = 0, scans_fed = 0, processed = 0, next_sample = every;
        while (fed < epochs || processed < scans_fed) {
            require_running(daemon, dir / "daemon.log");
            while (fed < epochs && scans_fed - processed < 2) {
                if (scans.feed(fed, dir / "ingest")) ++scans_fed;  // false: no scan this epoch
                ++fed;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            const int now = db.processed();
            if (now == processed) {
                if (seconds_since(t0) > 60.0 * (fed + 2)) throw std::runtime_error("stalled");
                continue;
            }
            processed = now;
            if (processed >= next_sample) {
                print_sample("after", processed, sample_process(daemon.pid()));
                next_sample += every;
            }
        }
        const double wall = seconds_since(t0);
        const ProcSample end = sample_process(daemon.pid());
        print_sample("end", processed, end);
        SQLite::Database& d = db.open();
        const int done = d.execAndGet("SELECT count(*) FROM epochs WHERE status = 'done'").getInt();
        const int rejected =
            d.execAndGet("SELECT count(*) FROM epochs WHERE status = 'rejected'").getInt();
        const int failed =
            d.execAndGet("SELECT count(*) FROM epochs WHERE status = 'failed'").getInt();
        const double mean_total =
            d.execAndGet("SELECT avg(total_ms) FROM epochs WHERE status = 'done'").getDouble();
        std::printf(
            "  %d epochs processed (%d done, %d rejected, %d failed) in %.0f s: %.1f epochs/min "
            "(the daemon's own total per done epoch: mean %.0f ms)\n",
            processed, done, rejected, failed, wall, 60.0 * processed / wall, mean_total);
        std::printf("  database %.1f MB (%.1f kB per epoch) with its WAL\n", db.bytes() / 1e6,
                    db.bytes() / 1e3 / std::max(1, processed));
        const int code = daemon.stop();
        std::printf("  daemon stopped, exit %d\n", code);
        return code == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_soak: %s\n", e.what());
        return 1;
    }
}
