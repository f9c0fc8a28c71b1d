#pragma once
// The scanner's stochastic model, one for the site ([station] in the configuration): the
// range noise σ_r = a + b·r and the σ of the beam's direction (the simulator's `constant`
// model and its defaults, docs/simulator.md). What a method needs of the measurement noise —
// the planarity test of the registration on planes, the floor of the keypoints' robust
// spread — it takes from here.
#include <numbers>

namespace tlsmon {

struct ScannerNoise {
    double range_sigma_a = 0.001;       // m
    double range_sigma_b_ppm = 10.0;    // of the range
    double angular_sigma_arcsec = 3.0;  // of the beam's direction

    // σ_r at range r (m).
    double range_sigma(double range) const {
        return range_sigma_a + 1e-6 * range_sigma_b_ppm * range;
    }
    // σ of a direction, rad.
    double angular_sigma() const {
        return angular_sigma_arcsec * std::numbers::pi / (180.0 * 3600.0);
    }
    // The largest σ of a point's coordinate at range r: max(σ_r, r·σ_θ).
    double point_sigma(double range) const {
        const double across = range * angular_sigma();
        const double along = range_sigma(range);
        return along > across ? along : across;
    }
};

}  // namespace tlsmon
