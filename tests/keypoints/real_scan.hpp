#pragma once
// The real structured scan of ../shared/data/ptx/pumpA_from_e57.ptx (INVENTORY.md: 345
// columns × 1074 rows, 155,201 returns, identity pose, range 1.98–5.43 m), read once, and
// the resampling the keypoint tests build their second epochs with.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "algorithms/keypoints/spherical_image.hpp"
#include "core/scan.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon::test {

inline const Scan& pump_scan() {
    static const Scan scan = [] {
        auto scans = read_scans(std::filesystem::path(TLSMON_DATA_DIR) / "ptx/pumpA_from_e57.ptx");
        return std::move(scans.at(0));
    }();
    return scan;
}

// Bilinear interpolation of a per-pixel quantity at (row, column) over the four pixels
// around it; nothing when one of them is empty or their ranges differ by more than 5 cm
// (an edge: the resampled "surface" would be neither side). Written independently of
// keypoint_to_3d.cpp, as the tests' own model of a scanner re-sampling a surface.
inline std::optional<Eigen::VectorXd> bilinear(
    const keypoints::SphericalImages& im, double row, double column,
    const std::function<Eigen::VectorXd(Eigen::Index, Eigen::Index)>& value) {
    const auto r0 = static_cast<Eigen::Index>(std::floor(row));
    const auto c0 = static_cast<Eigen::Index>(std::floor(column));
    if (r0 < 0 || c0 < 0 || r0 + 1 >= im.rows || c0 + 1 >= im.columns) return std::nullopt;
    double lo = 1e300, hi = -1e300;
    for (int k = 0; k < 4; ++k) {
        const Eigen::Index r = r0 + k / 2, c = c0 + k % 2;
        if (!im.valid(r, c)) return std::nullopt;
        lo = std::min(lo, im.range(r, c));
        hi = std::max(hi, im.range(r, c));
    }
    if (hi - lo > 0.05) return std::nullopt;
    const double t = row - static_cast<double>(r0), u = column - static_cast<double>(c0);
    return (1 - t) * (1 - u) * value(r0, c0) + (1 - t) * u * value(r0, c0 + 1) +
           t * (1 - u) * value(r0 + 1, c0) + t * u * value(r0 + 1, c0 + 1);
}

// The scanner-frame point of a pixel, from its own range and angles.
inline Eigen::Vector3d pixel_point(const keypoints::SphericalImages& im, Eigen::Index r,
                                   Eigen::Index c) {
    return keypoints::cartesian_of({im.range(r, c), im.azimuth(r, c), im.elevation(r, c)});
}

// A second epoch as the scanner would record it on its own lattice: for every pixel of
// `im`, the surface point `surface(row', column')` (a sub-pixel position in `im`, found by
// `locate`) with the intensity there. Returned as a structured scan in the images'
// orientation (row 0 at the top), identity pose.
inline Scan resampled_scan(
    const keypoints::SphericalImages& im,
    const std::function<std::optional<std::array<double, 2>>(Eigen::Index, Eigen::Index)>& locate,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& move) {
    Scan out;
    out.source = "resampled";
    ScanGrid grid;
    grid.rows = static_cast<std::uint32_t>(im.rows);
    grid.columns = static_cast<std::uint32_t>(im.columns);
    const auto xyzi = [&](Eigen::Index r, Eigen::Index c) {
        Eigen::VectorXd v(4);
        v << pixel_point(im, r, c), im.intensity(r, c);
        return v;
    };
    for (Eigen::Index r = 0; r < im.rows; ++r)
        for (Eigen::Index c = 0; c < im.columns; ++c) {
            const auto at = locate(r, c);
            if (!at) continue;
            const auto v = bilinear(im, (*at)[0], (*at)[1], xyzi);
            if (!v) continue;
            out.xyz.push_back(move(v->head<3>()));
            out.intensity.push_back(static_cast<float>((*v)(3)));
            grid.row.push_back(static_cast<std::uint32_t>(r));
            grid.column.push_back(static_cast<std::uint32_t>(c));
        }
    out.grid = std::move(grid);
    return out;
}

}  // namespace tlsmon::test
