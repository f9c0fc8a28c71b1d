// `tlsmon simulate` run as a process: files named by acquisition time, the real-time and
// slow-copy modes, a cut-short scan the PTX reader rejects, and scene-file errors naming the
// key and line.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "formats/format_error.hpp"
#include "formats/ptx_reader.hpp"
#include "tests/support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using tlsmon::test::read_file;
using tlsmon::test::TempDir;
using tlsmon::test::write_file;

int run(const std::string& args, const fs::path& log) {
    const std::string cmd =
        std::string(TLSMON_BINARY) + " simulate " + args + " > " + log.string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SimulateCommand, WritesTimedScansAndTruthAndSkipsMissingEpochs) {
    const TempDir scratch;
    const fs::path& dir = scratch.path();
    const fs::path scene = dir / "scene.toml";
    write_file(scene,
               "preset = \"small\"\n[events]\nmissing_epochs = [1]\n"
               "cut_short_epoch = 2\n");
    ASSERT_EQ(run("--config " + scene.string() + " --out " + (dir / "out").string() +
                      " --epochs 3 --cadence 30min --start 2026-06-01T22:00:00Z",
                  dir / "log"),
              0)
        << read_file(dir / "log");
    const fs::path out = dir / "out";
    EXPECT_TRUE(fs::exists(out / "small_20260601T220000Z.ptx"));
    EXPECT_TRUE(fs::exists(out / "small_20260601T220000Z.truth.json"));
    EXPECT_FALSE(fs::exists(out / "small_20260601T223000Z.ptx"));  // missing
    EXPECT_TRUE(fs::exists(out / "small_20260601T230000Z.ptx"));   // cut short
    // The weather station logs at every epoch, also when the scanner delivers nothing.
    for (const char* stem :
         {"small_20260601T220000Z", "small_20260601T223000Z", "small_20260601T230000Z"}) {
        const std::string meteo = read_file(out / (std::string(stem) + ".meteo.csv"));
        EXPECT_NE(meteo.find("\ntime_utc,air_temperature_c,pressure_hpa,relative_humidity_pct\n"),
                  std::string::npos)
            << stem;
    }
    EXPECT_NE(read_file(out / "small_20260601T223000Z.meteo.csv").find("2026-06-01T22:30:00Z,"),
              std::string::npos);
    const auto scans = tlsmon::read_ptx(out / "small_20260601T220000Z.ptx");
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].grid->rows, 541u);
    EXPECT_THROW(tlsmon::read_ptx(out / "small_20260601T230000Z.ptx"), tlsmon::FormatError);
    for (const auto& e : fs::directory_iterator(out)) {
        EXPECT_EQ(e.path().extension() == ".part", false) << e.path();
    }
}

TEST(SimulateCommand, RealtimeAndSlowCopyDeliverCompleteFiles) {
    const TempDir scratch;
    const fs::path dir = scratch / "out";
    fs::create_directories(dir);
    ASSERT_EQ(run("--preset small --out " + dir.string() +
                      " --epochs 2 --realtime 0.3 --slow-copy 0.2 --seed 9",
                  scratch / "realtime.log"),
              0);
    int ptx = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        EXPECT_NE(e.path().extension(), ".part");
        if (e.path().extension() == ".ptx") {
            ++ptx;
            EXPECT_EQ(tlsmon::read_ptx(e.path()).at(0).grid->columns, 331u);
        }
    }
    EXPECT_EQ(ptx, 2);
}

TEST(SimulateCommand, SceneFileErrorsNameTheKeyAndLine) {
    const TempDir scratch;
    const fs::path& dir = scratch.path();
    const fs::path scene = dir / "bad.toml";
    write_file(scene, "preset = \"small\"\n\n[noise]\nrange_a = 0.001\nrange_bppm = 10\n");
    EXPECT_EQ(run("--config " + scene.string() + " --out " + dir.string(), dir / "log"), 1);
    const std::string log = read_file(dir / "log");
    EXPECT_NE(log.find("bad.toml:5"), std::string::npos) << log;
    EXPECT_NE(log.find("noise.range_bppm"), std::string::npos) << log;
    EXPECT_NE(log.find("unknown key"), std::string::npos) << log;

    write_file(scene, "[scanner]\nazimuth_step_deg = -0.1\n");
    EXPECT_EQ(run("--config " + scene.string() + " --out " + dir.string(), dir / "log"), 1);
    const std::string log2 = read_file(dir / "log");
    EXPECT_NE(log2.find("bad.toml:2"), std::string::npos) << log2;
    EXPECT_NE(log2.find("scanner.azimuth_step_deg"), std::string::npos) << log2;
    EXPECT_TRUE(fs::is_empty(dir) || !fs::exists(dir / "small_20260601T060000Z.ptx"));
}

// etc/simulator-small.toml spells out the `small` preset: rendering it gives the same bytes.
TEST(SimulateCommand, ExampleSceneFileIsTheSmallPreset) {
    const TempDir scratch;
    const fs::path& dir = scratch.path();
    const std::string etc = std::string(TLSMON_SOURCE_DIR) + "/etc/simulator-small.toml";
    ASSERT_EQ(
        run("--config " + etc + " --out " + (dir / "a").string() + " --epochs 2", dir / "log_a"), 0)
        << read_file(dir / "log_a");
    ASSERT_EQ(run("--preset small --out " + (dir / "b").string() + " --epochs 2", dir / "log_b"),
              0);
    for (const char* name : {"small_20260601T061500Z.ptx", "small_20260601T061500Z.truth.json",
                             "small_20260601T061500Z.meteo.csv"}) {
        const std::string a = read_file(dir / "a" / name), b = read_file(dir / "b" / name);
        EXPECT_GT(a.size(), 300u);  // the meteo file's six readings: ≈ 360 bytes
        EXPECT_TRUE(a == b) << name;
    }
}

// Targets and events from a scene file reach the truth: the knocked target (named in the
// file) has moved 10 mm at its epoch; fewer than 4 targets is an error.
TEST(SimulateCommand, SceneFileTargetsAndKnockedTargetReachTheTruth) {
    const TempDir scratch;
    const fs::path& dir = scratch.path();
    const fs::path scene = dir / "scene.toml";
    write_file(scene, R"(preset = "small"
[events]
knocked_target = "B"
knocked_epoch = 1
[[target]]
name = "A"
centre = [8.0, 18.0, 1.0]
[[target]]
name = "B"
kind = "checkerboard"
centre = [9.7, 24.1, 1.2]
size = 0.3
[[target]]
name = "C"
centre = [-0.8, 22.0, 1.0]
[[target]]
name = "D"
kind = "checkerboard"
centre = [0.4, 22.0, 1.2]
)");
    ASSERT_EQ(
        run("--config " + scene.string() + " --out " + dir.string() + " --epochs 2", dir / "log"),
        0)
        << read_file(dir / "log");
    const auto t0 = nlohmann::json::parse(read_file(dir / "small_20260601T060000Z.truth.json"));
    const auto t1 = nlohmann::json::parse(read_file(dir / "small_20260601T061500Z.truth.json"));
    ASSERT_EQ(t1["targets"].size(), 4u);
    EXPECT_EQ(t1["targets"][1]["name"], "B");
    EXPECT_EQ(t1["targets"][1]["kind"], "checkerboard");
    EXPECT_DOUBLE_EQ(t1["targets"][1]["size"].get<double>(), 0.3);
    const double dx =
        t1["targets"][1]["centre"][0].get<double>() - t0["targets"][1]["centre"][0].get<double>();
    EXPECT_NEAR(dx, 0.010, 1e-12);
    EXPECT_EQ(t0["targets"][0]["centre"], t1["targets"][0]["centre"]);

    write_file(scene, "[[target]]\nname = \"A\"\ncentre = [8, 18, 1]\n");
    EXPECT_EQ(run("--config " + scene.string() + " --out " + dir.string(), dir / "log"), 1);
    EXPECT_NE(read_file(dir / "log").find("at least 4 targets"), std::string::npos)
        << read_file(dir / "log");
}

}  // namespace

// `[meteo] enabled = false`: no weather station, no meteo file; the scan and truth as before.
TEST(SimulateCommand, MeteoFileCanBeSwitchedOff) {
    const TempDir scratch;
    const fs::path& dir = scratch.path();
    const fs::path scene = dir / "scene.toml";
    write_file(scene, "preset = \"small\"\n[meteo]\nenabled = false\n");
    ASSERT_EQ(run("--config " + scene.string() + " --out " + (dir / "out").string() + " --epochs 1",
                  dir / "log"),
              0)
        << read_file(dir / "log");
    EXPECT_TRUE(fs::exists(dir / "out/small_20260601T060000Z.ptx"));
    EXPECT_FALSE(fs::exists(dir / "out/small_20260601T060000Z.meteo.csv"));
}
