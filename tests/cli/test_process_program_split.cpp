// The program in two executables (cli/CMakeLists.txt): `tlsmon` carries the reading commands
// and links neither PCL nor OpenCV, so that it starts in milliseconds; the measuring commands
// run in tlsmon-analysis beside it, to which `tlsmon` hands its command line over.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

// The shared libraries an executable names (the NEEDED entries of its dynamic section).
std::vector<std::string> needed_libraries(const fs::path& executable) {
    const std::string cmd = "readelf -d '" + executable.string() + "'";
    FILE* pipe = ::popen(cmd.c_str(), "r");
    std::vector<std::string> names;
    if (!pipe) return names;
    char line[1024];
    while (std::fgets(line, sizeof line, pipe)) {
        const std::string s(line);
        if (s.find("(NEEDED)") == std::string::npos) continue;
        const auto open = s.find('['), close = s.find(']');
        if (open != std::string::npos && close > open)
            names.push_back(s.substr(open + 1, close - open - 1));
    }
    ::pclose(pipe);
    return names;
}

bool names_any(const std::vector<std::string>& libraries, const std::string& prefix) {
    return std::any_of(libraries.begin(), libraries.end(),
                       [&](const std::string& l) { return l.rfind(prefix, 0) == 0; });
}

const fs::path tlsmon_program = TLSMON_BINARY;
const fs::path analysis_program = tlsmon_program.parent_path() / "tlsmon-analysis";

}  // namespace

TEST(ProgramSplit, TheReadingProgramLinksNeitherPclNorOpenCv) {
    const auto reading = needed_libraries(tlsmon_program);
    ASSERT_TRUE(names_any(reading, "libsqlite3")) << "readelf found no NEEDED entries";
    EXPECT_FALSE(names_any(reading, "libpcl_"));
    EXPECT_FALSE(names_any(reading, "libopencv_"));
    // The measuring commands' program does link them (the keypoints through OpenCV).
    const auto analysis = needed_libraries(analysis_program);
    EXPECT_TRUE(names_any(analysis, "libopencv_features2d"));
    EXPECT_TRUE(names_any(analysis, "libpcl_"));
}

TEST(ProgramSplit, AMeasuringCommandWithoutTheAnalysisProgramSaysWhatIsMissing) {
    tlsmon::test::TempDir dir;
    const fs::path alone = dir / "tlsmon";
    fs::copy_file(tlsmon_program, alone);
    fs::permissions(alone, fs::perms::owner_all);

    // A reading command works alone ...
    const auto config =
        tlsmon::test::run_tlsmon_at(alone.string(), "check-config /nonexistent.toml");
    EXPECT_EQ(config.status, 1);
    EXPECT_NE(config.out.find("/nonexistent.toml"), std::string::npos) << config.out;
    // ... a measuring one names the program it needs and where it looked.
    const auto simulate =
        tlsmon::test::run_tlsmon_at(alone.string(), "simulate --out " + (dir / "scans").string());
    EXPECT_EQ(simulate.status, 1);
    EXPECT_NE(simulate.out.find("tlsmon-analysis"), std::string::npos) << simulate.out;
    EXPECT_NE(simulate.out.find((dir / "tlsmon-analysis").string()), std::string::npos)
        << simulate.out;
    EXPECT_FALSE(fs::exists(dir / "scans"));
}

TEST(ProgramSplit, AMeasuringCommandRunsThroughTheReadingProgram) {
    // `tlsmon simulate` is carried out by tlsmon-analysis with the same arguments.
    tlsmon::test::TempDir dir;
    const auto r = tlsmon::test::run_tlsmon("simulate --preset small --epochs 1 --out '" +
                                            (dir / "scans").string() + "'");
    ASSERT_EQ(r.status, 0) << r.out;
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir / "scans"))
        files += e.path().extension() == ".ptx";
    EXPECT_EQ(files, 1u);
}
