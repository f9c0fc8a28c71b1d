// `tlsmon demo` end to end on a short series: the daemon is started, answers Modbus while
// the scans arrive, is stopped, and the report's registration figures agree with the
// simulator's truth — recomputed here from the truth files and the database, not taken
// from the report.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "demo/scene.hpp"
#include "report/truth.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/daemon_harness.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

// `tlsmon demo ...` as a child process, its output in `log`.
class DemoProcess {
  public:
    DemoProcess(const std::vector<std::string>& args, const fs::path& log) {
        pid_ = ::fork();
        if (pid_ == 0) {
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(fd, 1);
            ::dup2(fd, 2);
            std::vector<char*> argv{const_cast<char*>(TLSMON_BINARY), const_cast<char*>("demo")};
            for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            ::execv(TLSMON_BINARY, argv.data());
            ::_exit(127);
        }
    }
    ~DemoProcess() {
        if (running()) {
            ::kill(pid_, SIGINT);  // the demo stops its daemon on Ctrl-C
            ::waitpid(pid_, nullptr, 0);
        }
    }
    bool running() {
        if (exited_) return false;
        if (::waitpid(pid_, &status_, WNOHANG) == pid_) exited_ = true;
        return !exited_;
    }
    int exit_code() const { return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1; }

  private:
    pid_t pid_ = -1;
    bool exited_ = false;
    int status_ = 0;
};

std::vector<std::map<std::string, std::string>> read_csv(const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);
    std::vector<std::string> header;
    std::stringstream hs(line);
    for (std::string h; std::getline(hs, h, ',');) header.push_back(h);
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        std::map<std::string, std::string> row;
        std::stringstream ls(line);
        std::string cell;
        for (std::size_t i = 0; i < header.size() && std::getline(ls, cell, ','); ++i) {
            row[header[i]] = cell;
        }
        rows.push_back(row);
    }
    return rows;
}

TEST(DemoCommand, RunsTheDaemonOnASimulatedSeriesAndReportsAgainstTheTruth) {
    test::TempDir dir("demo");
    const fs::path work = dir.path() / "run";
    const int port = 20000 + static_cast<int>(::getpid() % 20000);
    constexpr int kEpochs = 8;  // the knocked target at epoch 2, the step at epoch 4
    const auto started = std::chrono::steady_clock::now();
    DemoProcess demo(
        {"--workdir", work.string(), "--epochs", std::to_string(kEpochs), "--interval", "1",
         "--modbus-port", std::to_string(port), "--start", "2026-06-01T00:00:00Z"},
        dir.path() / "demo.log");

    // Modbus answers while the scans arrive: the test float (docs/modbus.md) reads 123456.
    bool modbus_answered = false;
    const std::string mbpoll =
        "mbpoll -m tcp -p " + std::to_string(port) + " -0 -1 -t 3:float -B -r 7 -o 1 127.0.0.1";
    while (demo.running() && !modbus_answered) {
        modbus_answered = test::shell(mbpoll).output.find("123456") != std::string::npos;
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    ASSERT_TRUE(test::wait_until([&] { return !demo.running(); }, 90.0));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::ifstream log_in(dir.path() / "demo.log");
    const std::string log((std::istreambuf_iterator<char>(log_in)), {});
    ASSERT_EQ(demo.exit_code(), 0) << log;
    EXPECT_TRUE(modbus_answered) << log;
    EXPECT_NE(log.find("[  8/8 100%] epoch   7"), std::string::npos) << log;
    EXPECT_NE(log.find("daemon stopped (exit 0)"), std::string::npos) << log;
    std::cout << "demo of " << kEpochs << " epochs: " << seconds << " s\n";

    // The report and its tables exist; the plots when gnuplot is installed.
    for (const char* f : {"report.md", "registration.csv", "zones.csv", "alarms.csv"}) {
        EXPECT_TRUE(fs::exists(work / "report" / f)) << f;
    }
    if (test::shell("command -v gnuplot").status == 0) {
        EXPECT_GT(fs::file_size(work / "report" / "registration.png"), 10000u);
        EXPECT_TRUE(fs::exists(work / "report" / "zone_pier_south_top.png"));
    }

    // The truth files as the simulator wrote them; the report's field reproduces the
    // simulator's own sample displacements.
    const auto truth = report::read_truth_folder(work / "truth");
    ASSERT_EQ(truth.size(), static_cast<std::size_t>(kEpochs));
    for (const auto& t : truth) {
        for (const auto& s : t.samples) {
            EXPECT_LT((report::true_displacement(t, s.point) - s.displacement).norm(), 1e-12)
                << t.file << " " << s.name;
        }
    }
    ASSERT_TRUE(truth[2].knocked.has_value());
    EXPECT_EQ(truth[2].knocked->target, "T2");

    // Every epoch registered; the error at the pier's top centre recomputed from the stored
    // transformation and the truth, H₀⁻¹·Hᵢ, equals the report's and lies within 3 σ of the
    // registration's own uncertainty at the zones (and below 1.5 mm).
    const auto db = EpochDatabase::open(work / "tlsmon.sqlite", EpochDatabase::Mode::read_only);
    const auto epochs = db.series().epochs_in_range({});
    ASSERT_EQ(epochs.size(), static_cast<std::size_t>(kEpochs));
    const auto rows = read_csv(work / "report" / "registration.csv");
    ASSERT_EQ(rows.size(), static_cast<std::size_t>(kEpochs));
    const Eigen::Affine3d h0 = *truth[0].header_to_true;
    for (int i = 1; i < kEpochs; ++i) {
        const auto& e = epochs[static_cast<std::size_t>(i)];
        const auto reg = db.registrations().of_epoch(e.id);
        ASSERT_TRUE(reg && reg->accepted) << "epoch " << i;
        Eigen::Matrix4d m;
        for (int k = 0; k < 16; ++k) m(k / 4, k % 4) = reg->transform[static_cast<std::size_t>(k)];
        const Eigen::Affine3d hi = *truth[static_cast<std::size_t>(i)].header_to_true;
        const Eigen::Vector3d top = truth[static_cast<std::size_t>(i)].samples.back().point;
        const Eigen::Vector3d q = hi.inverse() * top;
        const double error = (Eigen::Affine3d(m) * q - h0.inverse() * hi * q).norm();
        double sigma = 0;
        for (const auto& z : db.registrations().zone_sigmas_of_epoch(e.id)) {
            sigma = std::max(sigma, z.max_sigma_3d_m);
        }
        EXPECT_NEAR(std::stod(rows[static_cast<std::size_t>(i)].at("top_error_mm")), 1e3 * error,
                    1e-3)
            << "epoch " << i;
        EXPECT_LT(error, 3.0 * sigma) << "epoch " << i;
        EXPECT_LT(error, 0.0015) << "epoch " << i;
        // The knocked target is out from the epoch it moved (truth), no other one ever.
        for (const auto& t : db.registrations().targets_of_epoch(e.id)) {
            const bool out = t.use == "excluded_outlier" || t.status == "excluded";
            EXPECT_EQ(out, t.target == "T2" && i >= 2) << "epoch " << i << " " << t.target;
        }
    }
    // The step (epoch 4) moves the band 25 mm: the rule with on_delay 1 raises at epoch 5,
    // not before; the west face, which the step does not move, raises nothing.
    std::map<EpochId, int> index_of;
    for (std::size_t i = 0; i < epochs.size(); ++i) index_of[epochs[i].id] = static_cast<int>(i);
    std::optional<int> raised_at;
    for (const auto& e : db.alarms().events(std::nullopt)) {
        if (e.rule.rfind("system.", 0) == 0) continue;
        EXPECT_EQ(e.rule, std::string(kStepRule)) << e.kind << " " << e.message;
        if (e.rule == kStepRule && e.kind == "raise" && e.epoch && !raised_at) {
            raised_at = index_of.at(*e.epoch);
        }
    }
    ASSERT_TRUE(raised_at.has_value()) << "the step alarm was not raised";
    EXPECT_EQ(*raised_at, 5);

    std::ifstream md_in(work / "report" / "report.md");
    const std::string md((std::istreambuf_iterator<char>(md_in)), {});
    EXPECT_NE(
        md.find("The registration excluded it from epoch 3 (simulator epoch 2) on (0 epoch(s) "
                "after it moved)"),
        std::string::npos)
        << md;
    EXPECT_NE(md.find("## Calibration: does each σ cover its true error?"), std::string::npos);

    // `tlsmon calibration` on the same run: the registration's tx row recomputed here from
    // the stored parameters and the truth's exact transformation.
    const auto calibration = test::shell(std::string(TLSMON_BINARY) + " calibration --db " +
                                         (work / "tlsmon.sqlite").string() + " --truth " +
                                         (work / "truth").string() + " --format csv");
    ASSERT_EQ(calibration.status, 0) << calibration.output;
    { std::ofstream(dir.path() / "calibration.csv") << calibration.output; }
    const auto table = read_csv(dir.path() / "calibration.csv");
    double sum = 0;
    int within95 = 0, n = 0;
    std::string method;
    for (int i = 1; i < kEpochs; ++i) {
        const auto reg = db.registrations().of_epoch(epochs[static_cast<std::size_t>(i)].id);
        const Eigen::Affine3d exact =
            h0.inverse() * *truth[static_cast<std::size_t>(i)].header_to_true;
        const double e = (*reg->parameters)[3] - exact.translation().x();
        sum += e;
        within95 += std::abs(e) <= 1.96 * (*reg->sigmas)[3];
        ++n;
        method = "registration:" + reg->method;
    }
    bool found = false;
    for (const auto& row : table) {
        if (row.at("method") != method || row.at("part") != "tx") continue;
        found = true;
        EXPECT_EQ(std::stoi(row.at("n")), n);
        EXPECT_NEAR(std::stod(row.at("bias")), 1e3 * sum / n, 1e-6);
        EXPECT_NEAR(std::stod(row.at("cover95_pct")), 100.0 * within95 / n, 1e-9);
    }
    EXPECT_TRUE(found) << calibration.output;

    // Without a truth: the demo's check zone on the abutment, which never moves, against
    // zero — every epoch but the reference, its change well under a millimetre, and most
    // of it within its LoD95 (a datum that drifted or an LoD that lied would show here).
    const auto no_truth = test::shell(std::string(TLSMON_BINARY) + " calibration --db " +
                                      (work / "tlsmon.sqlite").string() + " --format csv");
    ASSERT_EQ(no_truth.status, 0) << no_truth.output;
    { std::ofstream(dir.path() / "no_truth.csv") << no_truth.output; }
    bool checked = false;
    for (const auto& row : read_csv(dir.path() / "no_truth.csv")) {
        EXPECT_TRUE(row.at("method").starts_with("no_change:")) << row.at("method");
        if (row.at("method") != "no_change:m3c2_median_m") continue;
        checked = true;
        EXPECT_EQ(row.at("part"), "check_A-north");
        EXPECT_EQ(std::stoi(row.at("n")), kEpochs - 1);
        EXPECT_LT(std::stod(row.at("rms")), 0.5);
        EXPECT_GE(std::stod(row.at("cover95_pct")), 70.0);
    }
    EXPECT_TRUE(checked) << no_truth.output;
    // A folder without truth files is refused, naming it.
    const auto refused =
        test::shell(std::string(TLSMON_BINARY) + " calibration --db " +
                    (work / "tlsmon.sqlite").string() + " --truth " + (work / "report").string());
    EXPECT_EQ(refused.status, 1) << refused.output;
    EXPECT_NE(refused.output.find((work / "report").string()), std::string::npos) << refused.output;
}

}  // namespace
}  // namespace tlsmon
