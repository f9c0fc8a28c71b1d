#pragma once
// A site for the registration tests: sphere targets 22–36 m around a scanner at the origin,
// centres seen with anisotropic covariances (tighter along the line of sight, as a sphere fit
// gives them), a true transformation of the size of a day's drift (standing-axis rotation up
// to 60″, tilt up to 10″, translation up to 5 mm) and seeded noise on both epochs' centres.
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::registration::test {

constexpr double kArcsec = M_PI / (180.0 * 3600.0);

struct TargetSite {
    double azimuth_deg, distance, height;
};

// Targets around the scanner on 1 m masts on uneven ground, scanner 1.7 m up; any first n
// (n ≥ 3) have no three nearly on a line.
inline std::vector<Eigen::Vector3d> target_centres(int count) {
    static const TargetSite sites[] = {{-70, 24, -0.8}, {10, 31, -0.2},   {95, 22, -1.3},
                                       {170, 35, 0.3},  {-140, 27, -0.9}, {50, 33, -0.4}};
    std::vector<Eigen::Vector3d> out;
    for (int i = 0; i < count; ++i) {
        const double a = sites[i].azimuth_deg * M_PI / 180.0;
        out.emplace_back(sites[i].distance * std::cos(a), sites[i].distance * std::sin(a),
                         sites[i].height);
    }
    return out;
}

// The simulator's `pier` preset (simulator/presets.cpp): two spheres and two checkerboards
// in a 27° sector left and right of the pier, 22–36 m away, 0.5 and 0.3 m below the scanner
// on its 1.5 m tripod — nearly coplanar, in two radial pairs.
inline std::vector<Eigen::Vector3d> pier_preset_centres() {
    const TargetSite sites[] = {{65, 22, -0.5}, {68, 36, -0.3}, {92, 24, -0.5}, {89, 32, -0.3}};
    std::vector<Eigen::Vector3d> out;
    for (const auto& s : sites) {
        const double a = s.azimuth_deg * M_PI / 180.0;
        out.emplace_back(s.distance * std::cos(a), s.distance * std::sin(a), s.height);
    }
    return out;
}

// Covariance of a centre at `p` seen from the origin: σ_los along the line of sight, σ_lat across.
inline Eigen::Matrix3d centre_covariance(const Eigen::Vector3d& p, double sigma_los = 0.00015,
                                         double sigma_lat = 0.00025) {
    const Eigen::Vector3d los = p.normalized();
    return sigma_lat * sigma_lat * Eigen::Matrix3d::Identity() +
           (sigma_los * sigma_los - sigma_lat * sigma_lat) * los * los.transpose();
}

struct TrueTransform {
    Eigen::Matrix3d rotation;
    Eigen::Vector3d translation;
    double omega, phi, kappa;
};

inline TrueTransform drift(std::mt19937_64& rng, double base_kappa = 0.0) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    TrueTransform t;
    t.omega = 10.0 * kArcsec * u(rng);
    t.phi = 10.0 * kArcsec * u(rng);
    t.kappa = base_kappa + 60.0 * kArcsec * u(rng);
    t.rotation = rotation_from_euler(t.omega, t.phi, t.kappa);
    t.translation = 0.005 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    return t;
}

inline Eigen::Vector3d draw(std::mt19937_64& rng, const Eigen::Matrix3d& cov) {
    std::normal_distribution<double> n(0.0, 1.0);
    const Eigen::Matrix3d L = cov.llt().matrixL();
    return L * Eigen::Vector3d(n(rng), n(rng), n(rng));
}

// Observations of `truth_reference` centres: reference centres as measured in epoch 0, and
// the same targets measured in the epoch's frame, x = Rᵀ·(X − t), each with its noise. The
// epoch's covariance is the reference one turned into the epoch frame.
inline std::vector<CentreObservation> observe(const std::vector<Eigen::Vector3d>& truth_reference,
                                              const TrueTransform& T, std::mt19937_64& rng,
                                              double noise_scale = 1.0) {
    std::vector<CentreObservation> out;
    for (const auto& X : truth_reference) {
        CentreObservation c;
        const Eigen::Vector3d x = T.rotation.transpose() * (X - T.translation);
        c.reference_covariance = centre_covariance(X);
        c.epoch_covariance = centre_covariance(x);
        c.reference = X + noise_scale * draw(rng, c.reference_covariance);
        c.epoch = x + noise_scale * draw(rng, c.epoch_covariance);
        out.push_back(c);
    }
    return out;
}

}  // namespace tlsmon::registration::test
