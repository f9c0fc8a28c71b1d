#pragma once
// The registration configuration a site engineer would write for a simulated site: each
// target of the scene with its kind and size, its approximate position a few centimetres
// off the true centre (as a site's approximate positions are). Shared by the pipeline tests
// and the benches that register simulated epochs.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/registration_config.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/drift.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::test {

inline RegistrationConfig simulated_targets(const sim::Site& site) {
    RegistrationConfig c;
    for (const auto& t : site.targets) {
        TargetConfig g;
        g.name = t.name;
        g.kind =
            t.kind == sim::Target::Kind::sphere ? TargetKind::sphere : TargetKind::checkerboard;
        g.radius = t.radius;
        g.size = t.size;
        if (t.mount == sim::Target::Mount::none) g.mount = Eigen::Vector3d::Zero();
        g.approximate = t.centre + Eigen::Vector3d(0.02, -0.015, 0.01);
        c.targets.push_back(g);
    }
    return c;
}

// An epoch's scans registered on their targets against the reference's, as the stage outputs
// the analyses take: the range scales k_e (the epoch's) and k_r (the reference's) are the
// truth's air, as a site takes them from its weather station. nullopt when the registration
// refuses the epoch, `refused` then saying why.
inline std::optional<StageOutputs> simulated_outputs(const RegistrationConfig& targets,
                                                     const ReferenceTargets& reference,
                                                     const std::vector<Scan>& scans, double k_e,
                                                     double k_r, std::string& refused) {
    const RegistrationResult r = register_epoch(targets, reference, scans, {}, {k_e, k_r});
    if (!r.accepted()) {
        refused = r.tested.reason + " " + r.gate;
        return std::nullopt;
    }
    StageOutputs o;
    o.to_reference = r.tested.transform;
    o.range_scale = k_e;
    o.scanner = scans.front().scanner_position();
    o.reference_range_scale = k_r;
    return o;
}

// The exact map of epoch j's coordinates into epoch i's: H_i⁻¹·H_j, H_k = N·E_k·N⁻¹ (the
// scanner's pose error E_k through the nominal pose N: p_true = H_k·p).
inline Eigen::Affine3d exact_epoch_map(const sim::Site& site, const sim::EpochConditions& i,
                                       const sim::EpochConditions& j) {
    const Eigen::Affine3d N = sim::nominal_pose(site.scanner);
    const auto H = [&](const sim::EpochConditions& c) {
        return Eigen::Affine3d(N * sim::pose_error(site, c.epoch, c.hours).transform() *
                               N.inverse());
    };
    return H(i).inverse() * H(j);
}

// Where the scanner of epoch `c` sees y, a point of the project frame: (azimuth, elevation),
// degrees. Two epochs' difference at a zone over the image's step is the shift of the epoch's
// image on the reference's lattice there (docs/keypoints.md, "The lattice's phase").
inline Eigen::Vector2d seen_at(const sim::Site& site, const sim::EpochConditions& c,
                               const Eigen::Vector3d& y) {
    const Eigen::Affine3d actual =
        sim::nominal_pose(site.scanner) * sim::pose_error(site, c.epoch, c.hours).transform();
    const Eigen::Vector3d d = actual.inverse() * y;
    constexpr double deg = 180.0 / std::numbers::pi;
    return {std::atan2(d.y(), d.x()) * deg, std::atan2(d.z(), std::hypot(d.x(), d.y())) * deg};
}

// The stage outputs of an epoch registered by the exact map (no registration error, no σ_T),
// the range scales the truth's air: what an analysis's own error is scored with.
inline StageOutputs exact_outputs(const sim::Site& site, const sim::EpochConditions& e0,
                                  const sim::EpochConditions& e, const Scan& scan) {
    const Eigen::Affine3d exact = exact_epoch_map(site, e0, e);
    registration::RigidTransform T;
    T.rotation = exact.linear();
    T.translation = exact.translation();
    T.quaternion = Eigen::Quaterniond(T.rotation);
    StageOutputs o;
    o.to_reference = T;
    o.range_scale = e.atmosphere.range_scale;
    o.reference_range_scale = e0.atmosphere.range_scale;
    o.scanner = scan.scanner_position();
    return o;
}

// The registration's realized error at y, a point of the reference frame: where `T` puts the
// point of epoch `e` that truly lies at y, minus y. Every measurement of an epoch shares it,
// so a test scores an analysis's own σ against its error less this, and the registration's σ
// over independent series (bench/registration_coverage.cpp). One per epoch: the exact map is
// taken once.
struct RegistrationError {
    RegistrationError(const sim::Site& site, const sim::EpochConditions& e0,
                      const sim::EpochConditions& e, const registration::RigidTransform& T)
        : RegistrationError(exact_epoch_map(site, e0, e), T) {}
    // `exact`: the map of the epoch's coordinates into the reference's, however obtained.
    RegistrationError(const Eigen::Affine3d& exact, const registration::RigidTransform& T)
        : exact_inverse(exact.inverse()), T(T) {}
    Eigen::Vector3d operator()(const Eigen::Vector3d& y) const {
        return T.apply(exact_inverse * y) - y;
    }
    Eigen::Affine3d exact_inverse;
    registration::RigidTransform T;
};

inline Eigen::Vector3d registration_error_at(const sim::Site& site, const sim::EpochConditions& e0,
                                             const sim::EpochConditions& e,
                                             const registration::RigidTransform& T,
                                             const Eigen::Vector3d& y) {
    return RegistrationError(site, e0, e, T)(y);
}

}  // namespace tlsmon::test
