#include "simulator/render.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <numbers>

#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "simulator/random.hpp"
#include "simulator/ray_cast.hpp"

namespace tlsmon::sim {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kArcsec = kDeg / 3600.0;
constexpr std::uint64_t kNoiseStream = 0x6e6f697365ULL;

std::uint32_t steps(double lo, double hi, double step) {
    return static_cast<std::uint32_t>(std::floor((hi - lo) / step + 1e-9)) + 1;
}

struct CellPoint {
    std::uint32_t row;
    Eigen::Vector3d scanner_xyz;
    float intensity;
};

}  // namespace

GridShape grid_shape(const Scanner& s) {
    if (!(s.azimuth_step_deg > 0) || !(s.elevation_step_deg > 0) ||
        !(s.azimuth_max_deg > s.azimuth_min_deg) || !(s.elevation_max_deg > s.elevation_min_deg)) {
        throw Error("scanner window: steps must be > 0 and each maximum above its minimum");
    }
    return {steps(s.elevation_min_deg, s.elevation_max_deg, s.elevation_step_deg),
            steps(s.azimuth_min_deg, s.azimuth_max_deg, s.azimuth_step_deg)};
}

double cell_azimuth(const Scanner& s, std::uint32_t column) {
    return (s.azimuth_max_deg - column * s.azimuth_step_deg) * kDeg;
}

double cell_elevation(const Scanner& s, std::uint32_t row) {
    return (s.elevation_min_deg + row * s.elevation_step_deg) * kDeg;
}

RenderedScan render_epoch(const Site& site, int epoch, double hours, unsigned threads) {
    const Scanner& sc = site.scanner;
    const GridShape shape = grid_shape(sc);
    if (std::uint64_t{shape.rows} * shape.columns > max_scan_cells) {
        throw Error("scanner window gives " + std::to_string(shape.rows) + " x " +
                    std::to_string(shape.columns) + " cells, more than the " +
                    std::to_string(max_scan_cells / 1000000) + " M allowed");
    }
    RenderedScan out;
    out.epoch = epoch;
    out.hours = hours;
    out.pose_error = pose_error(site, epoch, hours);
    const Eigen::Affine3d nominal = nominal_pose(sc);
    // The beams leave the disturbed scanner: actual scanner -> project = N · E.
    const Eigen::Affine3d actual = nominal * out.pose_error.transform();
    const SceneAtEpoch scene(site, epoch, hours);
    const Noise& noise = site.noise;
    const Texture& tex = site.texture;

    // Readout directions: sines and cosines per row and per column, computed once.
    std::vector<double> sin_el(shape.rows), cos_el(shape.rows);
    for (std::uint32_t r = 0; r < shape.rows; ++r) {
        sin_el[r] = std::sin(cell_elevation(sc, r));
        cos_el[r] = std::cos(cell_elevation(sc, r));
    }
    const double sigma_angle = noise.enabled ? noise.angular_arcsec * kArcsec : 0.0;

    std::vector<std::vector<CellPoint>> columns(shape.columns);
    auto render_column = [&](std::uint32_t c) {
        Rng rng(hash_combine(
            hash_combine(hash_combine(noise.seed, kNoiseStream), static_cast<std::uint64_t>(epoch)),
            c));
        const double sa = std::sin(cell_azimuth(sc, c)), ca = std::cos(cell_azimuth(sc, c));
        std::vector<CellPoint>& col = columns[c];
        for (std::uint32_t r = 0; r < shape.rows; ++r) {
            const double se = sin_el[r], ce = cos_el[r];
            // Draw all random numbers of a cell unconditionally, so that one cell's outcome
            // never shifts the noise of the next.
            const double e_az = rng.normal(), e_el = rng.normal();
            const double e_r = rng.normal(), e_i = rng.normal();
            const Eigen::Vector3d readout(ce * ca, ce * sa, se);
            Eigen::Vector3d beam_dir = readout;
            if (sigma_angle > 0.0) {
                // d(φ + ε_φ, e + ε_e) to first order (ε ~ 1e-5 rad: the neglected second
                // order is ~1e-10 rad), then renormalised.
                beam_dir += sigma_angle * e_az * Eigen::Vector3d(-ce * sa, ce * ca, 0.0) +
                            sigma_angle * e_el * Eigen::Vector3d(-se * ca, -se * sa, ce);
                beam_dir.normalize();
            }
            const Eigen::Vector3d dir = actual.linear() * beam_dir;
            const Hit hit = cast_ray(scene, actual.translation(), dir, sc.max_range);
            if (hit.surface == Surface::none) continue;
            const double cos_incidence = std::abs(hit.normal.dot(dir));
            const double signal =
                hit.albedo * std::exp(-hit.range / tex.range_attenuation) * cos_incidence;
            if (signal < sc.min_return) continue;
            double range = hit.range;
            double intensity = signal;
            if (noise.enabled) {
                range += (noise.range_a + noise.range_b_ppm * 1e-6 * hit.range) * e_r;
                intensity += noise.intensity_sigma * e_i;
            }
            col.push_back(
                {r, range * readout, static_cast<float>(std::clamp(intensity, 0.0, 1.0))});
        }
    };

    parallel_for(shape.columns, [&](std::size_t c) { render_column(static_cast<std::uint32_t>(c)); },
                 threads);

    Scan& scan = out.scan;
    scan.name = sc.station;
    scan.pose = nominal;
    std::size_t total = 0;
    for (const auto& col : columns) total += col.size();
    scan.xyz.reserve(total);
    scan.intensity.reserve(total);
    ScanGrid grid;
    grid.rows = shape.rows;
    grid.columns = shape.columns;
    grid.row.reserve(total);
    grid.column.reserve(total);
    for (std::uint32_t c = 0; c < shape.columns; ++c) {
        for (const CellPoint& p : columns[c]) {
            scan.xyz.push_back(nominal * p.scanner_xyz);
            scan.intensity.push_back(p.intensity);
            grid.row.push_back(p.row);
            grid.column.push_back(c);
        }
        std::vector<CellPoint>().swap(columns[c]);
    }
    scan.grid = std::move(grid);
    return out;
}

}  // namespace tlsmon::sim
