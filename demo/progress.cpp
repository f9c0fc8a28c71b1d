#include "demo/progress.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

bool processed(EpochStatus s) {
    return s == EpochStatus::done || s == EpochStatus::rejected || s == EpochStatus::failed;
}

}  // namespace

DemoProgress::DemoProgress(std::filesystem::path database, int total, std::int64_t start,
                           double cadence, std::vector<std::string> zones, std::ostream& out)
    : database_(std::move(database)),
      total_(total),
      start_(start),
      cadence_(cadence),
      zones_(std::move(zones)),
      out_(out) {}

DemoProgress::~DemoProgress() = default;

std::string DemoProgress::line(const EpochDatabase& db, const Epoch& e) {
    const int index = static_cast<int>(std::lround((e.acquired - start_) / cadence_));
    const int done = static_cast<int>(printed_.size()) + 1;
    std::string s = fmt::format("[{:>3}/{} {:>3}%] epoch {:>3} {}", done, total_,
                                100 * done / std::max(1, total_), index,
                                format_utc(e.acquired).substr(11, 5) + "Z");
    const auto reg = db.registrations().of_epoch(e.id);
    if (reg && reg->accepted) {
        std::string out;
        for (const auto& t : db.registrations().targets_of_epoch(e.id)) {
            if (t.use == "excluded_outlier" || t.status == "excluded") out += " " + t.target;
        }
        s += fmt::format("  reg RMS {:.2f} mm, {} targets{}", 1e3 * reg->rms_m, reg->target_count,
                         out.empty() ? "" : " (excluded:" + out + ")");
    } else if (reg) {
        s += fmt::format("  reg not accepted ({})", reg->status);
    }
    if (e.status != EpochStatus::done) {
        s += fmt::format("  {}: {}", to_string(e.status), e.reason.substr(0, 90));
    }
    // Per zone: M3C2 along the normal, the keypoints along the surface (h, v), each labelled.
    for (const std::string& zone : zones_) {
        std::string values;
        for (const auto& [q, label] :
             {std::pair{"m3c2_median_m", "M3C2"}, std::pair{"keypoint_along_surface_h_m", "kp h"},
              std::pair{"keypoint_along_surface_v_m", "v"}}) {
            const auto points = db.series().points(zone, q, {e.acquired, e.acquired});
            for (const SeriesPoint& p : points) {
                if (p.epoch != e.id) continue;
                zone_values_seen_ = true;
                values += fmt::format(" {} {:+.1f}", label, 1e3 * p.value);
                if (p.uncertainty) values += fmt::format("±{:.1f}", 1e3 * *p.uncertainty);
                if (p.significant) values += "*";
                break;
            }
        }
        if (!values.empty()) s += "  " + zone + values + " mm";
    }
    for (const AlarmEvent& a : db.alarms().events(e.acquired)) {
        if (a.epoch != e.id || a.rule.rfind("system.", 0) == 0) continue;
        s += fmt::format("  ALARM {} {} {}", a.rule, a.kind, a.level);
    }
    return s;
}

int DemoProgress::poll() {
    if (!db_) {
        try {
            db_ = std::make_unique<EpochDatabase>(
                EpochDatabase::open(database_, EpochDatabase::Mode::read_only));
        } catch (const StorageError&) {
            return 0;  // not created or not migrated yet
        }
    }
    int count = 0;
    try {
        for (const Epoch& e : db_->series().epochs_in_range({})) {
            if (!processed(e.status)) continue;
            ++count;
            if (printed_.count(e.id)) continue;
            const std::string text = line(*db_, e);
            printed_.insert(e.id);
            out_ << text << std::endl;
            if (!zone_values_seen_ && !told_no_zone_values_ && printed_.size() == 2) {
                out_ << "      (no zone values: this build has no M3C2 or keypoint stage yet; "
                        "registration only)"
                     << std::endl;
                told_no_zone_values_ = true;
            }
        }
    } catch (const StorageError&) {
        // A read that met the daemon mid-commit; the next poll reads again.
    }
    return count;
}

}  // namespace tlsmon
