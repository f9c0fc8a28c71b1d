#pragma once
// The lines `tlsmon retention` and `tlsmon archive` share: a plan's tiers by age.
#include <string>
#include <utility>
#include <vector>

#include "cli/query_output.hpp"
#include "core/utc_time.hpp"
#include "storage/retention_policy.hpp"

namespace tlsmon {

// A time as UTC text; empty for 0 (no epoch yet).
inline Cell time_cell(UtcSeconds t) {
    return t == 0 ? Cell() : Cell(format_utc(t));
}

inline std::vector<std::pair<std::string, Cell>> tier_fields(const RetentionPlan& p) {
    return {{"series_time", time_cell(p.now)},
            {"kept_young", p.kept_young},
            {"kept_daily", p.kept_daily},
            {"kept_weekly", p.kept_weekly},
            {"kept_protected", p.kept_protected}};
}

}  // namespace tlsmon
