// The supervoxel-level covariance of the registration on stable areas
// (algorithms/registration/supervoxel_covariance.hpp) against drawn truths: supervoxels of a
// valley (level ground at z = 0, a face at y = 60 m, another at x = 20 m, a slope) seen from a
// scanner at the origin, each with its own noise by range; their changes drawn, the six
// parameters fitted to them by weighted least squares (as the adjustment weighs them) and the
// fit's error scored against the covariance the kernel returns for its residual changes.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <vector>

#include "algorithms/registration/supervoxel_covariance.hpp"

namespace tlsmon::registration {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

// A supervoxel of the scene: where it is (its true plane), its normal, and its own σ of a
// voxel mean and number of voxels, from its range.
struct Patch {
    Eigen::Vector3d centre, normal;
    double voxel_sigma;
    double voxels;
};

std::vector<Patch> valley() {
    std::vector<Patch> out;
    const auto add = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& n) {
        const double range = c.norm();
        // A voxel mean's σ grows with range, and far supervoxels hold fewer voxels.
        out.push_back({c, n.normalized(), 0.0001 + 0.000004 * range,
                       std::clamp(std::round(3000.0 / range), 8.0, 120.0)});
    };
    for (double x = -29.5; x < 30; x += 1.0)
        for (double y = 10.5; y < 60; y += 1.0) add({x, y, 0.0}, {0, 0, 1});  // level ground
    for (double x = -19.5; x < 20; x += 1.0)
        for (double z = 0.5; z < 8; z += 1.0) add({x, 60.0, z}, {0, -1, 0});  // the far face
    for (double y = 20.5; y < 60; y += 1.0)
        for (double z = 0.5; z < 6; z += 1.0) add({20.0, y, z}, {-1, 0, 0});  // the side face
    for (double x = -29.5; x < -10; x += 1.0)
        for (double y = 10.5; y < 60; y += 2.0)
            add({x, y, 0.3 * (-10 - x)}, {0.3, 0, 1});  // the valley side
    return out;
}

struct Score {
    Vector6 rms = Vector6::Zero();  // RMS(error/σ) per parameter
    // The same with the larger of the kernel's covariance and the cluster-robust sandwich of
    // the supervoxels' scores over the same cells, as the stage reports it (the adjustment's
    // sandwich, point_to_plane.hpp, is over its voxels' scores).
    Vector6 rms_reported = Vector6::Zero();
    double significant = 0;  // share of draws whose cells showed a common error
    double tau = 0;          // mean τ, m
};

// `draws` truths: each supervoxel's reference centroid off its plane by its own error and the
// epoch's mean by another (their σ² summing to σ_k²), plus an error common to each cell of
// `common_cells` of variance tau² (only to the supervoxels `shares` picks, when given); the
// kernel's cells from `origin`.
Score score(double tau, const CellGrid& common_cells, const Eigen::Vector3d& origin, int draws,
            unsigned seed, bool (*shares)(const Patch&) = nullptr) {
    const std::vector<Patch> patches = valley();
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    Score s;
    Vector6 q2 = Vector6::Zero(), q2_reported = Vector6::Zero();
    for (int d = 0; d < draws; ++d) {
        std::map<std::array<long, 3>, double> common;
        std::vector<SupervoxelObservation> obs;
        Covariance6 N = Covariance6::Zero();
        Vector6 g = Vector6::Zero();
        std::vector<Vector6> rows;
        for (const Patch& p : patches) {
            const double se = p.voxel_sigma / std::sqrt(p.voxels);  // each mean's σ
            const double reference_error = se * n(rng), epoch_error = se * n(rng);
            std::array<long, 3> key;
            for (int j = 0; j < 3; ++j)
                key[j] = static_cast<long>(
                    std::floor((p.centre(j) - common_cells.origin(j)) / common_cells.size));
            auto [it, fresh] = common.try_emplace(key, 0.0);
            if (fresh) it->second = tau * n(rng);
            const double u = shares == nullptr || shares(p) ? it->second : 0.0;
            SupervoxelObservation o;
            o.centroid = p.centre + reference_error * p.normal;  // where the reference put it
            o.normal = p.normal;
            o.weight = p.voxels / (p.voxel_sigma * p.voxel_sigma);
            o.change = epoch_error - reference_error + u;
            o.variance = 2 * se * se;
            Vector6 a;
            a.head<3>() = o.centroid.cross(o.normal);
            a.tail<3>() = o.normal;
            N += o.weight * a * a.transpose();
            g += o.weight * o.change * a;
            rows.push_back(a);
            obs.push_back(o);
        }
        // The parameters fitted to the changes; what is left is what the stage passes.
        const Vector6 error = N.ldlt().solve(g);
        for (std::size_t k = 0; k < obs.size(); ++k) obs[k].change -= rows[k].dot(error);
        const auto c = supervoxel_covariance(obs, Eigen::Vector3d::Zero(), {5.0, origin});
        if (!c) {
            ADD_FAILURE() << "no covariance";
            return s;
        }
        std::map<std::array<long, 3>, Vector6> scores;
        for (std::size_t k = 0; k < obs.size(); ++k) {
            std::array<long, 3> key;
            for (int j = 0; j < 3; ++j)
                key[j] = static_cast<long>(std::floor((obs[k].centroid(j) - origin(j)) / 5.0));
            scores.try_emplace(key, Vector6::Zero()).first->second +=
                obs[k].weight * obs[k].change * rows[k];
        }
        Covariance6 meat = Covariance6::Zero();
        for (const auto& [key, g_c] : scores) meat += g_c * g_c.transpose();
        const Covariance6 Ninv = N.inverse();
        const double cells = static_cast<double>(scores.size());
        const Covariance6 reported =
            larger_of(c->covariance, cells / (cells - 1) * Ninv * meat * Ninv);
        for (int k = 0; k < 6; ++k) {
            q2(k) += error(k) * error(k) / c->covariance(k, k);
            q2_reported(k) += error(k) * error(k) / reported(k, k);
        }
        s.significant += c->significant ? 1.0 / draws : 0.0;
        s.tau += c->cell_sigma / draws;
    }
    s.rms = (q2 / draws).cwiseSqrt();
    s.rms_reported = (q2_reported / draws).cwiseSqrt();
    return s;
}

void print(const char* what, const Score& s) {
    std::printf(
        "%s: common error significant in %.1f %% of draws, mean tau %.3f mm, "
        "RMS(error/sigma)",
        what, 100 * s.significant, 1e3 * s.tau);
    for (int k = 0; k < 6; ++k) std::printf(" %.2f", s.rms(k));
    std::printf("; with the sandwich");
    for (int k = 0; k < 6; ++k) std::printf(" %.2f", s.rms_reported(k));
    std::printf("\n");
}

const Eigen::Vector3d kOffTheMetres(1.91, 3.09, 2.5);

// Without an error common to the cells the test finds one at its level, about 5 % of draws,
// and the covariance is the supervoxels' own: RMS(error/σ) about 1 in every parameter, though
// their σ range over a factor of 10 (near ground against far faces): a cell whose few
// supervoxels are far and noisy counts by its precision, not as much as a near one.
TEST(SupervoxelCovariance, WithoutACommonErrorTheCovarianceIsTheSupervoxelsOwn) {
    const Score s = score(0.0, {5.0, kOffTheMetres}, kOffTheMetres, 300, 3);
    print("independent", s);
    EXPECT_LT(s.significant, 0.10);
    for (int k = 0; k < 6; ++k) {
        EXPECT_GT(s.rms(k), 0.85) << k;
        EXPECT_LT(s.rms(k), 1.15) << k;
    }
}

// An error common to each 5 m cell (0.05 mm, about the supervoxels' own σ near the scanner):
// found in most draws, τ close to it, and the covariance covers the fit's error.
TEST(SupervoxelCovariance, AnErrorCommonToTheCellsIsFoundAndCovered) {
    constexpr double tau = 0.00005;
    const Score s = score(tau, {5.0, kOffTheMetres}, kOffTheMetres, 300, 5);
    print("common to the cells", s);
    EXPECT_GT(s.significant, 0.9);
    EXPECT_NEAR(s.tau, tau, 0.25 * tau);
    for (int k = 0; k < 6; ++k) {
        EXPECT_GT(s.rms(k), 0.8) << k;
        EXPECT_LT(s.rms(k), 1.2) << k;
    }
}

// The ground at z = 0 and the faces at y = 60 and x = 20 lie on the faces of 5 m cells from
// the origin: each of their supervoxels falls into the cell above or below by the sign of its
// reference centroid's error, which is in its change with the opposite sign, and the two halves
// look like cells with opposite common errors. From the origin the test finds a common error
// that is not there and pads the σ; from a corner off the whole metres it does not.
TEST(SupervoxelCovariance, ACellFaceInASurfaceMakesNoCommonErrorOfTheCells) {
    const Score cut = score(0.0, {5.0, kOffTheMetres}, Eigen::Vector3d::Zero(), 150, 7);
    print("cells from the origin", cut);
    EXPECT_GT(cut.significant, 0.9);
    EXPECT_LT(cut.rms.minCoeff(), 0.8);
    const Score off = score(0.0, {5.0, kOffTheMetres}, kOffTheMetres, 150, 7);
    print("cells off the whole metres", off);
    EXPECT_LT(off.significant, 0.12);
    for (int k = 0; k < 6; ++k) {
        EXPECT_GT(off.rms(k), 0.85) << k;
        EXPECT_LT(off.rms(k), 1.15) << k;
    }
}

// An error common to the cells of one face only (the side face at x = 20 m, 0.15 mm: a part
// that moved by less than its LoD and stayed in the datum), none elsewhere. One τ pooled over
// every cell cannot describe it: found in every draw, but at 0.03 mm, κ and tx (which that
// face holds) come out 3.2–3.7 times short on the kernel's covariance alone and the rest padded.
// Such an error is the sandwich's to cover, which takes each cell's own scores: with it, as the
// stage reports, no parameter is more than a fifth short (RMS(error/σ) 1.07 and 1.17 for κ and
// tx).
TEST(SupervoxelCovariance, AnErrorCommonToAFewCellsIsTheSandwichs) {
    const auto side_face = [](const Patch& p) { return p.normal.x() < -0.9; };
    const Score s = score(0.00015, {5.0, kOffTheMetres}, kOffTheMetres, 300, 11, side_face);
    print("common to the side face's cells", s);
    EXPECT_GT(s.significant, 0.9);
    EXPECT_GT(s.rms.maxCoeff(), 2.0);  // the pooled τ alone is short where the face holds
    for (int k = 0; k < 6; ++k) EXPECT_LT(s.rms_reported(k), 1.25) << k;
}

}  // namespace
}  // namespace tlsmon::registration
