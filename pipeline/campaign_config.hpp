#pragma once
// [campaign] (docs/configuration.md; docs/campaigns.md): how the campaign epochs of every
// [[instrument]] are compared with the reference — the daemon's and `tlsmon campaign add`'s
// choice of what `tlsmon campaign compare` takes as options. The instrument adds its own
// range noise.
#include <cstdint>
#include <vector>

#include "core/config_key.hpp"
#include "pipeline/campaign_comparison.hpp"

namespace tlsmon {

struct CampaignConfig {
    campaign::IcpMetric metric = campaign::IcpMetric::point_to_plane;
    campaign::C2cModel c2c = campaign::C2cModel::local_plane;
    double radius = 0.10;        // m, the local planes' and verticality's neighbourhood
    double max_distance = 0.20;  // m, the farthest pair
    double thinning = 0.03;
    std::int64_t registration_points = 200000;
    int min_segment_points = 1000;
    double min_planar_share = 0.5;
    double min_overlap = 0.5;
    bool remove_ground = true;
    double alpha = 0.05;
    int threads = 0;
    CoarseRegistration coarse = CoarseRegistration::automatic;
    // m: a stored campaign keeps its registered points thinned to one per voxel this size,
    // each with its segment and C2C vector; 0: every point.
    double store_spacing = 0.05;
    // Whether each campaign adds its values to the zone series (campaign_* quantities, which
    // alarm rules may watch; docs/campaigns.md, "Zone series"), and the fewest of its stored
    // points a zone's value rests on.
    bool zone_series = false;
    int zone_min_points = 30;
};

// The comparison's parameters: these keys over the defaults, and the instrument's range noise.
CampaignParameters campaign_parameters(const CampaignConfig& config, double range_sigma);

// The keys of [campaign] (core/config_key.hpp).
std::vector<SectionKey<CampaignConfig>> campaign_keys();

}  // namespace tlsmon
