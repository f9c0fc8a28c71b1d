#include "pipeline/keypoint_results.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "core/error.hpp"

namespace tlsmon {

namespace {

// 1.96: the two-sided 95 % quantile of the normal distribution (Lague 2013, eq. 1).
constexpr double kLod95 = 1.96;

// To 1e-6°, so that 5 and -2.5 print without rounding noise; + 0.0 turns −0 into 0.
double degrees_of(double rad) {
    return std::round(rad * 180 / std::numbers::pi * 1e6) / 1e6 + 0.0;
}

std::string degrees(double rad) {
    std::ostringstream out;
    out << degrees_of(rad);
    return out.str();
}

}  // namespace

std::vector<ZoneResult> keypoint_zone_results(const std::string& zone,
                                              const keypoints::SegmentDisplacement& segment,
                                              const Eigen::Matrix3d& registration_covariance) {
    std::vector<ZoneResult> rows;
    const auto n = static_cast<std::int64_t>(segment.count);
    rows.push_back({zone, kKeypointCount, static_cast<double>(segment.count), std::nullopt,
                    static_cast<std::int64_t>(segment.matches), false});
    if (!segment.defined()) return rows;
    // Lague 2013, eq. 1, with the standard error of the segment's mean in place of the
    // cylinders' term and the registration's σ projected on the figure's own direction u,
    // added in quadrature: the two are independent (the matches' noise and the datum).
    const auto add = [&](const char* quantity, double value, double standard_error,
                         const Eigen::Vector3d& u) {
        const double registration_variance = std::max(0.0, u.dot(registration_covariance * u));
        if (!std::isfinite(value) || !std::isfinite(standard_error)) return;
        const double lod =
            kLod95 * std::sqrt(standard_error * standard_error + registration_variance);
        rows.push_back({zone, quantity, value, lod, n, std::abs(value) > lod});
    };
    add(kKeypointDx, segment.mean.x(), segment.standard_error.x(), Eigen::Vector3d::UnitX());
    add(kKeypointDy, segment.mean.y(), segment.standard_error.y(), Eigen::Vector3d::UnitY());
    add(kKeypointDz, segment.mean.z(), segment.standard_error.z(), Eigen::Vector3d::UnitZ());
    if (const auto& wall = segment.wall; wall.defined()) {
        add(kKeypointAlongNormal, segment.along[0], segment.along_standard_error[0], wall.normal);
        add(kKeypointAlongSurfaceH, segment.along[1], segment.along_standard_error[1],
            wall.horizontal);
        add(kKeypointAlongSurfaceV, segment.along[2], segment.along_standard_error[2],
            wall.vertical);
        if (std::isfinite(segment.wall.centroid.z()))
            rows.push_back(
                {zone, kKeypointHeight, segment.wall.centroid.z(), std::nullopt, n, false});
    }
    return rows;
}

std::string keypoint_band_zone(int band, double width) {
    const auto [lo, hi] = keypoints::vertical_angle_band_bounds(band, width);
    return "keypoint_band_" + degrees(lo) + "_" + degrees(hi);
}

std::string keypoint_band_zone_definition(int band, double width) {
    const auto [lo, hi] = keypoints::vertical_angle_band_bounds(band, width);
    return nlohmann::json{{"vertical_angle_deg", {degrees_of(lo), degrees_of(hi)}}}.dump();
}

std::vector<KeypointModelInput> stored_model_inputs(const SeriesReader& series,
                                                    std::span<const std::string> zones,
                                                    const std::string& quantity,
                                                    UtcSeconds reference_acquired) {
    std::vector<KeypointModelInput> inputs;
    for (const auto& zone : zones) {
        std::map<EpochId, double> height;
        for (const auto& p : series.points(zone, kKeypointHeight, {})) height[p.epoch] = p.value;
        for (const auto& p : series.points(zone, quantity, {})) {
            const auto z = height.find(p.epoch);
            if (z == height.end()) continue;
            const double t = static_cast<double>(p.acquired - reference_acquired) / 3600.0;
            inputs.push_back({zone, p.epoch, {t, z->second, p.value}});
        }
    }
    return inputs;
}

KeypointModelRow keypoint_model_row(const std::string& quantity, const std::string& variable,
                                    const keypoints::DisplacementModel& model,
                                    std::span<const KeypointModelInput> inputs,
                                    EpochId fitting_epoch) {
    KeypointModelRow row;
    row.quantity = quantity;
    row.variable = variable;
    row.observations = static_cast<std::int64_t>(model.observations);
    row.iterations = static_cast<std::int64_t>(model.iterations);
    row.converged = model.converged;
    row.defined = model.defined();
    row.reason = model.undefined_reason;
    if (!row.defined) return row;
    row.t_centre = model.t_centre;
    row.t_scale = model.t_scale;
    row.z_centre = model.z_centre;
    row.z_scale = model.z_scale;
    std::array<double, 10> a{};
    for (int k = 0; k < 10; ++k) a[k] = model.coefficients[k];
    row.coefficients = a;
    row.sum_abs_residuals = model.sum_abs_residuals;
    row.residual_scale = model.residual_scale;
    if (static_cast<Eigen::Index>(inputs.size()) != model.residuals.size())
        throw Error("keypoint model of '" + quantity + "': " + std::to_string(inputs.size()) +
                    " inputs for " + std::to_string(model.residuals.size()) + " residuals");
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        if (inputs[i].epoch != fitting_epoch) continue;
        const auto& o = inputs[i].observation;
        row.residuals.push_back(
            {inputs[i].zone, o.t, o.z, o.d, model.residuals[static_cast<Eigen::Index>(i)]});
    }
    return row;
}

}  // namespace tlsmon
