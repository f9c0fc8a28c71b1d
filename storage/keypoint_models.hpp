#pragma once
// The keypoint displacement model d(t, z) of each epoch (docs/keypoints.md, step 7;
// docs/schema.md, "keypoint_models"): written by the epoch's commit (ResultsWriter), read
// by `tlsmon query keypoint-models`.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct TimeRange;

// One residual d − model of the fitting epoch's own segment.
struct KeypointModelResidual {
    std::string zone;
    double t = 0, z = 0, d = 0, residual = 0;
};

// One fit of d(t, z) = Σ a_pq u^p w^q, u = (t − t_centre)/t_scale, w = (z − z_centre)/z_scale.
struct KeypointModelRow {
    std::string quantity;  // the modelled d, e.g. "keypoint_along_surface_h_m"
    std::string variable;  // what t is, e.g. "time_h" (hours since the reference epoch)
    bool defined = false;
    std::string reason;  // why not, when undefined
    std::int64_t observations = 0;
    std::int64_t iterations = 0;
    bool converged = false;
    // Present exactly when defined; the coefficients in the order 00 10 01 20 11 02 30 21 12 03.
    std::optional<double> t_centre, t_scale, z_centre, z_scale;
    std::optional<std::array<double, 10>> coefficients;
    std::optional<double> sum_abs_residuals, residual_scale;
    std::vector<KeypointModelResidual> residuals;

    // d(t, z) of the fit; none when undefined. The same sum as keypoints::DisplacementModel
    // (tests/pipeline/test_keypoint_results.cpp holds them equal).
    std::optional<double> at(double t, double z) const;
};

struct StoredKeypointModel {
    EpochId epoch = 0;
    UtcSeconds acquired = 0;
    KeypointModelRow model;
};

class KeypointModelStore {
  public:
    explicit KeypointModelStore(Connection& connection) : c_(&connection) {}

    // The fits of epochs acquired in the range, by acquisition time, then quantity; only
    // `quantity` when given. With their residuals.
    std::vector<StoredKeypointModel> in_range(
        const TimeRange& range, const std::optional<std::string>& quantity = std::nullopt) const;
    // The newest defined fit of `quantity` (by its epoch's acquisition time), with its
    // residuals; none when no fit of it is defined.
    std::optional<StoredKeypointModel> latest_defined(const std::string& quantity) const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
