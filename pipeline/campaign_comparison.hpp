#pragma once
// A campaign cloud compared with the TLS reference segment by segment (docs/campaigns.md; the
// segment-based analysis of Blaskow & Maas): the campaign's own frame brought near the
// reference's (the coarse step: both clouds' planes matched without a prior), the whole cloud
// registered on the reference (point-to-plane on the local planes: the fine step), then
// the ground found by the cloth simulation filter (kept for the registration, left out of the
// segments), verticality and the two-stage segmentation of the rest, each segment registered
// on its own (verticality and the segments on the cloud thinned to one point per voxel,
// thinning.hpp, and carried back to every point; the registrations on a subsample in the
// cloud's order), each matched to the reference's own segment it lies on (the reference
// segmented by the same steps), the test of whether the segments moved as one, and the C2C
// distance of every point after its segment's registration.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "algorithms/campaign/c2c.hpp"
#include "algorithms/campaign/cloud_planes.hpp"
#include "algorithms/campaign/cut_bias.hpp"
#include "algorithms/campaign/ground_filter.hpp"
#include "algorithms/campaign/reference_surface.hpp"
#include "algorithms/campaign/segment_consistency.hpp"
#include "algorithms/campaign/segment_matching.hpp"
#include "algorithms/campaign/segment_registration.hpp"
#include "algorithms/campaign/segmentation.hpp"
#include "algorithms/campaign/thinning.hpp"
#include "algorithms/campaign/verticality.hpp"
#include "algorithms/registration/plane_matching_without_prior.hpp"

namespace tlsmon {

// How a campaign's own frame is brought near the reference's before the whole cloud's ICP
// (docs/campaigns.md, "The campaign's frame"):
//   none       the files are in one frame (georeferenced in the field, or simulated so);
//   planes     both clouds' planes (cloud_planes.hpp) matched without a prior
//              (plane_matching_without_prior.hpp): a SLAM frame is levelled by the scanner's
//              inertial unit, so the two frames differ by a heading and a shift;
//   automatic  planes, and none where they give no match that is unambiguous.
enum class CoarseRegistration { none, planes, automatic };
const char* coarse_name(CoarseRegistration coarse);  // "none", "planes", "auto"

struct CampaignParameters {
    campaign::ReferenceSurfaceParameters surface;
    // m, the voxel verticality and segmentation thin the cloud to (0: every point): 0.03 leaves
    // about 35 points of a surface in the 0.10 m neighbourhood.
    double thinning = 0.03;
    // The most points a registration (the whole cloud's, each segment's) uses: every k-th of
    // its points in the cloud's order. Not the voxel-thinned points: which point of a voxel is
    // kept depends on where its noise put it, and on a noisy surface that biases the kept
    // points along the normal by up to ±1 mm (20 mm noise, 0.03 m voxels) with the surface's
    // place in the voxel grid. C2C is computed for every point.
    std::size_t registration_points = 200000;
    bool remove_ground = true;  // false: the ground is segmented like the rest
    campaign::GroundFilterParameters ground;
    campaign::VerticalityParameters verticality;
    campaign::SegmentationParameters segmentation;
    campaign::SegmentIcpParameters icp;  // the segments' (the global one is
                                         // point-to-plane whatever icp.metric)
    int min_segment_points = 1000;       // smaller segments are not registered
    // A registered segment whose pairs on modelled surfaces (local planes that hold) are
    // fewer than this share of its points is unobserved: its fit stands for a few planar
    // patches of a bush or a rubble pile, not for the segment, and its σ, from those patches
    // alone, would be tested as the segment's.
    double min_planar_share = 0.5;
    // A campaign segment is the reference segment at least this share of its points lie on
    // after the global registration (segment_matching.hpp); below it, none.
    double min_overlap = 0.5;
    // The bound on the bias of a segment's own cut (cut_bias.hpp), added to its translations'
    // variance: the campaign instrument's range noise (m, 1σ) and the band along the cuts.
    double range_sigma = 0.02;
    double cut_distance = 0.10;
    campaign::C2cModel c2c = campaign::C2cModel::local_plane;
    double alpha = 0.05;   // of the segments' consistency test
    unsigned threads = 0;  // 0: every core
    CoarseRegistration coarse = CoarseRegistration::automatic;
    campaign::CloudPlaneParameters planes;  // of the coarse step, in both clouds
    // The coarse step's matching; its either_sign is set (unstructured planes have no side).
    registration::PriorFreeMatchingParams plane_matching;
};

struct CampaignSegmentResult {
    campaign::Segment segment;
    // After the global registration; its covariance includes the cut's bias bound.
    campaign::SegmentTransform transform;
    double cut_fraction = 0;  // of its points within cut_distance of something else
    double cut_bias = 0;      // m, the bound added to each translation's variance (squared)
    campaign::SegmentMatch reference;  // the reference's segment it is
    campaign::C2cStatistics c2c;
};

// The reference prepared once for any number of campaigns: its local planes, and its own
// segments — ground, verticality and segmentation as a campaign's — that each campaign
// segment is matched to.
struct CampaignReference {
    // `points` must outlive it.
    CampaignReference(std::span<const Eigen::Vector3d> points, const CampaignParameters& p);
    campaign::ReferenceSurface surface;
    campaign::GroundClassification ground;
    campaign::Segmentation segmentation;  // per reference point, as a campaign's
    // Its planes for the coarse step (none when the parameters ask for no coarse step).
    std::vector<registration::FittedPlane> planes;
    double seconds = 0;  // wall time to prepare it
};

// The coarse step's outcome. `used` is none or planes; with automatic, `note` says why the
// planes were not used.
struct CoarseFrame {
    CoarseRegistration used = CoarseRegistration::none;
    Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();  // the campaign's frame, near the
                                                           // reference's: x' = M·x
    std::size_t campaign_planes = 0, reference_planes = 0;
    std::size_t support = 0;    // plane pairs the match rests on
    std::size_t runner_up = 0;  // the best other heading's pairs
    std::string note;
};

// Wall seconds of each step, for the operator to see where the time went.
struct CampaignTimings {
    double reference = 0;  // preparing the reference, when the comparison did
    double coarse = 0, global = 0, ground = 0, verticality = 0, segmentation = 0, matching = 0,
           segments = 0, c2c = 0;
    double total() const {
        return reference + coarse + global + ground + verticality + segmentation + matching +
               segments + c2c;
    }
};

struct CampaignComparison {
    CoarseFrame coarse;
    campaign::SegmentTransform global;      // the whole cloud after the coarse step onto the
                                            // reference
    std::size_t thinned = 0;                // voxels of the cloud thinned for classification
    campaign::GroundClassification ground;  // of the registered cloud; empty flags: not removed
    // Per campaign point (ground points: segment −1); the segments' point counts are of the
    // whole cloud, its spacing that of the thinned structure.
    campaign::Segmentation segmentation;
    std::vector<CampaignSegmentResult> segments;  // as segmentation.segments
    campaign::SegmentConsistency consistency;
    // Per campaign point: its position after the global and its segment's registration (the
    // global one alone outside a registered segment) and its C2C vector.
    std::vector<Eigen::Vector3d> registered;
    std::vector<Eigen::Vector3f> c2c;
    campaign::C2cStatistics c2c_all;
    CampaignTimings seconds;
    // The campaign's frame onto the reference: the coarse step, then the global registration.
    Eigen::Matrix4d frame() const { return global.matrix() * coarse.matrix; }
};

// Throws Error when the coarse step asked for fails, or when the global registration fails
// (no overlap within the surface's max_distance: the frames are not near each other).
CampaignComparison compare_campaign(std::span<const Eigen::Vector3d> reference,
                                    std::span<const Eigen::Vector3d> campaign,
                                    const CampaignParameters& parameters);
// The same on a reference prepared once (with the same parameters) for several campaigns.
CampaignComparison compare_campaign(const CampaignReference& reference,
                                    std::span<const Eigen::Vector3d> campaign,
                                    const CampaignParameters& parameters);

void validate(const CampaignParameters& parameters);

}  // namespace tlsmon
