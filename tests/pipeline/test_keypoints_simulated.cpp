// The keypoint stage after registration on simulated series of the `pier` preset (issue 12's
// acceptance), side by side with M3C2 in the same zones: per zone, the displacement along
// the surface (horizontal and vertical in the wall) against the truth, with the mean number
// of matches kept; and in a series without deformation, no zone beyond 3σ.
//
// Each epoch renders the targets' windows at the preset's step (what the registration
// measures) and only the pier's south and west faces, at the preset's step (0.013°): the same
// geometry, beam, texture, noise, scanner drift and air as a full epoch, in about 10 s of
// rendering instead of 25. The atmosphere's range scales are the truth's (a site takes them
// from its weather station's air). The west face is seen at 87°: its matches are grazing
// (keypoints.max_incidence_deg) and it stays undefined.
//
// Truth: the pier's displacement u_i at a point p of the zone (sim::pier_displacement; p
// stands for the material point, u varies by < 1e-5 over the millimetres it moved),
// (u_i(p) − u_0(p)) along the zone's wall directions, averaged over the zone's area as the
// reference saw it (its 0.25 m wall cells; algorithms/keypoints/zone_strata.hpp): the zone's
// displacement, not the mean over wherever its keypoints matched.
// Epoch 0 is not undeformed (docs/simulator.md): only differences are scored.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

#include "algorithms/keypoints/zone_strata.hpp"
#include "pipeline/keypoint_results.hpp"
#include "pipeline/keypoint_stage.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/pipeline/simulated_windows.hpp"
#include "tests/support/simulated_targets.hpp"

namespace tlsmon {
namespace {

// The preset's own step: at twice it (0.026°, 2.3 cm at 50 m, about the footprint's width)
// the intensity image is aliased and its sub-pixel shifts are biased by up to 0.2 pixel
// (5 mm) — a scanner for this method must sample the surface finer than its footprint.
constexpr double kFaceStepDeg = 0.013;

// The pier's two visible faces, 0.5 m inside their edges, in 10 m bands of the south face;
// M3C2 is scored side by side in the same zones with its estimated normals.
std::vector<ZoneShape> pier_zones(const sim::Site& site) {
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
std::vector<ZoneShape> strip_zones(const sim::Site& site) {
    const auto& p = site.pier;
    const ZoneShape strip = box_zone("strip", {4.7, p.y0 - 0.5, 1.0}, {7.6, p.y0 + 0.5, 130.0});
    return bands_of(strip, 2, 10.0, 0.0, 130.0);
}

// A preset's series as the tests render it: the zones and the pier's scans of an epoch.
struct Scenario {
    sim::Site site;
    std::vector<ZoneShape> zones;
    test::WindowedEpoch (*render)(const sim::Site&, int, double) = nullptr;
};

test::WindowedEpoch render_faces(const sim::Site& site, int epoch, double hours) {
    return test::render_windows(site, epoch, hours, kFaceStepDeg);
}

Scenario pier_scenario() {
    Scenario s{sim::preset_pier(), {}, render_faces};
    s.zones = pier_zones(s.site);
    return s;
}

// `hochmosel`'s pier is scanned by its overview at 0.03° (52–92 mm at 100–175 m: every
// zone undersampled) and by the detail strip at 0.005°; the strip is what is rendered.
Scenario hochmosel_scenario() {
    Scenario s{sim::preset_hochmosel(), {}, test::render_detail_windows};
    s.zones = strip_zones(s.site);
    return s;
}

KeypointConfig keypoint_config(const Scenario& s) {
    KeypointConfig c;
    c.zones = s.zones;
    return c;
}

M3c2Config m3c2_config(const Scenario& s) {
    M3c2Config c;
    c.core_spacing = 1.0;
    c.normal_radii = {0.5, 1.0};
    c.cylinder_radius = 0.5;
    c.max_depth = 0.5;
    c.zones = s.zones;
    return c;
}

using Epoch = test::WindowedEpoch;

// The stage's LoD95 of a zone quantity (keypoint_zone_results); NaN without one.
double lod_of(const std::string& zone, const keypoints::SegmentDisplacement& d,
              const Eigen::Matrix3d& registration, const std::string& quantity) {
    for (const auto& row : keypoint_zone_results(zone, d, registration))
        if (row.quantity == quantity && row.uncertainty) return *row.uncertainty;
    return NAN;
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
    double m3c2_median = NAN, m3c2_truth = NAN, m3c2_lod = NAN;
};

struct Series {
    std::vector<ZoneFigure> figures;
    double keypoint_s = 0, m3c2_s = 0;
    std::size_t reference_keypoints = 0;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Series run_series(const Scenario& scenario, const std::vector<double>& hours) {
    const sim::Site& site = scenario.site;
    const RegistrationConfig targets = test::simulated_targets(site);
    const KeypointConfig config = keypoint_config(scenario);
    const M3c2Config m3c2 = m3c2_config(scenario);
    const Epoch e0 = scenario.render(site, 0, hours[0]);
    const ReferenceTargets reference = measure_reference_targets(targets, e0.targets);
    Series out;
    auto t0 = std::chrono::steady_clock::now();
    const KeypointReference ref = prepare_keypoint_reference(config, e0.pier);
    out.reference_keypoints = ref.keypoints();
    // Each zone's area as the reference saw it (its wall cells): the zone's displacement is
    // the true change averaged over them, what the stage's strata stand for (zone_strata.hpp).
    std::vector<std::vector<Eigen::Vector3d>> cells;
    for (std::size_t z = 0; z < ref.walls.size(); ++z) {
        std::vector<Eigen::Vector3d> inside;
        for (const auto& scan : e0.pier)
            for (const auto& p : scan.xyz)
                if (p.allFinite() && config.zones[z].contains(p)) inside.push_back(p);
        cells.push_back(keypoints::wall_cell_centres(inside, ref.walls[z]));
    }
    const M3c2Reference m3c2_ref = prepare_m3c2_reference(m3c2, e0.pier);
    for (std::size_t i = 1; i < hours.size(); ++i) {
        const int epoch = static_cast<int>(i);
        const Epoch ei = scenario.render(site, epoch, hours[i]);
        const auto registered = test::registered_outputs(targets, reference, e0, ei, epoch);
        if (!registered) continue;
        const StageOutputs& o = *registered;

        t0 = std::chrono::steady_clock::now();
        KeypointEpoch measured = measure_keypoints(config, ref, ei.pier, o);
        const KeypointSegmentsResult segments =
            keypoint_segments(config, ref, std::move(measured.matches), o);
        out.keypoint_s += seconds_since(t0);

        t0 = std::chrono::steady_clock::now();
        const M3c2Epoch m = measure_m3c2(m3c2, m3c2_ref, ei.pier, o);
        out.m3c2_s += seconds_since(t0);
        const auto true_change = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
            return sim::pier_displacement(site, p, epoch, ei.conditions.bending) -
                   sim::pier_displacement(site, p, 0, e0.conditions.bending);
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
                Eigen::Vector3d sum = Eigen::Vector3d::Zero(), reg = Eigen::Vector3d::Zero();
                const auto in_wall = [&](const Eigen::Vector3d& u) {
                    return Eigen::Vector3d(u.dot(w.normal), u.dot(w.horizontal), u.dot(w.vertical));
                };
                for (const Eigen::Vector3d& c : cells[z]) {
                    sum += in_wall(true_change(c));
                    reg += in_wall(test::registration_error_at(site, e0.conditions, ei.conditions,
                                                               *o.to_reference, c));
                }
                f.truth = sum / double(cells[z].size());
                f.registration_error = reg / double(cells[z].size());
                // The bands with enough kept matches hold most of the zone's area (all of the
                // pier's faces; the top of the far strip the least).
                EXPECT_GT(s.displacement.covered_area_share, 0.5) << s.zone;
                std::printf("%s: the figures stand for %.0f %% of the zone's area\n",
                            s.zone.c_str(), 100 * s.displacement.covered_area_share);
            }
            // M3C2 in the same zone: its median and the truth's median along the normals.
            std::vector<double> d, t;
            for (auto k : m3c2_ref.zone_cores[z]) {
                const auto& dist = m.distances[k];
                if (!std::isfinite(dist.distance)) continue;
                const Eigen::Vector3d& c = m3c2_ref.reference.core_points()[k];
                const Eigen::Vector3d& nrm = m3c2_ref.reference.normals()[k];
                d.push_back(dist.distance);
                t.push_back(true_change(c).dot(nrm));
            }
            for (const auto& row : m3c2_zone_results(m3c2, m3c2_ref, m)) {
                if (row.zone == s.zone && row.quantity == "m3c2_median_m") {
                    f.m3c2_median = row.value;
                    f.m3c2_lod = row.uncertainty.value_or(NAN);
                }
            }
            if (!t.empty()) {
                std::sort(t.begin(), t.end());
                f.m3c2_truth =
                    t.size() % 2 ? t[t.size() / 2] : 0.5 * (t[t.size() / 2 - 1] + t[t.size() / 2]);
            }
            out.figures.push_back(std::move(f));
        }
    }
    return out;
}

struct Score {
    double sum2 = 0, bias = 0, worst = 0;
    int n = 0;
    void add(double e) {
        sum2 += e * e;
        bias += e;
        worst = std::max(worst, std::abs(e));
        ++n;
    }
    double rms() const { return std::sqrt(sum2 / n); }
};

void print_score(const char* what, const Score& s) {
    std::printf("%-34s bias %+.3f mm, RMS %.3f mm, max %.3f mm over %d zone epochs\n", what,
                1e3 * s.bias / s.n, 1e3 * s.rms(), 1e3 * s.worst, s.n);
}

// The keypoints' own standard error against their error less the epoch's realized
// registration error, which every zone of the epoch shares (test::registration_error_at): what
// the matches claim of themselves, apart from the datum. RMS(e/SE) at most 2: with the kept
// matches' s/√n it was 1.6–3.5 on these series, with the trimmed mean's 0.73–1.59
// (docs/keypoints.md, "The matches' own σ").
struct OwnScore {
    int n = 0, within = 0;
    double sum_z2 = 0;
    void add(double z) {
        ++n;
        within += std::abs(z) <= 1.96;
        sum_z2 += z * z;
    }
    double rms() const { return std::sqrt(sum_z2 / n); }
    void check(const char* what) const {
        std::printf(
            "own standard error, the registration's realized error out, %s: within 1.96 SE %d of "
            "%d, RMS(e/SE) %.2f\n",
            what, within, n, rms());
        EXPECT_LE(rms(), 2.0) << what;
    }
};

// The acceptance over `hours`: every zone but the grazing "west" defined, along the surface
// within 1.0 mm RMS of the truth in h and v; printed beside M3C2's medians. Returns the
// number of zone epochs scored.
int check_along_surface(const Scenario& scenario, const std::vector<double>& hours) {
    const Series s = run_series(scenario, hours);
    std::printf("reference: %zu keypoints; keypoint stage %.1f s, M3C2 %.1f s over %zu epochs\n",
                s.reference_keypoints, s.keypoint_s, s.m3c2_s, hours.size() - 1);
    std::printf(
        "epoch zone          kept | along h: kp  truth | along v: kp  truth | normal: kp  truth "
        "  M3C2  truth | σ_h LoD95 (mm)\n");
    Score h, v, normal, m3c2;
    std::map<std::string, std::pair<double, int>> kept;
    double largest = 0;
    int lod_covers = 0, lod_rows = 0;
    OwnScore own[2];  // h, v
    for (const auto& f : s.figures) {
        const auto& d = f.d;
        std::printf(
            "%d  %-14s %4zu | %+6.2f %+6.2f | %+6.2f %+6.2f | %+6.2f %+6.2f  %+6.2f %+6.2f | "
            "%.2f %.2f\n",
            f.epoch, f.zone.c_str(), f.kept, 1e3 * d.along[1], 1e3 * f.truth[1], 1e3 * d.along[2],
            1e3 * f.truth[2], 1e3 * d.along[0], 1e3 * f.truth[0], 1e3 * f.m3c2_median,
            1e3 * f.m3c2_truth, 1e3 * d.along_standard_error[1],
            1e3 * lod_of(f.zone, d, f.registration, kKeypointAlongSurfaceH));
        kept[f.zone].first += double(f.kept);
        kept[f.zone].second += 1;
        if (f.zone == "west") {
            EXPECT_FALSE(d.defined()) << "the grazing west face gave a displacement";
            continue;
        }
        EXPECT_TRUE(d.defined()) << f.zone << " epoch " << f.epoch << ": " << d.undefined_reason;
        if (!d.defined()) continue;
        EXPECT_TRUE(f.truth.allFinite()) << f.zone;
        if (!f.truth.allFinite()) continue;
        h.add(d.along[1] - f.truth[1]);
        v.add(d.along[2] - f.truth[2]);
        normal.add(d.along[0] - f.truth[0]);
        m3c2.add(f.m3c2_median - f.m3c2_truth);
        largest = std::max({largest, std::abs(f.truth[1]), std::abs(f.truth[2])});
        for (int k = 1; k < 3; ++k) {
            own[k - 1].add((d.along[k] - f.truth[k] - f.registration_error[k]) /
                           d.along_standard_error[k]);
            ++lod_rows;
            lod_covers += std::abs(d.along[k] - f.truth[k]) <=
                          lod_of(f.zone, d, f.registration,
                                 k == 1 ? kKeypointAlongSurfaceH : kKeypointAlongSurfaceV);
        }
    }
    for (const auto& [zone, sum] : kept)
        std::printf("mean matches kept, %-14s %.0f\n", zone.c_str(), sum.first / sum.second);
    print_score("keypoints, along the surface h", h);
    print_score("keypoints, along the surface v", v);
    print_score("keypoints, along the normal", normal);
    print_score("M3C2 median, along the normal", m3c2);
    std::printf("LoD95 covers the error in %d of %d along-surface figures\n", lod_covers, lod_rows);
    own[0].check("along h"), own[1].check("along v");
    EXPECT_LE(h.rms(), 0.001);
    EXPECT_LE(v.rms(), 0.001);
    // The truth moves by millimetres along the surface: the test measures something.
    EXPECT_GT(largest, 0.001);
    return h.n;
}

// Without deformation every stored figure with a σ (the vector's components and along the
// wall; σ = LoD95 / 1.96, the standard error and the registration's in quadrature) within 3σ of
// zero. Returns the number of figures.
int check_no_movement(Scenario scenario, const std::vector<double>& hours) {
    scenario.site.deformation.enabled = false;
    scenario.site.noise.seed = 5;
    const Series s = run_series(scenario, hours);
    int rows = 0;
    double worst = 0;
    OwnScore own[2];  // h, v
    for (const auto& f : s.figures) {
        EXPECT_EQ(f.d.defined(), f.zone != "west") << f.zone << ": " << f.d.undefined_reason;
        const Eigen::Vector3d h = f.d.wall.horizontal;
        std::printf("epoch %d %-14s kept %zu: h %+.2f v %+.2f n %+.2f mm (σ_h %.2f, reg %.2f)\n",
                    f.epoch, f.zone.c_str(), f.kept, 1e3 * f.d.along[1], 1e3 * f.d.along[2],
                    1e3 * f.d.along[0], 1e3 * f.d.along_standard_error[1],
                    h.allFinite() ? 1e3 * std::sqrt(h.dot(f.registration * h)) : NAN);
        for (int k = 1; k < 3 && f.d.defined() && f.registration_error.allFinite(); ++k)
            own[k - 1].add((f.d.along[k] - f.registration_error[k]) / f.d.along_standard_error[k]);
        for (const auto& row : keypoint_zone_results(f.zone, f.d, f.registration)) {
            if (!row.uncertainty) continue;
            const double sigma = *row.uncertainty / 1.96;
            const double ratio = std::abs(row.value) / sigma;
            worst = std::max(worst, ratio);
            ++rows;
            EXPECT_LE(ratio, 3.0) << "epoch " << f.epoch << " " << f.zone << " " << row.quantity
                                  << " = " << 1e3 * row.value << " mm, σ " << 1e3 * sigma << " mm";
        }
    }
    std::printf("no deformation: %d figures, the largest |value| / σ = %.2f\n", rows, worst);
    own[0].check("along h"), own[1].check("along v");
    return rows;
}

// Morning to afternoon: the sun on the south and west faces bends the pier by millimetres,
// along the south face too (ΔT between the west and east faces).
TEST(KeypointsSimulated, AlongTheSurfaceWithin1MmRmsOfTheTruthSideBySideWithM3c2) {
    EXPECT_EQ(check_along_surface(pier_scenario(), {0.0, 3.0, 6.0, 9.0}),
              3 * 5);  // 3 epochs x (the face and its 4 bands)
}

TEST(KeypointsSimulated, WithoutDeformationNoZoneExceeds3Sigma) {
    // 2 epochs x the face and its 4 bands x 6 figures with a σ
    EXPECT_EQ(check_no_movement(pier_scenario(), {0.0, 4.0, 8.0}), 2 * 5 * 6);
}

// The 140 m pier at 100–175 m, through its detail strip: 13 bands of 10 m.
TEST(KeypointsSimulated, HochmoselAlongTheSurfaceWithin1MmRmsOfTheTruthSideBySideWithM3c2) {
    EXPECT_EQ(check_along_surface(hochmosel_scenario(), {0.0, 3.0, 6.0}), 2 * 13);
}

TEST(KeypointsSimulated, HochmoselWithoutDeformationNoZoneExceeds3Sigma) {
    EXPECT_EQ(check_no_movement(hochmosel_scenario(), {0.0, 4.0}), 1 * 13 * 6);
}

}  // namespace
}  // namespace tlsmon
