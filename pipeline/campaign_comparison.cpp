#include "pipeline/campaign_comparison.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon {

const char* coarse_name(CoarseRegistration coarse) {
    switch (coarse) {
        case CoarseRegistration::none:
            return "none";
        case CoarseRegistration::planes:
            return "planes";
        case CoarseRegistration::automatic:
            return "auto";
    }
    return "?";
}

void validate(const CampaignParameters& p) {
    campaign::validate(p.surface);
    campaign::validate(p.planes);
    campaign::validate(p.ground);
    campaign::validate(p.verticality);
    campaign::validate(p.segmentation);
    campaign::validate(p.icp);
    if (p.min_segment_points < p.icp.min_pairs)
        throw Error("campaign: min_segment_points must be at least the ICP's min_pairs");
    if (!(p.alpha > 0 && p.alpha < 0.5)) throw Error("campaign: alpha must lie in (0, 0.5)");
    if (!(p.thinning >= 0 && p.thinning <= 1))
        throw Error("campaign: thinning must lie in [0, 1] m");
    if (!(p.min_planar_share >= 0 && p.min_planar_share <= 1))
        throw Error("campaign: min_planar_share must lie in [0, 1]");
    if (!(p.min_overlap > 0 && p.min_overlap <= 1))
        throw Error("campaign: min_overlap must lie in (0, 1]");
    if (!(p.range_sigma >= 0 && p.range_sigma <= 1))
        throw Error("campaign: range_sigma must lie in [0, 1] m");
    if (!(p.cut_distance > 0 && p.cut_distance <= 10))
        throw Error("campaign: cut_distance must lie in (0, 10] m");
    if (p.registration_points < std::size_t(p.icp.min_pairs))
        throw Error("campaign: registration_points must be at least the ICP's min_pairs");
}

namespace {

std::vector<Eigen::Vector3d> transformed(std::span<const Eigen::Vector3d> points,
                                         const Eigen::Matrix4d& M, unsigned threads) {
    std::vector<Eigen::Vector3d> out(points.size());
    parallel_for(
        points.size(), [&](std::size_t i) { out[i] = (M * points[i].homogeneous()).head<3>(); },
        threads);
    return out;
}

// Every k-th of n points (point(j) the j-th), in their order, at most `most` of them.
template <class Point>
std::vector<Eigen::Vector3d> subsample(std::size_t n, std::size_t most, Point&& point) {
    const std::size_t k = std::max<std::size_t>(1, (n + most - 1) / most);
    std::vector<Eigen::Vector3d> out;
    out.reserve(n / k + 1);
    for (std::size_t j = 0; j < n; j += k) out.push_back(point(j));
    return out;
}

// Wall seconds since `start`, restarting it.
double lap(std::chrono::steady_clock::time_point& start) {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - start).count();
    start = now;
    return seconds;
}

// A cloud (registered) as its structure: the ground found (kept apart unless remove_ground
// is off), verticality on the whole cloud thinned to voxels (the ground's own points still
// hold the structure's verticality at its foot), the segments on the thinned structure —
// each voxel of points that are not ground kept by its first such point, of its whole
// voxel's class — and every point given its voxel's segment.
struct Structure {
    campaign::GroundClassification ground;
    campaign::VoxelThinning whole;  // every point's voxel
    campaign::Segmentation segmentation;
};

Structure segment_structure(std::span<const Eigen::Vector3d> points, const CampaignParameters& p,
                            CampaignTimings& seconds) {
    const unsigned threads = p.threads;
    auto clock = std::chrono::steady_clock::now();
    Structure out;
    if (p.remove_ground) out.ground = campaign::classify_ground(points, p.ground, threads);
    seconds.ground = lap(clock);
    out.whole = campaign::thin_by_voxel(points, p.thinning, {}, threads);
    std::vector<std::uint8_t> structure_flag;
    if (!out.ground.ground.empty()) {
        structure_flag.resize(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) structure_flag[i] = !out.ground.ground[i];
    }
    const std::vector<float> verticality =
        campaign::verticality(campaign::kept_points(points, out.whole), p.verticality, threads);
    seconds.verticality = lap(clock);
    const campaign::VoxelThinning structure =
        campaign::thin_by_voxel(points, p.thinning, structure_flag, threads);
    std::vector<campaign::VerticalityClass> classes;
    classes.reserve(structure.voxels());
    for (const auto i : structure.kept)
        classes.push_back(campaign::classify(verticality[out.whole.of[i]], p.verticality));
    out.segmentation = campaign::segment_cloud(campaign::kept_points(points, structure), classes,
                                               p.segmentation, threads);
    std::vector<std::int32_t> cluster(points.size(), -1), segment(cluster);
    for (auto& s : out.segmentation.segments) s.points = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::uint32_t v = structure.of[i];
        if (v == campaign::VoxelThinning::kNone) continue;
        cluster[i] = out.segmentation.cluster[v];
        segment[i] = out.segmentation.segment[v];
        if (segment[i] >= 0) ++out.segmentation.segments[std::size_t(segment[i])].points;
    }
    out.segmentation.cluster = std::move(cluster);
    out.segmentation.segment = std::move(segment);
    seconds.segmentation = lap(clock);
    return out;
}

// The coarse step (campaign_comparison.hpp): the campaign's planes matched to the reference's
// without a prior. With `automatic`, a failure leaves the frame as it is and says why.
CoarseFrame coarse_frame(const CampaignReference& reference, std::span<const Eigen::Vector3d> cloud,
                         const CampaignParameters& p) {
    CoarseFrame out;
    if (p.coarse == CoarseRegistration::none) return out;
    const auto planes = campaign::detect_cloud_planes(cloud, p.planes, p.threads);
    out.campaign_planes = planes.size();
    out.reference_planes = reference.planes.size();
    registration::PriorFreeMatchingParams matching = p.plane_matching;
    matching.either_sign = true;
    const auto match = registration::match_planes_without_prior(reference.planes, planes, matching);
    std::string why;
    if (!match) {
        why = "no heading and shift make " + std::to_string(matching.min_support) + " of its " +
              std::to_string(planes.size()) + " planes fall on the reference's " +
              std::to_string(reference.planes.size());
    } else if (match->runner_up >= match->support) {
        why = "ambiguous: two headings each make " + std::to_string(match->support) +
              " planes fall on the reference's";
    }
    if (why.empty()) {
        out.used = CoarseRegistration::planes;
        out.matrix.topLeftCorner<3, 3>() = match->approximate.rotation;
        out.matrix.topRightCorner<3, 1>() = match->approximate.translation;
        out.support = match->support;
        out.runner_up = match->runner_up;
        return out;
    }
    if (p.coarse == CoarseRegistration::planes)
        throw Error("campaign: no coarse registration on planes (" + why + ")");
    out.note = why + "; the files are taken as in one frame";
    return out;
}

}  // namespace

CampaignComparison compare_campaign(std::span<const Eigen::Vector3d> reference,
                                    std::span<const Eigen::Vector3d> cloud,
                                    const CampaignParameters& p) {
    validate(p);
    const CampaignReference prepared(reference, p);
    CampaignComparison out = compare_campaign(prepared, cloud, p);
    out.seconds.reference = prepared.seconds;
    return out;
}

CampaignReference::CampaignReference(std::span<const Eigen::Vector3d> points,
                                     const CampaignParameters& p)
    : surface(points, p.surface, p.threads) {
    validate(p);
    const auto start = std::chrono::steady_clock::now();
    CampaignTimings unused;
    Structure structure = segment_structure(points, p, unused);
    ground = std::move(structure.ground);
    segmentation = std::move(structure.segmentation);
    if (p.coarse != CoarseRegistration::none)
        planes = campaign::detect_cloud_planes(points, p.planes, p.threads);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

CampaignComparison compare_campaign(const CampaignReference& reference,
                                    std::span<const Eigen::Vector3d> cloud,
                                    const CampaignParameters& p) {
    validate(p);
    const campaign::ReferenceSurface& surface = reference.surface;
    const unsigned threads = p.threads;
    CampaignComparison out;
    auto clock = std::chrono::steady_clock::now();
    out.coarse = coarse_frame(reference, cloud, p);
    out.seconds.coarse = lap(clock);
    campaign::SegmentIcpParameters global = p.icp;
    global.metric = campaign::IcpMetric::point_to_plane;
    const Eigen::Matrix4d& C = out.coarse.matrix;
    out.global = campaign::register_segment(
        surface,
        subsample(
            cloud.size(), p.registration_points,
            [&](std::size_t j) { return Eigen::Vector3d((C * cloud[j].homogeneous()).head<3>()); }),
        global, threads);
    if (!out.global.registered()) {
        const std::string coarse =
            out.coarse.used == CoarseRegistration::planes
                ? "after the coarse step on " + std::to_string(out.coarse.support) + " planes"
            : out.coarse.note.empty() ? "without a coarse step: are both files in one frame?"
                                      : "without a coarse step: " + out.coarse.note;
        throw Error("campaign: the global registration failed (" +
                    std::string(campaign::outcome_name(out.global.outcome)) + ", " +
                    std::to_string(out.global.pairs) + " pairs of " +
                    std::to_string(out.global.points) + " points within max_distance) " + coarse);
    }
    out.registered = transformed(cloud, out.frame(), threads);
    out.seconds.global = lap(clock);
    Structure structure = segment_structure(out.registered, p, out.seconds);
    out.ground = std::move(structure.ground);
    out.segmentation = std::move(structure.segmentation);
    const campaign::VoxelThinning& whole = structure.whole;
    out.thinned = whole.voxels();
    clock = std::chrono::steady_clock::now();
    const std::size_t S = out.segmentation.segments.size();
    // Each segment as the reference's segment most of its points lie on (up to 2000 of them:
    // a share to ±1 %).
    const auto matches = campaign::match_segments(
        out.registered, out.segmentation.segment, S,
        [&](const Eigen::Vector3d& x) { return surface.nearest(x); },
        reference.segmentation.segment, p.min_overlap, 2000, threads);
    out.seconds.matching = lap(clock);

    std::vector<std::vector<std::size_t>> members(S);
    for (std::size_t i = 0; i < cloud.size(); ++i)
        if (out.segmentation.segment[i] >= 0)
            members[std::size_t(out.segmentation.segment[i])].push_back(i);
    // Each segment's share of points next to a cut, among the thinned cloud's points, from up
    // to 20 000 of its points (a share to ±0.4 %).
    std::vector<std::int32_t> thinned_label(whole.voxels());
    for (std::size_t v = 0; v < whole.voxels(); ++v)
        thinned_label[v] = out.segmentation.segment[whole.kept[v]];
    const std::vector<double> cut =
        campaign::cut_fractions(campaign::kept_points(out.registered, whole), thinned_label, S,
                                p.cut_distance, 20000, threads);
    out.segments.resize(S);
    std::vector<campaign::SegmentTransform> transforms(S);
    for (std::size_t s = 0; s < S; ++s) {
        out.segments[s].segment = out.segmentation.segments[s];
        out.segments[s].reference = matches[s];
        if (members[s].size() < std::size_t(p.min_segment_points)) continue;
        transforms[s] = campaign::register_segment(
            surface,
            subsample(members[s].size(), p.registration_points,
                      [&](std::size_t j) { return out.registered[members[s][j]]; }),
            p.icp, threads);
        if (transforms[s].registered() &&
            double(transforms[s].planar_pairs) < p.min_planar_share * double(transforms[s].points))
            transforms[s].outcome = campaign::SegmentOutcome::unobserved;
        if (!transforms[s].registered()) {
            out.segments[s].transform = transforms[s];
            continue;
        }
        out.segments[s].cut_fraction = std::isfinite(cut[s]) ? cut[s] : 0.0;
        out.segments[s].cut_bias = campaign::cut_bias_bound(
            out.segments[s].cut_fraction, p.cut_distance, p.range_sigma, transforms[s].sigma0);
        transforms[s].add_translation_variance(out.segments[s].cut_bias * out.segments[s].cut_bias);
        out.segments[s].transform = transforms[s];
        const Eigen::Matrix4d M = transforms[s].matrix();
        for (const auto i : members[s])
            out.registered[i] = (M * out.registered[i].homogeneous()).head<3>();
    }
    out.consistency = campaign::test_segment_consistency(transforms, p.alpha);
    out.seconds.segments = lap(clock);

    out.c2c = campaign::c2c_vectors(surface, out.registered, p.c2c, threads);
    out.c2c_all = campaign::summarise(out.c2c);
    for (std::size_t s = 0; s < S; ++s) {
        std::vector<Eigen::Vector3f> v;
        v.reserve(members[s].size());
        for (const auto i : members[s]) v.push_back(out.c2c[i]);
        out.segments[s].c2c = campaign::summarise(v);
    }
    out.seconds.c2c = lap(clock);
    return out;
}

}  // namespace tlsmon
