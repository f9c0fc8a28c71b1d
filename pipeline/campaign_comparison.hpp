#pragma once
// A campaign cloud compared with the TLS reference segment by segment (docs/campaigns.md; the
// segment-based analysis of Blaskow & Maas): the whole cloud registered on the reference
// (point-to-plane on the local planes: the fine step, the files already in one frame), then
// the ground found by the cloth simulation filter (kept for the registration, left out of the
// segments), verticality and the two-stage segmentation of the rest, each segment registered
// on its own, the test of whether the segments moved as one, and the C2C distance of every
// point after its segment's registration.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/campaign/c2c.hpp"
#include "algorithms/campaign/ground_filter.hpp"
#include "algorithms/campaign/reference_surface.hpp"
#include "algorithms/campaign/segment_consistency.hpp"
#include "algorithms/campaign/segment_registration.hpp"
#include "algorithms/campaign/segmentation.hpp"
#include "algorithms/campaign/verticality.hpp"

namespace tlsmon {

struct CampaignParameters {
    campaign::ReferenceSurfaceParameters surface;
    bool remove_ground = true;  // false: the ground is segmented like the rest
    campaign::GroundFilterParameters ground;
    campaign::VerticalityParameters verticality;
    campaign::SegmentationParameters segmentation;
    campaign::SegmentIcpParameters icp;  // the segments' (the global one is
                                         // point-to-plane whatever icp.metric)
    int min_segment_points = 1000;       // smaller segments are not registered
    campaign::C2cModel c2c = campaign::C2cModel::local_plane;
    double alpha = 0.05;   // of the segments' consistency test
    unsigned threads = 0;  // 0: every core
};

struct CampaignSegmentResult {
    campaign::Segment segment;
    campaign::SegmentTransform transform;  // after the global registration
    campaign::C2cStatistics c2c;
};

struct CampaignComparison {
    campaign::SegmentTransform global;      // the whole cloud onto the reference
    campaign::GroundClassification ground;  // of the registered cloud; empty flags: not removed
    campaign::Segmentation segmentation;    // per campaign point (ground points: segment −1)
    std::vector<CampaignSegmentResult> segments;  // as segmentation.segments
    campaign::SegmentConsistency consistency;
    // Per campaign point: its position after the global and its segment's registration (the
    // global one alone outside a registered segment) and its C2C vector.
    std::vector<Eigen::Vector3d> registered;
    std::vector<Eigen::Vector3f> c2c;
    campaign::C2cStatistics c2c_all;
};

// Throws Error when the global registration fails (no overlap within the surface's
// max_distance: the files are not in one frame).
CampaignComparison compare_campaign(std::span<const Eigen::Vector3d> reference,
                                    std::span<const Eigen::Vector3d> campaign,
                                    const CampaignParameters& parameters);
// The same on a reference surface built once (with parameters.surface) for several campaigns.
CampaignComparison compare_campaign(const campaign::ReferenceSurface& reference,
                                    std::span<const Eigen::Vector3d> campaign,
                                    const CampaignParameters& parameters);

void validate(const CampaignParameters& parameters);

}  // namespace tlsmon
