#include "pipeline/campaign_config.hpp"

#include <array>

namespace tlsmon {

namespace {

constexpr std::array<Named<campaign::IcpMetric>, 2> kMetrics{{
    {campaign::IcpMetric::point_to_plane, "point-to-plane"},
    {campaign::IcpMetric::point_to_point, "point-to-point"},
}};
constexpr std::array<Named<campaign::C2cModel>, 2> kC2c{{
    {campaign::C2cModel::local_plane, "local-plane"},
    {campaign::C2cModel::nearest_point, "nearest-point"},
}};

constexpr std::array<Named<CoarseRegistration>, 3> kCoarse{{
    {CoarseRegistration::automatic, "auto"},
    {CoarseRegistration::planes, "planes"},
    {CoarseRegistration::none, "none"},
}};

}  // namespace

CampaignParameters campaign_parameters(const CampaignConfig& c, double range_sigma) {
    CampaignParameters p;
    p.icp.metric = c.metric;
    p.c2c = c.c2c;
    p.verticality.radius = p.surface.plane_radius = c.radius;
    p.surface.max_distance = c.max_distance;
    p.thinning = c.thinning;
    p.registration_points = std::size_t(c.registration_points);
    p.min_segment_points = c.min_segment_points;
    p.min_planar_share = c.min_planar_share;
    p.min_overlap = c.min_overlap;
    p.remove_ground = c.remove_ground;
    p.alpha = c.alpha;
    p.threads = unsigned(c.threads);
    p.range_sigma = range_sigma;
    p.coarse = c.coarse;
    return p;
}

std::vector<SectionKey<CampaignConfig>> campaign_keys() {
    using K = Keys<CampaignConfig>;
    return {
        K::choice(&CampaignConfig::metric, "metric", kMetrics,
                  "The segments' ICP: to the reference's local plane, or to its nearest point as "
                  "the study did (the whole cloud's registration is point-to-plane either way)."),
        K::choice(&CampaignConfig::c2c, "c2c", kC2c,
                  "Each point's cloud-to-cloud distance: to the local plane at its nearest "
                  "reference point, or to that point."),
        K::number(&CampaignConfig::radius, "radius", 0.01, 10, "m",
                  "The neighbourhood of the local planes and of the verticality (the study's "
                  "0.10 m)."),
        K::number(&CampaignConfig::max_distance, "max_distance", 0.001, 100, "m",
                  "The farthest a campaign point's nearest reference point may be for a pair: "
                  "beyond the largest displacement expected after the coarse frame."),
        K::number(&CampaignConfig::thinning, "thinning", 0, 1, "m",
                  "The voxel the cloud is thinned to for verticality and segmentation (each "
                  "point takes its voxel's class and segment); 0: every point."),
        K::integer(&CampaignConfig::registration_points, "registration_points", 100, 1000000000, "",
                   "The most points a registration (the whole cloud's, each segment's) uses: "
                   "every k-th in the file's order."),
        K::integer(&CampaignConfig::min_segment_points, "min_segment_points", 10, 100000000, "",
                   "Smaller segments are not registered."),
        K::number(&CampaignConfig::min_planar_share, "min_planar_share", 0, 1, "",
                  "A segment whose pairs on surfaces a local plane models are fewer than this "
                  "share of its points is unobserved (a bush, rubble, small pieces on edges)."),
        K::number(&CampaignConfig::min_overlap, "min_overlap", 0.01, 1, "",
                  "A segment is the reference's segment at least this share of its points lie "
                  "on; below it, none."),
        K::flag(&CampaignConfig::remove_ground, "remove_ground",
                "Leave the ground (the cloth simulation filter's) out of the segments; it serves "
                "the registration either way."),
        K::number(&CampaignConfig::alpha, "alpha", 0.0001, 0.4999, "",
                  "The level of the test of whether the segments moved as one."),
        K::integer(&CampaignConfig::threads, "threads", 0, 256, "",
                   "Threads of a comparison; 0: every core."),
        K::choice(&CampaignConfig::coarse, "coarse", kCoarse,
                  "How a campaign's own frame (a SLAM cloud's, levelled) is brought near the "
                  "reference's before the whole cloud's ICP: both clouds' planes matched without "
                  "a prior; auto: planes, else the files taken as in one frame; none: they are."),
        K::number(&CampaignConfig::store_spacing, "store_spacing", 0, 10, "m",
                  "A stored campaign keeps its registered points thinned to one per voxel this "
                  "size, each with its segment and C2C vector (for export and drawing); 0: "
                  "every point."),
        K::flag(&CampaignConfig::zone_series, "zone_series",
                "Each stored campaign adds campaign_c2c_median_m to every zone with a design "
                "normal its points cover (the change of shape within its segment, after each "
                "segment's registration; docs/campaigns.md), which alarm rules may watch; off: "
                "campaigns stay out of the zone series and the alarms."),
        K::integer(&CampaignConfig::zone_min_points, "zone_min_points", 1, 100000000, "",
                   "The fewest stored points of registered segments a campaign's zone value "
                   "rests on."),
    };
}

}  // namespace tlsmon
