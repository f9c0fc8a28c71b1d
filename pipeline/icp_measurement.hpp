#pragma once
// What the ICP on stable regions measured in one epoch (pipeline/icp_registration.hpp), as
// the registration row records it.
#include <cstddef>
#include <optional>
#include <string>

#include "algorithms/registration/point_to_plane.hpp"
#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon {

struct IcpMeasurement {
    std::string role;              // "refine": after accepted targets; "fallback": in their place
    bool used = false;             // entered the epoch's transformation
    std::string refused;           // why it did not, in words ("" when used)
    std::size_t epoch_points = 0;  // the epoch's thinned points in the stable regions
    std::size_t reference_points = 0;  // the reference surface's points with normals
    std::size_t pairs = 0;             // matched within the correspondence distance, used
    std::size_t outliers = 0;          // matched but left out as too far from their plane
    std::size_t clusters = 0;          // cells of the cluster-robust covariance
    double overlap = 0;                // pairs / epoch points (the fitness)
    double rms = 0;                    // m, of the point-to-plane distances
    double inflation = 1;              // largest σ ratio, correlated / independent residuals
    int iterations = 0;
    int recuts = 0;  // times the epoch was cut again where the ICP had put it
    bool converged = false;
    // Refinement: χ² of the difference to the targets' transformation (6 degrees of freedom).
    std::optional<double> agreement;
    double milliseconds = 0;
    // The targets' verdict the fallback replaced ("" when refining).
    std::string targets_status;
    // The ICP's own estimate (epoch -> reference) with its covariance.
    std::optional<registration::RigidTransform> transform;
    // The adjustment behind it: its candidate covariances (independent residuals, the cells'
    // random effect, the cluster-robust sandwich), of which `transform` carries the largest.
    std::optional<registration::PointToPlaneFit> fit;
};

}  // namespace tlsmon
