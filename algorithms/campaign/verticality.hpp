#pragma once
// Verticality of every point of a cloud, as the segment-based comparison of a personal laser
// scanner's cloud with a TLS reference uses it (Blaskow & Maas, "Structural health
// monitoring of bridges with personal laser scanning: segment-based analysis of systematic
// point cloud deformations", eq. 1): the 3-D structure tensor (the covariance of the
// neighbours within `radius`) gives the local normal e3, the eigenvector of its smallest
// eigenvalue, and
//     V = 1 − |e3,z|,
// 1 on a vertical surface (a pier's face), 0 on a horizontal one (the deck, the ground).
// Classes by thresholds on V: vertical, horizontal, the rest "other" (inclined faces,
// edges, vegetation); a point with fewer than `min_neighbours` neighbours has none.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace tlsmon::campaign {

struct VerticalityParameters {
    double radius = 0.10;  // m, the study's neighbourhood
    int min_neighbours = 6;
    // Surfaces within about 15° of vertical (|e3,z| ≤ 0.25) and within about 18° of horizontal
    // (|e3,z| ≥ 0.95). The study's own thresholds are not stated with its eq. 1; these are
    // this project's, set before any scene was scored.
    double vertical_min = 0.75;
    double horizontal_max = 0.05;
};

enum class VerticalityClass : std::uint8_t { vertical, horizontal, other, undefined };
const char* class_name(VerticalityClass c);

VerticalityClass classify(double verticality, const VerticalityParameters& parameters);

// V per point (NaN: too few neighbours or a point that is not finite), parallel over points.
std::vector<float> verticality(std::span<const Eigen::Vector3d> points,
                               const VerticalityParameters& parameters, unsigned threads = 0);

// Throws Error naming the parameter when a value cannot give a meaningful result.
void validate(const VerticalityParameters& parameters);

}  // namespace tlsmon::campaign
