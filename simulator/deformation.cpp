#include "simulator/deformation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tlsmon::sim {

double thermal_time_factor(const Deformation& d, double hours) {
    return 0.5 * (1.0 - std::cos(std::numbers::pi * hours / d.peak_hours));
}

PierDisplacementField::PierDisplacementField(const Site& site, int epoch, double hours)
    : site_(&site) {
    const Events& e = site.events;
    stepped_ = e.step_epoch >= 0 && epoch >= e.step_epoch;
    const Deformation& d = site.deformation;
    if (d.enabled) {
        s_ = thermal_time_factor(d, hours);
        const double a = d.direction_deg * std::numbers::pi / 180.0;
        cos_a_ = std::cos(a);
        sin_a_ = std::sin(a);
    }
}

Eigen::Vector3d PierDisplacementField::operator()(const Eigen::Vector3d& p) const {
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    const Deformation& d = site_->deformation;
    const double h = site_->pier.height;
    const double zeta = std::clamp(p.z() / h, 0.0, 1.0);
    if (d.enabled) {
        const double profile = d.exponent == 2.0 ? zeta * zeta : std::pow(zeta, d.exponent);
        const double uh = d.top_displacement * profile * s_;
        u += Eigen::Vector3d(uh * cos_a_, uh * sin_a_, d.vertical_extension * zeta * s_);
    }
    const Events& e = site_->events;
    if (stepped_ && p.z() >= e.step_z_min && p.z() <= e.step_z_max) u += e.step_displacement;
    return u;
}

Eigen::Vector3d pier_displacement(const Site& site, const Eigen::Vector3d& p, int epoch,
                                  double hours) {
    return PierDisplacementField(site, epoch, hours)(p);
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
