#pragma once
// The keypoint stage after registration on simulated series of the `pier` and `hochmosel`
// presets, side by side with M3C2 (and, on request, PB-M3C2) in the same zones: per zone and
// epoch the stage's figures, the truth and the epoch's realized registration error over the
// zone's area. Shared by the keypoint tests (tests/pipeline/test_keypoints_simulated.cpp) and the
// coverage bench over independent series (bench/keypoint_coverage.cpp).
//
// Each epoch renders the targets' windows at the preset's step (what the registration
// measures) and only the pier's south and west faces, at the preset's step (0.013°), or the
// preset's detail strip (tests/pipeline/simulated_windows.hpp). The atmosphere's range scales
// are the truth's (a site takes them from its weather station's air).
//
// Truth: the pier's displacement u_i at a point p of the zone (sim::pier_displacement; p
// stands for the material point, u varies by < 1e-5 over the millimetres it moved),
// (u_i(p) − u_0(p)) along the zone's wall directions, averaged over the zone's area as the
// reference saw it (its 0.25 m wall cells; algorithms/keypoints/zone_strata.hpp): the zone's
// displacement, not the mean over wherever its keypoints matched.
// Epoch 0 is not undeformed (docs/simulator.md): only differences are scored.
#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "algorithms/keypoints/zone_strata.hpp"
#include "core/statistics.hpp"
#include "pipeline/keypoint_results.hpp"
#include "pipeline/keypoint_stage.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/pbm3c2_stage.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/pipeline/simulated_windows.hpp"
#include "tests/support/pbm3c2_truth.hpp"
#include "tests/support/seconds_since.hpp"
#include "tests/support/simulated_targets.hpp"

namespace tlsmon::test {

// The preset's own step: at twice it (0.026°, 2.3 cm at 50 m, about the footprint's width)
// the intensity image is aliased and its sub-pixel shifts are biased by up to 0.2 pixel
// (5 mm) — a scanner for this method must sample the surface finer than its footprint.
constexpr double kFaceStepDeg = 0.013;

// The pier's two visible faces, 0.5 m inside their edges, in 10 m bands of the south face;
// M3C2 is scored side by side in the same zones with its estimated normals.
inline std::vector<ZoneShape> pier_zones(const sim::Site& site) {
    const auto& p = site.pier;
    std::vector<ZoneShape> zones;
    const ZoneShape south =
        box_zone("south", {p.x0 + 0.5, p.y0 - 0.5, 1.0}, {p.x1 - 0.5, p.y0 + 0.5, p.height - 1.0});
    zones.push_back(south);
    for (auto& b : bands_of(south, 2, 10.0, 0.0, p.height)) zones.push_back(b);
    zones.push_back(
        box_zone("west", {p.x0 - 0.5, p.y0 + 0.5, 1.0}, {p.x0 + 0.5, p.y1 - 0.5, p.height - 1.0}));
    return zones;
}

// `hochmosel`: the strip of the south face its detail scan covers (x ≈ 4.4–7.9 m at 0.005°),
// 0.3 m inside its sides, in 10 m bands up to 130 m: the top 10 m, in the deck's shadow and
// seen at 50°, hold too few keypoints (4–16 of 21 matches kept) for min_matches.
inline std::vector<ZoneShape> strip_zones(const sim::Site& site) {
    const auto& p = site.pier;
    const ZoneShape strip = box_zone("strip", {4.7, p.y0 - 0.5, 1.0}, {7.6, p.y0 + 0.5, 130.0});
    return bands_of(strip, 2, 10.0, 0.0, 130.0);
}

// A preset's series as the tests render it: the zones and the pier's scans of an epoch.
struct Scenario {
    sim::Site site;
    std::vector<ZoneShape> zones;
    WindowedEpoch (*render)(const sim::Site&, int, double) = nullptr;
    double image_step_deg = kFaceStepDeg;  // the pier's scans' step
    // The targets' variance factor (registration.covariance_scaling).
    registration::CovarianceScaling covariance_scaling = RegistrationConfig{}.covariance_scaling;
    double m3c2_stray_distance = M3c2Config{}.stray_distance;  // m3c2.stray_distance
};

inline WindowedEpoch render_faces(const sim::Site& site, int epoch, double hours) {
    return render_windows(site, epoch, hours, kFaceStepDeg);
}

inline Scenario pier_scenario() {
    Scenario s{sim::preset_pier(), {}, render_faces};
    s.zones = pier_zones(s.site);
    return s;
}

// `hochmosel`'s pier is scanned by its overview at 0.03° (52–92 mm at 100–175 m: every
// zone undersampled) and by the detail strip at 0.005°; the strip is what is rendered.
inline Scenario hochmosel_scenario() {
    Scenario s{sim::preset_hochmosel(), {}, render_detail_windows};
    s.zones = strip_zones(s.site);
    s.image_step_deg = s.site.scanner.details.front().step_deg;  // the strip's
    return s;
}

inline KeypointConfig keypoint_config(const Scenario& s) {
    KeypointConfig c;
    c.zones = s.zones;
    return c;
}

inline M3c2Config m3c2_config(const Scenario& s) {
    M3c2Config c;
    c.core_spacing = 1.0;
    c.normal_radii = {0.5, 1.0};
    c.cylinder_radius = 0.5;
    c.max_depth = 0.5;
    c.stray_distance = s.m3c2_stray_distance;
    c.zones = s.zones;
    return c;
}

// The stage's LoD95 of a zone quantity (keypoint_zone_results); NaN without one.
inline double lod_of(const std::string& zone, const keypoints::SegmentDisplacement& d,
                     const Eigen::Matrix3d& registration, const std::string& quantity) {
    for (const auto& row : keypoint_zone_results(zone, d, registration))
        if (row.quantity == quantity && row.uncertainty) return *row.uncertainty;
    return NAN;
}

// Each zone's area as the reference saw it: the centres of its wall cells holding reference
// points. A zone's displacement is the true change averaged over them, what the stage's
// strata stand for (zone_strata.hpp).
inline std::vector<std::vector<Eigen::Vector3d>> zone_cells(const KeypointConfig& config,
                                                            const KeypointReference& ref,
                                                            const std::vector<Scan>& reference) {
    std::vector<std::vector<Eigen::Vector3d>> cells;
    for (std::size_t z = 0; z < ref.walls.size(); ++z) {
        std::vector<Eigen::Vector3d> inside;
        for (const auto& scan : reference)
            for (const auto& p : scan.xyz)
                if (p.allFinite() && config.zones[z].contains(p)) inside.push_back(p);
        cells.push_back(keypoints::wall_cell_centres(inside, ref.walls[z]));
    }
    return cells;
}

// u in the wall's frame: (normal, h, v).
inline Eigen::Vector3d in_wall(const keypoints::WallFrame& w, const Eigen::Vector3d& u) {
    return {u.dot(w.normal), u.dot(w.horizontal), u.dot(w.vertical)};
}

// The mean of `change` (a 3D vector field) over a zone's cells, in the wall's frame: the
// zone's true displacement, or the registration's realized error over its area.
template <class Field>
Eigen::Vector3d zone_truth(const std::vector<Eigen::Vector3d>& cells, const keypoints::WallFrame& w,
                           const Field& change) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& c : cells) sum += in_wall(w, change(c));
    return sum / double(cells.size());
}

// A zone aggregate along the normals (M3C2's core points', PB-M3C2's patches' median or
// mean): the stage's row, the same aggregate of the true change at its places, and the
// registration's σ in its LoD and its realized error, both averaged over the places.
struct NormalFigure {
    double value = NAN, lod = NAN, truth = NAN;
    double registration_sigma = NAN, registration_error = NAN;
};

// One measuring place's truth along its normal, the registration's σ and realized error there.
struct NormalPlace {
    double truth, registration_sigma, registration_error;
};

// A zone's `method`_median_m and `method`_mean_m figures from the stage's rows and the places
// that gave them.
inline std::pair<NormalFigure, NormalFigure> normal_figures(
    const std::string& method, const std::string& zone, const std::vector<ZoneResult>& rows,
    const std::vector<NormalPlace>& places) {
    NormalFigure median, mean;
    if (places.empty()) return {median, mean};
    std::vector<double> t;
    double sigma = 0, error = 0;
    for (const auto& p : places)
        t.push_back(p.truth), sigma += p.registration_sigma, error += p.registration_error;
    const double n = double(places.size());
    for (NormalFigure* f : {&median, &mean})
        f->registration_sigma = sigma / n, f->registration_error = error / n;
    mean.truth = std::accumulate(t.begin(), t.end(), 0.0) / n;
    median.truth = tlsmon::median(std::move(t));
    for (const auto& row : rows) {
        if (row.zone != zone) continue;
        NormalFigure* f = row.quantity == method + "_median_m" ? &median
                          : row.quantity == method + "_mean_m" ? &mean
                                                               : nullptr;
        if (f) f->value = row.value, f->lod = row.uncertainty.value_or(NAN);
    }
    return {median, mean};
}

// One zone's figures in one epoch, with the truth.
struct ZoneFigure {
    int epoch = 0;
    std::string zone;
    std::size_t kept = 0;
    keypoints::SegmentDisplacement d;
    Eigen::Matrix3d registration = Eigen::Matrix3d::Zero();  // its covariance at the segment
    Eigen::Vector3d truth = Eigen::Vector3d::Constant(NAN);  // (normal, h, v)
    // The epoch's realized registration error averaged over the same area (normal, h, v).
    Eigen::Vector3d registration_error = Eigen::Vector3d::Constant(NAN);
    // The epoch's image on the reference's lattice at the zone: its shift, in pixels
    // (azimuth, elevation; docs/keypoints.md, "The lattice's phase").
    Eigen::Vector2d lattice_shift = Eigen::Vector2d::Constant(NAN);
    NormalFigure m3c2_median, m3c2_mean;
    NormalFigure pbm3c2_median, pbm3c2_mean;  // with run_series' `patches` only
};

struct Series {
    std::vector<ZoneFigure> figures;
    double keypoint_s = 0, m3c2_s = 0, pbm3c2_s = 0;
    std::size_t reference_keypoints = 0;
    std::vector<std::string> refused;  // the epochs the registration refused, and why
};

// The series at `hours` (the reference first); `patches`: PB-M3C2 beside M3C2 in the same
// zones (its defaults, on the reference's supervoxels).
inline Series run_series(const Scenario& scenario, const std::vector<double>& hours,
                         bool patches = false) {
    const sim::Site& site = scenario.site;
    RegistrationConfig targets = simulated_targets(site);
    targets.covariance_scaling = scenario.covariance_scaling;
    const KeypointConfig config = keypoint_config(scenario);
    const M3c2Config m3c2 = m3c2_config(scenario);
    PbM3c2Config pb;
    pb.zones = scenario.zones;
    const WindowedEpoch e0 = scenario.render(site, 0, hours[0]);
    const ReferenceTargets reference = measure_reference_targets(targets, e0.targets);
    Series out;
    auto t0 = std::chrono::steady_clock::now();
    const KeypointReference ref = prepare_keypoint_reference(config, e0.pier);
    out.reference_keypoints = ref.keypoints();
    const std::vector<std::vector<Eigen::Vector3d>> cells = zone_cells(config, ref, e0.pier);
    const M3c2Reference m3c2_ref = prepare_m3c2_reference(m3c2, e0.pier);
    const std::optional<PbM3c2Reference> pb_ref =
        patches ? std::optional(prepare_pbm3c2_reference(
                      pb, build_supervoxels(pb.segmentation, e0.pier), e0.pier))
                : std::nullopt;
    for (std::size_t i = 1; i < hours.size(); ++i) {
        const int epoch = static_cast<int>(i);
        const WindowedEpoch ei = scenario.render(site, epoch, hours[i]);
        std::string refused;
        const auto registered = registered_windows(targets, reference, e0, ei, refused);
        if (!registered) {
            out.refused.push_back("epoch " + std::to_string(epoch) + ": " + refused);
            continue;
        }
        const StageOutputs& o = *registered;
        const RegistrationError registration_error(site, e0.conditions, ei.conditions,
                                                   *o.to_reference);

        t0 = std::chrono::steady_clock::now();
        KeypointEpoch measured = measure_keypoints(config, ref, ei.pier, o);
        const KeypointSegmentsResult segments =
            keypoint_segments(config, ref, std::move(measured.matches), o);
        out.keypoint_s += seconds_since(t0);

        t0 = std::chrono::steady_clock::now();
        const M3c2Epoch m = measure_m3c2(m3c2, m3c2_ref, ei.pier, o);
        const std::vector<ZoneResult> m3c2_rows = m3c2_zone_results(m3c2, m3c2_ref, m);
        out.m3c2_s += seconds_since(t0);
        std::optional<PbM3c2Epoch> p;
        std::vector<ZoneResult> pb_rows;
        if (pb_ref) {
            t0 = std::chrono::steady_clock::now();
            p = measure_pbm3c2(pb, *pb_ref, ei.pier, o);
            pb_rows = pbm3c2_zone_results(*pb_ref, *p);
            out.pbm3c2_s += seconds_since(t0);
        }
        const auto true_change = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
            return sim::pier_displacement(site, x, epoch, ei.conditions.bending) -
                   sim::pier_displacement(site, x, 0, e0.conditions.bending);
        };
        const auto place = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& normal,
                               double registration_sigma) {
            return NormalPlace{true_change(x).dot(normal), registration_sigma,
                               registration_error(x).dot(normal)};
        };
        for (std::size_t z = 0; z < segments.segments.size(); ++z) {
            const auto& s = segments.segments[z];
            ZoneFigure f;
            f.epoch = epoch;
            f.zone = s.zone;
            f.d = s.displacement;
            f.kept = s.displacement.count;
            f.registration = s.registration_covariance;
            const auto& w = s.displacement.wall;
            if (s.displacement.defined() && w.defined() && !cells[z].empty()) {
                f.truth = zone_truth(cells[z], w, true_change);
                f.registration_error = zone_truth(cells[z], w, registration_error);
                f.lattice_shift = (seen_at(site, ei.conditions, w.centroid) -
                                   seen_at(site, e0.conditions, w.centroid)) /
                                  scenario.image_step_deg;
            }
            // M3C2 in the same zone, at the core points that gave a distance.
            std::vector<NormalPlace> cores;
            for (auto k : m3c2_ref.zone_cores[z])
                if (std::isfinite(m.distances[k].distance))
                    cores.push_back(place(m3c2_ref.reference.core_points()[k],
                                          m3c2_ref.reference.normals()[k],
                                          m.registration_sigma[k]));
            std::tie(f.m3c2_median, f.m3c2_mean) = normal_figures("m3c2", s.zone, m3c2_rows, cores);
            // PB-M3C2 in the same zone, at the patches that gave a distance.
            // Its zones follow the configuration's order, as the keypoint segments do.
            if (pb_ref) {
                std::vector<NormalPlace> measured_patches;
                for (auto k : pb_ref->zone_patches[z])
                    if (std::isfinite(p->results[k].distance.distance))
                        measured_patches.push_back(place(pb_ref->measured_at(k, &p->results[k]),
                                                         pb_ref->patches[k].frame.normal,
                                                         p->registration_sigma[k]));
                std::tie(f.pbm3c2_median, f.pbm3c2_mean) =
                    normal_figures("pbm3c2", s.zone, pb_rows, measured_patches);
                // The median's truth is over the zone's area, as the row's value.
                if (!measured_patches.empty())
                    f.pbm3c2_median.truth = areal_median_truth(*pb_ref, *p, z, true_change);
            }
            out.figures.push_back(std::move(f));
        }
    }
    return out;
}

}  // namespace tlsmon::test
