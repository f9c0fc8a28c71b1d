#pragma once
// The demo's scenario for the end-to-end process tests: the scene `tlsmon demo` writes (the
// `small` preset at 0.05°, five spheres, target T2 knocked at N/4, the band z 30–40 m of the
// south face stepped 25 mm towards the scanner at N/2), rendered once by `tlsmon simulate`
// with its truth files; the daemon's configuration as the demo writes it; scans fed into the
// ingest folder one epoch at a time; the database read with the `sqlite3` program (not
// through tlsmon's storage code); the simulator's truth read from its JSON files by the
// field definitions of docs/simulator.md (not through tlsmon's report code).
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "demo/scene.hpp"
#include "tests/support/daemon_harness.hpp"
#include "tests/support/text_file.hpp"

namespace tlsmon::test::e2e {

using nlohmann::json;

// A word for the shell: single-quoted.
inline std::string quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// `query` run by the sqlite3 program on `database` (read-only, waiting up to 5 s for a
// writer), its rows as JSON objects. REALs come out with 17 significant digits or more, so
// they read back to the stored double.
inline json sql(const fs::path& database, const std::string& query) {
    const auto r = shell("sqlite3 -readonly -cmd '.timeout 5000' -json " +
                         quoted(database.string()) + " " + quoted(query));
    if (r.status != 0) throw std::runtime_error("sqlite3: " + r.output + "\nfor: " + query);
    if (r.output.find_first_not_of(" \n") == std::string::npos) return json::array();
    try {
        return json::parse(r.output);
    } catch (const json::exception& e) {
        throw std::runtime_error(std::string(e.what()) + "\nfor: " + query);
    }
}

// Modbus through mbpoll (0-based addresses, one poll): the raw 16-bit words (input
// registers, `-t 3:hex`) or bits (discrete inputs `-t 1`, coils `-t 0`) from `address`,
// `count` of them; empty when mbpoll failed.
inline std::vector<std::uint32_t> mbpoll_read(int port, const std::string& table, int address,
                                              int count) {
    const auto r = shell("timeout 10 mbpoll -m tcp -a 1 -p " + std::to_string(port) +
                         " -0 -1 -o 2 -t " + table + " -r " + std::to_string(address) + " -c " +
                         std::to_string(count) + " 127.0.0.1");
    std::vector<std::uint32_t> out;
    if (r.status != 0) return out;
    const std::regex row(R"(\[(\d+)\]:\s+(\S+))");
    for (std::sregex_iterator it(r.output.begin(), r.output.end(), row), end; it != end; ++it) {
        out.push_back(static_cast<std::uint32_t>(std::stoul((*it)[2], nullptr, 0)));
    }
    if (static_cast<int>(out.size()) != count) out.clear();
    return out;
}

// One epoch's truth file (docs/simulator.md, "Truth").
struct Truth {
    int epoch = 0;
    std::int64_t time = 0;
    Eigen::Affine3d header_to_true = Eigen::Affine3d::Identity();
    json doc;

    // The pier's displacement at the undeformed point p (docs/simulator.md, "Deformation"):
    // u_h = top_h (z/H)^exponent, u_z = top_z z/H, plus the step vector inside its band once
    // the step has happened.
    Eigen::Vector3d displacement(const Eigen::Vector3d& p) const {
        Eigen::Vector3d u = Eigen::Vector3d::Zero();
        const json& d = doc.at("deformation");
        if (d.at("enabled").get<bool>()) {
            const double h = d.at("height_m"), e = d.at("exponent");
            const auto& top = d.at("top_displacement_m");
            const double s = std::pow(p.z() / h, e);
            u = {top[0].get<double>() * s, top[1].get<double>() * s,
                 top[2].get<double>() * p.z() / h};
        }
        for (const auto& ev : doc.at("events")) {
            if (ev.at("type") != "step" || ev.at("since_epoch").get<int>() > epoch) continue;
            if (p.z() >= ev.at("z_min").get<double>() && p.z() <= ev.at("z_max").get<double>()) {
                const auto& v = ev.at("displacement");
                u += Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
            }
        }
        return u;
    }
};

inline Truth read_truth(const fs::path& file) {
    Truth t;
    t.doc = json::parse(read_text(file));
    t.epoch = t.doc.at("epoch");
    t.time = t.doc.at("time_unix");
    const auto& m = t.doc.at("scanner").at("header_to_true");
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) t.header_to_true.matrix()(r, c) = m[r][c].get<double>();
    }
    return t;
}

// The scenario rendered into `dir`/scans: N epochs 15 min apart from `start`.
struct Scenario {
    fs::path dir;
    int epochs = 0;
    std::int64_t start = 0;
    DemoScene scene;
    std::vector<std::string> stems;  // <station>_<time>, by acquisition time
    std::vector<Truth> truth;        // by epoch
    fs::path scans() const { return dir / "scans"; }
};

// 15-minute cadence from the next midnight UTC. Ahead of the wall clock (by at most a day and
// the run, within the demo's max_clock_ahead of 2 d), so the newest epoch is never older than
// the system alarm's 3 × 15 min (system.stale) and the Modbus values are never stale. At a
// fixed time of day because the simulator's thermal bending follows the sun: started in the
// afternoon, the step band moves up to 7 mm towards the scanner within three hours, above the
// step rule's 5 mm before any step; started at midnight, at most 1.3 mm along the south
// face's normal and 4.2 mm along the west face's over the run (the simulator's weather over
// two years from 2026-12, computed from its thermal model).
inline std::int64_t next_midnight() {
    const std::int64_t now = now_utc();
    return now - now % 86400 + 86400;
}

// The scenario as rendered into `dir` by render_scenario.
inline Scenario read_scenario(const fs::path& dir, int epochs, std::int64_t start) {
    Scenario s;
    s.dir = dir;
    s.epochs = epochs;
    s.start = start;
    s.scene = demo_scene("small", epochs);
    for (const auto& f : fs::directory_iterator(s.scans())) {
        const std::string name = f.path().filename().string();
        const auto at = name.find(".truth.json");
        if (at != std::string::npos && at + 11 == name.size()) {
            s.stems.push_back(name.substr(0, at));
        }
    }
    std::sort(s.stems.begin(), s.stems.end());  // names carry the UTC time
    for (const auto& stem : s.stems)
        s.truth.push_back(read_truth(s.scans() / (stem + ".truth.json")));
    return s;
}

inline Scenario render_scenario(const fs::path& dir, int epochs, std::int64_t start) {
    fs::create_directories(dir);
    write_text(dir / "scene.toml", scene_file_text(demo_scene("small", epochs)));
    const auto r = shell(std::string(TLSMON_BINARY) + " simulate --config " +
                         (dir / "scene.toml").string() + " --out " + (dir / "scans").string() +
                         " --epochs " + std::to_string(epochs) + " --start " + format_utc(start));
    if (r.status != 0) throw std::runtime_error("tlsmon simulate: " + r.output);
    return read_scenario(dir, epochs, start);
}

// The scenario rendered once and shared by the process tests that run it (they copy its scans
// into their own ingest folders and never write to it): in the build's
// test-cache/scenario-<tlsmon's size and time>-<epochs>-<start>. Its rendering takes as long
// as a daemon's whole run, and the simulator is deterministic, so each test rendering its own
// copy only repeated the same bytes. Keyed by the tlsmon executable as well, so that a
// rebuilt simulator renders afresh. The first test renders it under an exclusive flock (tests
// run in parallel), the others wait for the lock and read it; a folder without its `complete`
// mark (a render killed midway) is rendered again. Scenarios of another executable, or of a
// start two days older, are removed.
inline Scenario shared_scenario(int epochs, std::int64_t start) {
    const fs::path cache = TLSMON_TEST_CACHE;
    fs::create_directories(cache);
    struct stat binary {};
    if (::stat(TLSMON_BINARY, &binary) != 0) throw std::runtime_error("no " TLSMON_BINARY);
    const std::string stamp = "scenario-" + std::to_string(binary.st_size) + "." +
                              std::to_string(binary.st_mtim.tv_sec) + "." +
                              std::to_string(binary.st_mtim.tv_nsec) + "-";
    const std::string name = stamp + std::to_string(epochs) + "-" + std::to_string(start);
    const int lock = ::open((cache / (name + ".lock")).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock < 0) throw std::runtime_error("cannot open the lock of " + (cache / name).string());
    const fs::path dir = cache / name;
    try {
        if (::flock(lock, LOCK_EX) != 0) throw std::runtime_error("cannot lock " + dir.string());
        if (!fs::exists(dir / "complete")) {
            fs::remove_all(dir);
            render_scenario(dir, epochs, start);
            write_text(dir / "complete", "");
        }
        for (const auto& f : fs::directory_iterator(cache)) {
            const std::string other = f.path().filename().string();
            if (other.rfind("scenario-", 0) != 0) continue;
            const auto dash = other.rfind('-');
            if (other.rfind(stamp, 0) != 0 ||
                std::atoll(other.c_str() + dash + 1) < start - 2 * 86400)
                fs::remove_all(f.path());
        }
    } catch (...) {
        ::close(lock);
        throw;
    }
    ::close(lock);
    return read_scenario(dir, epochs, start);
}

// The demo's daemon configuration for this scenario (demo/scene.cpp), in `run`:
// the site the simulator wrote, the step band as a zone, the two rules; the dashboard on
// `http_port` (0: none).
inline fs::path write_config(const Scenario& s, const fs::path& run, int modbus_port,
                             bool modbus = true, int http_port = 0) {
    fs::create_directories(run / "ingest");
    const json& last = s.truth.back().doc;
    DemoSite ds;
    ds.site_toml = read_text(s.scans() / "site.toml");
    const json& pier = last.at("pier");
    for (const auto& ev : last.at("events")) {
        if (ev.at("type") != "step") continue;
        ds.step_min = {pier.at("x0"), pier.at("y0").get<double>() - 0.5, ev.at("z_min")};
        ds.step_max = {pier.at("x1"), pier.at("y0").get<double>() + 0.5, ev.at("z_max")};
    }
    ds.modbus_port = modbus_port;
    ds.http_port = http_port;
    std::string text = demo_daemon_config(ds);
    if (!modbus) {
        const std::string on = "[modbus]\nenabled = true";
        text.replace(text.find(on), on.size(), "[modbus]\nenabled = false");
    }
    // The disk alarm watches the host's file system, which a test does not control (a
    // nearly full CI disk raised it); test_system_alarm_watch.cpp covers it.
    const std::string rules = "[[alarm.rule]]";
    text.insert(text.find(rules), "[alarm]\ndisk_free_min = 0\n\n");
    write_text(run / "tlsmon.toml", text);
    return run / "tlsmon.toml";
}

// Epoch k's sidecar, then its scan, each complete at once (hidden name, then a rename).
inline void feed(const Scenario& s, int k, const fs::path& ingest) {
    for (const char* ext : {".meteo.csv", ".ptx"}) {
        const fs::path from = s.scans() / (s.stems.at(static_cast<std::size_t>(k)) + ext);
        if (!fs::exists(from)) continue;
        const fs::path part = ingest / ("." + from.filename().string() + ".part");
        fs::copy_file(from, part, fs::copy_options::overwrite_existing);
        fs::rename(part, ingest / from.filename());
    }
}

// Epochs done, rejected or failed (0 while the database does not exist yet).
inline int processed(const fs::path& database) {
    if (!fs::exists(database)) return 0;
    try {
        return sql(database,
                   "SELECT count(*) AS n FROM epochs WHERE status IN ('done','rejected','failed')")
            .at(0)
            .at("n");
    } catch (const std::exception&) {
        return 0;  // not yet migrated
    }
}

}  // namespace tlsmon::test::e2e
