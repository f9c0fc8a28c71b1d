#include "storage/archive_policy.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace tlsmon {

bool is_e57_path(const std::string& path) {
    if (path.size() < 4) return false;
    std::string ext = path.substr(path.size() - 4);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".e57";
}

ArchivePlan plan_archive(std::vector<ArchivedScan> scans, UtcSeconds now,
                         const ArchivePolicy& policy) {
    // Newest first, as the tiers thin (storage/retention_policy.hpp): `remove` in their order.
    std::sort(scans.begin(), scans.end(), [](const ArchivedScan& a, const ArchivedScan& b) {
        return a.acquired != b.acquired ? a.acquired > b.acquired : a.id > b.id;
    });
    std::vector<MapEpoch> epochs;
    epochs.reserve(scans.size());
    for (const auto& s : scans) epochs.push_back({s.id, s.acquired, s.is_protected});
    ArchivePlan plan;
    plan.tiers = plan_by_age(std::move(epochs), now, policy.keep_all_days, policy.keep_daily_days);
    const std::set<EpochId> removed(plan.tiers.thin.begin(), plan.tiers.thin.end());
    const auto young_after =
        now - static_cast<UtcSeconds>(std::llround(policy.keep_all_days * 86400.0));
    for (auto& s : scans) {
        ++plan.scans;
        plan.bytes += s.bytes;
        if (removed.count(s.id)) {
            plan.bytes_to_free += s.bytes;
            plan.remove.push_back(std::move(s));
        } else if (policy.reencode == ScanReencoding::e57 && s.acquired < young_after &&
                   !s.named_by_state && !s.reencode_failed && !is_e57_path(s.path)) {
            plan.reencode.push_back(std::move(s));
        }
    }
    return plan;
}

}  // namespace tlsmon
