// read_scans (from the file) and parse_scans (from its bytes in memory) must give the same
// scans for every format, and the format of a file with no known extension is found from
// its first bytes.
#include <gtest/gtest.h>

#include <cctype>
#include <string>
#include <vector>

#include "formats/format_error.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
const fs::path kData = TLSMON_DATA_DIR;

void expect_same_scans(const std::vector<Scan>& a, const std::vector<Scan>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        ASSERT_EQ(a[k].size(), b[k].size()) << "scan " << k;
        ASSERT_GT(a[k].size(), 0u);
        for (std::size_t i : {std::size_t{0}, a[k].size() / 2, a[k].size() - 1}) {
            EXPECT_EQ(a[k].xyz[i], b[k].xyz[i]) << "scan " << k << " point " << i;
        }
        EXPECT_EQ(a[k].intensity, b[k].intensity);
        EXPECT_EQ(a[k].grid.has_value(), b[k].grid.has_value());
        EXPECT_TRUE(a[k].pose.isApprox(b[k].pose, 0.0));
    }
}

TEST(ScanFile, BytesInMemoryGiveTheSameScansAsTheFile) {
    for (const char* name :
         {"ptx/multiple-and-transform.ptx", "ptx/pumpA_from_e57.ptx", "xyz/plane_horizontal_t1.xyz",
          "las/laspy/test1_4.las", "las/libLAS/1.2-with-color.las",
          "e57/pumpARowColumnIndexNoInvalidPoints.e57"}) {
        SCOPED_TRACE(name);
        const fs::path path = kData / name;
        expect_same_scans(read_scans(path), parse_scans(test::read_file(path), path));
    }
}

TEST(ScanFile, FormatWithoutKnownExtensionComesFromTheFirstBytes) {
    test::TempDir dir;
    const fs::path las = kData / "las/laspy/simple.las";
    const fs::path renamed = test::write_file(dir / "scan.bin", test::read_file(las));
    EXPECT_EQ(detect_format(renamed), ScanFormat::las);
    const auto scans = parse_scans(test::read_file(renamed), renamed);
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].size(), 1065u);

    const fs::path text = test::write_file(dir / "notes.bin", "hello\n");
    EXPECT_EQ(detect_format(text), ScanFormat::unknown);
    EXPECT_THROW(parse_scans(test::read_file(text), text), FormatError);
}

TEST(ScanFile, PlyAndPcdAreFoundFromTheirFirstBytes) {
    test::TempDir dir;
    const fs::path ply = test::write_file(
        dir / "cloud.bin",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n1 2 3\n");
    EXPECT_EQ(detect_format(ply), ScanFormat::ply);
    EXPECT_EQ(parse_scans(test::read_file(ply), ply).at(0).xyz.at(0), Eigen::Vector3d(1, 2, 3));
    const fs::path pcd = test::write_file(
        dir / "cloud.dat",
        "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n"
        "4 5 6\n");
    EXPECT_EQ(detect_format(pcd), ScanFormat::pcd);
    EXPECT_EQ(read_scans(pcd).at(0).xyz.at(0), Eigen::Vector3d(4, 5, 6));
}

// The ingest default is the first extension of each format in the table: .txt and .asc
// (XYZ) are read when named but not taken from the ingest folder by default.
TEST(ScanFile, ScanExtensionsAreOnePerFormat) {
    EXPECT_EQ(scan_extensions(),
              (std::vector<std::string>{"ptx", "pts", "xyz", "ply", "pcd", "las", "laz", "e57"}));
    for (const std::string& ext : scan_extensions()) {
        const ScanFormat f = detect_format("scan." + ext);
        EXPECT_NE(f, ScanFormat::unknown) << ext;
        std::string upper = ext;
        for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        EXPECT_EQ(to_string(f), upper);
    }
    EXPECT_EQ(detect_format("notes.TXT"), ScanFormat::xyz);
    EXPECT_EQ(to_string(ScanFormat::unknown), "unknown");
}

}  // namespace
}  // namespace tlsmon
