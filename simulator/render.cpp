#include "simulator/render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>

#include "core/angles.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "simulator/footprint.hpp"
#include "simulator/footprint_albedo.hpp"
#include "simulator/random.hpp"
#include "simulator/range_noise.hpp"
#include "simulator/ray_cast.hpp"
#include "simulator/terrain.hpp"

namespace tlsmon::sim {

namespace {

constexpr double kArcsec = kDeg / 3600.0;
constexpr std::uint64_t kNoiseStream = 0x6e6f697365ULL;

std::uint32_t steps(double lo, double hi, double step) {
    return static_cast<std::uint32_t>(std::floor((hi - lo) / step + 1e-9)) + 1;
}

struct CellPoint {
    std::uint32_t row;
    Eigen::Vector3d scanner_xyz;
    float intensity;
    std::uint8_t surface;
};

// What one cell's beam returns before noise.
struct Return {
    bool hit = false;
    double range = 0.0;      // signal-weighted over the footprint, m
    double intensity = 0.0;  // noise-free
    double signal = 0.0;     // ρ·|cos α|, footprint-weighted
    bool mixed = false;
    Surface surface = Surface::none;  // the sub-ray surface returning the most power
};

// The surface element a sub-ray met (surface kind, face, target).
std::uint64_t surface_id(const Hit& h) {
    return ((static_cast<std::uint64_t>(h.surface) * 64 + static_cast<std::uint64_t>(h.face + 1)) *
                65536 +
            static_cast<std::uint64_t>(h.target + 1)) *
               65536 +
           static_cast<std::uint64_t>(h.part + 1);
}

Return thin_ray(const Hit& hit, const Eigen::Vector3d& dir, const Texture& tex) {
    Return r;
    if (hit.surface == Surface::none) return r;
    r.hit = true;
    r.surface = hit.surface;
    r.range = hit.range;
    r.signal = hit.albedo * std::abs(hit.normal.dot(dir));
    r.intensity = r.signal * std::exp(-hit.range / tex.range_attenuation);
    return r;
}

// The footprint integral (simulator/footprint.hpp). `centre` is the central ray's hit along
// `dir` (project frame); the sub-rays fan out about the scanner-frame beam direction
// `beam_dir` along `across` and `up` by the angular footprint radius at the central range.
// Adaptive: the centre and the triangle of ring rays are cast first; where all four meet the
// same surface (or all miss) they are the footprint (weights 1/2, 1/6, 1/6, 1/6: the same
// second moment), otherwise the other three ring rays are cast and the hexagon is used.
// Intensity: Σ wₖ ρₖ |cos αₖ| e^(−rₖ/r_att) over all sub-rays (misses return nothing).
// Range: the mean of rₖ weighted by the power each sub-ray returns, wₖ ρₖ |cos αₖ| / rₖ²
// (a phase meter sees the sum of the phasors; for spreads well below the modulation
// wavelength their phase is the power-weighted mean).
template <typename Cast>
Return footprint(const Hit& centre, const Eigen::Vector3d& beam_dir, const Eigen::Vector3d& across,
                 const Eigen::Vector3d& up, const Eigen::Matrix3d& to_project, const Beam& beam,
                 const Scanner& sc, const Texture& tex, Cast&& cast) {
    const auto& pattern = footprint_pattern();
    const double angle =
        footprint_angle(beam, centre.surface != Surface::none ? centre.range : sc.max_range);
    std::array<Hit, kSubRays> hits;
    std::array<Eigen::Vector3d, kSubRays> dirs;
    hits[0] = centre;
    dirs[0] = to_project * beam_dir;
    const auto cast_sub_ray = [&](std::size_t k) {
        const Eigen::Vector3d d =
            beam_dir + angle * (pattern[k].across * across + pattern[k].up * up);
        dirs[k] = to_project * d.normalized();
        hits[k] = cast(dirs[k]);
    };
    for (const std::size_t k : kTriangle) cast_sub_ray(k);
    bool uniform = true;
    for (const std::size_t k : kTriangle) {
        if (surface_id(hits[k]) != surface_id(centre)) uniform = false;
    }
    if (!uniform) {
        for (const std::size_t k : kTriangleComplement) cast_sub_ray(k);
    }

    // A footprint on one surface sees the texture integrated over the beam's Gaussian
    // profile, which for the sharp-edged features (joints, tie holes, checker edges) is the
    // texture blurred with σ = w/2 at the centre: all four sub-rays take that reflectance.
    // Their own samples would give the right second moment but pass an edge's high
    // frequencies (the centre alone carries half the weight), so a 2 cm joint sampled every
    // 1–1.5 cm would still alias into dashes fixed to the scan's lattice (a moiré that
    // slides along the joint when the joint moves across itself).
    const double filtered = uniform && centre.surface != Surface::none
                                ? footprint_albedo(centre, tex, 0.5 * angle * centre.range)
                                : -1.0;
    Return r;
    double power = 0.0, power_range = 0.0;
    double r_min = std::numeric_limits<double>::infinity(), r_max = -r_min;
    std::uint64_t first_id = 0;
    bool any = false, several = false;
    double strongest = -1.0;
    for (std::size_t k = 0; k < kSubRays; ++k) {
        const double w = uniform ? triangle_weight(k) : pattern[k].weight;
        const Hit& h = hits[k];
        if (w == 0.0 || h.surface == Surface::none) continue;
        const double s = (filtered >= 0.0 ? filtered : h.albedo) * std::abs(h.normal.dot(dirs[k]));
        r.signal += w * s;
        r.intensity += w * s * std::exp(-h.range / tex.range_attenuation);
        const double p = w * s / (h.range * h.range);
        power += p;
        power_range += p * h.range;
        r_min = std::min(r_min, h.range);
        r_max = std::max(r_max, h.range);
        if (p > strongest) {
            strongest = p;
            r.surface = h.surface;
        }
        const std::uint64_t id = surface_id(h);
        if (!any) first_id = id;
        any = true;
        if (id != first_id) several = true;
    }
    if (power <= 0.0) return r;
    r.hit = true;
    r.range = power_range / power;
    r.mixed = several && r_max - r_min > kMixedPixelSpread;
    return r;
}

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
    return render_epoch(site, epoch_conditions(site, epoch, hours), threads);
}

Scanner detail_scanner(const Scanner& overview, const DetailScan& d) {
    Scanner s = overview;
    s.first_column = s.first_row = 0;  // a lattice of its own
    s.azimuth_min_deg = d.azimuth_min_deg;
    s.azimuth_max_deg = d.azimuth_max_deg;
    s.elevation_min_deg = d.elevation_min_deg;
    s.elevation_max_deg = d.elevation_max_deg;
    s.azimuth_step_deg = s.elevation_step_deg = d.step_deg;
    s.details.clear();
    return s;
}

namespace {

RenderedScan render_grid(const Site& site, const Scanner& sc, std::uint64_t noise_stream,
                         const EpochConditions& conditions, unsigned threads) {
    const int epoch = conditions.epoch;
    const double hours = conditions.hours;
    const GridShape shape = grid_shape(sc);
    if (std::uint64_t{shape.rows} * shape.columns > max_scan_cells) {
        throw Error("scanner window gives " + std::to_string(shape.rows) + " x " +
                    std::to_string(shape.columns) + " cells, more than the " +
                    std::to_string(max_scan_cells / 1000000) + " M allowed");
    }
    validate_terrain(site.terrain);
    validate_occlusion(site.occlusion);
    RenderedScan out;
    out.epoch = epoch;
    out.hours = hours;
    out.pose_error = pose_error(site, epoch, hours);
    const Eigen::Affine3d nominal = nominal_pose(sc);
    // The beams leave the disturbed scanner: actual scanner -> project = N · E.
    const Eigen::Affine3d actual = nominal * out.pose_error.transform();
    const SceneAtEpoch scene(site, conditions);
    // The atmosphere scales every range (n_true / n_setting); the noise comes after.
    const double range_scale = conditions.atmosphere.range_scale;
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
    std::vector<std::uint64_t> mixed(shape.columns, 0);
    auto render_column = [&](std::uint32_t c) {
        // The overview keeps stream 0's seed; a detail scan draws from its own stream.
        std::uint64_t seed = hash_combine(noise.seed, kNoiseStream);
        if (noise_stream != 0) seed = hash_combine(seed, noise_stream);
        Rng rng(hash_combine(hash_combine(seed, static_cast<std::uint64_t>(epoch)),
                             std::uint64_t{c} + sc.first_column));
        // The rows below this window in its scan's column drew theirs first.
        for (std::uint64_t k = 0; k < 4 * std::uint64_t{sc.first_row}; ++k) rng.normal();
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
            Return ret;
            if (!site.beam.footprint) {
                ret = thin_ray(hit, dir, tex);
            } else {
                const Eigen::Vector3d across(-sa, ca, 0.0), up(-se * ca, -se * sa, ce);
                ret = footprint(hit, beam_dir, across, up, actual.linear(), site.beam, sc, tex,
                                [&](const Eigen::Vector3d& d) {
                                    return cast_ray(scene, actual.translation(), d, sc.max_range);
                                });
            }
            if (!ret.hit || ret.intensity < sc.min_return) continue;
            if (ret.mixed) ++mixed[c];
            double range = ret.range * range_scale;
            double intensity = ret.intensity;
            if (noise.enabled) {
                range += range_sigma(noise, ret.range, ret.signal) * e_r;
                intensity += noise.intensity_sigma * e_i;
            }
            col.push_back({r, range * readout, static_cast<float>(std::clamp(intensity, 0.0, 1.0)),
                           static_cast<std::uint8_t>(ret.surface)});
        }
    };

    parallel_for(
        shape.columns, [&](std::size_t c) { render_column(static_cast<std::uint32_t>(c)); },
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
    out.surface.reserve(total);
    for (std::uint32_t c = 0; c < shape.columns; ++c) {
        for (const CellPoint& p : columns[c]) {
            scan.xyz.push_back(nominal * p.scanner_xyz);
            scan.intensity.push_back(p.intensity);
            grid.row.push_back(p.row);
            grid.column.push_back(c);
            out.surface.push_back(p.surface);
            ++out.points_by_surface[p.surface];
        }
        std::vector<CellPoint>().swap(columns[c]);
    }
    scan.grid = std::move(grid);
    for (const std::uint64_t m : mixed) out.mixed_pixels += m;
    return out;
}

}  // namespace

RenderedScan render_epoch(const Site& site, const EpochConditions& conditions, unsigned threads) {
    return render_grid(site, site.scanner, 0, conditions, threads);
}

RenderedScan render_detail(const Site& site, std::size_t detail, const EpochConditions& conditions,
                           unsigned threads) {
    if (detail >= site.scanner.details.size())
        throw Error("no detail scan " + std::to_string(detail));
    RenderedScan out = render_grid(site, detail_scanner(site.scanner, site.scanner.details[detail]),
                                   detail + 1, conditions, threads);
    out.scan.name += "-" + site.scanner.details[detail].name;
    return out;
}

}  // namespace tlsmon::sim
