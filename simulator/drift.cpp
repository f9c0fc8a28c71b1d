#include "simulator/drift.hpp"

#include <cmath>
#include <numbers>

#include "simulator/random.hpp"

namespace tlsmon::sim {

namespace {
constexpr double kArcsec = std::numbers::pi / (180.0 * 3600.0);
constexpr std::uint64_t kDriftStream = 0x64726966747374ULL;
}  // namespace

Eigen::Affine3d PoseError::transform() const {
    Eigen::Affine3d e = Eigen::Affine3d::Identity();
    e.translate(translation);
    e.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    e.rotate(Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()));
    e.rotate(Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()));
    return e;
}

PoseError pose_error(const Site& site, int epoch, double hours) {
    PoseError e;
    const Events& ev = site.events;
    if (ev.station_change_epoch >= 0 && epoch >= ev.station_change_epoch) {
        e.yaw = ev.station_turn_deg * std::numbers::pi / 180.0;
        e.translation = ev.station_shift;
    }
    const Drift& d = site.drift;
    if (!d.enabled) return e;
    const double w = 2.0 * std::numbers::pi * hours / d.yaw_period_hours;
    Rng rng(hash_combine(hash_combine(site.noise.seed, kDriftStream),
                         static_cast<std::uint64_t>(epoch)));
    e.yaw += (d.yaw_amplitude_arcsec * std::sin(w) + d.yaw_jitter_arcsec * rng.normal()) * kArcsec;
    e.tilt_x =
        (d.tilt_amplitude_arcsec * std::sin(w) + d.tilt_jitter_arcsec * rng.normal()) * kArcsec;
    e.tilt_y = (d.tilt_amplitude_arcsec * 0.5 * (1.0 - std::cos(w)) +
                d.tilt_jitter_arcsec * rng.normal()) *
               kArcsec;
    for (int i = 0; i < 3; ++i) e.translation[i] += d.translation_sigma * rng.normal();
    return e;
}

Eigen::Affine3d nominal_pose(const Scanner& scanner) {
    Eigen::Affine3d n = Eigen::Affine3d::Identity();
    n.translate(scanner.position);
    n.rotate(Eigen::AngleAxisd(scanner.heading_deg * std::numbers::pi / 180.0,
                               Eigen::Vector3d::UnitZ()));
    return n;
}

}  // namespace tlsmon::sim
