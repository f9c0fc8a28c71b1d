// The keypoint stage after registration on simulated series of the `pier` preset (issue 12's
// acceptance), side by side with M3C2 in the same zones: per zone, the displacement along
// the surface (horizontal and vertical in the wall) against the truth, with the mean number
// of matches kept; and in a series without deformation, no zone beyond 3σ. The series, their
// zones and their truth: tests/pipeline/keypoint_series.hpp. The west face is seen at 87°:
// its matches are grazing (keypoints.max_incidence_deg) and it stays undefined.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "pipeline/keypoint_results.hpp"
#include "tests/pipeline/keypoint_series.hpp"

namespace tlsmon {
namespace {

using test::pier_scenario, test::hochmosel_scenario, test::run_series, test::lod_of;
using test::Scenario, test::Series;

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
// within `rms_bound` (m) RMS of the truth in h and v; printed beside M3C2's medians. Returns
// the number of zone epochs scored.
int check_along_surface(const Scenario& scenario, const std::vector<double>& hours,
                        double rms_bound = 0.001) {
    const Series s = run_series(scenario, hours);
    EXPECT_TRUE(s.refused.empty()) << s.refused.front();
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
            1e3 * f.truth[2], 1e3 * d.along[0], 1e3 * f.truth[0], 1e3 * f.m3c2_median.value,
            1e3 * f.m3c2_median.truth, 1e3 * d.along_standard_error[1],
            1e3 * lod_of(f.zone, d, f.registration, kKeypointAlongSurfaceH));
        kept[f.zone].first += double(f.kept);
        kept[f.zone].second += 1;
        if (f.zone == "west") {
            EXPECT_FALSE(d.defined()) << "the grazing west face gave a displacement";
            continue;
        }
        EXPECT_TRUE(d.defined()) << f.zone << " epoch " << f.epoch << ": " << d.undefined_reason;
        if (!d.defined()) continue;
        // The bands with enough kept matches hold most of the zone's area (all of the pier's
        // faces; the top of the far strip the least).
        EXPECT_GT(d.covered_area_share, 0.5) << f.zone;
        std::printf("%s: the figures stand for %.0f %% of the zone's area\n", f.zone.c_str(),
                    100 * d.covered_area_share);
        EXPECT_TRUE(f.truth.allFinite()) << f.zone;
        if (!f.truth.allFinite()) continue;
        h.add(d.along[1] - f.truth[1]);
        v.add(d.along[2] - f.truth[2]);
        normal.add(d.along[0] - f.truth[0]);
        m3c2.add(f.m3c2_median.value - f.m3c2_median.truth);
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
    EXPECT_LE(h.rms(), rms_bound);
    EXPECT_LE(v.rms(), rms_bound);
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
    EXPECT_TRUE(s.refused.empty()) << s.refused.front();
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

// The 140 m pier at 100–175 m, through its detail strip: 13 bands of 10 m, within the
// 0.35 mm RMS along the surface the method is accepted at there. With the detector's former
// threshold (0.001) the zones above 90 m kept 19–48 matches instead of 131–292, and v erred
// 0.43 mm RMS (docs/keypoints.md, "The detector's threshold").
TEST(KeypointsSimulated, HochmoselAlongTheSurfaceWithin035MmRmsOfTheTruthSideBySideWithM3c2) {
    EXPECT_EQ(check_along_surface(hochmosel_scenario(), {0.0, 3.0, 6.0}, 0.35e-3), 2 * 13);
}

TEST(KeypointsSimulated, HochmoselWithoutDeformationNoZoneExceeds3Sigma) {
    EXPECT_EQ(check_no_movement(hochmosel_scenario(), {0.0, 4.0}), 1 * 13 * 6);
}

}  // namespace
}  // namespace tlsmon
