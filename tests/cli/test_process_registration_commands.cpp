// `tlsmon register`, `tlsmon query registrations` and `tlsmon targets [resurvey]`, the built
// binary on scans of the simulator with known drift (standing axis 60″, tilt 10″, translation
// σ 1.5 mm): the exact map of epoch i into epoch 0's frame is H₀⁻¹·Hᵢ, H = header_to_true of
// each scan's truth (docs/simulator.md). The scene is the `small` preset's, its window
// narrowed to the targets' band of elevations and sampled at 0.01° so that its spheres and
// boards are resolved (the preset's 0.1° is too coarse for them), the air off and with it the
// weather station: a meteo sidecar beside a scan whose ranges carry no air would make the
// stage correct them by a few ppm that are not there (0.05–0.1 mm at the targets, several
// times their σ). Rendered once for the whole suite.
#include <SQLiteCpp/Database.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "formats/ptx_writer.hpp"
#include "formats/scan_file.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/daemon_harness.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
using test::shell;
using test::TempDir;

constexpr double kArcsec = 180.0 * 3600.0 / 3.141592653589793;  // per rad

struct Truth {
    Eigen::Matrix4d header_to_true;
};

Truth read_truth(const fs::path& ptx) {
    fs::path p = ptx;
    p.replace_extension(".truth.json");
    std::ifstream in(p);
    const auto j = nlohmann::json::parse(in);
    Truth t;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            t.header_to_true(r, c) = j["scanner"]["header_to_true"][r][c].get<double>();
    return t;
}

// ω, φ, κ (″) and tx, ty, tz (m) of the exact answer H₀⁻¹·Hᵢ, R = R_z(κ)·R_y(φ)·R_x(ω).
std::array<double, 6> true_parameters(const Truth& t0, const Truth& ti) {
    const Eigen::Matrix4d M = t0.header_to_true.inverse() * ti.header_to_true;
    const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
    return {std::atan2(R(2, 1), R(2, 2)) * kArcsec,
            -std::asin(R(2, 0)) * kArcsec,
            std::atan2(R(1, 0), R(0, 0)) * kArcsec,
            M(0, 3),
            M(1, 3),
            M(2, 3)};
}

std::string log_of(const test::Site& site) {
    std::ifstream in(site.log());
    return std::string(std::istreambuf_iterator<char>(in), {});
}

const char* const kNames[6] = {"omega_arcsec", "phi_arcsec", "kappa_arcsec",
                               "tx_m",         "ty_m",       "tz_m"};

class RegistrationCommands : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir("registration-commands");
        const fs::path scene = dir_->path() / "scene.toml";
        std::ofstream(scene) << "preset = \"small\"\n"
                                "[scanner]\n"
                                "azimuth_min_deg = 63.0\nazimuth_max_deg = 94.0\n"
                                "elevation_min_deg = -2.5\nelevation_max_deg = 1.5\n"
                                "azimuth_step_deg = 0.01\nelevation_step_deg = 0.01\n"
                                "[drift]\nyaw_amplitude_arcsec = 60.0\n"
                                "tilt_amplitude_arcsec = 10.0\ntranslation_sigma = 0.0015\n"
                                "[atmosphere]\nenabled = false\n[meteo]\nenabled = false\n";
        scans_ = dir_->path() / "scans";
        const auto r = shell(std::string(TLSMON_BINARY) + " simulate --config " + scene.string() +
                             " --epochs 3 --cadence 4h --out " + scans_.string());
        ASSERT_EQ(r.status, 0) << r.output;
        for (const auto& e : fs::directory_iterator(scans_)) {
            if (e.path().extension() == ".ptx") files_.push_back(e.path());
        }
        std::sort(files_.begin(), files_.end());
        ASSERT_EQ(files_.size(), 3u);
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }

    // The simulator's site.toml (targets, zones) without its [station] table, for a site
    // of the harness.
    static std::string site_tables() {
        std::ifstream in(scans_ / "site.toml");
        std::string out, line;
        bool station = false;
        while (std::getline(in, line)) {
            if (line.rfind("[", 0) == 0) station = line == "[station]";
            if (!station) out += line + "\n";
        }
        return out;
    }

    static inline TempDir* dir_ = nullptr;
    static inline fs::path scans_;
    static inline std::vector<fs::path> files_;
};

TEST_F(RegistrationCommands, RegisterPrintsTheTrueTransformWithinItsSigma) {
    const Truth t0 = read_truth(files_[0]);
    for (std::size_t i = 1; i < files_.size(); ++i) {
        const auto r = shell(std::string(TLSMON_BINARY) + " register " + files_[0].string() + " " +
                             files_[i].string() + " --config " + (scans_ / "site.toml").string() +
                             " --format json");
        ASSERT_EQ(r.status, 0) << r.output;
        const auto j = nlohmann::json::parse(r.output);
        EXPECT_TRUE(j["accepted"].get<bool>());
        EXPECT_EQ(j["targets_used"].get<int>(), 4) << r.output;
        const auto truth = true_parameters(t0, read_truth(files_[i]));
        for (int k = 0; k < 6; ++k) {
            const double est = j[kNames[k]].get<double>();
            const double sigma = j[std::string("sigma_") + kNames[k]].get<double>();
            EXPECT_LE(std::fabs(est - truth[k]), 3.0 * sigma)
                << "epoch " << i << " " << kNames[k] << ": " << est << " vs true " << truth[k]
                << " ± " << sigma;
            EXPECT_GT(sigma, 0.0);
        }
        // The matrix maps the epoch's points into the reference frame: at the pier's top
        // (x 5–15, y 60–67, 45 m high; 75 m away) within 3 mm of the exact answer.
        Eigen::Matrix4d M;
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) M(a, b) = j["matrix"][a][b].get<double>();
        const Eigen::Matrix4d exact =
            t0.header_to_true.inverse() * read_truth(files_[i]).header_to_true;
        const Eigen::Vector4d p(10.0, 60.0, 45.0, 1.0);
        EXPECT_LT((M * p - exact * p).head<3>().norm(), 0.003) << "epoch " << i;
    }
}

TEST_F(RegistrationCommands, RegisterOnPlanesAloneFindsTheTrueTransformWithinItsSigma) {
    // The same files on the scene's planes (floor, foundation, abutment, the two walls set at
    // an angle), the targets not measured; the pier's foot lies in a zone (monitored).
    const Truth t0 = read_truth(files_[0]);
    const auto r = shell(std::string(TLSMON_BINARY) + " register " + files_[0].string() + " " +
                         files_[2].string() + " --config " + (scans_ / "site.toml").string() +
                         " --method planes --format json");
    ASSERT_EQ(r.status, 0) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["method"].get<std::string>().rfind("planes", 0), 0u) << j["method"];
    EXPECT_EQ(j["targets_used"].get<int>(), 0);
    EXPECT_TRUE(j["targets"].empty());
    const auto& planes = j["planes"];
    EXPECT_TRUE(planes["used"].get<bool>());
    EXPECT_GE(planes["in_datum"].get<int>(), 4);
    int monitored = 0;
    for (const auto& p : planes["planes"]) {
        if (p["role"] == "monitored") {
            ++monitored;
            EXPECT_NE(p["zone"].get<std::string>(), "");
        }
    }
    EXPECT_GE(monitored, 1);
    const auto truth = true_parameters(t0, read_truth(files_[2]));
    for (int k = 0; k < 6; ++k) {
        const double est = j[kNames[k]].get<double>();
        const double sigma = j[std::string("sigma_") + kNames[k]].get<double>();
        EXPECT_LE(std::fabs(est - truth[k]), 3.0 * sigma + (k < 3 ? 0.5 : 0.0002))
            << kNames[k] << ": " << est << " vs true " << truth[k] << " ± " << sigma;
    }
    // The table names each plane's role and change.
    const auto t = shell(std::string(TLSMON_BINARY) + " register " + files_[0].string() + " " +
                         files_[2].string() + " --config " + (scans_ / "site.toml").string() +
                         " --method planes");
    EXPECT_TRUE(
        std::regex_search(t.output, std::regex("matched: [0-9]+ in the datum, [0-9]+ moved")))
        << t.output;
    EXPECT_TRUE(std::regex_search(t.output, std::regex("pier_south_face +monitored")));
}

TEST_F(RegistrationCommands, RegisterTableAndRefusal) {
    const std::string site = (scans_ / "site.toml").string();
    auto r = shell(std::string(TLSMON_BINARY) + " register " + files_[0].string() + " " +
                   files_[1].string() + " --config " + site);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(std::regex_search(r.output, std::regex("status +accepted")));
    EXPECT_NE(r.output.find("matrix (epoch -> reference):"), std::string::npos);
    // Two targets in the configuration: registered but refused, exit 3, with the reason.
    const fs::path two = dir_->path() / "two.toml";
    {
        std::ifstream in(site);
        std::ofstream out(two);
        std::string line;
        int targets = 0;
        bool keep = true;
        while (std::getline(in, line)) {
            if (line == "[[target]]") keep = ++targets <= 2;
            if (line.rfind("[", 0) == 0 && line != "[[target]]") keep = true;
            if (keep) out << line << "\n";
        }
    }
    r = shell(std::string(TLSMON_BINARY) + " register " + files_[0].string() + " " +
              files_[1].string() + " --config " + two.string() + " --format json");
    EXPECT_EQ(r.status, 3) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["status"], "too_few_targets");
    EXPECT_FALSE(j["accepted"].get<bool>());
    EXPECT_NE(j["reason"].get<std::string>().find("2 usable targets, at least 3 needed"),
              std::string::npos);
}

TEST_F(RegistrationCommands, RegisterLeavesOutTheTargetsTheSiteHadExcludedBeforeTheEpoch) {
    // The site's database (paths.database, beside its configuration) holds three exclusions:
    // T1 by an epoch acquired before the scan (still out), T2 likewise but re-surveyed since
    // (back in), T3 by an epoch acquired after the scan (not yet out when it arrived).
    TempDir dir("register-history");
    fs::copy_file(scans_ / "site.toml", dir.path() / "site.toml");
    {
        auto db =
            EpochDatabase::open(dir.path() / "tlsmon.sqlite", EpochDatabase::Mode::read_write);
        db.epochs().insert({std::string(64, '1'), 0, "earlier.ptx", 1, std::nullopt});
        db.epochs().insert({std::string(64, '3'), 4'000'000'000, "later.ptx", 1, std::nullopt});
    }
    {
        SQLite::Database raw((dir.path() / "tlsmon.sqlite").string(), SQLite::OPEN_READWRITE);
        raw.exec(
            "INSERT INTO target_exclusions (target, epoch_id, resurveyed) VALUES "
            "('T1', 1, NULL), ('T2', 1, 1000), ('T3', 2, NULL)");
    }
    const auto r = shell(std::string(TLSMON_BINARY) + " register " + files_[0].string() + " " +
                         files_[1].string() + " --config " + (dir.path() / "site.toml").string() +
                         " --format json");
    // Registered on the three others (exit 0, or 3 when the quality gate refuses the
    // weaker geometry; 1 would be an error).
    ASSERT_TRUE(r.status == 0 || r.status == 3) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["targets_used"].get<int>(), 3) << r.output;
    for (const auto& t : j["targets"]) {
        EXPECT_EQ(t["status"] == "excluded", t["name"] == "T1") << t.dump();
    }
}

TEST_F(RegistrationCommands, RegisterBadArgumentsAreClearErrors) {
    const std::string bin = TLSMON_BINARY;
    const std::string site = (scans_ / "site.toml").string();
    // A missing file: exit 1, the file named.
    auto r = shell(bin + " register /nonexistent/a.ptx " + files_[1].string() + " --config " +
                   site + " 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("/nonexistent/a.ptx"), std::string::npos) << r.output;
    // A configuration without targets: exit 1, said so.
    const fs::path none = dir_->path() / "none.toml";
    std::ofstream(none) << "[station]\nname = \"x\"\n";
    r = shell(bin + " register " + files_[0].string() + " " + files_[1].string() + " --config " +
              none.string() + " 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("no [[target]] tables"), std::string::npos) << r.output;
    // A bad key in the configuration: exit 1, the key named.
    const fs::path bad = dir_->path() / "bad.toml";
    std::ofstream(bad) << "[registration]\nglobal_alpha = 0.01\nglobal_reject_alpha = 0.02\n";
    r = shell(bin + " register " + files_[0].string() + " " + files_[1].string() + " --config " +
              bad.string() + " 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("global_reject_alpha"), std::string::npos) << r.output;
    // Not a scan: exit 1, the file named.
    r = shell(bin + " register " + site + " " + files_[1].string() + " --config " + site + " 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("site.toml"), std::string::npos) << r.output;
    // A missing argument or an unknown format: the parser's error, exit 105 / 106.
    r = shell(bin + " register " + files_[0].string() + " --config " + site + " 2>&1");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("EPOCH"), std::string::npos) << r.output;
    r = shell(bin + " register " + files_[0].string() + " " + files_[1].string() + " --config " +
              site + " --format xml 2>&1");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("xml"), std::string::npos) << r.output;
}

// The daemon registers the three scans; `tlsmon query registrations` shows each against the
// truth; `tlsmon targets` lists the targets; a target marked excluded (as the pipeline does)
// is listed with its reason and cleared by `tlsmon targets resurvey`, which records who.
TEST_F(RegistrationCommands, DaemonQueryRegistrationsAndTargetsResurvey) {
    test::Site site("registration-daemon", site_tables());
    for (const auto& f : files_) fs::copy_file(f, site.ingest() / f.filename());
    test::DaemonProcess daemon(site.config(), site.log(), true);
    ASSERT_EQ(daemon.wait(120), 0) << log_of(site);
    const std::string bin = TLSMON_BINARY;
    const std::string db = " --db " + site.database().string();

    auto r = shell(bin + " query registrations" + db + " --format json");
    ASSERT_EQ(r.status, 0) << r.output;
    const auto rows = nlohmann::json::parse(r.output);
    ASSERT_EQ(rows.size(), 3u) << r.output;
    const Truth t0 = read_truth(files_[0]);
    for (std::size_t i = 0; i < 3; ++i) {
        const auto& row = rows[i];
        EXPECT_EQ(row["registration"], "accepted") << row.dump();
        EXPECT_EQ(row["status"], "done") << row.dump();
        EXPECT_EQ(row["targets_used"].get<int>(), 4);
        const auto truth = true_parameters(t0, read_truth(files_[i]));
        for (int k = 0; k < 6; ++k) {
            const double est = row[kNames[k]].get<double>();
            const double sigma = row[std::string("sigma_") + kNames[k]].get<double>();
            EXPECT_LE(std::fabs(est - truth[k]), 3.0 * sigma)
                << "epoch " << i << " " << kNames[k] << ": " << est << " vs true " << truth[k]
                << " ± " << sigma;
        }
    }

    r = shell(bin + " targets" + db + " --format json");
    ASSERT_EQ(r.status, 0) << r.output;
    auto targets = nlohmann::json::parse(r.output);
    ASSERT_EQ(targets.size(), 4u) << r.output;
    for (const auto& t : targets) {
        EXPECT_EQ(t["status"], "found") << t.dump();
        EXPECT_EQ(t["use"], "used") << t.dump();
        EXPECT_EQ(t["excluded"], "no") << t.dump();
    }
    // Nothing is excluded: a re-survey is refused, naming the target.
    r = shell(bin + " targets resurvey T2" + db + " 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("target 'T2' is not excluded (excluded now: none)"), std::string::npos)
        << r.output;

    // T2 excluded by the last epoch, as the pipeline records a target that moved.
    {
        SQLite::Database raw(site.database().string(), SQLite::OPEN_READWRITE);
        raw.exec("INSERT INTO target_exclusions (target, epoch_id) VALUES ('T2', " +
                 std::to_string(rows[2]["epoch"].get<std::int64_t>()) + ")");
    }
    r = shell(bin + " targets" + db + " --format json");
    ASSERT_EQ(r.status, 0) << r.output;
    targets = nlohmann::json::parse(r.output);
    const auto t2 = std::find_if(targets.begin(), targets.end(),
                                 [](const auto& t) { return t["target"] == "T2"; });
    ASSERT_NE(t2, targets.end());
    EXPECT_EQ((*t2)["excluded"], "yes");
    EXPECT_EQ((*t2)["excluded_since"], "2026-06-01T14:00:00Z");  // the third epoch, 06:00 + 8 h
    EXPECT_NE((*t2)["why"].get<std::string>().find("outlier test"), std::string::npos);

    r = shell(bin + " targets resurvey T2 --by 'J. Surveyor'" + db + " 2>&1");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("target T2 re-surveyed by J. Surveyor"), std::string::npos);
    EXPECT_TRUE(site.open_db().registrations().excluded_targets().empty());
    r = shell(bin + " targets" + db + " --format json");
    targets = nlohmann::json::parse(r.output);
    for (const auto& t : targets) EXPECT_EQ(t["excluded"], "no") << t.dump();
    r = shell(bin + " events" + db + " --format json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("target T2 re-surveyed by J. Surveyor"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("target_resurveyed"), std::string::npos) << r.output;
    // Twice: nothing left to clear.
    r = shell(bin + " targets resurvey T2" + db + " 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    // Neither --db nor --config: a clear error.
    r = shell(bin + " targets resurvey T2 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("--db PATH or --config FILE"), std::string::npos) << r.output;
}

// The one-shot command registers as the stage does: with the ICP fallback on a stable
// region and no target at all (it refused without targets, and never ran the ICP). The real
// pump-room scan onto itself keeps its datum (the identity); moved by (2, -3, +6) mm and
// 0.02° about z, the ICP finds the movement back.
TEST(RegisterCommand, IcpAloneRegistersTheRealPumpScan) {
    test::TempDir dir("icponly");
    const fs::path pump = fs::path(TLSMON_DATA_DIR) / "ptx/pumpA_from_e57.ptx";
    Scan moved = read_scans(pump).at(0);
    const Eigen::Affine3d T = Eigen::Translation3d(0.002, -0.003, 0.006) *
                              Eigen::AngleAxisd(0.02 * M_PI / 180, Eigen::Vector3d::UnitZ());
    moved.pose = T * moved.pose;
    for (auto& p : moved.xyz) p = T * p;
    write_ptx(moved, dir / "moved.ptx");
    const fs::path site = dir / "site.toml";
    std::ofstream(site)
        << "[registration]\nicp = \"fallback\"\nicp_voxel_size = 0.05\nicp_min_overlap = 0.2\n"
           "max_sigma_angle_arcsec = 120\n[[stable_region]]\n"
           "name = \"room\"\nmin = [-3, -5.4, -1.6]\nmax = [1.8, -0.7, 1.9]\n";
    const auto run = [&](const fs::path& epoch) {
        const auto r = test::shell(std::string(TLSMON_BINARY) + " register " + pump.string() + " " +
                                   epoch.string() + " --config " + site.string() +
                                   " --format json 2>/dev/null");
        EXPECT_EQ(r.status, 0) << r.output;
        return nlohmann::json::parse(r.output);
    };
    const auto same = run(pump);
    EXPECT_EQ(same["method"], "icp");
    EXPECT_LT(std::abs(same["kappa_arcsec"].get<double>()), 0.1) << same.dump(2);
    EXPECT_LT(std::abs(same["tx_m"].get<double>()), 1e-5) << same.dump(2);
    const auto back = run(dir / "moved.ptx");
    EXPECT_EQ(back["method"], "icp");
    EXPECT_TRUE(back["accepted"].get<bool>()) << back.dump(2);
    // κ to 20″, the translation to a millimetre, each with a σ (on this room too small to
    // hold the error within 3σ: tests/daemon/test_datum_without_targets.cpp).
    const std::pair<const char*, double> truth[] = {
        {"tx_m", -0.002}, {"ty_m", 0.003}, {"tz_m", -0.006}};
    for (const auto& [name, value] : truth) {
        EXPECT_GT(back["sigma_" + std::string(name)].get<double>(), 0.0) << name;
        EXPECT_LT(std::abs(back[name].get<double>() - value), 0.001) << name << back.dump(2);
    }
    EXPECT_LT(std::abs(back["kappa_arcsec"].get<double>() + 72.0), 20.0);
    // The tilts within the 120″ the site's σ gate allows.
    EXPECT_LT(std::abs(back["omega_arcsec"].get<double>()), 120.0);
    EXPECT_LT(std::abs(back["phi_arcsec"].get<double>()), 120.0);
}

}  // namespace
}  // namespace tlsmon
