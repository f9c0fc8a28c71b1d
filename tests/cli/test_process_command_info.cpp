// `tlsmon info`: runs the built binary on the real files of ../shared/data and checks the
// values it prints against INVENTORY.md.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path data = TLSMON_DATA_DIR;

struct CommandRun {
    int exit_code = -1;
    std::string out;
    std::string err;
};

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

class InfoCommand : public ::testing::Test {
  protected:
    CommandRun info(const std::vector<std::string>& args) {
        std::string cmd = quoted(TLSMON_BINARY) + " info";
        for (const auto& a : args) cmd.append(" ").append(quoted(a));
        const fs::path out = dir_ / "stdout", err = dir_ / "stderr";
        cmd += " >" + quoted(out.string()) + " 2>" + quoted(err.string());
        const int status = std::system(cmd.c_str());
        CommandRun r;
        r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = tlsmon::test::read_file(out);
        r.err = tlsmon::test::read_file(err);
        return r;
    }

    json info_json(const std::vector<std::string>& files) {
        std::vector<std::string> args{"--json"};
        args.insert(args.end(), files.begin(), files.end());
        const CommandRun r = info(args);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return json::parse(r.out);
    }

    tlsmon::test::TempDir dir_;
};

std::size_t total_points(const json& file) {
    std::size_t n = 0;
    for (const auto& s : file.at("scans")) n += s.at("points").get<std::size_t>();
    return n;
}

}  // namespace

TEST_F(InfoCommand, PumpPtxGridFillIntensityAndColour) {
    const json j = info_json({(data / "ptx/pumpA_from_e57.ptx").string()});
    ASSERT_EQ(j.size(), 1u);
    EXPECT_EQ(j[0]["format"], "PTX");
    ASSERT_EQ(j[0]["scans"].size(), 1u);
    const json& s = j[0]["scans"][0];
    EXPECT_EQ(s["points"], 155201);
    EXPECT_EQ(s["grid"]["rows"], 1074);
    EXPECT_EQ(s["grid"]["columns"], 345);
    EXPECT_EQ(s["grid"]["cells"], 370530);
    EXPECT_NEAR(s["grid"]["fill_ratio"].get<double>(), 155201.0 / 370530.0, 1e-12);
    EXPECT_NEAR(s["intensity"]["min"].get<double>(), 0.3838, 0.0001);
    EXPECT_NEAR(s["intensity"]["max"].get<double>(), 0.6984, 0.0001);
    EXPECT_EQ(s["intensity"]["raw_scale"], json({0.0, 1.0}));
    EXPECT_EQ(s["colour"], true);
    EXPECT_EQ(s["pose"]["is_rotation"], true);
    EXPECT_NEAR(s["pose"]["angle_deg"].get<double>(), 0.0, 1e-9);
    EXPECT_TRUE(s["acquired_utc"].is_null());
    // The box lies within the range 1.98–5.43 m of the scanner at the origin.
    for (int k = 0; k < 3; ++k) {
        EXPECT_LE(std::abs(s["bounding_box"]["min"][k].get<double>()), 5.43);
        EXPECT_LE(std::abs(s["bounding_box"]["max"][k].get<double>()), 5.43);
    }
}

TEST_F(InfoCommand, MultipleAndTransformShowsBothScansAndTheScaledPose) {
    const json j = info_json({(data / "ptx/multiple-and-transform.ptx").string()});
    const json& scans = j[0]["scans"];
    ASSERT_EQ(scans.size(), 2u);
    for (const json& s : scans) {
        EXPECT_EQ(s["points"], 4);
        EXPECT_NEAR(s["bounding_box"]["max"][0].get<double>(), 637012.24, 1e-6);
        EXPECT_NEAR(s["bounding_box"]["min"][2].get<double>(), 425.39, 1e-6);
        EXPECT_NEAR(s["bounding_box"]["max"][2].get<double>(), 446.39, 1e-6);
    }
    EXPECT_EQ(scans[0]["pose"]["position"], json({600000.0, 800000.0, 400.0}));
    EXPECT_EQ(scans[0]["pose"]["linear"][2][2], 2.0);
    EXPECT_EQ(scans[0]["pose"]["is_rotation"], false);
    EXPECT_EQ(scans[1]["pose"]["is_rotation"], true);
}

TEST_F(InfoCommand, ComplexTransformFillRatioAndRotationAngle) {
    const json j = info_json({(data / "ptx/complex-transform.ptx").string()});
    const json& s = j[0]["scans"][0];
    EXPECT_NEAR(s["grid"]["fill_ratio"].get<double>(), 4.0 / 12.0, 1e-12);
    ASSERT_EQ(s["pose"]["is_rotation"], true);
    // acos((trace - 1) / 2) of the header's matrix, trace 2.999955: 0.3843°.
    EXPECT_NEAR(s["pose"]["angle_deg"].get<double>(), 0.3843, 0.005);
    EXPECT_NEAR(s["pose"]["position"][0].get<double>(), -3.028748, 1e-9);
}

TEST_F(InfoCommand, TextReport) {
    const CommandRun r = info({(data / "ptx/no-color.ptx").string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("format: PTX"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("scans: 1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("points: 15\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("grid: 1 rows x 15 columns, 15 of 15 cells filled (100.0 %)"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("intensity: 0.000244 .. 0.050537"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("colour: no"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("max 637012.2400 849390.7800 446.3900"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("acquired: unknown"), std::string::npos) << r.out;
}

TEST_F(InfoCommand, UnreadableFilesGoToStderrWithExitCode2AndOthersAreStillReported) {
    const fs::path garbage = dir_ / "garbage.ptx";
    tlsmon::test::write_file(garbage, "\x01\x02\xff binary\n");
    const CommandRun r = info({(dir_ / "missing.ptx").string(), garbage.string(),
                               (data / "xyz/plane_horizontal_t2.xyz").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find((dir_ / "missing.ptx").string() + ": cannot open"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find(garbage.string() + ":1: "), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("format: XYZ"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("points: 441"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("grid: none"), std::string::npos) << r.out;
}

// Operator defect 7: for a bad PLY or PCD the first line on stderr is tlsmon's own error
// naming the file and the place (PCL used to print its "[pcl::...]" messages first).
TEST_F(InfoCommand, BadPlyAndPcdGiveTlsmonsOwnErrorAsTheFirstLine) {
    const fs::path ply = dir_ / "bad.ply";
    tlsmon::test::write_file(ply,
                             "ply\nformat binary_little_endian 1.0\nelement vertex 9\n"
                             "property float x\nproperty float y\nproperty float z\n"
                             "end_header\n\x01\x02");
    const fs::path pcd = dir_ / "bad.pcd";
    tlsmon::test::write_file(pcd, "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n");
    for (const auto& [file, first] :
         {std::pair{ply, "tlsmon info: " + ply.string() +
                             ":3: element vertex declares 9 records of at least 12 bytes, "
                             "but only 2 bytes follow\n"},
          std::pair{pcd, "tlsmon info: " + pcd.string() +
                             ":5: file ends inside the PCD header (no DATA line)\n"}}) {
        const CommandRun r = info({file.string()});
        EXPECT_EQ(r.exit_code, 2);
        EXPECT_EQ(r.err, first);  // the whole of stderr: one line, tlsmon's own
        EXPECT_EQ(r.err.find("[pcl"), std::string::npos) << r.err;
        EXPECT_TRUE(r.out.empty()) << r.out;
    }
}

TEST_F(InfoCommand, EveryReadableFileInTheDataFolder) {
    // INVENTORY.md: these must fail; LAZ/COPC is rejected as compressed.
    const std::set<std::string> must_fail = {"InvalidFileLength.e57", "NoPrototype.e57",
                                             "ZeroPointsInvalid.e57", "InvalidCVHeader.e57",
                                             "bad-crc.e57"};
    const std::set<std::string> scan_extensions = {".ptx", ".pts", ".xyz", ".ply",
                                                   ".pcd", ".las", ".e57"};
    std::vector<std::string> readable;
    for (const auto& e : fs::recursive_directory_iterator(data)) {
        if (!e.is_regular_file()) continue;
        const fs::path& p = e.path();
        if (scan_extensions.count(p.extension().string()) &&
            !must_fail.count(p.filename().string())) {
            readable.push_back(p.string());
        }
    }
    ASSERT_GE(readable.size(), 58u);  // INVENTORY.md lists 58 readable files
    const json j = info_json(readable);
    ASSERT_EQ(j.size(), readable.size());
    std::size_t checked = 0;
    for (const json& f : j) {
        ASSERT_FALSE(f.contains("error")) << f["error"];
        const std::string name = fs::path(f["file"].get<std::string>()).filename().string();
        const auto expect = [&](const char* file, std::size_t points) {
            if (name == file) {
                EXPECT_EQ(total_points(f), points) << file;
                ++checked;
            }
        };
        expect("pumpARowColumnIndexNoInvalidPoints.e57", 155201);
        expect("bunnyFloat.e57", 30571);
        expect("ZeroPoints.e57", 0);
        expect("simple1_4.las", 22600);
        expect("vegetation_1_3.las", 10683);
        expect("plane_horizontal_t1.xyz", 441);
        expect("pumpA_from_e57.ptx", 155201);
    }
    EXPECT_EQ(checked, 7u);

    const CommandRun laz = info({(data / "las/laspy/simple.laz").string()});
    EXPECT_EQ(laz.exit_code, 2);
    EXPECT_NE(laz.err.find("simple.laz"), std::string::npos) << laz.err;
}
