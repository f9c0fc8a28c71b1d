#pragma once
// Campaign epochs (docs/campaigns.md, "Campaign epochs"; docs/schema.md, "campaigns"): a
// cloud of an [[instrument]] compared with the station's reference segment by segment, with
// one row per segment. Apart from the station's epochs: no zone series, no alarms.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct TimeRange;
using CampaignId = std::int64_t;

// One segment, as segments.csv has it: a parameter and its σ are empty where the segment's
// surfaces do not observe it (there it is the start, not a measurement).
struct CampaignSegmentRow {
    std::int64_t segment = 0;
    std::string kind;  // vertical, horizontal, other
    std::int64_t cluster = 0, points = 0, voxels = 0;
    std::string outcome;  // registered, few pairs, unobserved, diverged, too small
    // The reference's segment it lies on (none: below the overlap asked) and the share of its
    // points that do (none: no point was looked at).
    std::optional<std::int64_t> reference_segment;
    std::optional<double> reference_overlap;
    std::int64_t pairs = 0, rank = 0, iterations = 0;
    bool converged = false;
    std::array<std::optional<double>, 3> centroid;  // m
    // Rotation vector (rad) then translation (m) about the centroid, and their σ.
    std::array<std::optional<double>, 6> parameters, sigmas;
    std::optional<double> cut_fraction, cut_bias, rmse;
    std::optional<double> test_statistic, test_p;
    std::optional<std::int64_t> test_dof;
    std::optional<double> c2c_mean, c2c_sigma, c2c_median, c2c_p95, c2c_max;
};

struct CampaignRow {
    CampaignId id = 0;  // set by add()
    std::string sha256, instrument, kind, file_path;
    std::int64_t file_size = 0;
    UtcSeconds acquired = 0, added = 0;
    EpochId reference_epoch = 0;
    std::int64_t points = 0, ground_points = 0;
    std::array<double, 6> global{};  // the whole cloud's rotation vector (rad), translation (m)
    std::int64_t global_pairs = 0;
    double global_rmse = 0;
    std::int64_t segments = 0, registered_segments = 0;
    std::optional<double> test_statistic, test_p;  // whether the segments moved as one
    std::optional<std::int64_t> test_dof;
    std::optional<bool> segments_differ;  // none: not testable
    double alpha = 0.05;
    std::optional<double> c2c_mean, c2c_sigma, c2c_median, c2c_p95;
    std::int64_t c2c_missing = 0;
    std::string parameters_json;
    double seconds = 0;
};

class CampaignStore {
  public:
    explicit CampaignStore(Connection& connection) : c_(&connection) {}

    // The campaign and its segments in one transaction; returns its id. A sha256 already
    // stored is a StorageError (find() first).
    CampaignId add(const CampaignRow& campaign, const std::vector<CampaignSegmentRow>& segments);
    std::optional<CampaignRow> find(const std::string& sha256) const;
    std::optional<CampaignRow> get(CampaignId id) const;
    // Acquired in the range, oldest first.
    std::vector<CampaignRow> in_range(const TimeRange& range) const;
    std::vector<CampaignSegmentRow> segments(CampaignId id) const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
