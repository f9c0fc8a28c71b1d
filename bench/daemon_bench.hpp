#pragma once
// Shared by the benches that run the real daemon (soak, backlog, epoch_budget): a working
// folder written as `tlsmon demo` writes it (its scene and daemon configuration, Modbus off so
// that parallel runs do not fight over a port), scans rendered once into a folder that a later
// run can reuse, files fed into the ingest folder the way the scanner's export appears (written
// under a hidden name, then renamed), the daemon's memory and descriptors from /proc, and the
// count of processed epochs read from its database.
#include <SQLiteCpp/SQLiteCpp.h>
#include <sys/types.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_support.hpp"
#include "demo/daemon_process.hpp"
#include "demo/scene.hpp"
#include "demo/site_config_writer.hpp"
#include "simulator/scene_file.hpp"
#include "simulator/series.hpp"
#include "tests/support/text_file.hpp"

namespace tlsmon::bench {

namespace fs = std::filesystem;

using test::read_text;
using test::write_text;

// Complete at once for the daemon's watcher: a hidden ".name.part", then a rename.
inline void place(const fs::path& from, const fs::path& folder) {
    const fs::path part = folder / ("." + from.filename().string() + ".part");
    fs::copy_file(from, part, fs::copy_options::overwrite_existing);
    fs::rename(part, folder / from.filename());
}

// The scans of a series, rendered once: `<stem>.ptx` and `<stem>.meteo.csv` in `folder`,
// beside the scene.toml they come from. Epochs already there are not rendered again; a folder
// holding another scene is refused.
class ScanSeries {
  public:
    ScanSeries(fs::path folder, const std::string& preset, int scene_epochs, std::int64_t start)
        : folder_(std::move(folder)), start_(start) {
        fs::create_directories(folder_);
        scene_text_ = scene_file_text(demo_scene(preset, scene_epochs));
        const fs::path scene = folder_ / "scene.toml";
        if (fs::exists(scene) && read_text(scene) != scene_text_) {
            throw std::runtime_error(folder_.string() + " holds scans of another scene");
        }
        write_text(scene, scene_text_);
        site_ = load_scene_file(scene, std::nullopt);
    }

    const sim::Site& site() const { return site_; }
    const std::string& scene_text() const { return scene_text_; }
    std::int64_t acquired(int epoch) const {
        return start_ + std::llround(epoch * site_.cadence_seconds);  // as simulate_epoch
    }
    std::string stem(int epoch) const {
        return sim::scan_file_stem(site_.scanner.station, acquired(epoch));
    }

    // Renders epochs [first, first + count) not yet in the folder; returns the seconds spent.
    double render(int first, int count, unsigned threads) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = first; k < first + count; ++k) {
            if (fs::exists(folder_ / (stem(k) + ".rendered"))) continue;
            const sim::EpochFiles f = sim::simulate_epoch(site_, k, start_, threads);
            if (!f.meteo.empty()) write_text(folder_ / (f.stem + ".meteo.csv"), f.meteo);
            if (!f.missing) write_text(folder_ / (f.stem + ".ptx"), f.ptx);
            write_text(folder_ / (f.stem + ".rendered"), "");
        }
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }

    // Copies epoch k's files into `ingest` (sidecar first, as the scanner's PC writes them).
    // False when the scanner exported no scan at this epoch.
    bool feed(int epoch, const fs::path& ingest) const {
        const fs::path meteo = folder_ / (stem(epoch) + ".meteo.csv");
        const fs::path ptx = folder_ / (stem(epoch) + ".ptx");
        if (fs::exists(meteo)) place(meteo, ingest);
        if (!fs::exists(ptx)) return false;
        place(ptx, ingest);
        return true;
    }
    std::uintmax_t scan_bytes(int epoch) const {
        const fs::path ptx = folder_ / (stem(epoch) + ".ptx");
        return fs::exists(ptx) ? fs::file_size(ptx) : 0;
    }

  private:
    fs::path folder_;
    std::int64_t start_;
    std::string scene_text_;
    sim::Site site_;
};

// tlsmon.toml (the demo's configuration with Modbus off), ingest/ and the scene in `dir`.
inline fs::path write_daemon_folder(const fs::path& dir, const std::string& scene_text,
                                    const sim::Site& site) {
    fs::create_directories(dir / "ingest");
    write_text(dir / "scene.toml", scene_text);
    DemoSite ds;
    ds.site_toml = site_configuration(site);
    ds.step_min = {site.pier.x0, site.pier.y0 - 0.5, site.events.step_z_min};
    ds.step_max = {site.pier.x1, site.pier.y0 + 0.5, site.events.step_z_max};
    ds.check_zone_toml = abutment_check_zone(site);
    std::string config = demo_daemon_config(ds);
    const std::string on = "[modbus]\nenabled = true";
    const auto at = config.find(on);
    if (at == std::string::npos) throw std::runtime_error("the demo configuration has no [modbus]");
    config.replace(at, on.size(), "[modbus]\nenabled = false");
    write_text(dir / "tlsmon.toml", config);
    return dir / "tlsmon.toml";
}

inline fs::path write_daemon_folder(const fs::path& dir, const ScanSeries& scans) {
    return write_daemon_folder(dir, scans.scene_text(), scans.site());
}

// The daemon as the kernel sees it.
struct ProcSample {
    long rss_kb = -1;  // VmRSS
    long hwm_kb = -1;  // VmHWM: the peak resident set
    long fds = -1;     // entries of /proc/PID/fd
};

inline ProcSample sample_process(pid_t pid) {
    ProcSample s;
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("VmRSS:", 0) == 0) s.rss_kb = std::stol(line.substr(6));
        if (line.rfind("VmHWM:", 0) == 0) s.hwm_kb = std::stol(line.substr(6));
    }
    std::error_code ec;
    long n = 0;
    for (fs::directory_iterator it("/proc/" + std::to_string(pid) + "/fd", ec), end;
         !ec && it != end; it.increment(ec)) {
        ++n;
    }
    if (!ec) s.fds = n;
    return s;
}

inline void print_sample(const char* when, int processed, const ProcSample& s) {
    std::printf("  %-6s %4d epochs: RSS %7.1f MB (peak %7.1f MB), %3ld open fds\n", when, processed,
                s.rss_kb / 1024.0, s.hwm_kb / 1024.0, s.fds);
    std::fflush(stdout);
}

// Read-only look at the daemon's database (WAL: beside the writing daemon).
class DatabaseView {
  public:
    explicit DatabaseView(fs::path path) : path_(std::move(path)) {}

    // Epochs done, rejected or failed; 0 while the daemon has not created the tables.
    int processed() {
        try {
            SQLite::Database& db = open();
            return db
                .execAndGet(
                    "SELECT count(*) FROM epochs WHERE status IN ('done','rejected','failed')")
                .getInt();
        } catch (const SQLite::Exception&) {
            db_.reset();
            return 0;
        }
    }
    SQLite::Database& open() {
        if (!db_) {
            db_.emplace(path_.string(), SQLite::OPEN_READONLY);
            db_->setBusyTimeout(5000);
        }
        return *db_;
    }
    // The database file with its write-ahead log.
    std::uintmax_t bytes() const {
        std::uintmax_t n = 0;
        for (const char* suffix : {"", "-wal", "-shm"}) {
            std::error_code ec;
            const auto size = fs::file_size(fs::path(path_.string() + suffix), ec);
            if (!ec) n += size;
        }
        return n;
    }

  private:
    fs::path path_;
    std::optional<SQLite::Database> db_;
};

// Polls until `done()` or `timeout` s; throws naming `what` on the timeout.
template <class Done>
void wait_for(Done&& done, double timeout, const std::string& what) {
    const auto t0 = std::chrono::steady_clock::now();
    while (!done()) {
        if (seconds_since(t0) > timeout) throw std::runtime_error("timed out waiting for " + what);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

// After a wait: a daemon that stopped on its own ends the bench, with the end of its log
// (the working folder is removed on the way out).
inline void require_running(DaemonChild& daemon, const fs::path& log) {
    if (daemon.running()) return;
    const std::string text = read_text(log);
    throw std::runtime_error("the daemon stopped (exit " + std::to_string(daemon.exit_code()) +
                             "); the end of its log:\n" +
                             text.substr(text.size() > 2000 ? text.size() - 2000 : 0));
}

// 2026-06-01T00:00:00Z: a fixed day, so that rendered scans can be reused between runs.
inline constexpr std::int64_t kSeriesStart = 1780272000;

}  // namespace tlsmon::bench
