// The archive policy's plan (storage/archive_policy.hpp) on hand-made scan lists: the tiers
// of the maps' policy, protected scans never removed, and which kept scans are re-encoded.
#include <gtest/gtest.h>

#include "storage/archive_policy.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kStart = 1767225600;  // 2026-01-01T00:00:00Z, a Thursday
constexpr UtcSeconds kDay = 86400;

// `days` x 4 scans a day, 1000 bytes each, as PTX files.
std::vector<ArchivedScan> scans(int days) {
    std::vector<ArchivedScan> out;
    for (int i = 0; i < days * 4; ++i) {
        out.push_back({i + 1, kStart + i * kDay / 4, "/archive/s" + std::to_string(i) + ".ptx",
                       std::string(64, 'a'), 1000, false, false, false});
    }
    return out;
}

ArchivePolicy policy(ScanReencoding reencode = ScanReencoding::none) {
    ArchivePolicy p;
    p.keep_all_days = 3;
    p.keep_daily_days = 10;
    p.reencode = reencode;
    return p;
}

TEST(ArchivePolicy, ThinsByAgeAndReportsTheSpace) {
    auto list = scans(20);  // 80 scans; the newest at day 19.75
    const UtcSeconds now = list.back().acquired;
    const auto plan = plan_archive(list, now, policy());
    // Young: acquired >= day 16.75 -> 13 scans; daily: days 10..16 (day 16's first, at 16.0,
    // is older than 16.75) -> 7; weekly: days 0..9: weeks starting Thu 1 Jan and Mon 5 Jan
    // -> 2.
    EXPECT_EQ(plan.tiers.kept_young, 13);
    EXPECT_EQ(plan.tiers.kept_daily, 7);
    EXPECT_EQ(plan.tiers.kept_weekly, 2);
    EXPECT_EQ(plan.scans, 80);
    EXPECT_EQ(plan.bytes, 80000);
    ASSERT_EQ(plan.remove.size(), 80u - 13 - 7 - 2);
    EXPECT_EQ(plan.bytes_to_free, 1000 * static_cast<std::int64_t>(plan.remove.size()));
    EXPECT_TRUE(plan.reencode.empty());  // reencode = none
    // Newest first, in the tiers' order; the first scan of the series is the first weekly
    // one, so kept, and the second is the last removed.
    EXPECT_EQ(plan.remove.back().id, 2);
    ASSERT_EQ(plan.tiers.thin.size(), plan.remove.size());
    for (std::size_t k = 0; k < plan.remove.size(); ++k) {
        EXPECT_EQ(plan.remove[k].id, plan.tiers.thin[k]);
        if (k > 0) {
            EXPECT_GT(plan.remove[k - 1].acquired, plan.remove[k].acquired);
        }
    }
}

TEST(ArchivePolicy, NeverRemovesAProtectedScan) {
    auto list = scans(20);
    list[1].is_protected = true;   // an alarm's epoch, in the weekly tier
    list[41].is_protected = true;  // a pinned one, in the daily tier (day 10, not its first)
    const auto plan = plan_archive(list, list.back().acquired, policy());
    EXPECT_EQ(plan.tiers.kept_protected, 2);
    for (const auto& s : plan.remove) {
        EXPECT_NE(s.id, list[1].id);
        EXPECT_NE(s.id, list[41].id);
    }
    EXPECT_EQ(plan.remove.size(), 80u - 13 - 7 - 2 - 2);
}

TEST(ArchivePolicy, ReencodesKeptScansPastTheYoungTierButNotTheReference) {
    auto list = scans(20);
    list[0].named_by_state = true;  // the reference: kept byte for byte
    list[0].is_protected = true;
    list[44].path = "/archive/already.E57";  // day 11's first, an E57 export
    list[48].reencode_failed = true;         // day 12's first, tried once
    const auto plan = plan_archive(list, list.back().acquired, policy(ScanReencoding::e57));
    // Kept and older than 3 days: 7 daily + 2 weekly (one of them the reference), less the
    // reference, the E57 file and the one that failed before.
    ASSERT_EQ(plan.reencode.size(), 7u + 2 - 3);
    for (const auto& s : plan.reencode) {
        EXPECT_LT(s.acquired, list.back().acquired - 3 * kDay);
        EXPECT_NE(s.id, list[0].id);
        EXPECT_NE(s.id, list[44].id);
        EXPECT_NE(s.id, list[48].id);
    }
    // Removal does not depend on re-encoding.
    EXPECT_EQ(plan.remove.size(), plan_archive(list, list.back().acquired, policy()).remove.size());
}

TEST(ArchivePolicy, KnowsAnE57FileByItsExtension) {
    EXPECT_TRUE(is_e57_path("/a/b.e57"));
    EXPECT_TRUE(is_e57_path("B.E57"));
    EXPECT_FALSE(is_e57_path("/a/b.e57.part"));
    EXPECT_FALSE(is_e57_path("/a/b.ptx"));
    EXPECT_FALSE(is_e57_path("e57"));
}

}  // namespace
}  // namespace tlsmon
