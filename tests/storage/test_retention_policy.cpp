// The retention plan (storage/retention_policy.hpp) against hand-counted answers: all maps
// while young, the first of each UTC day, then of each ISO week; protected epochs whatever
// their age; a plan never needs what an earlier plan thinned, and a pass stopped part-way
// leaves the rest of its plan to the next.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "storage/retention_policy.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kDay = 86400;
constexpr UtcSeconds kThursday = 1767225600;  // 2026-01-01T00:00:00Z, a Thursday

// `per_day` epochs a day for `days` days from 2026-01-01, ids from 1.
std::vector<MapEpoch> series(int days, int per_day) {
    std::vector<MapEpoch> out;
    for (int i = 0; i < days * per_day; ++i) {
        out.push_back({i + 1, kThursday + i * (kDay / per_day), false});
    }
    return out;
}

RetentionPolicy policy(double all, double daily) {
    RetentionPolicy p;
    p.keep_all_days = all;
    p.keep_daily_days = daily;
    return p;
}

TEST(RetentionPlan, KeepsAllYoungThenTheDaysFirstThenTheWeeksFirst) {
    // 70 days of 4 epochs; the plan at the last epoch's time (day 69, 18:00).
    const auto epochs = series(70, 4);
    const UtcSeconds now = epochs.back().acquired;
    const auto plan = plan_retention(epochs, now, policy(10, 40));
    // Young: acquired >= now - 10 d = day 59 18:00 -> day 59's 18:00 epoch and days 60..69.
    EXPECT_EQ(plan.kept_young, 1 + 10 * 4);
    // Daily: the days whose first epoch (00:00) is >= now - 40 d = day 29 18:00, and older
    // than young: days 30..59 -> 30.
    EXPECT_EQ(plan.kept_daily, 30);
    // Weekly: days 0..29 (and day 29's 18:00 epoch, which is not a first). ISO weeks: days
    // 0-3 (Thu-Sun), 4-10, 11-17, 18-24, 25-31 -> firsts on days 0, 4, 11, 18, 25.
    EXPECT_EQ(plan.kept_weekly, 5);
    EXPECT_EQ(plan.kept_protected, 0);
    EXPECT_EQ(static_cast<std::int64_t>(plan.thin.size()),
              70 * 4 - plan.kept_young - plan.kept_daily - plan.kept_weekly);
    const std::set<EpochId> thin(plan.thin.begin(), plan.thin.end());
    for (int day : {0, 4, 11, 18, 25}) EXPECT_FALSE(thin.count(day * 4 + 1)) << day;
    EXPECT_TRUE(thin.count(1 * 4 + 1));   // day 1 (Fri): weekly zone, not a week's first
    EXPECT_TRUE(thin.count(30 * 4 + 2));  // day 30's 06:00: daily zone, not the day's first
    EXPECT_FALSE(thin.count(30 * 4 + 1));
    EXPECT_TRUE(std::is_sorted(plan.thin.rbegin(), plan.thin.rend()));  // newest first
}

TEST(RetentionPlan, ProtectedEpochsAreNeverThinned) {
    auto epochs = series(60, 4);
    epochs[2].is_protected = true;           // day 0, 12:00
    epochs[4 * 45 + 3].is_protected = true;  // day 45, 18:00
    const auto plan = plan_retention(epochs, epochs.back().acquired, policy(5, 20));
    const std::set<EpochId> thin(plan.thin.begin(), plan.thin.end());
    EXPECT_FALSE(thin.count(epochs[2].id));
    EXPECT_FALSE(thin.count(epochs[4 * 45 + 3].id));
    EXPECT_EQ(plan.kept_protected, 2);
    // The same plan without protection thins both.
    epochs[2].is_protected = epochs[4 * 45 + 3].is_protected = false;
    const auto unprotected = plan_retention(epochs, epochs.back().acquired, policy(5, 20));
    EXPECT_EQ(unprotected.thin.size(), plan.thin.size() + 2);
}

TEST(RetentionPlan, AgeCountsFromTheSeriesNotTheOrderGiven) {
    auto epochs = series(40, 2);
    std::reverse(epochs.begin(), epochs.end());
    const auto plan = plan_retention(epochs, epochs.front().acquired, policy(40, 400));
    EXPECT_TRUE(plan.thin.empty());  // all of it younger than 40 days
    EXPECT_EQ(plan.kept_young, 80);
}

// A pass a day for 400 days over 96 epochs a day, each pass applied to what the previous
// ones left: in the end exactly what one plan over the whole series keeps (an earlier pass
// never thinned an epoch a later one keeps: the day's first stays the week's first).
TEST(RetentionPlan, SuccessivePassesEndWhereOnePassWould) {
    const auto all = series(400, 96);
    const auto p = policy(30, 365);
    std::vector<MapEpoch> with_maps;
    std::size_t next = 0;
    for (int day = 0; day < 400; ++day) {
        while (next < all.size() && all[next].acquired < kThursday + (day + 1) * kDay) {
            with_maps.push_back(all[next++]);
        }
        const auto plan = plan_retention(with_maps, with_maps.back().acquired, p);
        const std::set<EpochId> thin(plan.thin.begin(), plan.thin.end());
        std::erase_if(with_maps, [&](const MapEpoch& e) { return thin.count(e.id) > 0; });
    }
    const auto once = plan_retention(all, all.back().acquired, p);
    const std::set<EpochId> thin(once.thin.begin(), once.thin.end());
    std::vector<EpochId> kept_once, kept_daily_passes;
    for (const auto& e : all)
        if (!thin.count(e.id)) kept_once.push_back(e.id);
    for (const auto& e : with_maps) kept_daily_passes.push_back(e.id);
    EXPECT_EQ(kept_daily_passes, kept_once);
    // 30 days of 96 (and the boundary's epoch), the firsts of 335 days, of 6 ISO weeks.
    EXPECT_EQ(once.kept_young, 30 * 96 + 1);
    EXPECT_EQ(once.kept_daily, 335);
    EXPECT_EQ(once.kept_weekly, 6);
}

// A pass stopped after any number of its plan's epochs (a kill, the daemon's stop between
// batches): the plan of what it left is the rest of its plan, in the same order. Day 29 lies
// astride the daily tier's edge (its 18:00 epoch is in the daily tier, not the day's first),
// so thinning its older epochs first would make that one the day's first and keep it.
TEST(RetentionPlan, APassStoppedPartWayLeavesTheRestOfItsPlan) {
    const auto epochs = series(70, 4);
    const UtcSeconds now = epochs.back().acquired;
    const auto plan = plan_retention(epochs, now, policy(10, 40));
    const EpochId astride = 29 * 4 + 4;  // day 29, 18:00: acquired == now - 40 d
    ASSERT_EQ(epochs[astride - 1].acquired, now - 40 * kDay);
    ASSERT_TRUE(std::count(plan.thin.begin(), plan.thin.end(), astride));
    for (std::size_t done = 0; done <= plan.thin.size(); ++done) {
        const std::set<EpochId> gone(plan.thin.begin(), plan.thin.begin() + done);
        auto left = epochs;
        std::erase_if(left, [&](const MapEpoch& e) { return gone.count(e.id) > 0; });
        const auto next = plan_retention(left, now, policy(10, 40));
        ASSERT_EQ(next.thin, std::vector<EpochId>(plan.thin.begin() + done, plan.thin.end()))
            << "stopped after " << done;
    }
}

}  // namespace
}  // namespace tlsmon
