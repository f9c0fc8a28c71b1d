// The daemon configuration: defaults, path resolution, and every error naming key and line.
#include <gtest/gtest.h>

#include "config/config.hpp"
#include "tests/support/config_text.hpp"

namespace tlsmon {
namespace {

using test::error_of;
using test::parse;

TEST(Config, EmptyFileGivesDefaults) {
    const Config c = parse("");
    EXPECT_EQ(c.station.name, "station");
    EXPECT_EQ(c.paths.ingest, "/srv/tlsmon/ingest");
    EXPECT_EQ(c.paths.database, "/srv/tlsmon/tlsmon.sqlite");
    EXPECT_DOUBLE_EQ(c.ingest.stable_seconds, 10.0);
    EXPECT_DOUBLE_EQ(c.ingest.rescan_interval, 60.0);
    EXPECT_EQ(c.ingest.archive, ArchiveMode::move);
    EXPECT_EQ(c.ingest.acquisition_time,
              (std::vector{TimeSource::scan, TimeSource::file_name, TimeSource::mtime}));
    EXPECT_EQ(c.logging.level, LogLevel::info);
    EXPECT_EQ(c.logging.journald, JournaldMode::automatic);
    EXPECT_TRUE(c.zones.empty());
}

TEST(Config, ReadsEverySection) {
    const Config c = parse(R"(
[station]
name = "hochmosel"
[paths]
ingest = "/data/in"
archive = "arch"
[ingest]
extensions = ["PTX", "e57"]
stable_seconds = "2s"
rescan_interval = 5
archive = "keep"
acquisition_time = ["file_name", "mtime"]
[logging]
level = "debug"
file = "log/tlsmon.log"
[[zone]]
name = "pier P3"
min = [0, 0, 0]
max = [10, 2, 30]
)");
    EXPECT_EQ(c.station.name, "hochmosel");
    EXPECT_EQ(c.paths.ingest, "/data/in");
    EXPECT_EQ(c.paths.archive, "/srv/tlsmon/arch");
    EXPECT_EQ(c.ingest.extensions, (std::vector<std::string>{"ptx", "e57"}));
    EXPECT_DOUBLE_EQ(c.ingest.stable_seconds, 2.0);
    EXPECT_DOUBLE_EQ(c.ingest.rescan_interval, 5.0);
    EXPECT_EQ(c.ingest.archive, ArchiveMode::keep);
    EXPECT_EQ(c.ingest.acquisition_time, (std::vector{TimeSource::file_name, TimeSource::mtime}));
    EXPECT_EQ(c.logging.level, LogLevel::debug);
    EXPECT_EQ(c.logging.file, "/srv/tlsmon/log/tlsmon.log");
    ASSERT_EQ(c.zones.size(), 1u);
    EXPECT_EQ(c.zones[0].name, "pier P3");
    EXPECT_DOUBLE_EQ(c.zones[0].max[2], 30.0);
}

TEST(Config, UnknownKeyNamesKeyAndLine) {
    const std::string e = error_of("[ingest]\nstable_seconds = 3\nstable_second = 4\n");
    EXPECT_NE(e.find("site.toml:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'ingest.stable_second'"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(Config, UnknownSectionIsRejected) {
    const std::string e = error_of("[station]\nname = \"a\"\n\n[ingets]\nx = 1\n");
    EXPECT_NE(e.find("key 'ingets'"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(Config, WrongTypeNamesKeyAndLine) {
    const std::string e = error_of("[logging]\n\nmax_files = \"many\"\n");
    EXPECT_NE(e.find("site.toml:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'logging.max_files'"), std::string::npos) << e;
    EXPECT_NE(e.find("whole number"), std::string::npos) << e;
}

TEST(Config, OutOfRangeNamesKeyAndLine) {
    const std::string e = error_of("[ingest]\nrescan_interval = \"0s\"\n");
    EXPECT_NE(e.find("site.toml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'ingest.rescan_interval'"), std::string::npos) << e;
    EXPECT_NE(e.find("outside"), std::string::npos) << e;
}

TEST(Config, BadChoiceNamesAllowedValues) {
    const std::string e = error_of("[ingest]\narchive = \"delete\"\n");
    EXPECT_NE(e.find("key 'ingest.archive'"), std::string::npos) << e;
    EXPECT_NE(e.find("move, keep"), std::string::npos) << e;
}

TEST(Config, StringListsAreChecked) {
    std::string e = error_of("[ingest]\nextensions = [\".ptx\"]\n");
    EXPECT_NE(e.find("site.toml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'ingest.extensions'"), std::string::npos) << e;
    e = error_of("[ingest]\nextensions = [1, 2]\n");
    EXPECT_NE(e.find("array of strings"), std::string::npos) << e;
    e = error_of("[ingest]\nacquisition_time = [\"gps\"]\n");
    EXPECT_NE(e.find("key 'ingest.acquisition_time'"), std::string::npos) << e;
    EXPECT_NE(e.find("'gps'"), std::string::npos) << e;
    e = error_of("[ingest]\nextensions = [\"ptx\", \"PTX\"]\n");
    EXPECT_NE(e.find("listed twice"), std::string::npos) << e;
}

TEST(Config, CrossFieldRules) {
    std::string e = error_of("[paths]\ningest = \"/d/in\"\narchive = \"/d/in\"\n");
    EXPECT_NE(e.find("key 'paths.archive'"), std::string::npos) << e;
    EXPECT_NE(e.find("must be apart"), std::string::npos) << e;
    e = error_of("[ingest]\nstable_seconds = 60\nmax_growing = 30\n");
    EXPECT_NE(e.find("key 'ingest.max_growing'"), std::string::npos) << e;
    e = error_of("[ingest]\nretry_initial = 60\nretry_max = 30\n");
    EXPECT_NE(e.find("key 'ingest.retry_max'"), std::string::npos) << e;
    e = error_of("[ingest]\nreference_epoch = \"a/b.ptx\"\n");
    EXPECT_NE(e.find("key 'ingest.reference_epoch'"), std::string::npos) << e;
}

// The coordinate system is checked by PROJ when the file is read, not when a LAS file is
// written months later.
TEST(Config, TheCoordinateSystemIsOnePROJKnows) {
    EXPECT_EQ(parse("[station]\ncrs = \"EPSG:25832\"\n").station.crs, "EPSG:25832");
    EXPECT_EQ(parse("").station.crs, "");
    std::string e = error_of("[station]\ncrs = \"EPSG:99999999\"\n");
    EXPECT_NE(e.find("site.toml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'station.crs'"), std::string::npos) << e;
    EXPECT_NE(e.find("crs not found"), std::string::npos) << e;
    e = error_of("[station]\ncrs = \"+proj=utm +zone=32\"\n");
    EXPECT_NE(e.find("not a coordinate reference system"), std::string::npos) << e;
}

// The folders compared as folders, not as text: "ingest/" is "ingest", and a folder inside
// another is refused (a scan archived into the ingest folder is taken again and removed as
// a duplicate of itself).
TEST(Config, FoldersMustBeApartWhateverTheirSpelling) {
    std::string e = error_of("[paths]\ningest = \"ingest/\"\narchive = \"ingest\"\n");
    EXPECT_NE(e.find("key 'paths.archive'"), std::string::npos) << e;
    EXPECT_NE(e.find("/srv/tlsmon/ingest is the folder of paths.ingest"), std::string::npos) << e;
    e = error_of("[paths]\ningest = \"./in/../ingest\"\narchive = \"ingest//done\"\n");
    EXPECT_NE(e.find("lies inside paths.ingest"), std::string::npos) << e;
    e = error_of("[paths]\ningest = \"data/ingest\"\nquarantine = \"data\"\n");
    EXPECT_NE(e.find("key 'paths.quarantine'"), std::string::npos) << e;
    EXPECT_NE(e.find("holds paths.ingest"), std::string::npos) << e;
    e = error_of("[paths]\ndatabase = \"archive/db/t.sqlite\"\n");
    EXPECT_NE(e.find("key 'paths.database'"), std::string::npos) << e;
    EXPECT_NE(e.find("lies in paths.archive"), std::string::npos) << e;
    // The default layout: the database's folder holds the three folders.
    EXPECT_EQ(error_of("[paths]\ningest = \"ingest/\"\narchive = \"archive/\"\n"), "");
    EXPECT_EQ(parse("[paths]\ningest = \"ingest/\"\n").paths.ingest, "/srv/tlsmon/ingest");
}

TEST(Config, ZonesAreValidated) {
    std::string e = error_of("[[zone]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, 1]\n");
    EXPECT_NE(e.find("site.toml:4:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'zone[0].max'"), std::string::npos) << e;
    e = error_of(
        "[[zone]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
        "[[zone]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n");
    EXPECT_NE(e.find("key 'zone[1].name'"), std::string::npos) << e;
    EXPECT_NE(e.find("defined twice"), std::string::npos) << e;
    e = error_of("[[zone]]\nname = \"a\"\nmin = [0, 0, 5]\nmax = [1, 1, 1]\n");
    EXPECT_NE(e.find("must exceed"), std::string::npos) << e;
    e = error_of("[[zone]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n");
    EXPECT_NE(e.find("needs a name"), std::string::npos) << e;
}

TEST(Config, DescribeListsEveryEffectiveValue) {
    const auto lines = describe(parse("[ingest]\nstable_seconds = 3\n"));
    auto has = [&](const std::string& l) {
        return std::find(lines.begin(), lines.end(), l) != lines.end();
    };
    EXPECT_TRUE(has("ingest.stable_seconds = 3"));
    EXPECT_TRUE(has("paths.ingest = \"/srv/tlsmon/ingest\""));
    EXPECT_TRUE(has("logging.journald = \"auto\""));
}

TEST(Config, ChoicesBecomeTheirEnumerators) {
    const Config c = parse(
        "[ingest]\nacquisition_time = [\"mtime\", \"scan\"]\n"
        "[logging]\nlevel = \"warn\"\njournald = \"off\"\n");
    EXPECT_EQ(c.ingest.acquisition_time, (std::vector{TimeSource::mtime, TimeSource::scan}));
    EXPECT_EQ(c.logging.level, LogLevel::warn);
    EXPECT_EQ(c.logging.journald, JournaldMode::off);
    const auto lines = describe(c);
    EXPECT_NE(
        std::find(lines.begin(), lines.end(), "ingest.acquisition_time = [\"mtime\", \"scan\"]"),
        lines.end());
    EXPECT_NE(std::find(lines.begin(), lines.end(), "logging.journald = \"off\""), lines.end());
    const std::string e = error_of("[ingest]\nacquisition_time = [\"scan\", \"scan\"]\n");
    EXPECT_NE(e.find("'scan' is listed twice"), std::string::npos) << e;
}

TEST(Config, PipelineGetsTheArchiveModeAndFolders) {
    const PipelineConfig p = pipeline_config(parse("[ingest]\narchive = \"keep\"\n"));
    EXPECT_EQ(p.archive_mode, ArchiveMode::keep);
    EXPECT_EQ(p.quarantine, "/srv/tlsmon/quarantine");
}

TEST(Config, ThinningTiersMustGrowWithAge) {
    for (const char* section : {"retention", "archive"}) {
        const std::string e =
            error_of("[" + std::string(section) + "]\nkeep_all_days = 40\nkeep_daily_days = 20\n");
        EXPECT_NE(e.find(std::string(section) + ".keep_daily_days"), std::string::npos) << e;
        EXPECT_NE(e.find("must be >= " + std::string(section) + ".keep_all_days"),
                  std::string::npos)
            << e;
    }
    const Config c = parse("[archive]\nenabled = true\nreencode = \"e57\"\nkeep_all_days = 2\n");
    EXPECT_TRUE(c.archive.enabled);
    EXPECT_EQ(c.archive.reencode, ScanReencoding::e57);
    EXPECT_EQ(c.archive.keep_all_days, 2);
    EXPECT_EQ(c.archive.keep_daily_days, 90);
    EXPECT_NE(error_of("[archive]\nreencode = \"laz\"\n").find("archive.reencode"),
              std::string::npos);
}

TEST(Config, MissingFileSaysWhy) {
    try {
        load_config("/nonexistent/tlsmon-site.toml");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "cannot open /nonexistent/tlsmon-site.toml: No such file or directory");
    }
}

}  // namespace
}  // namespace tlsmon
