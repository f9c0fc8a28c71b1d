#include "pipeline/primitive_stage.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/pcl_adapter.hpp"
#include "pipeline/primitive_seed.hpp"

namespace tlsmon {

namespace {

constexpr double kArcsecPerRad = 180.0 * 3600.0 / std::numbers::pi;

// Every scan's points inside the zone, mapped by q = map(p).
std::vector<Eigen::Vector3d> zone_points(const std::vector<Scan>& scans, const ZoneShape& zone,
                                         const EpochToReference& map) {
    std::vector<Eigen::Vector3d> out;
    const bool identity = map.identity();
    for (const Scan& scan : scans) {
        for (const Eigen::Vector3d& p : scan.xyz) {
            const Eigen::Vector3d q = identity ? p : map.apply(p);
            if (zone.contains(q)) out.push_back(q);
        }
    }
    return out;
}

// The axial distance from the cylinder's frame origin to the zone's far end along the axis.
double far_end(const primitives::Primitive& p, const ZoneShape& zone) {
    double most = 0.0;
    const Eigen::Vector3d a = p.direction();
    for (int corner = 0; corner < 8; ++corner) {
        const auto c = zone.box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
        most = std::max(most, a.dot(c - p.frame.origin));
    }
    return most;
}

PrimitiveReference::Entry reference_entry(const PrimitivesConfig& config, const PrimitiveZone& z,
                                          const std::vector<Scan>& scans,
                                          const Eigen::Vector3d& scanner) {
    PrimitiveReference::Entry e;
    e.zone = z.shape.name;
    e.fit.primitive.kind = z.kind;
    const auto points = zone_points(scans, z.shape, EpochToReference{});
    // Coarse: RANSAC on a thinned sample with normals.
    const auto sample = voxel_centroids(points, config.sample_voxel);
    const SurfaceSample with_normals =
        surface_with_normals(sample, config.normal_radius, 0.1, scanner);
    PrimitiveSeedParams sp;
    sp.threshold = config.ransac_threshold;
    sp.iterations = config.ransac_iterations;
    const auto seed = ransac_primitive(z.kind, with_normals, sp);
    if (!seed) {
        e.refused =
            fmt::format("RANSAC found no {} in {} sample points of the zone's {}",
                        primitives::to_string(z.kind), with_normals.points.size(), points.size());
        return e;
    }
    e.seed_inliers = seed->inliers;
    primitives::Primitive start = seed->primitive;
    // A plane's normal towards the scanner.
    if (z.kind == primitives::Kind::plane && start.frame.a.dot(scanner - start.frame.origin) < 0)
        start = primitives::plane_through(start.frame.origin, -start.frame.a);
    // Fine: every point of the zone.
    e.fit =
        primitives::fit_primitive(points, scanner, config.noise, start, config.fit_parameters());
    if (e.fit.status != primitives::FitStatus::fitted) {
        e.refused = fmt::format("the fit of the reference's {} points: {}", points.size(),
                                primitives::to_string(e.fit.status));
        return e;
    }
    if (z.kind == primitives::Kind::cylinder) e.far_end = far_end(e.fit.primitive, z.shape);
    return e;
}

void add(std::vector<ZoneResult>& rows, const std::string& zone, const char* quantity, double value,
         double lod, bool significant, std::int64_t n) {
    rows.push_back({zone, quantity, value, lod, n, significant});
}

}  // namespace

std::string primitives_reference_parameters(const PrimitivesConfig& c) {
    std::string s = fmt::format(
        "sample_voxel={:.17g};normal_radius={:.17g};ransac_threshold={:.17g};"
        "ransac_iterations={};band={:.17g};max_incidence_deg={:.17g};clip_k={:.17g};"
        "min_points={};noise={:.17g},{:.17g},{:.17g}",
        c.sample_voxel, c.normal_radius, c.ransac_threshold, c.ransac_iterations, c.band,
        c.max_incidence_deg, c.clip_k, c.min_points, c.noise.range_sigma_a,
        c.noise.range_sigma_b_ppm, c.noise.angular_sigma_arcsec);
    std::vector<ZoneShape> shapes;
    for (const auto& z : c.zones) {
        shapes.push_back(z.shape);
        s += fmt::format(";{}={}", z.shape.name, primitives::to_string(z.kind));
    }
    return s + zone_parameters(shapes);
}

PrimitiveReference prepare_primitives_reference(const PrimitivesConfig& config,
                                                const std::vector<Scan>& scans) {
    if (scans.empty()) throw Error("primitives: the reference epoch holds no scan");
    PrimitiveReference r;
    r.scanner = scans.front().scanner_position();
    for (const auto& z : config.zones)
        r.entries.push_back(reference_entry(config, z, scans, r.scanner));
    return r;
}

PrimitiveEpoch measure_primitives(const PrimitivesConfig& config,
                                  const PrimitiveReference& reference,
                                  const std::vector<Scan>& scans, const StageOutputs& outputs) {
    if (scans.empty()) throw Error("primitives: the epoch holds no scan");
    if (reference.entries.size() != config.zones.size())
        throw Error("primitives: the reference product holds " +
                    std::to_string(reference.entries.size()) + " zones, the configuration " +
                    std::to_string(config.zones.size()));
    const EpochToReference map = epoch_to_reference(outputs, reference.scanner);
    const Eigen::Vector3d scanner = map.apply(scans.front().scanner_position());
    Eigen::Matrix<double, 7, 7> registration = Eigen::Matrix<double, 7, 7>::Zero();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    if (outputs.to_reference) {
        registration = outputs.to_reference->small_rotation_covariance;
        centre = outputs.to_reference->translation;
    }
    PrimitiveEpoch out;
    for (std::size_t k = 0; k < config.zones.size(); ++k) {
        const auto& ref = reference.entries[k];
        primitives::Fit fit;
        primitives::Change change;
        if (ref.fit.status == primitives::FitStatus::fitted) {
            const auto points = zone_points(scans, config.zones[k].shape, map);
            fit = primitives::fit_primitive(points, scanner, config.noise, ref.fit.primitive,
                                            config.fit_parameters());
            if (fit.status == primitives::FitStatus::fitted)
                change = primitives::parameter_change(ref.fit.primitive, ref.fit.covariance,
                                                      fit.primitive, fit.covariance, registration,
                                                      centre);
        }
        out.fits.push_back(std::move(fit));
        out.changes.push_back(std::move(change));
    }
    return out;
}

Eigen::Matrix<double, 2, 5> cylinder_top_jacobian(double far_end) {
    Eigen::Matrix<double, 2, 5> J = Eigen::Matrix<double, 2, 5>::Zero();
    J(0, 0) = J(1, 1) = 1.0;
    J(0, 2) = J(1, 3) = far_end;
    return J;
}

std::vector<ZoneResult> primitive_zone_results(const PrimitivesConfig& config,
                                               const PrimitiveReference& reference,
                                               const PrimitiveEpoch& epoch) {
    using primitives::test_change;
    std::vector<ZoneResult> rows;
    const double a = config.alpha;
    for (std::size_t k = 0; k < epoch.fits.size(); ++k) {
        const auto& fit = epoch.fits[k];
        const auto& c = epoch.changes[k];
        if (fit.status != primitives::FitStatus::fitted || c.delta.size() == 0) continue;
        const std::string& zone = reference.entries[k].zone;
        const auto n = static_cast<std::int64_t>(fit.used);
        // One component i of the change: its value and test.
        const auto one = [&](int i, const char* quantity, double unit) {
            const auto t = test_change(c.delta.segment(i, 1), c.covariance.block(i, i, 1, 1), a);
            add(rows, zone, quantity, unit * c.delta[i], unit * t.lod, t.significant, n);
        };
        // A vector of components i..i+m−1: its magnitude and χ² test.
        const auto vector = [&](int i, int m, const char* quantity, double unit) {
            const auto t = test_change(c.delta.segment(i, m), c.covariance.block(i, i, m, m), a);
            add(rows, zone, quantity, unit * t.magnitude, unit * t.lod, t.significant, n);
        };
        switch (fit.primitive.kind) {
            case primitives::Kind::cylinder: {
                vector(2, 2, "cylinder_tilt_arcsec", kArcsecPerRad);
                one(2, "cylinder_lean_x_arcsec", kArcsecPerRad);
                one(3, "cylinder_lean_y_arcsec", kArcsecPerRad);
                const Eigen::MatrixXd J = cylinder_top_jacobian(reference.entries[k].far_end);
                const Eigen::VectorXd top = J * c.delta;
                const Eigen::MatrixXd S = J * c.covariance * J.transpose();
                for (int i = 0; i < 2; ++i) {
                    const auto t = test_change(top.segment(i, 1), S.block(i, i, 1, 1), a);
                    add(rows, zone, i == 0 ? "cylinder_top_x_m" : "cylinder_top_y_m", top[i], t.lod,
                        t.significant, n);
                }
                one(4, "cylinder_radius_change_m", 1.0);
                break;
            }
            case primitives::Kind::plane:
                vector(0, 2, "fitted_plane_tilt_arcsec", kArcsecPerRad);
                one(2, "fitted_plane_offset_m", 1.0);
                break;
            case primitives::Kind::sphere:
                vector(0, 3, "sphere_displacement_m", 1.0);
                one(0, "sphere_dx_m", 1.0);
                one(1, "sphere_dy_m", 1.0);
                one(2, "sphere_dz_m", 1.0);
                one(3, "sphere_radius_change_m", 1.0);
                break;
        }
        rows.push_back({zone, "primitive_s0", fit.s0, std::nullopt, n, false});
        rows.push_back({zone, "primitive_rms_m", fit.rms, std::nullopt, n, false});
    }
    return rows;
}

std::shared_ptr<const PrimitiveReference> PrimitivesStage::reference(ReferenceEpoch& reference,
                                                                     ReferenceCache& cache) const {
    return cache.get<PrimitiveReference>(
        reference,
        ProductKey{PrimitiveReference::kStage, primitives_reference_parameters(config_),
                   PrimitiveReference::kFormatVersion},
        [&](const std::vector<Scan>& scans) {
            return prepare_primitives_reference(config_, scans);
        });
}

StageVerdict PrimitivesStage::run(StageContext& ctx) const {
    const auto product = reference(ctx.reference, ctx.cache);
    const PrimitiveEpoch epoch =
        measure_primitives(config_, *product, *ctx.input.scans, ctx.outputs);
    auto rows = primitive_zone_results(config_, *product, epoch);
    ctx.results.zone_results.insert(ctx.results.zone_results.end(),
                                    std::make_move_iterator(rows.begin()),
                                    std::make_move_iterator(rows.end()));
    std::string detail;
    for (std::size_t k = 0; k < epoch.fits.size(); ++k) {
        const auto& ref = product->entries[k];
        const auto& fit = epoch.fits[k];
        detail += detail.empty() ? "" : "; ";
        if (!ref.refused.empty()) {
            detail += fmt::format("{}: no {} in the reference ({})", ref.zone,
                                  primitives::to_string(ref.fit.primitive.kind), ref.refused);
        } else if (fit.status != primitives::FitStatus::fitted) {
            detail += fmt::format("{}: {} of {} points: {}", ref.zone,
                                  primitives::to_string(ref.fit.primitive.kind), fit.candidates,
                                  primitives::to_string(fit.status));
        } else {
            detail += fmt::format("{}: {} on {} points, s0 {:.2f}, rms {:.2f} mm", ref.zone,
                                  primitives::to_string(fit.primitive.kind), fit.used, fit.s0,
                                  1e3 * fit.rms);
        }
    }
    return StageVerdict{"", detail};
}

}  // namespace tlsmon
