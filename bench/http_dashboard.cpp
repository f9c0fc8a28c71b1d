// Dashboard API benchmark (reported, not asserted), on the one-year database that
// bench_epoch_database generates (35,040 epochs, 50 zones x 4 quantities):
//  1. GET /api/v1/site (target 20 ms);
//  2. GET /api/v1/series, one zone's quantity over the whole year decimated to 1,200 pixels
//     (target 50 ms), and the same at full resolution for a zoomed week;
//     GET /api/v1/calibration over 30 days and over the year (no target);
//  3. 20 clients polling /api/v1/site, each once a second (target p99 200 ms), then back to
//     back (saturation): median, p99, requests per second.
// Each through a real connection to the HttpService the daemon runs (cpp-httplib's client).
// Usage: bench_http_dashboard DIR   (DIR holds year.sqlite: run bench_epoch_database DIR first)
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "daemon/http/http_service.hpp"
#include "storage/epoch_database.hpp"

namespace fs = std::filesystem;
using namespace tlsmon;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

double quantile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    const double at = q * static_cast<double>(v.size() - 1);
    const auto below = static_cast<std::size_t>(at);
    const std::size_t above = std::min(below + 1, v.size() - 1);
    return v[below] + (at - static_cast<double>(below)) * (v[above] - v[below]);
}

std::string spread(const std::vector<double>& v) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "median %.2f ms (quartiles %.2f-%.2f, p99 %.2f, max %.2f, n=%zu)",
                  quantile(v, 0.5), quantile(v, 0.25), quantile(v, 0.75), quantile(v, 0.99),
                  quantile(v, 1.0), v.size());
    return buf;
}

// `n` timed GETs of `path` on one kept-alive connection; the body size of the last.
std::vector<double> timed_gets(int port, const std::string& path, int n, std::size_t* bytes) {
    httplib::Client client("127.0.0.1", port);
    client.set_keep_alive(true);
    std::vector<double> ms;
    for (int k = 0; k < n; ++k) {
        const auto t = Clock::now();
        const auto r = client.Get(path.c_str());
        ms.push_back(ms_since(t));
        if (!r || r->status != 200)
            throw std::runtime_error(path + ": " + (r ? std::to_string(r->status) : "no answer"));
        if (bytes) *bytes = r->body.size();
    }
    return ms;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_http_dashboard DIR (with DIR/year.sqlite)\n");
        return 2;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    try {
        const fs::path year = fs::path(argv[1]) / "year.sqlite";
        if (!fs::exists(year))
            throw std::runtime_error(year.string() + " missing: run bench_epoch_database first");
        {  // a database of an older schema is migrated first (its time reported)
            const auto t = Clock::now();
            auto db = EpochDatabase::open(year, EpochDatabase::Mode::read_write);
            std::printf("opened read-write (migrated to schema %d if older): %.1f s\n",
                        db.schema_version(), ms_since(t) / 1000);
        }
        HttpConfig config;
        config.enabled = true;
        config.port = 18080;
        config.web_root = fs::read_symlink("/proc/self/exe").parent_path() / ".." / "web";
        DashboardSite site;
        site.station = "bench";
        site.started = now_utc();
        HttpService service(config, year, site, nullptr);
        std::size_t bytes = 0;

        auto site_ms = timed_gets(config.port, "/api/v1/site", 31, &bytes);
        std::printf("GET /api/v1/site: first %.1f ms, then %s, %zu B (target 20 ms: %.2fx)\n",
                    site_ms.front(), spread({site_ms.begin() + 1, site_ms.end()}).c_str(), bytes,
                    quantile({site_ms.begin() + 1, site_ms.end()}, 0.5) / 20.0);

        const std::string series = "/api/v1/series?zone=zone%2017&quantity=m3c2_mean_m&width=1200";
        auto year_ms = timed_gets(config.port, series, 21, &bytes);
        std::printf(
            "GET one year decimated to 1200 px: first %.1f ms, then %s, %zu B (target 50 "
            "ms: %.2fx)\n",
            year_ms.front(), spread({year_ms.begin() + 1, year_ms.end()}).c_str(), bytes,
            quantile({year_ms.begin() + 1, year_ms.end()}, 0.5) / 50.0);
        auto week_ms = timed_gets(
            config.port, series + "&from=2026-06-01T00:00:00Z&to=2026-06-07T23:59:59Z", 21, &bytes);
        std::printf("GET one week, full resolution: %s, %zu B\n", spread(week_ms).c_str(), bytes);

        // The calibration page: its default window (30 days back from the newest epoch), and
        // the whole year (every epoch's registration and targets read).
        auto month_ms =
            timed_gets(config.port, "/api/v1/calibration?from=2026-12-01T00:00:00Z", 6, &bytes);
        std::printf("GET calibration, 30 days: %s, %zu B\n", spread(month_ms).c_str(), bytes);
        auto all_ms = timed_gets(config.port, "/api/v1/calibration", 4, &bytes);
        std::printf("GET calibration, the year: %s, %zu B\n", spread(all_ms).c_str(), bytes);

        // 3. 20 open pages, each asking for the overview once a second (a page with its live
        //    stream asks only after a commit: this is the harsher case), for 15 s; then the
        //    same 20 clients back to back, as fast as they are answered (saturation).
        constexpr int kClients = 20;
        for (const bool paced : {true, false}) {
            std::mutex m;
            std::vector<double> all;
            std::vector<std::thread> clients;
            const auto t = Clock::now();
            for (int c = 0; c < kClients; ++c) {
                clients.emplace_back([&, c] {
                    httplib::Client client("127.0.0.1", config.port);
                    client.set_keep_alive(true);
                    std::vector<double> ms;
                    // Staggered starts, as pages are opened at different moments.
                    std::this_thread::sleep_for(std::chrono::milliseconds(paced ? 50 * c : 0));
                    for (int k = 0; k < (paced ? 15 : 25); ++k) {
                        const auto due = t + std::chrono::milliseconds(50 * c + 1000 * k);
                        if (paced) std::this_thread::sleep_until(due);
                        const auto r0 = Clock::now();
                        const auto r = client.Get("/api/v1/site");
                        ms.push_back(ms_since(r0));
                        if (!r || r->status != 200) throw std::runtime_error("/api/v1/site failed");
                    }
                    std::lock_guard lock(m);
                    all.insert(all.end(), ms.begin(), ms.end());
                });
            }
            for (auto& c : clients) c.join();
            std::printf("%d clients, /api/v1/site %s: %s; %.0f requests/s%s\n", kClients,
                        paced ? "once a second each for 15 s" : "back to back, 25 each",
                        spread(all).c_str(), all.size() / (ms_since(t) / 1000),
                        paced ? (" (target p99 200 ms: " +
                                 std::to_string(quantile(all, 0.99) / 200.0).substr(0, 4) + "x)")
                                    .c_str()
                              : "");
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_http_dashboard: %s\n", e.what());
        return 1;
    }
}
