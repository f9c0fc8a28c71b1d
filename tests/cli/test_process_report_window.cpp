// `tlsmon report --from/--to`: the report of a window of epochs (and the reference epoch);
// windows that cannot be read are refused naming the argument.
#include <gtest/gtest.h>

#include "core/utc_time.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kT0 = 1772366400;  // 2026-03-01T12:00:00Z

std::string sha(int n) {
    std::string s = std::to_string(n);
    return std::string(64 - s.size(), 'c') + s;
}

// Six epochs an hour apart, each with a value in one zone; epoch 1 the reference.
void fill(const std::filesystem::path& path) {
    auto db = EpochDatabase::open(path, EpochDatabase::Mode::read_write);
    db.site().upsert_zone("deck", R"({"type":"box","min":[0,0,0],"max":[1,1,1]})");
    for (int i = 0; i < 6; ++i) {
        const auto id =
            db.epochs().insert({sha(i), kT0 + 3600 * i, "/ingest/s.ptx", 1, std::nullopt}).id;
        db.epochs().claim(id);
        EpochResults r;
        r.point_count = 1000;
        r.zone_results = {{"deck", "m3c2_median_m", 0.001 * i, 0.002, 100, false}};
        db.results().commit(id, r);
    }
    db.epochs().set_reference(1);
}

TEST(ReportWindow, OnlyTheWindowsEpochsAndTheReference) {
    test::TempDir dir;
    const auto db = dir / "e.sqlite";
    fill(db);
    const std::string base = "report --database " + db.string() + " --out ";
    auto r = test::run_tlsmon(base + (dir / "all").string());
    ASSERT_EQ(r.status, 0) << r.out;
    std::string md = test::read_file(dir / "all/report.md");
    EXPECT_NE(md.find("Epochs processed: 6 done"), std::string::npos) << md;
    EXPECT_EQ(md.find("- Window:"), std::string::npos);

    // 14:00 to 16:00: epochs 3, 4, 5, and the reference (epoch 1) beside them.
    r = test::run_tlsmon(base + (dir / "window").string() +
                         " --from 2026-03-01T14:00:00Z --to 2026-03-01T16:00:00Z");
    ASSERT_EQ(r.status, 0) << r.out;
    md = test::read_file(dir / "window/report.md");
    EXPECT_NE(md.find("Epochs processed: 4 done"), std::string::npos) << md;
    EXPECT_NE(md.find("- Window: epochs acquired from 2026-03-01T14:00:00Z to "
                      "2026-03-01T16:00:00Z"),
              std::string::npos)
        << md;
    // A window reaching to now, from a duration before it: every epoch (all in the past).
    r = test::run_tlsmon(base + (dir / "recent").string() + " --from -36500d");
    ASSERT_EQ(r.status, 0) << r.out;
    md = test::read_file(dir / "recent/report.md");
    EXPECT_NE(md.find("Epochs processed: 6 done"), std::string::npos) << md;
    EXPECT_NE(md.find(" to now"), std::string::npos) << md;

    r = test::run_tlsmon(base + (dir / "bad").string() + " --from yesterday");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("tlsmon report: --from: "), std::string::npos) << r.out;
    r = test::run_tlsmon(base + (dir / "bad").string() +
                         " --from 2026-03-02T00:00Z --to 2026-03-01T00:00Z");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("--from 2026-03-02T00:00Z is after --to 2026-03-01T00:00Z"),
              std::string::npos)
        << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad/report.md"));
}

}  // namespace
}  // namespace tlsmon
