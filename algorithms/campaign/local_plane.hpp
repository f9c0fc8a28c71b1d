#pragma once
// The local plane of every point of an unstructured cloud from its 3-D structure tensor (the
// covariance of its neighbours within a radius): the normal e3 is the eigenvector of the
// smallest eigenvalue, the plane passes through the neighbours' mean. Verticality classes
// points by the normal's tilt; the reference surface of the segment-wise registration and the
// C2C distance's local model measure along it (CloudCompare's "least squares plane" model).
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

namespace tlsmon::campaign {

struct LocalPlane {
    Eigen::Vector3f normal = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
    float offset = std::numeric_limits<float>::quiet_NaN();  // m: nᵀ·mean of the neighbours
    // λ3/(λ1 + λ2 + λ3) of the structure tensor, the "surface variation" (Pauly, Gross &
    // Kobbelt 2002): about σ²/(r²/2) on a plane with noise σ, large where the neighbourhood
    // spans an edge or a corner and the plane is no model of the surface.
    float variation = std::numeric_limits<float>::quiet_NaN();
    bool defined() const { return std::isfinite(offset); }
    // Signed distance of x from the plane, m.
    double distance(const Eigen::Vector3d& x) const {
        return normal.cast<double>().dot(x) - offset;
    }
};

// Per point (undefined: fewer than `min_neighbours` neighbours within `radius`, or a point
// that is not finite), parallel over points; the result does not depend on `threads`. With
// `at`, one plane per point it names, of that point's neighbours among all the points.
std::vector<LocalPlane> local_planes(std::span<const Eigen::Vector3d> points, double radius,
                                     int min_neighbours, unsigned threads = 0,
                                     std::span<const std::size_t> at = {});

}  // namespace tlsmon::campaign
