#include "pipeline/vector_stage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "algorithms/patches/patch_index.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "algorithms/vectors/between_area_variance.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/stored_area_vectors.hpp"
#include "pipeline/zone_patches.hpp"

namespace tlsmon {

namespace {

constexpr double kCell = 0.05;   // m, the windows' footprint cells
constexpr double kReach = 0.05;  // m, the epoch's window beyond the search radius: the kernel's
constexpr double kLod95 = 1.96;  // two-sided 95 %

unsigned threads_of(const VectorConfig& c) {
    return static_cast<unsigned>(std::max(0, c.threads));
}

// The square of side `side` about the frame's origin, as a footprint.
patches::Patch window(const patches::PatchFrame& frame, double side) {
    patches::Patch p;
    p.frame = frame;
    auto& f = p.footprint;
    f.cell = kCell;
    const int half = int(std::ceil(0.5 * side / kCell));
    f.u0 = f.v0 = -half;
    f.width = f.height = 2 * half;
    f.occupied.assign(std::size_t(f.width * f.height), 1);
    return p;
}

// Every scan's points on the areas' windows after q = A·p + t, as samples.
std::vector<std::vector<vectors::AreaSample>> samples_of(const patches::PatchIndex& index,
                                                         const std::vector<Scan>& scans,
                                                         const Eigen::Matrix3d& A,
                                                         const Eigen::Vector3d& t, double half_side,
                                                         unsigned threads) {
    std::vector<std::vector<vectors::AreaSample>> out(index.patches().size());
    for (const auto& scan : scans) {
        const bool has_intensity = scan.intensity.size() == scan.xyz.size();
        // Windows of neighbouring patches overlap: a point counts in each.
        const auto hits = patches::patch_hits(index, scan.xyz, A, t, threads, true);
        for (std::size_t k = 0; k < hits.size(); ++k)
            for (const auto& h : hits[k]) {
                if (std::abs(h.uvw.x()) > half_side || std::abs(h.uvw.y()) > half_side) continue;
                out[k].push_back({h.uvw.x(), h.uvw.y(), h.uvw.z(),
                                  has_intensity ? scan.intensity[h.point] : 0.0f});
            }
    }
    return out;
}

// The frame's axes as the columns of R: area (u, v, n) to project.
Eigen::Matrix3d axes(const patches::PatchFrame& f) {
    Eigen::Matrix3d R;
    R.col(0) = f.u, R.col(1) = f.v, R.col(2) = f.normal;
    return R;
}

// Σ_T at a project-frame point (registration_error.hpp, at its place in the epoch's frame).
Eigen::Matrix3d registration_covariance(const StageOutputs& outputs, const Eigen::Vector3d& q) {
    if (!outputs.to_reference) return Eigen::Matrix3d::Zero();
    const auto& T = *outputs.to_reference;
    const Eigen::Vector3d x = T.rotation.transpose() * (q - T.translation) / T.scale;
    return registration::registration_covariance_at(T, x);
}

Eigen::Vector3d design_normal(const VectorConfig& config, std::size_t zone) {
    return zone < config.zones.size() ? config.zones[zone].normal
                                      : Eigen::Vector3d::Constant(std::nan(""));
}

// τ of the zone's measured areas along its normal, h and v: their vectors about the zone's
// smooth field against their fits' σ (between_area_variance.hpp).
Eigen::Vector3d between_sigma(const VectorReference& reference, std::size_t zone,
                              const ZoneWall& wall, const std::vector<AreaDisplacement>& areas) {
    std::vector<std::size_t> measured;
    for (const auto k : reference.zone_areas[zone])
        if (areas[k].fit.measured()) measured.push_back(k);
    const auto n = Eigen::Index(measured.size());
    const Eigen::Matrix3d W = wall.rows();
    Eigen::MatrixX2d positions(n, 2);
    Eigen::MatrixX3d values(n, 3), variances(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
        const AreaDisplacement& a = areas[measured[std::size_t(i)]];
        const Eigen::Vector3d& c = reference.frames[measured[std::size_t(i)]].origin;
        positions.row(i) << wall.horizontal.dot(c), wall.vertical.dot(c);
        values.row(i) = (W * a.displacement).transpose();
        variances.row(i) = (W * a.fit_covariance * W.transpose()).diagonal().transpose();
    }
    const Eigen::MatrixXd field = vectors::zone_field(positions);
    Eigen::Vector3d sigma;
    for (int c = 0; c < 3; ++c)
        sigma(c) =
            std::sqrt(vectors::between_area_variance(field, values.col(c), variances.col(c)).tau2);
    return sigma;
}

Eigen::Vector3d zone_centroid(const VectorReference& reference, std::size_t zone) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto k : reference.zone_areas[zone]) c += reference.frames[k].origin;
    return reference.zone_areas[zone].empty() ? c : c / double(reference.zone_areas[zone].size());
}

}  // namespace

std::string vector_reference_parameters(const VectorConfig& c) {
    return supervoxel_parameters(c.segmentation) +
           fmt::format(";window={:.17g};search_depth={:.17g};max_incidence_deg={:.17g}", c.window,
                       c.search_depth, c.max_incidence_deg) +
           zone_parameters(c.zones);
}

VectorReference prepare_vector_reference(const VectorConfig& config,
                                         const ReferenceSupervoxels& supervoxels,
                                         const std::vector<Scan>& scans) {
    validate(config);
    if (scans.empty()) throw Error("vectors: the reference epoch holds no scan");
    VectorReference out;
    out.scanner = scans.front().scanner_position();
    ZonePatches selected =
        zone_patches(config.segmentation, supervoxels, config.zones, config.max_incidence_deg);
    std::vector<patches::Patch> windows;
    for (const auto& p : selected.patches) {
        out.frames.push_back(p.frame);
        windows.push_back(window(p.frame, config.window));
    }
    out.supervoxel = std::move(selected.supervoxel);
    out.zone_names = std::move(selected.zone_names);
    out.zone_areas = std::move(selected.zone_patches);
    const patches::PatchIndex index(std::move(windows), config.search_depth);
    const auto samples =
        samples_of(index, scans, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(),
                   0.5 * config.window, threads_of(config));
    for (const auto& area : samples) {
        out.samples.insert(out.samples.end(), area.begin(), area.end());
        out.offsets.push_back(out.samples.size());
    }
    return out;
}

VectorEpoch measure_vectors(const VectorConfig& config, const VectorReference& reference,
                            const std::vector<Scan>& scans, const StageOutputs& outputs) {
    validate(config);
    const std::size_t n = reference.areas();
    const EpochToReference map = epoch_to_reference(outputs, reference.scanner);
    // The epoch's window reaches beyond the reference's by the search radius and the kernel.
    const double half = 0.5 * config.window + config.search_radius + kReach;
    std::vector<patches::Patch> windows;
    for (const auto& f : reference.frames) windows.push_back(window(f, 2.0 * half));
    const patches::PatchIndex index(std::move(windows), config.search_depth);
    const auto samples = samples_of(index, scans, map.factor * map.rotation, map.translation, half,
                                    threads_of(config));
    VectorEpoch out;
    out.areas.resize(n);
    parallel_for(
        n,
        [&](std::size_t k) {
            AreaDisplacement& a = out.areas[k];
            a.fit = vectors::register_area(reference.area_samples(k), samples[k], config);
            if (!a.fit.measured()) return;
            const Eigen::Matrix3d R = axes(reference.frames[k]);
            a.displacement = R * a.fit.displacement;
            a.fit_covariance = R * a.fit.covariance * R.transpose();
            a.registration_covariance =
                registration_covariance(outputs, reference.frames[k].origin);
        },
        threads_of(config));
    for (std::size_t z = 0; z < reference.zone_names.size(); ++z) {
        out.zone_registration_covariance.push_back(
            registration_covariance(outputs, zone_centroid(reference, z)));
        const ZoneWall wall = zone_wall(reference, z, design_normal(config, z));
        const Eigen::Vector3d tau = between_sigma(reference, z, wall, out.areas);
        const Eigen::Matrix3d W = wall.rows();
        const Eigen::Matrix3d T = W.transpose() * tau.cwiseAbs2().asDiagonal() * W;
        out.zone_between_sigma.push_back(tau);
        out.zone_between_covariance.push_back(T);
        // An area in several zones (a face and its bands) takes the largest.
        for (const auto k : reference.zone_areas[z])
            if (T.trace() > out.areas[k].between_covariance.trace())
                out.areas[k].between_covariance = T;
    }
    return out;
}

ZoneWall zone_wall(const VectorReference& reference, std::size_t zone,
                   const Eigen::Vector3d& design_normal) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    if (design_normal.allFinite()) {
        n = design_normal.normalized();
    } else {
        for (const auto k : reference.zone_areas[zone]) n += reference.frames[k].normal;
        n.normalize();
    }
    if (n.dot(reference.scanner - zone_centroid(reference, zone)) < 0) n = -n;
    // As the keypoints' wall frame (algorithms/keypoints/segment_displacement.hpp): h = up × n,
    // the projected x axis on a horizontal surface.
    Eigen::Vector3d h = Eigen::Vector3d::UnitZ().cross(n);
    if (h.norm() < std::sin(M_PI / 180.0))
        h = Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(n) * n;
    h.normalize();
    return {n, h, n.cross(h)};
}

std::vector<ZoneResult> vector_zone_results(const VectorConfig& config,
                                            const VectorReference& reference,
                                            const VectorEpoch& epoch) {
    std::vector<ZoneResult> rows;
    for (std::size_t z = 0; z < reference.zone_names.size(); ++z) {
        const std::string& zone = reference.zone_names[z];
        const auto& members = reference.zone_areas[z];
        // The plain mean: each area is an equal piece of the zone's surface (an inverse-
        // covariance weighting would lean towards the best-textured areas, and on a face that
        // bends, towards their part of it). The areas' errors — their fits' and the part only
        // their scatter shows, T — are independent; the registration's error is common to
        // them and enters once.
        Eigen::Matrix3d fit_sum = Eigen::Matrix3d::Zero();
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        std::int64_t valid = 0;
        for (const auto k : members) {
            const auto& a = epoch.areas[k];
            if (!a.fit.measured()) continue;
            fit_sum += a.fit_covariance + epoch.zone_between_covariance[z];
            sum += a.displacement;
            ++valid;
        }
        rows.push_back({zone, "vector_count", double(valid), std::nullopt,
                        static_cast<std::int64_t>(members.size()), false});
        if (valid == 0) continue;
        const double n = double(valid);
        const Eigen::Vector3d d = sum / n;
        const Eigen::Matrix3d S = fit_sum / (n * n) + epoch.zone_registration_covariance[z];
        const ZoneWall wall = zone_wall(reference, z, design_normal(config, z));
        const auto row = [&](const char* quantity, const Eigen::Vector3d& e) {
            const double value = e.dot(d), lod = kLod95 * std::sqrt(e.dot(S * e));
            rows.push_back({zone, quantity, value, lod, valid, std::abs(value) > lod});
        };
        row("vector_dx_m", Eigen::Vector3d::UnitX());
        row("vector_dy_m", Eigen::Vector3d::UnitY());
        row("vector_dz_m", Eigen::Vector3d::UnitZ());
        row("vector_along_normal_m", wall.normal);
        row("vector_along_surface_h_m", wall.horizontal);
        row("vector_along_surface_v_m", wall.vertical);
    }
    return rows;
}

std::vector<CorePointArray> vector_area_arrays(const VectorReference& reference,
                                               const VectorEpoch& epoch) {
    const std::size_t n = reference.areas();
    std::vector<CorePointArray> out;
    for (const char* name : kAreaVectorArrays) out.push_back({name, std::vector<float>(n)});
    for (std::size_t k = 0; k < n; ++k) {
        const auto& a = epoch.areas[k];
        const Eigen::Vector3d sigma = a.covariance().diagonal().cwiseSqrt();
        for (int c = 0; c < 3; ++c) {
            out[std::size_t(c)].values[k] = float(reference.frames[k].origin(c));
            out[std::size_t(3 + c)].values[k] = float(a.displacement(c));
            out[std::size_t(6 + c)].values[k] =
                a.fit.measured() ? float(sigma(c)) : std::numeric_limits<float>::quiet_NaN();
        }
    }
    return out;
}

std::shared_ptr<const VectorReference> VectorStage::reference(ReferenceEpoch& reference,
                                                              ReferenceCache& cache) const {
    const auto supervoxels = cached_supervoxels(config_.segmentation, reference, cache);
    return cache.get<VectorReference>(
        reference,
        ProductKey{VectorReference::kStage, vector_reference_parameters(config_),
                   VectorReference::kFormatVersion},
        [&](const std::vector<Scan>& scans) {
            return prepare_vector_reference(config_, *supervoxels, scans);
        });
}

StageVerdict VectorStage::run(StageContext& ctx) const {
    const auto product = reference(ctx.reference, ctx.cache);
    const VectorEpoch epoch = measure_vectors(config_, *product, *ctx.input.scans, ctx.outputs);
    auto rows = vector_zone_results(config_, *product, epoch);
    auto arrays = vector_area_arrays(*product, epoch);
    std::size_t measured = 0, sparse = 0, coarse = 0;
    for (const auto& a : epoch.areas) {
        measured += a.fit.measured();
        sparse += a.fit.outcome == vectors::AreaOutcome::few_points;
        coarse += a.fit.outcome == vectors::AreaOutcome::undersampled ||
                  a.fit.outcome == vectors::AreaOutcome::mixed_sampling;
    }
    auto& results = ctx.results;
    results.zone_results.insert(results.zone_results.end(), std::make_move_iterator(rows.begin()),
                                std::make_move_iterator(rows.end()));
    results.core_point_arrays.insert(results.core_point_arrays.end(),
                                     std::make_move_iterator(arrays.begin()),
                                     std::make_move_iterator(arrays.end()));
    double tau = 0;  // the largest between-area σ along the surface
    for (const auto& t : epoch.zone_between_sigma) tau = std::max({tau, t(1), t(2)});
    return StageVerdict{
        "", fmt::format("{} of {} areas with a vector ({} with too few points, {} sampled too "
                        "coarsely or unevenly); between-area σ along the surface up to {:.2f} mm",
                        measured, epoch.areas.size(), sparse, coarse, 1e3 * tau)};
}

}  // namespace tlsmon
