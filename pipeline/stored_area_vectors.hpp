#pragma once
// One epoch's 3-D vectors as the stage stored them (pipeline/vector_stage.hpp: per-area float32
// arrays, docs/vectors.md "Quantities"), read back for the dashboard's epoch view and the
// report's figure.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "storage/epoch_database.hpp"

namespace tlsmon {

// The per-area arrays in their order: centre x, y, z; vector dx, dy, dz; σ x, y, z (m).
inline constexpr std::array<const char*, 9> kAreaVectorArrays = {
    "vector_x_m",  "vector_y_m",       "vector_z_m",       "vector_dx_m",     "vector_dy_m",
    "vector_dz_m", "vector_sigma_x_m", "vector_sigma_y_m", "vector_sigma_z_m"};

struct StoredAreaVector {
    Eigen::Vector3d centre, displacement, sigma;  // m, project frame; σ per axis
    // 1.96 σ along the unit direction e from the per-axis σ: √Σ eᵢ² σᵢ². The arrays keep the
    // covariance's diagonal only, so the axes' correlation is left out (exact along an axis).
    double lod95_along(const Eigen::Vector3d& e) const;
};

// The epoch's measured areas (those with a σ stored); empty when it has no vectors, or arrays
// of unequal lengths.
std::vector<StoredAreaVector> read_area_vectors(const EpochDatabase& db, EpochId epoch);

}  // namespace tlsmon
