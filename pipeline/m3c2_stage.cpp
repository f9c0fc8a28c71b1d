#include "pipeline/m3c2_stage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/depth_discontinuity.hpp"
#include "algorithms/m3c2/core_points.hpp"
#include "algorithms/m3c2/zone_uncertainty.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "core/statistics.hpp"

namespace tlsmon {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

unsigned threads_of(const M3c2Config& c) {
    return static_cast<unsigned>(std::max(0, c.threads));
}

// Not their neighbours: a cylinder averages hundreds of points, and the beam one step from an
// edge blends little of it in (1.1 mm at 0.013°); on a coarse grid the neighbours of a grazing
// face's edges are the face itself (docs/m3c2.md).
std::vector<std::uint8_t> edge_points(const Scan& scan, unsigned threads) {
    return depth_discontinuities(scan, kMixedPixelJump, threads, /*with_neighbours=*/false);
}

}  // namespace

M3c2Cloud m3c2_cloud(const std::vector<Scan>& scans, unsigned threads) {
    M3c2Cloud c;
    if (scans.size() == 1) {
        c.scan_points = &scans.front().xyz;
        c.left_out = edge_points(scans.front(), threads);
        return c;
    }
    std::size_t n = 0;
    for (const auto& s : scans) n += s.size();
    c.joined.reserve(n);
    for (const auto& s : scans) {
        const auto edges = edge_points(s, threads);
        for (std::size_t i = 0; i < s.xyz.size(); ++i)
            if (edges.empty() || !edges[i]) c.joined.push_back(s.xyz[i]);
    }
    return c;
}

std::size_t M3c2Cloud::kept() const {
    return points().size() -
           static_cast<std::size_t>(std::count(left_out.begin(), left_out.end(), std::uint8_t{1}));
}

std::vector<Eigen::Vector3d> M3c2Cloud::kept_points() const {
    const auto& all = points();
    if (left_out.empty()) return all;
    std::vector<Eigen::Vector3d> out;
    out.reserve(all.size());
    for (std::size_t i = 0; i < all.size(); ++i)
        if (!is_left_out(i)) out.push_back(all[i]);
    return out;
}

std::string zone_parameters(const std::vector<ZoneShape>& zones) {
    std::string s;
    for (const auto& z : zones) {
        s += fmt::format(";zone={}:{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", z.name,
                         z.box.min().x(), z.box.min().y(), z.box.min().z(), z.box.max().x(),
                         z.box.max().y(), z.box.max().z());
        for (const auto& v : z.polygon) s += fmt::format(":{:.17g},{:.17g}", v.x(), v.y());
        if (z.normal.allFinite()) {
            s += fmt::format(":normal={:.17g},{:.17g},{:.17g}", z.normal.x(), z.normal.y(),
                             z.normal.z());
        }
    }
    return s;
}

std::string m3c2_reference_parameters(const M3c2Config& c) {
    std::string s = fmt::format("core_spacing={:.17g};radii=", c.core_spacing);
    for (double r : c.normal_radii) s += fmt::format("{:.17g},", r);
    s += fmt::format(
        ";cylinder_radius={:.17g};max_depth={:.17g};statistic={};stray_distance={:.17g};"
        "orientation=",
        c.cylinder_radius, c.max_depth,
        c.statistic == m3c2::CylinderStatistic::median ? "median" : "mean", c.stray_distance);
    if (c.orient_to_scanner) {
        s += "scanner";
    } else {
        s += fmt::format("{:.17g},{:.17g},{:.17g}", c.orientation.x(), c.orientation.y(),
                         c.orientation.z());
    }
    return s + zone_parameters(c.zones);
}

M3c2Reference prepare_m3c2_reference(const M3c2Config& config, const std::vector<Scan>& scans) {
    if (scans.empty()) throw Error("m3c2: the reference epoch holds no scan");
    M3c2Reference out;
    out.scanner = scans.front().scanner_position();
    const M3c2Cloud cloud = m3c2_cloud(scans, threads_of(config));
    const auto& points = cloud.points();
    // Core points from the reference's points inside a zone, on one lattice of cubes: a core
    // point in two overlapping zones (a band and its face) is one core point of both.
    std::vector<char> inside(points.size(), 0);
    parallel_for(
        points.size(),
        [&](std::size_t i) {
            const auto& p = points[i];
            if (!p.allFinite() || cloud.is_left_out(i)) return;
            for (const auto& z : config.zones) {
                if (z.contains(p)) {
                    inside[i] = 1;
                    return;
                }
            }
        },
        threads_of(config));
    std::vector<Eigen::Vector3d> in_zones;
    in_zones.reserve(static_cast<std::size_t>(std::count(inside.begin(), inside.end(), 1)));
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (inside[i]) in_zones.push_back(points[i]);
    }
    inside = {};
    std::vector<Eigen::Vector3d> cores =
        m3c2::subsample(in_zones, config.core_spacing, threads_of(config));
    in_zones = {};
    // A core point takes the design normal of the first zone (in the configuration's order)
    // that holds it and has one; zones with different normals do not overlap
    // (config/config.cpp), so only a point on two boundaries has a choice.
    std::vector<Eigen::Vector3d> given(cores.size(), Eigen::Vector3d::Constant(kNaN));
    for (const auto& z : config.zones) {
        out.zone_names.push_back(z.name);
        auto& members = out.zone_cores.emplace_back();
        for (std::size_t k = 0; k < cores.size(); ++k) {
            if (!z.contains(cores[k])) continue;
            members.push_back(static_cast<std::uint32_t>(k));
            if (!given[k].allFinite()) given[k] = z.normal;
        }
    }
    out.reference = m3c2::prepare_reference(
        points, std::move(cores), m3c2::normal_parameters(config, out.scanner),
        m3c2::cylinder_parameters(config), threads_of(config), given, cloud.left_out);
    return out;
}

bool EpochToReference::identity() const {
    return factor == 1.0 && rotation == Eigen::Matrix3d::Identity() &&
           translation == Eigen::Vector3d::Zero();
}

EpochToReference epoch_to_reference(const StageOutputs& o, const Eigen::Vector3d& s_r) {
    // x = s_e + (p − s_e)/k_e;  y = s_T·R·x + t;  q = s_r + k_r·(y − s_r).
    const double k_e = o.range_scale, k_r = o.reference_range_scale;
    if (!(k_e > 0.0 && k_r > 0.0)) throw Error("m3c2: a range scale is not positive");
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    double s_T = 1.0;
    if (o.to_reference) {
        R = o.to_reference->rotation;
        t = o.to_reference->translation;
        s_T = o.to_reference->scale;
    }
    EpochToReference m;
    m.factor = k_r * s_T / k_e;
    m.rotation = R;
    if (k_e == 1.0 && k_r == 1.0) {
        m.translation = t;  // exact: no rounding through the scales
    } else {
        m.translation = k_r * (s_T * (R * o.scanner) * (1.0 - 1.0 / k_e) + t) + s_r * (1.0 - k_r);
    }
    return m;
}

M3c2Epoch measure_m3c2(const M3c2Config& config, const M3c2Reference& product,
                       const std::vector<Scan>& scans, const StageOutputs& outputs) {
    const m3c2::Reference& ref = product.reference;
    const std::size_t n = ref.size();
    const EpochToReference map = epoch_to_reference(outputs, product.scanner);
    const M3c2Cloud cloud = m3c2_cloud(scans, threads_of(config));
    M3c2Epoch out;
    if (map.identity()) {
        out.compared =
            m3c2::cylinder_sides(ref.cylinders, cloud.points(), threads_of(config), cloud.left_out);
    } else {
        // The cylinders pulled back into the epoch's frame: centre f⁻¹·Rᵀ(c − t), axis Rᵀn,
        // radius and half-length divided by f; a projection there times f is the projection
        // of the mapped point in the reference frame.
        std::vector<Eigen::Vector3d> centres(n), axes(n);
        for (std::size_t k = 0; k < n; ++k) {
            centres[k] = map.inverse(ref.cylinders.centres[k]);
            axes[k] = map.rotation.transpose() * ref.cylinders.axes[k];
        }
        m3c2::CylinderParameters pulled = ref.cylinders.parameters;
        pulled.radius /= map.factor;
        pulled.max_depth /= map.factor;
        const m3c2::Cylinders cylinders =
            m3c2::make_cylinders(std::move(centres), std::move(axes), pulled, threads_of(config));
        out.compared =
            m3c2::cylinder_sides(cylinders, cloud.points(), threads_of(config), cloud.left_out);
        for (auto& side : out.compared) {
            side.centre *= map.factor;
            side.spread *= map.factor;
            side.roughness *= map.factor;
        }
    }
    out.registration_sigma.assign(n, config.registration_error);
    if (outputs.to_reference) {
        const auto& T = *outputs.to_reference;
        parallel_for(
            n,
            [&](std::size_t k) {
                const Eigen::Vector3d& normal = ref.cylinders.axes[k];
                if (!normal.allFinite()) return;
                // Σ_p at the core point's place in the epoch's frame (where T is applied).
                const Eigen::Vector3d x =
                    T.rotation.transpose() * (ref.cylinders.centres[k] - T.translation) / T.scale;
                out.registration_sigma[k] = registration::registration_sigma_along(T, x, normal);
            },
            threads_of(config));
    }
    out.distances.resize(n);
    m3c2::DistanceParameters dp = m3c2::distance_parameters(config);
    for (std::size_t k = 0; k < n; ++k) {
        dp.registration_error = out.registration_sigma[k];
        out.distances[k] = m3c2::distance_between(ref.reference_side[k], out.compared[k], dp);
    }
    return out;
}

std::vector<ZoneResult> m3c2_zone_results(const M3c2Config& config, const M3c2Reference& product,
                                          const M3c2Epoch& epoch) {
    std::vector<ZoneResult> rows;
    const auto& ref = product.reference;
    for (std::size_t z = 0; z < product.zone_names.size(); ++z) {
        const std::string& zone = product.zone_names[z];
        std::vector<double> d, lod, sampling, registration;
        std::int64_t significant = 0;
        for (auto k : product.zone_cores[z]) {
            const auto& r = epoch.distances[k];
            if (!std::isfinite(r.distance)) continue;
            d.push_back(r.distance);
            lod.push_back(r.lod);
            sampling.push_back(m3c2::sampling_sigma(ref.reference_side[k], epoch.compared[k]));
            registration.push_back(epoch.registration_sigma[k]);
            significant += r.significant;
        }
        const auto valid = static_cast<std::int64_t>(d.size());
        const auto cores = static_cast<std::int64_t>(product.zone_cores[z].size());
        rows.push_back({zone, "m3c2_valid_count", double(valid), std::nullopt, cores, false});
        if (valid == 0) continue;
        double mean = 0;
        for (double v : d) mean += v;
        mean /= double(valid);
        const auto [median_d, mad_d] = median_and_mad(d);
        const double lod_median = median(lod);
        const double spread = kMadToSigma * mad_d;
        // The aggregates' own LoD95 (algorithms/m3c2/zone_uncertainty.hpp), not one core
        // point's: their sampling part averages out over the zone, the registration's not.
        const m3c2::ZoneUncertainty u = m3c2::zone_uncertainty(
            d, sampling, registration, ref.cylinders.parameters.radius, config.core_spacing);
        const double lod_of_median = 1.96 * u.median_sigma, lod_of_mean = 1.96 * u.mean_sigma;
        rows.push_back({zone, "m3c2_median_m", median_d, lod_of_median, valid,
                        std::abs(median_d) > lod_of_median});
        rows.push_back(
            {zone, "m3c2_mean_m", mean, lod_of_mean, valid, std::abs(mean) > lod_of_mean});
        rows.push_back({zone, "m3c2_spread_m", spread, std::nullopt, valid, false});
        rows.push_back({zone, "m3c2_lod95_median_m", lod_median, std::nullopt, valid, false});
        rows.push_back({zone, "m3c2_significant_share", double(significant) / double(valid),
                        std::nullopt, valid, false});
    }
    return rows;
}

std::vector<CorePointArray> m3c2_core_point_arrays(const M3c2Reference& product,
                                                   const M3c2Epoch& epoch) {
    const std::size_t n = product.reference.size();
    CorePointArray distance{"m3c2_distance_m", std::vector<float>(n)};
    CorePointArray lod{"m3c2_lod95_m", std::vector<float>(n)};
    CorePointArray n1{"m3c2_n1", std::vector<float>(n)};
    CorePointArray n2{"m3c2_n2", std::vector<float>(n)};
    for (std::size_t k = 0; k < n; ++k) {
        distance.values[k] = static_cast<float>(epoch.distances[k].distance);
        lod.values[k] = static_cast<float>(epoch.distances[k].lod);
        n1.values[k] = static_cast<float>(product.reference.reference_side[k].count);
        n2.values[k] = static_cast<float>(epoch.compared[k].count);
    }
    return {std::move(distance), std::move(lod), std::move(n1), std::move(n2)};
}

std::string M3c2Stage::reference_parameters() const {
    return m3c2_reference_parameters(config_);
}

M3c2Reference M3c2Stage::prepare_reference(const std::vector<Scan>& reference_scans) const {
    return prepare_m3c2_reference(config_, reference_scans);
}

StageVerdict M3c2Stage::measure(StageContext& ctx, const M3c2Reference& reference) const {
    const M3c2Config& config = config_;
    EpochResults& results = ctx.results;
    const M3c2Epoch epoch = measure_m3c2(config, reference, *ctx.input.scans, ctx.outputs);
    auto rows = m3c2_zone_results(config_, reference, epoch);
    auto arrays = m3c2_core_point_arrays(reference, epoch);
    std::size_t valid = 0, rough = 0;
    double reg_max = 0;
    for (std::size_t k = 0; k < epoch.distances.size(); ++k) {
        rough += reference.reference.reference_side[k].roughness > config.max_roughness;
        if (!std::isfinite(epoch.distances[k].distance)) continue;
        ++valid;
        reg_max = std::max(reg_max, epoch.registration_sigma[k]);
    }
    results.zone_results.insert(results.zone_results.end(), std::make_move_iterator(rows.begin()),
                                std::make_move_iterator(rows.end()));
    results.core_point_arrays.insert(results.core_point_arrays.end(),
                                     std::make_move_iterator(arrays.begin()),
                                     std::make_move_iterator(arrays.end()));
    StageVerdict verdict;
    verdict.note =
        fmt::format("{} of {} core points with a distance", valid, epoch.distances.size());
    if (rough > 0) {
        verdict.note +=
            fmt::format(" ({} rougher than {:g} mm: edges)", rough, 1e3 * config.max_roughness);
    }
    verdict.note += fmt::format("; registration σ along the normal up to {:.2f} mm", 1e3 * reg_max);
    return verdict;
}

}  // namespace tlsmon
