#include "algorithms/orthoimage.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tlsmon {

namespace {

void check(const std::vector<Eigen::Vector3d>& xyz, const std::vector<float>& intensity,
           const OrthoPlane& plane, const OrthoGrid& grid) {
    if (xyz.size() != intensity.size()) {
        throw Error("orthoimage: " + std::to_string(xyz.size()) + " points but " +
                    std::to_string(intensity.size()) + " intensities");
    }
    constexpr double tol = 1e-9;
    if (std::abs(plane.u.norm() - 1.0) > tol || std::abs(plane.v.norm() - 1.0) > tol ||
        std::abs(plane.u.dot(plane.v)) > tol) {
        throw Error("orthoimage: the plane's axes u and v must be orthonormal");
    }
    if (!(plane.max_distance >= 0.0)) throw Error("orthoimage: max_distance must be >= 0");
    if (!(grid.pixel_size > 0.0) || !(grid.kernel_sigma > 0.0)) {
        throw Error("orthoimage: pixel_size and kernel_sigma must be > 0");
    }
    if (grid.rows <= 0 || grid.columns <= 0) throw Error("orthoimage: the grid is empty");
}

}  // namespace

Orthoimage rasterise_orthoimage(const std::vector<Eigen::Vector3d>& xyz,
                                const std::vector<float>& intensity, const OrthoPlane& plane,
                                const OrthoGrid& grid) {
    check(xyz, intensity, plane, grid);
    Orthoimage out;
    out.plane = plane;
    out.grid = grid;
    out.weight = Eigen::ArrayXXd::Zero(grid.rows, grid.columns);
    Eigen::ArrayXXd weighted = Eigen::ArrayXXd::Zero(grid.rows, grid.columns);

    const Eigen::Vector3d normal = plane.u.cross(plane.v);
    const double ps = grid.pixel_size;
    const double reach = 3.0 * grid.kernel_sigma;  // weights below e^(−4.5) = 1 % left out
    const double inv_two_var = 1.0 / (2.0 * grid.kernel_sigma * grid.kernel_sigma);
    for (std::size_t i = 0; i < xyz.size(); ++i) {
        const Eigen::Vector3d d = xyz[i] - plane.origin;
        if (std::abs(normal.dot(d)) > plane.max_distance) continue;
        // Orthogonal projection onto the plane, in pixel units from the first centre.
        const Eigen::Vector2d q(plane.u.dot(d), plane.v.dot(d));
        const Eigen::Vector2d pix = (q - grid.first_centre) / ps;
        const auto lo_c = static_cast<Eigen::Index>(std::ceil(pix.x() - reach / ps));
        const auto hi_c = static_cast<Eigen::Index>(std::floor(pix.x() + reach / ps));
        const auto lo_r = static_cast<Eigen::Index>(std::ceil(pix.y() - reach / ps));
        const auto hi_r = static_cast<Eigen::Index>(std::floor(pix.y() + reach / ps));
        if (hi_c < 0 || hi_r < 0 || lo_c >= grid.columns || lo_r >= grid.rows) continue;
        for (Eigen::Index r = std::max<Eigen::Index>(lo_r, 0);
             r <= std::min<Eigen::Index>(hi_r, grid.rows - 1); ++r) {
            const double dv = (pix.y() - static_cast<double>(r)) * ps;
            for (Eigen::Index c = std::max<Eigen::Index>(lo_c, 0);
                 c <= std::min<Eigen::Index>(hi_c, grid.columns - 1); ++c) {
                const double du = (pix.x() - static_cast<double>(c)) * ps;
                const double w = std::exp(-(du * du + dv * dv) * inv_two_var);
                out.weight(r, c) += w;
                weighted(r, c) += w * static_cast<double>(intensity[i]);
            }
        }
    }
    out.image.valid = out.weight >= grid.min_weight;
    out.image.value = out.image.valid.select(weighted / out.weight.max(1e-300), 0.0);
    return out;
}

}  // namespace tlsmon
