// The least-squares patch refinement (patch_refinement.hpp) against known sub-pixel shifts:
// a finely sampled texture is found to a hundredth of a pixel at every sub-pixel phase, and
// without the interpolant's pull (below 0.001 pixel with detail up to a quarter cycle per
// pixel); on a texture sampled coarser than its detail (aliased, as a scan sampled at about
// its footprint) every patch's shift is pulled the same way by the lattice, and the
// Gaussian prefilter removes most of that pull (and finds the patches where the lattices
// are half a pixel apart); empty pixels are neither darkened nor filled by the prefilter.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "algorithms/keypoints/patch_refinement.hpp"

namespace {

using namespace tlsmon::keypoints;

// A texture of `waves` plane waves, frequencies up to `max_frequency` cycles per pixel, each
// attenuated as by a Gaussian beam of σ = `blur` pixels (its transfer function
// exp(−2π²σ²f²)); sampled at (row − shift_row, column − shift_column).
struct Texture {
    struct Wave {
        double fy, fx, phase, amplitude;
    };
    std::vector<Wave> waves;
    Texture(int count, double max_frequency, double blur, unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> f(-max_frequency, max_frequency), ph(0, 6.283);
        for (int k = 0; k < count; ++k) {
            const double fy = f(rng), fx = f(rng), f2 = fy * fy + fx * fx;
            waves.push_back(
                {fy, fx, ph(rng),
                 std::exp(-2 * std::numbers::pi * std::numbers::pi * blur * blur * f2)});
        }
    }
    SphericalImages image(Eigen::Index size, double shift_row, double shift_column) const {
        SphericalImages im;
        im.rows = im.columns = size;
        im.valid = tlsmon::ImageMask::Constant(size, size, true);
        im.intensity.resize(size, size);
        for (Eigen::Index r = 0; r < size; ++r)
            for (Eigen::Index c = 0; c < size; ++c) {
                double v = 0.5;
                for (const auto& w : waves)
                    v += 0.4 / std::sqrt(double(waves.size())) * w.amplitude *
                         std::cos(2 * std::numbers::pi *
                                      (w.fy * (double(r) - shift_row) +
                                       w.fx * (double(c) - shift_column)) +
                                  w.phase);
                im.intensity(r, c) = v;
            }
        return im;
    }
};

struct ShiftErrors {
    double mean_row = 0, mean_column = 0, worst = 0;
    int found = 0;
};

// The patches on a grid of the reference, each sought in the epoch from its own pixel: the
// found shift against (shift_row, shift_column).
ShiftErrors refine_grid(const Texture& t, double shift_row, double shift_column, double prefilter) {
    constexpr Eigen::Index kSize = 160;
    const tlsmon::Image reference = gaussian_prefiltered(t.image(kSize, 0, 0), prefilter);
    const tlsmon::BSplineImage epoch = tlsmon::bspline_image(
        gaussian_prefiltered(t.image(kSize, shift_row, shift_column), prefilter));
    ShiftErrors e;
    for (int row = 20; row < kSize - 20; row += 12) {
        for (int column = 20; column < kSize - 20; column += 12) {
            const auto patch = intensity_patch(reference, row, column, 7);
            EXPECT_TRUE(patch.has_value());
            const auto m = match_patch(*patch, epoch, row, column);
            if (!m) continue;
            const double er = m->row - row - shift_row, ec = m->column - column - shift_column;
            e.mean_row += er;
            e.mean_column += ec;
            e.worst = std::max({e.worst, std::abs(er), std::abs(ec)});
            ++e.found;
        }
    }
    if (e.found > 0) {
        e.mean_row /= e.found;
        e.mean_column /= e.found;
    }
    return e;
}

TEST(PatchRefinement, FindsAFinelySampledShiftToAHundredthOfAPixelAtEveryPhase) {
    const Texture fine(40, 0.1, 0.0, 1);
    for (double s = 0.0; s < 1.0; s += 0.125) {
        for (const double prefilter : {0.0, 1.5}) {
            const ShiftErrors e = refine_grid(fine, s, -0.6 * s, prefilter);
            std::printf("fine: shift %.3f, prefilter %.1f: mean (%+.4f, %+.4f), worst %.4f px\n", s,
                        prefilter, e.mean_row, e.mean_column, e.worst);
            EXPECT_EQ(e.found, 100) << "shift " << s << ", prefilter " << prefilter;
            EXPECT_LT(e.worst, 0.01) << "shift " << s << ", prefilter " << prefilter;
            EXPECT_LT(std::abs(e.mean_row), 0.001) << "shift " << s << ", prefilter " << prefilter;
            EXPECT_LT(std::abs(e.mean_column), 0.001) << "shift " << s;
        }
    }
}

// Detail up to 0.25 cycles per pixel, the prefilter's default: at every phase the shifts
// are found without the interpolant's pull. Keys' cubic convolution pulled a patch at a
// quarter pixel by 0.006–0.027 pixel at 0.1–0.2 cycles per pixel (cubic_bspline.hpp); the
// cubic B-spline by 0.0001–0.0025, the prefilter taking the upper band's weight.
TEST(PatchRefinement, TheInterpolantPullsNoShiftAtAnyPhase) {
    const Texture detailed(60, 0.25, 0.0, 4);
    double worst = 0;
    for (double s = 0.125; s < 1.0; s += 0.125) {
        const ShiftErrors e = refine_grid(detailed, s, -s, 1.5);
        std::printf("detailed: shift %.3f: mean (%+.5f, %+.5f), worst %.4f px\n", s, e.mean_row,
                    e.mean_column, e.worst);
        EXPECT_EQ(e.found, 100) << "shift " << s;
        worst = std::max({worst, std::abs(e.mean_row), std::abs(e.mean_column)});
    }
    EXPECT_LT(worst, 0.001);
}

// The texture holds detail up to 0.7 cycles per pixel, blurred as by a beam of σ = 0.45
// pixel: above 0.5 cycles per pixel its samples alias, the same way in every patch. Without
// the prefilter the shifts are pulled by up to 0.02 pixel, or the patches are not found at
// all where the two lattices are half a pixel apart; with it, by 0.001.
TEST(PatchRefinement, ThePrefilterKeepsTheLatticesAliasingOutOfTheShift) {
    const Texture aliased(60, 0.7, 0.45, 2);
    double worst_without = 0, worst_with = 0;
    for (double s = 0.125; s < 1.0; s += 0.25) {
        const ShiftErrors without = refine_grid(aliased, s, s, 0.0);
        const ShiftErrors with = refine_grid(aliased, s, s, 1.5);
        std::printf(
            "shift %.3f px: without a prefilter %3d patches found, mean error (%+.4f, "
            "%+.4f) px; with σ = 1.5 px %3d, (%+.4f, %+.4f) px\n",
            s, without.found, without.mean_row, without.mean_column, with.found, with.mean_row,
            with.mean_column);
        EXPECT_EQ(with.found, 100) << "shift " << s;
        if (without.found > 0)
            worst_without = std::max(
                {worst_without, std::abs(without.mean_row), std::abs(without.mean_column)});
        worst_with = std::max({worst_with, std::abs(with.mean_row), std::abs(with.mean_column)});
    }
    EXPECT_GT(worst_without, 0.008);  // the pull is there
    EXPECT_LT(worst_with, worst_without / 5);
}

TEST(PatchRefinement, ThePrefilterNeitherDarkensNorFillsAroundEmptyPixels) {
    SphericalImages im = Texture(10, 0.1, 0, 3).image(40, 0, 0);
    im.intensity.setConstant(0.7);
    im.valid(20, 20) = false;
    im.intensity(20, 20) = 0;
    const tlsmon::Image f = gaussian_prefiltered(im, 1.5);
    EXPECT_FALSE(f.valid(20, 20));
    EXPECT_EQ(f.value(20, 20), 0.0);
    EXPECT_NEAR(f.value(20, 21), 0.7, 1e-12);
    EXPECT_NEAR(f.value(0, 0), 0.7, 1e-12);  // the image's edge: no darkening either
    EXPECT_EQ(gaussian_prefiltered(im, 0.0).value(5, 5), im.intensity(5, 5));
}

}  // namespace
