#include "storage/retention_policy.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace tlsmon {

namespace {

constexpr std::int64_t kDay = 86400;

// Floor division: a day or week index also before 1970.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    return a / b - ((a % b != 0) && ((a < 0) != (b < 0)));
}

// ISO weeks start on Monday; 1970-01-01 was a Thursday, so day 4 (1970-01-05) starts one.
std::int64_t iso_week(UtcSeconds t) {
    return floor_div(floor_div(t, kDay) - 4, 7);
}

}  // namespace

RetentionPlan plan_by_age(std::vector<MapEpoch> epochs, UtcSeconds now, double keep_all_days,
                          double keep_daily_days) {
    std::sort(epochs.begin(), epochs.end(), [](const MapEpoch& a, const MapEpoch& b) {
        return a.acquired != b.acquired ? a.acquired < b.acquired : a.id < b.id;
    });
    const auto young_after = now - static_cast<UtcSeconds>(std::llround(keep_all_days * kDay));
    const auto daily_after = now - static_cast<UtcSeconds>(std::llround(keep_daily_days * kDay));
    RetentionPlan plan;
    plan.now = now;
    std::set<std::int64_t> days_seen, weeks_seen;
    for (const auto& e : epochs) {
        // Every epoch claims its day and week, so the first one of each is the one kept.
        const bool first_of_day = days_seen.insert(floor_div(e.acquired, kDay)).second;
        const bool first_of_week = weeks_seen.insert(iso_week(e.acquired)).second;
        if (e.acquired >= young_after) {
            ++plan.kept_young;
        } else if (e.acquired >= daily_after && first_of_day) {
            ++plan.kept_daily;
        } else if (e.acquired < daily_after && first_of_week) {
            ++plan.kept_weekly;
        } else if (e.is_protected) {
            ++plan.kept_protected;
        } else {
            plan.thin.push_back(e.id);
        }
    }
    // Newest first: a pass stopped part-way has thinned only epochs newer than every one it
    // left, so no epoch it left has lost an earlier one of its day or week, and the next plan
    // thins exactly the rest of this one. In acquisition order, a day astride the daily
    // tier's edge whose older epochs went first would make its newest one the day's first.
    std::reverse(plan.thin.begin(), plan.thin.end());
    return plan;
}

RetentionPlan plan_retention(std::vector<MapEpoch> epochs, UtcSeconds now,
                             const RetentionPolicy& policy) {
    return plan_by_age(std::move(epochs), now, policy.keep_all_days, policy.keep_daily_days);
}

}  // namespace tlsmon
