#include "simulator/deformation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tlsmon::sim {

ThermalBending thermal_bending(const Site& site, const ThermalState& s) {
    ThermalBending b;
    const auto& f = s.face_c;
    const auto& c = s.section_c;
    b.delta_driving = {f[0] - f[1], f[2] - f[3]};
    b.delta_lagged = {c[0] - c[1], c[2] - c[3]};
    const Deformation& d = site.deformation;
    b.mean_change = 0.25 * (c[0] + c[1] + c[2] + c[3]) - d.reference_temperature_c;
    const Pier& p = site.pier;
    const double alpha = d.expansion_coefficient;
    const Eigen::Vector2d depth = p.section_depth();
    b.curvature = {alpha * b.delta_lagged.x() / depth.x(), alpha * b.delta_lagged.y() / depth.y()};
    if (d.enabled) {
        const double h = p.height;
        b.top = {0.5 * b.curvature.x() * h * h, 0.5 * b.curvature.y() * h * h,
                 alpha * b.mean_change * h};
    }
    return b;
}

PierDisplacementField::PierDisplacementField(const Site& site, int epoch,
                                             const ThermalBending& bending)
    : site_(&site), top_(bending.top) {
    const Events& e = site.events;
    stepped_ = e.step_epoch >= 0 && epoch >= e.step_epoch;
    tilt_ = pier_tilt(site, epoch);
    if (!site.deformation.enabled) top_.setZero();
}

Eigen::Vector3d PierDisplacementField::operator()(const Eigen::Vector3d& p) const {
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    const Deformation& d = site_->deformation;
    const double h = site_->pier.height;
    const double zeta = std::clamp(p.z() / h, 0.0, 1.0);
    if (d.enabled) {
        const double profile = d.exponent == 2.0 ? zeta * zeta : std::pow(zeta, d.exponent);
        u += Eigen::Vector3d(top_.x() * profile, top_.y() * profile, top_.z() * zeta);
    }
    const Events& e = site_->events;
    if (stepped_ && p.z() >= e.step_z_min && p.z() <= e.step_z_max) u += e.step_displacement;
    if (tilt_.x() != 0.0 || tilt_.y() != 0.0) {
        const Eigen::Vector2d r = p.head<2>() - site_->pier.centre();
        u += Eigen::Vector3d(tilt_.x() * p.z(), tilt_.y() * p.z(), -tilt_.dot(r));
    }
    return u;
}

Eigen::Vector2d pier_tilt(const Site& site, int epoch) {
    const Events& e = site.events;
    if (e.tilt_epoch < 0 || epoch < e.tilt_epoch) return Eigen::Vector2d::Zero();
    return e.tilt_arcsec * std::numbers::pi / (180.0 * 3600.0);
}

Eigen::Vector3d pier_displacement(const Site& site, const Eigen::Vector3d& p, int epoch,
                                  const ThermalBending& bending) {
    return PierDisplacementField(site, epoch, bending)(p);
}

Eigen::Vector3d target_centre(const Site& site, std::size_t index, int epoch) {
    Eigen::Vector3d c = site.targets.at(index).centre;
    const Events& e = site.events;
    if (e.knocked_target == static_cast<int>(index) && e.knocked_epoch >= 0 &&
        epoch >= e.knocked_epoch) {
        c += e.knocked_displacement;
    }
    return c;
}

}  // namespace tlsmon::sim
