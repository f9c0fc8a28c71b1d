// `tlsmon demo`: the whole system on a simulated day in a few minutes. A working folder with
// the scene, the site's configuration and a fresh database; the daemon started from this
// binary; the simulator writing one scan (with its meteo sidecar and truth) every few seconds
// into the ingest folder, stamped 15 minutes apart; a line per epoch as the daemon commits
// it; then the daemon stopped and the run scored against the truth (`tlsmon report`).
#include <signal.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/utc_time.hpp"
#include "demo/daemon_process.hpp"
#include "demo/progress.hpp"
#include "demo/scene.hpp"
#include "demo/site_config_writer.hpp"
#include "simulator/scene_file.hpp"
#include "simulator/series.hpp"

namespace tlsmon {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t g_interrupted = 0;

void on_signal(int) {
    g_interrupted = 1;
}

// SIGINT (Ctrl-C) and SIGTERM end the demo in order: the daemon is stopped, not left behind.
void catch_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    ::sigaction(SIGINT, &sa, nullptr);
    ::sigaction(SIGTERM, &sa, nullptr);
}

struct Interrupted {};

void check_interrupt() {
    if (g_interrupted) throw Interrupted{};
}

void write_all(const fs::path& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    f.close();
    if (!f) throw Error("cannot write " + path.string());
}

// Under a hidden temporary name, then renamed: the daemon sees each file complete at once.
void write_then_rename(const fs::path& path, const std::string& text) {
    const fs::path part = path.parent_path() / ("." + path.filename().string() + ".part");
    write_all(part, text);
    fs::rename(part, path);
}

constexpr const char* kMarker = ".tlsmon-demo";

// A new folder, or a previous demo's (marked) emptied; any other non-empty folder is refused.
void prepare_workdir(const fs::path& dir) {
    if (fs::exists(dir)) {
        if (!fs::is_directory(dir)) throw Error(dir.string() + " exists and is not a folder");
        const bool empty = fs::directory_iterator(dir) == fs::directory_iterator();
        if (!empty && !fs::exists(dir / kMarker)) {
            throw Error(dir.string() +
                        " is not empty and not a tlsmon demo folder; give another --workdir");
        }
        for (const auto& entry : fs::directory_iterator(dir)) fs::remove_all(entry.path());
    }
    fs::create_directories(dir);
    write_all(dir / kMarker, "A `tlsmon demo` working folder; the next demo here clears it.\n");
}

// 00:00 UTC of today: the reference epoch is then taken at night, when the pier is near its
// rest, whatever the hour the demo is run (the thermal bending follows the sun).
std::int64_t default_start() {
    const std::int64_t now = now_utc();
    return now - now % 86400;
}

std::string tail_of(const fs::path& log, std::size_t lines) {
    std::ifstream in(log);
    std::vector<std::string> all;
    for (std::string l; std::getline(in, l);) all.push_back(l);
    std::string out;
    for (std::size_t i = all.size() > lines ? all.size() - lines : 0; i < all.size(); ++i) {
        out += "  " + all[i] + "\n";
    }
    return out;
}

// Polls the progress until `until`, the daemon's end or an interrupt.
void wait_printing(Clock::time_point until, DemoProgress& progress, DaemonChild& daemon,
                   const fs::path& log) {
    do {
        check_interrupt();
        progress.poll();
        if (!daemon.running()) {
            throw Error("the daemon stopped (exit " + std::to_string(daemon.exit_code()) +
                        "); the end of " + log.string() + ":\n" + tail_of(log, 15));
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    } while (Clock::now() < until);
}

int demo(const DemoOptions& o) {
    const fs::path dir = fs::absolute(o.workdir).lexically_normal();
    prepare_workdir(dir);
    const DemoScene scene = demo_scene(o.preset, o.epochs);
    write_all(dir / "scene.toml", scene_file_text(scene));
    const sim::Site site = load_scene_file(dir / "scene.toml", std::nullopt);
    const std::int64_t start = o.start.empty() ? default_start() : sim::parse_utc(o.start);

    DemoSite ds;
    ds.site_toml = site_configuration(site);
    write_all(dir / "site.toml", ds.site_toml);
    const auto& p = site.pier;
    ds.step_min = {p.x0, p.y0 - 0.5, site.events.step_z_min};
    ds.step_max = {p.x1, p.y0 + 0.5, site.events.step_z_max};
    ds.check_zone_toml = abutment_check_zone(site);
    ds.modbus_port = o.modbus_port;
    ds.http_port = o.http_port;
    const std::string dashboard =
        o.http_port > 0 ? "http://127.0.0.1:" + std::to_string(o.http_port) + "/" : "";
    const fs::path config = dir / "tlsmon.toml";
    write_all(config, demo_daemon_config(ds));
    const fs::path ingest = dir / "ingest", truth = dir / "truth", log = dir / "daemon.log";
    const fs::path database = dir / "tlsmon.sqlite";
    fs::create_directories(ingest);
    fs::create_directories(truth);

    std::cout << "tlsmon demo: " << o.epochs << " epochs of the '" << o.preset
              << "' scene, 15 min apart from " << sim::format_utc(start) << ", one every "
              << o.interval << " s\n"
              << "  events (truth): target " << scene.knocked_target << " knocked 10 mm at epoch "
              << scene.knocked_epoch << "; pier z " << site.events.step_z_min << "-"
              << site.events.step_z_max << " m steps " << 1e3 * site.events.step_displacement.norm()
              << " mm towards the scanner at epoch " << scene.step_epoch << "\n"
              << "  folder " << dir.string() << ": scene.toml, tlsmon.toml, ingest/, truth/, "
              << "tlsmon.sqlite, daemon.log\n"
              << "  daemon: " << own_executable().string() << " run --config " << config.string()
              << " (Modbus on 127.0.0.1:" << o.modbus_port << ")\n";
    if (!dashboard.empty())
        std::cout << "  dashboard: " << dashboard << " (open it in a browser)\n";
    std::cout << std::flush;

    DaemonChild daemon(own_executable(), config, log);
    DemoProgress progress(database, o.epochs, start, site.cadence_seconds,
                          {kStepZone, ds.west_zone, "pier_south_face"}, std::cout);
    const auto ready_by = Clock::now() + std::chrono::seconds(30);
    while (!fs::exists(database)) {
        if (Clock::now() > ready_by) throw Error("the daemon did not create " + database.string());
        wait_printing(Clock::now() + std::chrono::milliseconds(100), progress, daemon, log);
    }

    const auto wall_start = Clock::now();
    for (int epoch = 0; epoch < o.epochs; ++epoch) {
        check_interrupt();
        const sim::EpochFiles f = sim::simulate_epoch(site, epoch, start, o.threads);
        // The truth beside the run, not in the ingest folder: a site has none.
        write_then_rename(truth / (f.stem + ".truth.json"), f.truth.dump(2) + "\n");
        if (!f.meteo.empty()) write_then_rename(ingest / (f.stem + ".meteo.csv"), f.meteo);
        if (!f.missing) write_then_rename(ingest / (f.stem + ".ptx"), f.ptx);
        wait_printing(wall_start + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(o.interval * (epoch + 1))),
                      progress, daemon, log);
    }
    // The last scans: each is processed within a few seconds of its arrival.
    const auto finish_by = Clock::now() + std::chrono::seconds(120);
    while (progress.poll() < o.epochs) {
        if (Clock::now() > finish_by) {
            std::cout << "  (not every epoch was processed within 120 s after the last scan)\n";
            break;
        }
        wait_printing(Clock::now() + std::chrono::milliseconds(200), progress, daemon, log);
    }
    // With --serve the daemon stays up for the dashboard while the report is written.
    const int code = o.serve ? 0 : daemon.stop();
    if (!o.serve) {
        std::cout << "daemon stopped (exit " << code << "), "
                  << std::chrono::duration<double>(Clock::now() - wall_start).count()
                  << " s after the first scan; log " << log.string() << "\n\n";
    }

    ReportOptions r;
    r.database = database.string();
    r.truth = truth.string();
    r.out = (dir / "report").string();
    r.config = config.string();
    r.modbus_port = o.modbus_port;
    std::cout << "Scored against the truth (tlsmon report --database " << r.database << " --truth "
              << r.truth << " --out " << r.out << "):\n";
    const int rc = run_report(r);
    std::cout << "\nLook further: tlsmon query registrations --config " << config.string()
              << "\n              tlsmon run --config " << config.string()
              << "   # the daemon again, then: mbpoll -m tcp -p " << o.modbus_port
              << " -0 -1 -t 3 -r 0 -c 7 127.0.0.1"
              << (dashboard.empty() ? "" : "\n              and the dashboard: " + dashboard)
              << std::endl;
    if (o.serve) {
        std::cout << "\nServing the dashboard at " << dashboard << " until Ctrl-C." << std::endl;
        try {
            wait_printing(Clock::time_point::max(), progress, daemon, log);
        } catch (const Interrupted&) {
            std::cout << "\ndaemon stopped (exit " << daemon.stop() << ")" << std::endl;
        }
    }
    return rc == 0 && code == 0 ? 0 : 1;
}

}  // namespace

int run_demo(const DemoOptions& options) {
    catch_signals();
    try {
        return demo(options);
    } catch (const Interrupted&) {
        const fs::path dir = fs::absolute(options.workdir).lexically_normal();
        std::cerr << "\ntlsmon demo: interrupted; the daemon was stopped. What was done is in "
                  << dir.string() << "; its report: tlsmon report --database "
                  << (dir / "tlsmon.sqlite").string() << " --truth " << (dir / "truth").string()
                  << " --out " << (dir / "report").string() << std::endl;
        return 130;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon demo: " << e.what() << '\n';
        return 1;
    }
}

}  // namespace tlsmon
