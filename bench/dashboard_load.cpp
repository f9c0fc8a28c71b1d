// The ingest while the dashboard is watched (issue 26): the `small` scene's epochs fed to a
// real daemon one at a time, alternately with the dashboard idle and with 20 clients polling
// as open pages do (each once a second, in turn: the overview, the step zone's whole series
// decimated to 1,200 pixels, the newest epoch's M3C2 map). Alternating keeps the comparison
// fair when the machine's speed drifts. Prints each epoch's total_ms as the daemon stored
// it, the median of each group and their ratio (target: within 10 %), and the clients'
// answer times (target p99 200 ms). Nothing is asserted.
// Usage: bench_dashboard_load [--scans DIR] [EPOCHS]   (default 13: the reference and 12)
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_support.hpp"
#include "bench/daemon_bench.hpp"
#include "demo/daemon_process.hpp"
#include "tests/support/modbus_client.hpp"

// Last: its resolver header defines `_res`, which Eigen (above) names a parameter.
#include <httplib.h>

using namespace tlsmon;
using namespace tlsmon::bench;

namespace {

constexpr int kClients = 20;

// 20 pages, each asking once a second; the answer times of every request, in ms.
class Pollers {
  public:
    Pollers(int port, std::vector<std::string> paths) : port_(port), paths_(std::move(paths)) {
        for (int c = 0; c < kClients; ++c) threads_.emplace_back([this, c] { poll(c); });
    }
    ~Pollers() { stop(); }
    void stop() {
        stopping_ = true;
        for (auto& t : threads_)
            if (t.joinable()) t.join();
    }
    std::vector<double> times() {
        std::lock_guard lock(mutex_);
        return ms_;
    }
    int failures() const { return failures_; }

  private:
    void poll(int client) {
        auto next = std::chrono::steady_clock::now() + std::chrono::milliseconds(50 * client);
        for (std::size_t k = static_cast<std::size_t>(client); !stopping_; ++k) {
            std::this_thread::sleep_until(next);
            next += std::chrono::seconds(1);
            httplib::Client http("127.0.0.1", port_);
            http.set_read_timeout(10, 0);
            const auto t0 = std::chrono::steady_clock::now();
            const auto answer = http.Get(paths_[k % paths_.size()]);
            const double ms = seconds_since(t0) * 1000.0;
            std::lock_guard lock(mutex_);
            if (!answer || answer->status != 200) {
                ++failures_;
            } else {
                ms_.push_back(ms);
            }
        }
    }

    int port_;
    std::vector<std::string> paths_;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::vector<double> ms_;
    int failures_ = 0;
    std::vector<std::thread> threads_;
};

double median_of(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double quantile_of(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

int run(const fs::path& scans_dir, int epochs) {
    BenchDir tmp;
    ScanSeries scans(scans_dir.empty() ? tmp / "scans" : scans_dir, "small", 96, kSeriesStart);
    const double render_s = scans.render(0, epochs, 2);
    std::printf("small: %d epochs rendered in %.0f s (0 when reused)\n", epochs, render_s);
    const fs::path dir = tmp / "run";
    const fs::path config = write_daemon_folder(dir, scans);
    const int port = test::free_tcp_port();
    {
        std::string text = read_text(config);
        // The demo's [http] (demo/scene.cpp) is enabled; here on this bench's own port.
        const auto at = text.find("[http]\nenabled = true\n");
        const auto port_at = at == std::string::npos ? at : text.find("port = ", at);
        if (port_at == std::string::npos)
            throw std::runtime_error("the demo configuration's [http] is not as expected");
        text.replace(port_at, text.find('\n', port_at) - port_at, "port = " + std::to_string(port));
        write_text(config, text);
    }
    DatabaseView db(dir / "tlsmon.sqlite");
    DaemonChild daemon(TLSMON_BINARY, config, dir / "daemon.log");
    wait_for([&] { return fs::exists(dir / "tlsmon.sqlite"); }, 60, "the database");
    const std::vector<std::string> paths{
        "/api/v1/site",
        std::string("/api/v1/series?zone=") + kStepZone + "&quantity=m3c2_median_m&width=1200",
        "/api/v1/epochs/1/corepoints"};
    std::vector<double> idle_ms, watched_ms, answers;
    int failures = 0;
    for (int k = 0; k < epochs; ++k) {
        const bool watched = k > 0 && k % 2 == 0;
        std::optional<Pollers> pollers;
        if (watched) pollers.emplace(port, paths);
        if (!scans.feed(k, dir / "ingest"))
            throw std::runtime_error("no scan of epoch " + std::to_string(k));
        wait_for([&] { return db.processed() > k || !daemon.running(); }, 600,
                 "epoch " + std::to_string(k));
        require_running(daemon, dir / "daemon.log");
        if (pollers) {
            pollers->stop();
            const auto t = pollers->times();
            answers.insert(answers.end(), t.begin(), t.end());
            failures += pollers->failures();
        }
        SQLite::Database& d = db.open();
        const double total =
            d.execAndGet("SELECT total_ms FROM epochs ORDER BY id DESC LIMIT 1").getDouble();
        std::printf("  epoch %2d %-8s total %7.0f ms\n", k,
                    k == 0    ? "(ref)"
                    : watched ? "watched"
                              : "idle",
                    total);
        std::fflush(stdout);
        if (k > 0) (watched ? watched_ms : idle_ms).push_back(total);
    }
    const double idle = median_of(idle_ms), seen = median_of(watched_ms);
    std::printf(
        "epoch total_ms, median: idle %.0f ms (n=%zu), with %d clients polling %.0f ms (n=%zu): "
        "ratio %.3f (target within 10 %%)\n",
        idle, idle_ms.size(), kClients, seen, watched_ms.size(), idle > 0 ? seen / idle : 0.0);
    std::printf(
        "client answers while epochs ingest: %zu, median %.1f ms, p99 %.1f ms, max %.1f ms, "
        "%d failed (target p99 200 ms)\n",
        answers.size(), median_of(answers), quantile_of(answers, 0.99),
        answers.empty() ? 0.0 : *std::max_element(answers.begin(), answers.end()), failures);
    return daemon.stop(120);
}

}  // namespace

int main(int argc, char** argv) {
    fs::path scans;
    int epochs = 13;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--scans") && i + 1 < argc) {
            scans = argv[++i];
        } else {
            epochs = std::max(3, std::atoi(argv[i]));
        }
    }
    try {
        return run(scans, epochs) == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_dashboard_load: %s\n", e.what());
        return 1;
    }
}
