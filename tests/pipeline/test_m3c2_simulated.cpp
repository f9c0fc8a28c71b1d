// M3C2 after registration on simulated series of the `pier` preset (issue 11's acceptance):
// per-zone medians and means against the truth on whole faces, and the honesty of the LoD in
// a series without deformation. Each epoch renders the targets' windows and the pier's faces
// at a coarser 0.05° (4–5 cm at 45–60 m; tests/pipeline/simulated_windows.hpp). The atmosphere's
// range scales are the truth's (a site takes them from its weather station's air,
// docs/registration.md).
//
// Truth: the pier's displacement u_i at a core point c (sim::pier_displacement; c stands for
// the material point: u varies by < 1e-5 over the millimetres it moved); the true change
// along the core point's normal n is (u_i(c) − u_0(c))·n, and a zone's true value is its
// median over the zone's valid core points. Epoch 0 is not undeformed (docs/simulator.md):
// only differences are scored.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "algorithms/m3c2/distance.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/pipeline/registered_outputs.hpp"
#include "tests/support/simulated_targets.hpp"
#include "tests/support/simulated_zones.hpp"

namespace tlsmon {
namespace {

// The zones of tests/support/simulated_zones.hpp (whole faces with their design normals;
// the cylinders at an edge take in the other face, and max_roughness leaves them out).
M3c2Config m3c2_config(const sim::Site& site) {
    M3c2Config c;
    c.core_spacing = 1.0;
    c.normal_radii = {0.5, 1.0};
    c.cylinder_radius = 0.5;
    c.max_depth = 0.5;
    c.min_points = 10;
    c.zones = test::simulated_pier_zones(site);
    return c;
}

using Epoch = test::WindowedEpoch;

Epoch render(const sim::Site& site, int epoch, double hours) {
    return test::render_windows(site, epoch, hours, 0.05);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mean(const std::vector<double>& v) {
    double sum = 0;
    for (double x : v) sum += x;
    return sum / double(v.size());
}

struct Series {
    std::vector<ZoneResult> rows;  // every epoch's zone rows, epochs 1.., in order
    std::vector<int> row_epoch;
    std::vector<double> truth;  // per row: the zone's true median change (m3c2_median_m rows)
    std::size_t cores = 0, valid = 0, within = 0;
    double lod_sum = 0;
    std::vector<double> south_ratio;  // |d − truth| / LoD95 at the south face's core points
    // The same with the registration's σ added in quadrature, 1.96·√(σ_s² + σ_reg²), in
    // place of Lague's linear sum 1.96·(σ_s + σ_reg).
    std::vector<double> south_ratio_quadrature;
    std::size_t within_quadrature = 0;
};

// Core point k's LoD95 with the registration's σ in quadrature.
double lod_quadrature(const M3c2Epoch& m, const M3c2Reference& ref, std::size_t k) {
    const double s = m3c2::sampling_sigma(ref.reference.reference_side[k], m.compared[k]);
    return 1.96 * std::hypot(s, m.registration_sigma[k]);
}

// Epochs 0..hours.size()-1 at those hours; epoch 0 is the reference.
Series run_series(const sim::Site& site, const std::vector<double>& hours) {
    const RegistrationConfig targets = test::simulated_targets(site);
    const M3c2Config config = m3c2_config(site);
    const Epoch e0 = render(site, 0, hours[0]);
    const ReferenceTargets reference = measure_reference_targets(targets, e0.targets);
    const M3c2Reference ref = prepare_m3c2_reference(config, e0.pier);
    Series out;
    for (std::size_t i = 1; i < hours.size(); ++i) {
        const Epoch ei = render(site, static_cast<int>(i), hours[i]);
        const auto registered =
            test::registered_outputs(targets, reference, e0, ei, static_cast<int>(i));
        if (!registered) continue;
        const StageOutputs& o = *registered;
        const M3c2Epoch m = measure_m3c2(config, ref, ei.pier, o);
        // True change along each core point's normal.
        std::vector<double> truth(ref.reference.size(), std::nan(""));
        for (std::size_t k = 0; k < truth.size(); ++k) {
            const Eigen::Vector3d& c = ref.reference.core_points()[k];
            const Eigen::Vector3d& n = ref.reference.normals()[k];
            if (!n.allFinite()) continue;
            const Eigen::Vector3d du =
                sim::pier_displacement(site, c, static_cast<int>(i), ei.conditions.bending) -
                sim::pier_displacement(site, c, 0, e0.conditions.bending);
            truth[k] = du.dot(n);
        }
        for (std::size_t k = 0; k < m.distances.size(); ++k) {
            ++out.cores;
            const auto& d = m.distances[k];
            if (!std::isfinite(d.distance)) continue;
            ++out.valid;
            out.lod_sum += d.lod;
            out.within += std::abs(d.distance - truth[k]) <= d.lod;
            out.within_quadrature += std::abs(d.distance - truth[k]) <= lod_quadrature(m, ref, k);
        }
        for (auto k : ref.zone_cores[0]) {
            const auto& d = m.distances[k];
            if (std::isfinite(d.distance)) {
                out.south_ratio.push_back(std::abs(d.distance - truth[k]) / d.lod);
                out.south_ratio_quadrature.push_back(std::abs(d.distance - truth[k]) /
                                                     lod_quadrature(m, ref, k));
            }
        }
        for (const auto& row : m3c2_zone_results(config, ref, m)) {
            out.rows.push_back(row);
            out.row_epoch.push_back(static_cast<int>(i));
            double t = std::nan("");
            if (row.quantity == "m3c2_median_m" || row.quantity == "m3c2_mean_m") {
                const auto z = std::find(ref.zone_names.begin(), ref.zone_names.end(), row.zone) -
                               ref.zone_names.begin();
                std::vector<double> v;
                for (auto k : ref.zone_cores[z]) {
                    if (std::isfinite(m.distances[k].distance)) v.push_back(truth[k]);
                }
                t = row.quantity == "m3c2_mean_m" ? mean(v) : median(v);
            }
            out.truth.push_back(t);
        }
    }
    return out;
}

// Bias, RMS and largest error of a quantity's rows against the truth, over `zones`.
struct Score {
    double bias = 0, rms = 0, worst = 0;
    int n = 0;
};

Score score(const Series& s, const std::string& quantity, bool west) {
    Score out;
    for (std::size_t r = 0; r < s.rows.size(); ++r) {
        const auto& row = s.rows[r];
        if (row.quantity != quantity || (row.zone == "west") != west) continue;
        const double error = row.value - s.truth[r];
        std::printf(
            "epoch %d %-14s %s %+.3f mm, truth %+.3f mm, error %+.3f mm, LoD %.3f mm, "
            "%lld core points\n",
            s.row_epoch[r], row.zone.c_str(), quantity.c_str(), 1e3 * row.value, 1e3 * s.truth[r],
            1e3 * error, 1e3 * row.uncertainty.value_or(0), static_cast<long long>(row.n));
        out.rms += error * error;
        out.bias += error;
        out.worst = std::max(out.worst, std::abs(error));
        ++out.n;
    }
    out.rms = std::sqrt(out.rms / out.n);
    out.bias /= out.n;
    std::printf("%s zones, %s: bias %+.3f mm, RMS %.3f mm, max %.3f mm over %d rows\n",
                west ? "west face (grazing)" : "south face", quantity.c_str(), 1e3 * out.bias,
                1e3 * out.rms, 1e3 * out.worst, out.n);
    return out;
}

// Whole faces, edges included: the median and the mean of each zone (the mean is what a
// straddling cylinder at an edge would spoil).
TEST(M3c2Simulated, ZoneMediansAndMeansMatchTheTruthOnWholeFaces) {
    const sim::Site site = sim::preset_pier();
    // Morning to afternoon: the sun on the south and west faces bends the pier by millimetres.
    const Series s = run_series(site, {0.0, 3.0, 6.0, 9.0});
    for (const char* quantity : {"m3c2_median_m", "m3c2_mean_m"}) {
        const Score south = score(s, quantity, false);
        ASSERT_EQ(south.n, 3 * 5);  // 3 epochs x (the face and its 4 bands)
        EXPECT_LE(south.rms, 0.0005) << quantity;
        // The grazing west face (87°) is not a face seen by the scanner: its figures are
        // reported, and held to twice the bound.
        const Score west = score(s, quantity, true);
        ASSERT_EQ(west.n, 3);
        EXPECT_LE(west.rms, 0.001) << quantity;
    }
    // The truth changes by millimetres over the day: the test measures something.
    double largest = 0;
    for (double t : s.truth) {
        if (std::isfinite(t)) largest = std::max(largest, std::abs(t));
    }
    EXPECT_GT(largest, 0.001);
}

TEST(M3c2Simulated, WithoutDeformationTheLodHoldsAtLeast95PercentOfCorePoints) {
    sim::Site site = sim::preset_pier();
    site.deformation.enabled = false;
    site.noise.seed = 5;
    const Series s = run_series(site, {0.0, 4.0, 8.0});
    ASSERT_GT(s.valid, 1000u);
    // Nothing moved: a core point is within its LoD exactly when it is not significant.
    const auto within = [&](const std::string& zone) {
        double in = 0, all = 0;
        for (const auto& row : s.rows) {
            if (row.zone != zone || row.quantity != "m3c2_significant_share") continue;
            in += (1.0 - row.value) * double(row.n);
            all += double(row.n);
        }
        return in / all;
    };
    const double south = within("south"), west = within("west");
    std::printf(
        "no deformation: %zu of %zu core points valid, %.1f %% with |d| <= LoD95 "
        "(mean LoD95 %.3f mm); south face %.1f %%, west face (grazing) %.1f %%\n",
        s.valid, s.cores, 100.0 * double(s.within) / double(s.valid),
        1e3 * s.lod_sum / double(s.valid), 100 * south, 100 * west);
    // How far inside: the 95th percentile of |d| / LoD95 on the south face (1 = honest).
    std::vector<double> ratio = s.south_ratio;
    std::sort(ratio.begin(), ratio.end());
    std::printf("south face: 95th percentile of |d| / LoD95 = %.2f\n",
                ratio[static_cast<std::size_t>(0.95 * double(ratio.size() - 1))]);
    // Lague's linear sum against the quadratic one (docs/m3c2.md, "Level of detection").
    std::vector<double> q = s.south_ratio_quadrature;
    std::sort(q.begin(), q.end());
    std::printf(
        "registration σ in quadrature: %.1f %% of core points with |d| <= LoD95; south face: "
        "95th percentile of |d| / LoD95 = %.2f\n",
        100.0 * double(s.within_quadrature) / double(s.valid),
        q[static_cast<std::size_t>(0.95 * double(q.size() - 1))]);
    // Both faces: on the grazing one (87°) with its design normal; an estimated normal
    // leans there (its cylinders hold one or two scan columns) and covered only about half.
    EXPECT_GE(south, 0.95);
    EXPECT_GE(west, 0.95);
}

// The grazing west face (87°) at the scanner's own step, 0.013°, registered by the exact map so
// that only M3C2's own error is left. Along the face's far edge the beams straddle the
// silhouette and return blends of the face and what lies beyond it, and which beams do so
// changes with the grid's phase on the edge from epoch to epoch. With the points at a depth
// discontinuity left out (pipeline/m3c2_stage.hpp, m3c2_cloud) the zone's median is within
// 0.02 mm of the truth in each of three epochs (+0.005, +0.006, −0.005 mm); with them it was
// +0.096, +0.084 and +0.021 mm off, every epoch towards the scanner (docs/m3c2.md, "Edge
// points").
TEST(M3c2Simulated, GrazingFaceAtTheScannersStepIsMeasuredWithoutItsEdgeBlends) {
    const sim::Site site = sim::preset_pier();
    const auto& p = site.pier;
    const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
    // The window around the face, its silhouette and what lies behind it.
    test::Window window{360, -360, 90, -90};
    for (double y : {p.y0, p.y1}) {
        for (double z : {0.0, p.height}) {
            const Eigen::Vector2d a = test::seen_at(site, c0, {p.x0, y, z});
            window.azimuth_min = std::min(window.azimuth_min, a.x() - 0.3);
            window.azimuth_max = std::max(window.azimuth_max, a.x() + 0.3);
            window.elevation_min = std::min(window.elevation_min, a.y() - 0.5);
            window.elevation_max = std::max(window.elevation_max, a.y() + 0.5);
        }
    }
    M3c2Config config;
    for (const auto& z : test::simulated_pier_zones(site)) {
        if (z.name == "west") config.zones.push_back(z);
    }
    const Scan s0 = test::render_window(site, c0, 0.013, window);
    const M3c2Reference ref = prepare_m3c2_reference(config, {s0});
    ASSERT_GT(ref.zone_cores[0].size(), 100u);
    double worst = 0, largest_change = 0;
    for (int e = 1; e <= 3; ++e) {
        const sim::EpochConditions ce = sim::epoch_conditions(site, e, 3.0 * e);
        const Scan se = test::render_window(site, ce, 0.013, window);
        const M3c2Epoch m = measure_m3c2(config, ref, {se}, test::exact_outputs(site, c0, ce, se));
        std::vector<double> value, truth;
        for (auto k : ref.zone_cores[0]) {
            if (!std::isfinite(m.distances[k].distance)) continue;
            const Eigen::Vector3d& c = ref.reference.core_points()[k];
            const Eigen::Vector3d du = sim::pier_displacement(site, c, e, ce.bending) -
                                       sim::pier_displacement(site, c, 0, c0.bending);
            value.push_back(m.distances[k].distance);
            truth.push_back(du.dot(ref.reference.normals()[k]));
        }
        ASSERT_GT(value.size(), 100u);
        const double error = median(value) - median(truth);
        std::printf(
            "epoch %d: west face median %+.3f mm, truth %+.3f mm, error %+.3f mm, %zu core "
            "points\n",
            e, 1e3 * median(value), 1e3 * median(truth), 1e3 * error, value.size());
        worst = std::max(worst, std::abs(error));
        largest_change = std::max(largest_change, std::abs(median(truth)));
    }
    EXPECT_GT(largest_change, 0.0005);  // the face moved
    EXPECT_LT(worst, 0.00002);
}

}  // namespace
}  // namespace tlsmon
