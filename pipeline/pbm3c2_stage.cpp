#include "pipeline/pbm3c2_stage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "algorithms/depth_discontinuity.hpp"
#include "algorithms/m3c2/zone_uncertainty.hpp"
#include "algorithms/patches/zone_median.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "core/statistics.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/zone_patches.hpp"

namespace tlsmon {

namespace {

unsigned threads_of(const PbM3c2Config& c) {
    return static_cast<unsigned>(std::max(0, c.threads));
}

// The moments of the points that belong to each patch's plane (plane_inliers), per block of
// side `block_side(k, inliers)` (like_with_like.hpp), of every scan's points mapped by
// q = A·p + t, but for the points at a depth discontinuity of their scan
// (algorithms/depth_discontinuity.hpp): at a face's edge the beams that straddle it return
// blends a little behind the face, fewer or more of them as the grid's phase on the edge
// moves between epochs.
template <class BlockSide>
std::vector<std::vector<patches::BlockMoments>> moments_of(
    const patches::PatchIndex& index, const std::vector<Scan>& scans, const Eigen::Matrix3d& A,
    const Eigen::Vector3d& t, unsigned threads, const BlockSide& block_side) {
    std::vector<std::vector<Eigen::Vector3f>> on_patch(index.patches().size());
    for (const auto& scan : scans) {
        const auto edges = depth_discontinuities(scan, kMixedPixelJump, threads);
        auto more = patches::patch_points(index, scan.xyz, A, t, threads, edges);
        for (std::size_t k = 0; k < on_patch.size(); ++k)
            on_patch[k].insert(on_patch[k].end(), more[k].begin(), more[k].end());
    }
    std::vector<std::vector<patches::BlockMoments>> out(on_patch.size());
    parallel_for(
        out.size(),
        [&](std::size_t k) {
            const auto keep = patches::plane_inliers(on_patch[k]);
            const auto inliers = std::size_t(std::count(keep.begin(), keep.end(), 1));
            out[k] = patches::block_moments(on_patch[k], keep, block_side(k, inliers));
        },
        threads);
    return out;
}

}  // namespace

std::string pbm3c2_reference_parameters(const PbM3c2Config& c) {
    return supervoxel_parameters(c.segmentation) +
           fmt::format(";search_depth={:.17g};max_incidence_deg={:.17g}", c.search_depth,
                       c.max_incidence_deg) +
           zone_parameters(c.zones);
}

PbM3c2Reference prepare_pbm3c2_reference(const PbM3c2Config& config,
                                         const ReferenceSupervoxels& supervoxels,
                                         const std::vector<Scan>& scans) {
    if (scans.empty()) throw Error("pbm3c2: the reference epoch holds no scan");
    PbM3c2Reference out;
    out.scanner = scans.front().scanner_position();
    ZonePatches selected =
        zone_patches(config.segmentation, supervoxels, config.zones, config.max_incidence_deg);
    out.patches = std::move(selected.patches);
    out.supervoxel = std::move(selected.supervoxel);
    out.zone_names = std::move(selected.zone_names);
    out.zone_patches = std::move(selected.zone_patches);
    const patches::PatchIndex index(out.patches, config.search_depth);
    out.block_side.assign(out.patches.size(), patches::kBlock);
    out.blocks = moments_of(index, scans, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(),
                            threads_of(config), [&](std::size_t k, std::size_t inliers) {
                                const auto& f = out.patches[k].footprint;
                                return out.block_side[k] = patches::block_side(
                                           double(f.cells()) * f.cell * f.cell, inliers);
                            });
    for (const auto& b : out.blocks) out.moments.push_back(patches::total(b));
    return out;
}

PbM3c2Epoch measure_pbm3c2(const PbM3c2Config& config, const PbM3c2Reference& reference,
                           const std::vector<Scan>& scans, const StageOutputs& outputs) {
    patches::validate(config);
    const std::size_t n = reference.patches.size();
    const EpochToReference map = epoch_to_reference(outputs, reference.scanner);
    const patches::PatchIndex index(reference.patches, config.search_depth);
    PbM3c2Epoch out;
    const auto blocks =
        moments_of(index, scans, map.factor * map.rotation, map.translation, threads_of(config),
                   [&](std::size_t k, std::size_t) { return reference.block_side[k]; });
    for (const auto& b : blocks) out.moments.push_back(patches::total(b));
    out.registration_sigma.assign(n, 0.0);
    out.results.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const auto& frame = reference.patches[k].frame;
        if (outputs.to_reference) {
            // Σ_p at the patch's place in the epoch's frame (where T is applied).
            const auto& T = *outputs.to_reference;
            const Eigen::Vector3d x =
                T.rotation.transpose() * (frame.origin - T.translation) / T.scale;
            out.registration_sigma[k] = registration::registration_sigma_along(T, x, frame.normal);
        }
        out.results[k] = patches::compared_distance(reference.blocks[k], blocks[k],
                                                    out.registration_sigma[k], config);
    }
    return out;
}

std::vector<ZoneResult> pbm3c2_zone_results(const PbM3c2Reference& reference,
                                            const PbM3c2Epoch& epoch) {
    std::vector<ZoneResult> rows;
    for (std::size_t z = 0; z < reference.zone_names.size(); ++z) {
        const std::string& zone = reference.zone_names[z];
        std::vector<double> d, lod, sampling, registration;
        std::vector<patches::PatchChange> changes;
        std::int64_t significant = 0;
        for (const auto k : reference.zone_patches[z]) {
            const auto& r = epoch.results[k];
            if (r.outcome != patches::PatchOutcome::measured) continue;
            d.push_back(r.distance.distance);
            lod.push_back(r.distance.lod);
            sampling.push_back(r.distance.sampling_sigma);
            registration.push_back(epoch.registration_sigma[k]);
            significant += r.distance.significant;
            changes.push_back({reference.measured_at(k, &r), r.distance.distance,
                               r.distance.sampling_sigma,
                               patches::cell_centres(reference.patches[k])});
        }
        const auto valid = static_cast<std::int64_t>(d.size());
        const auto all = static_cast<std::int64_t>(reference.zone_patches[z].size());
        rows.push_back({zone, "pbm3c2_valid_count", double(valid), std::nullopt, all, false});
        if (valid == 0) continue;
        double mean = 0;
        for (double v : d) mean += v;
        mean /= double(valid);
        const double mad_d = median_and_mad(d).mad;
        // The median over the zone's area with its own sampling variance; the mean over the
        // patches with aggregate_uncertainty's σ; the registration's σ at the zone for both.
        const patches::ArealMedian areal = patches::areal_median(changes);
        const double median_d = areal.value;
        const m3c2::ZoneUncertainty u = m3c2::aggregate_uncertainty(d, sampling, registration, 1.0);
        const double lod_of_median =
            1.96 * std::sqrt(areal.sampling_variance + u.registration * u.registration);
        const double lod_of_mean = 1.96 * u.mean_sigma;
        rows.push_back({zone, "pbm3c2_median_m", median_d, lod_of_median, valid,
                        std::abs(median_d) > lod_of_median});
        rows.push_back(
            {zone, "pbm3c2_mean_m", mean, lod_of_mean, valid, std::abs(mean) > lod_of_mean});
        rows.push_back({zone, "pbm3c2_spread_m", kMadToSigma * mad_d, std::nullopt, valid, false});
        rows.push_back({zone, "pbm3c2_lod95_median_m", median(lod), std::nullopt, valid, false});
        rows.push_back({zone, "pbm3c2_significant_share", double(significant) / double(valid),
                        std::nullopt, valid, false});
    }
    return rows;
}

std::vector<CorePointArray> pbm3c2_patch_arrays(const PbM3c2Reference& reference,
                                                const PbM3c2Epoch& epoch) {
    const std::size_t n = epoch.results.size();
    std::vector<CorePointArray> arrays;
    for (const char* name : kPbM3c2PatchArrays) arrays.push_back({name, std::vector<float>(n)});
    for (std::size_t k = 0; k < n; ++k) {
        const auto& r = epoch.results[k];
        // A patch compared whole was measured at the whole plane's place: no shift.
        const Eigen::Vector3d shift = r.partial
                                          ? Eigen::Vector3d(reference.measured_in_frame(k, &r) -
                                                            reference.measured_in_frame(k))
                                          : Eigen::Vector3d::Zero();
        const double values[] = {r.distance.distance,
                                 r.distance.lod,
                                 double(r.reference.count),
                                 double(r.epoch.count),
                                 shift.x(),
                                 shift.y(),
                                 shift.z()};
        for (std::size_t a = 0; a < arrays.size(); ++a)
            arrays[a].values[k] = static_cast<float>(values[a]);
    }
    // The shifts only where a patch has one.
    const auto zero = [](const CorePointArray& a) {
        return std::all_of(a.values.begin(), a.values.end(), [](float x) { return x == 0.0f; });
    };
    if (std::all_of(arrays.begin() + kPbM3c2FirstShift, arrays.end(), zero))
        arrays.resize(kPbM3c2FirstShift);
    return arrays;
}

std::shared_ptr<const PbM3c2Reference> PbM3c2Stage::reference(ReferenceEpoch& reference,
                                                              ReferenceCache& cache) const {
    const auto supervoxels = cached_supervoxels(config_.segmentation, reference, cache);
    return cache.get<PbM3c2Reference>(
        reference,
        ProductKey{PbM3c2Reference::kStage, pbm3c2_reference_parameters(config_),
                   PbM3c2Reference::kFormatVersion},
        [&](const std::vector<Scan>& scans) {
            return prepare_pbm3c2_reference(config_, *supervoxels, scans);
        });
}

StageVerdict PbM3c2Stage::run(StageContext& ctx) const {
    const auto product = reference(ctx.reference, ctx.cache);
    const PbM3c2Epoch epoch = measure_pbm3c2(config_, *product, *ctx.input.scans, ctx.outputs);
    auto rows = pbm3c2_zone_results(*product, epoch);
    auto arrays = pbm3c2_patch_arrays(*product, epoch);
    std::size_t measured = 0, rough = 0, sparse = 0, partly = 0;
    for (const auto& r : epoch.results) {
        measured += r.outcome == patches::PatchOutcome::measured;
        rough += r.outcome == patches::PatchOutcome::rough;
        sparse += r.outcome == patches::PatchOutcome::few_epoch_points;
        partly += r.outcome == patches::PatchOutcome::partly_seen;
    }
    auto& results = ctx.results;
    results.zone_results.insert(results.zone_results.end(), std::make_move_iterator(rows.begin()),
                                std::make_move_iterator(rows.end()));
    results.core_point_arrays.insert(results.core_point_arrays.end(),
                                     std::make_move_iterator(arrays.begin()),
                                     std::make_move_iterator(arrays.end()));
    return StageVerdict{
        "", fmt::format("{} of {} patches with a distance ({} not planar, {} with too few points, "
                        "{} seen too little alike)",
                        measured, epoch.results.size(), rough, sparse, partly)};
}

}  // namespace tlsmon
