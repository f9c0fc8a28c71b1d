#pragma once
// A synthetic site of twelve planar patches — ground, pier faces, a foundation block, the
// deck's underside, walls, a slope; 10–100 m from the scanner — sampled at 400 points each
// with 2 mm noise per axis, seen from a station that drifts like the simulator's (60″ about
// the standing axis, 10″ of tilt, 1.5 mm σ of translation). Fast enough for hundreds of
// seeded epochs (the false-alarm rate of the congruence test).
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "algorithms/registration/plane_fit.hpp"
#include "algorithms/registration/plane_registration.hpp"

namespace tlsmon::test::synthetic_planes {

inline constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);
inline constexpr double kSigma = 0.002;  // m, each point's noise per axis
inline constexpr int kPointsPerPlane = 400;

struct SitePlane {
    Eigen::Vector3d normal, centre;
};

// Ground, pier faces, the foundation block (index 4: top, 5: south face), an abutment and a
// retaining wall, the deck's underside, a building, a slope; 10–100 m from the scanner.
inline std::vector<SitePlane> site_planes() {
    const auto p = [](Eigen::Vector3d n, Eigen::Vector3d c) {
        return SitePlane{n.normalized(), c};
    };
    return {p({0.01, 0.0, 1.0}, {0, 20, -1.5}), p({0.0, 0.02, 1.0}, {30, 60, -1.0}),
            p({0, -1, 0}, {10, 45, 20}),        p({-1, 0, 0}, {2, 48, 20}),
            p({0, 0, 1}, {10, 43, 0.5}),        p({0, -1, 0}, {10, 40.5, 0}),
            p({0.7, -0.7, 0}, {-20, 30, 3}),    p({1, 0, 0}, {-30, 10, 2}),
            p({0, 0, -1}, {10, 60, 38}),        p({0.2, -0.98, 0}, {40, 90, 5}),
            p({-0.9, -0.3, 0.1}, {60, 20, 2}),  p({0, -0.5, 0.87}, {0, 100, 10})};
}

// 400 points on a 3 × 3 m patch of the plane, each moved by `motion` (applied to the true
// points), then mapped into the scanner's frame by `to_frame` and given noise.
inline std::vector<Eigen::Vector3d> sample(const SitePlane& s, const Eigen::Affine3d& motion,
                                           const Eigen::Affine3d& to_frame, std::mt19937& rng) {
    const Eigen::Vector3d a = s.normal.unitOrthogonal(), b = s.normal.cross(a);
    std::uniform_real_distribution<double> along(-1.5, 1.5);
    std::normal_distribution<double> noise(0.0, kSigma);
    std::vector<Eigen::Vector3d> out(kPointsPerPlane);
    for (auto& q : out) {
        const Eigen::Vector3d p = motion * (s.centre + along(rng) * a + along(rng) * b);
        q = to_frame * p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    }
    return out;
}

// A station drift like the simulator's: yaw up to 60″, tilt 10″, translation σ 1.5 mm.
inline Eigen::Affine3d drift(std::mt19937& rng) {
    std::normal_distribution<double> yaw(0.0, 60.0 * kArcsec), tilt(0.0, 10.0 * kArcsec),
        shift(0.0, 0.0015);
    return Eigen::Translation3d(shift(rng), shift(rng), shift(rng)) *
           Eigen::AngleAxisd(yaw(rng), Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(tilt(rng), Eigen::Vector3d::UnitX()) *
           Eigen::AngleAxisd(tilt(rng), Eigen::Vector3d::UnitY());
}

struct Epoch {
    std::vector<registration::PlaneCorrespondence> planes;
    Eigen::Affine3d truth;  // epoch frame → reference frame
};

// One epoch against the reference; `moved` (index, motion of that plane) or none.
inline Epoch epoch(std::mt19937& rng, int moved = -1,
                   const Eigen::Affine3d& motion = Eigen::Affine3d::Identity()) {
    const auto site = site_planes();
    const Eigen::Affine3d station = drift(rng);  // epoch frame → reference frame
    Epoch e;
    e.truth = station;
    for (std::size_t i = 0; i < site.size(); ++i) {
        const auto ref =
            sample(site[i], Eigen::Affine3d::Identity(), Eigen::Affine3d::Identity(), rng);
        const auto now = sample(site[i], int(i) == moved ? motion : Eigen::Affine3d::Identity(),
                                station.inverse(), rng);
        e.planes.push_back(
            {registration::fit_plane(ref, kSigma), registration::fit_plane(now, kSigma)});
    }
    return e;
}

}  // namespace tlsmon::test::synthetic_planes
