#pragma once
// Campaign epochs (docs/campaigns.md, "Campaign epochs"; docs/schema.md, "campaigns"): a
// cloud of an [[instrument]] compared with the station's reference segment by segment, with
// one row per segment. Apart from the station's epochs; in the zone series and the alarms only
// under quantities of its own (campaign_*) when [campaign] zone_series says so.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/epoch_results.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct TimeRange;
class SeriesReader;
using CampaignId = std::int64_t;

// The campaigns' own zone quantities (docs/campaigns.md, "Zone series"): stored apart from
// the station's (campaign_zone_results), read through the same series.
inline constexpr std::string_view kCampaignQuantityPrefix = "campaign_";
inline constexpr const char* kCampaignC2cMedian = "campaign_c2c_median_m";
inline bool is_campaign_quantity(std::string_view quantity) {
    return quantity.substr(0, kCampaignQuantityPrefix.size()) == kCampaignQuantityPrefix;
}

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
    // How the cloud's own frame was brought near the reference before the global
    // registration: "none" (the files were in one frame) or "planes", with the plane pairs
    // the match rests on.
    std::string coarse = "none";
    std::optional<std::int64_t> coarse_planes;
    // The campaign's frame onto the reference (the coarse step, then the global
    // registration): x_ref = M·x, row-major. None for a campaign stored before 0016.
    std::optional<std::array<double, 16>> frame;
};

// A stored campaign's points: its registered cloud thinned to one point per `spacing` voxel
// ([campaign] store_spacing), as float32 arrays of one length, by quantity:
//   x_m, y_m, z_m           the point after its segment's registration, in the reference's
//                           frame, less `origin` (float32 keeps 8 µm at 100 m from it)
//   segment                 its segment (−1: ground, or in no segment)
//   c2c_dx_m, c2c_dy_m, c2c_dz_m   its C2C vector (NaN: no reference point within reach)
inline constexpr std::array<const char*, 7> kCampaignPointArrays{
    "x_m", "y_m", "z_m", "segment", "c2c_dx_m", "c2c_dy_m", "c2c_dz_m"};

struct CampaignPoints {
    std::array<double, 3> origin{};  // m
    double spacing = 0;              // m, 0: every point
    std::vector<CorePointArray> arrays;
    std::size_t size() const { return arrays.empty() ? 0 : arrays.front().values.size(); }
    const std::vector<float>* array(const std::string& quantity) const;
    // The arrays of kCampaignPointArrays, in its order; Error naming the first one missing.
    std::array<const std::vector<float>*, 7> columns() const;
};

class CampaignStore {
  public:
    explicit CampaignStore(Connection& connection) : c_(&connection) {}

    // The alarm evaluation of a campaign, run inside its transaction once its zone rows are
    // written (as ResultsWriter's for an epoch): it gets the campaign's id.
    using AlarmEvaluation = std::function<AlarmRows(CampaignId id, const AlarmStore& alarms,
                                                    const SeriesReader& series)>;

    // The campaign, its segments, its points, its zone rows (campaign_* quantities only; the
    // zones must exist) and the alarm rows `evaluate` returns, in one transaction; returns its
    // id. A sha256 already stored is a StorageError (find() first), and so are arrays of
    // unequal lengths and a zone row of another quantity.
    CampaignId add(const CampaignRow& campaign, const std::vector<CampaignSegmentRow>& segments,
                   const CampaignPoints& points = {},
                   const std::vector<ZoneResult>& zone_results = {},
                   const AlarmEvaluation& evaluate = {});
    std::optional<CampaignRow> find(const std::string& sha256) const;
    std::optional<CampaignRow> get(CampaignId id) const;
    // Acquired in the range, oldest first.
    std::vector<CampaignRow> in_range(const TimeRange& range) const;
    std::vector<CampaignSegmentRow> segments(CampaignId id) const;
    // None when the campaign kept no points (stored before 0016).
    std::optional<CampaignPoints> points(CampaignId id) const;
    // Its zone rows, by zone and quantity.
    std::vector<ZoneResult> zone_results(CampaignId id) const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
