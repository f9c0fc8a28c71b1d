#include "pipeline/campaign_comparison.hpp"

#include <Eigen/Geometry>
#include <string>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon {

void validate(const CampaignParameters& p) {
    campaign::validate(p.surface);
    campaign::validate(p.ground);
    campaign::validate(p.verticality);
    campaign::validate(p.segmentation);
    campaign::validate(p.icp);
    if (p.min_segment_points < p.icp.min_pairs)
        throw Error("campaign: min_segment_points must be at least the ICP's min_pairs");
    if (!(p.alpha > 0 && p.alpha < 0.5)) throw Error("campaign: alpha must lie in (0, 0.5)");
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

}  // namespace

CampaignComparison compare_campaign(std::span<const Eigen::Vector3d> reference,
                                    std::span<const Eigen::Vector3d> cloud,
                                    const CampaignParameters& p) {
    validate(p);
    return compare_campaign(campaign::ReferenceSurface(reference, p.surface, p.threads), cloud, p);
}

CampaignComparison compare_campaign(const campaign::ReferenceSurface& surface,
                                    std::span<const Eigen::Vector3d> cloud,
                                    const CampaignParameters& p) {
    validate(p);
    const unsigned threads = p.threads;
    CampaignComparison out;
    campaign::SegmentIcpParameters global = p.icp;
    global.metric = campaign::IcpMetric::point_to_plane;
    out.global = campaign::register_segment(surface, cloud, global, threads);
    if (!out.global.registered()) {
        throw Error("campaign: the global registration failed (" +
                    std::string(campaign::outcome_name(out.global.outcome)) + ", " +
                    std::to_string(out.global.pairs) + " pairs of " +
                    std::to_string(out.global.points) +
                    " points within max_distance): are both files in one frame?");
    }
    out.registered = transformed(cloud, out.global.matrix(), threads);

    // Verticality and segments of what is not ground (the ground's own points still hold
    // the structure's verticality at its foot, so it is computed on the whole cloud).
    std::vector<std::size_t> kept;  // campaign index of each segmented point
    if (p.remove_ground) out.ground = campaign::classify_ground(out.registered, p.ground, threads);
    for (std::size_t i = 0; i < out.registered.size(); ++i)
        if (out.ground.ground.empty() || !out.ground.ground[i]) kept.push_back(i);
    const std::vector<float> verticality =
        campaign::verticality(out.registered, p.verticality, threads);
    std::vector<Eigen::Vector3d> structure;
    std::vector<campaign::VerticalityClass> classes;
    structure.reserve(kept.size());
    classes.reserve(kept.size());
    for (const auto i : kept) {
        structure.push_back(out.registered[i]);
        classes.push_back(campaign::classify(verticality[i], p.verticality));
    }
    out.segmentation = campaign::segment_cloud(structure, classes, p.segmentation, threads);
    std::vector<std::int32_t> cluster(out.registered.size(), -1), segment(cluster);
    for (std::size_t k = 0; k < kept.size(); ++k) {
        cluster[kept[k]] = out.segmentation.cluster[k];
        segment[kept[k]] = out.segmentation.segment[k];
    }
    out.segmentation.cluster = std::move(cluster);
    out.segmentation.segment = std::move(segment);

    const std::size_t S = out.segmentation.segments.size();
    std::vector<std::vector<std::size_t>> members(S);
    for (std::size_t i = 0; i < out.registered.size(); ++i)
        if (out.segmentation.segment[i] >= 0)
            members[std::size_t(out.segmentation.segment[i])].push_back(i);
    out.segments.resize(S);
    std::vector<campaign::SegmentTransform> transforms(S);
    for (std::size_t s = 0; s < S; ++s) {
        out.segments[s].segment = out.segmentation.segments[s];
        if (members[s].size() < std::size_t(p.min_segment_points)) continue;
        std::vector<Eigen::Vector3d> points;
        points.reserve(members[s].size());
        for (const auto i : members[s]) points.push_back(out.registered[i]);
        transforms[s] = campaign::register_segment(surface, points, p.icp, threads);
        out.segments[s].transform = transforms[s];
        if (!transforms[s].registered()) continue;
        const Eigen::Matrix4d M = transforms[s].matrix();
        for (const auto i : members[s])
            out.registered[i] = (M * out.registered[i].homogeneous()).head<3>();
    }
    out.consistency = campaign::test_segment_consistency(transforms, p.alpha);

    out.c2c = campaign::c2c_vectors(surface, out.registered, p.c2c, threads);
    out.c2c_all = campaign::summarise(out.c2c);
    for (std::size_t s = 0; s < S; ++s) {
        std::vector<Eigen::Vector3f> v;
        v.reserve(members[s].size());
        for (const auto i : members[s]) v.push_back(out.c2c[i]);
        out.segments[s].c2c = campaign::summarise(v);
    }
    return out;
}

}  // namespace tlsmon
