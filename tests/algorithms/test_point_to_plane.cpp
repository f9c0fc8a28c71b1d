// The point-to-plane adjustment and its covariance (algorithms/registration/point_to_plane.hpp)
// against known answers: planes of a site (ground, walls facing two ways, a slope) seen from
// a transformation of arc seconds and millimetres, with independent noise and with noise
// shared by patches of surface.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "algorithms/cell_key.hpp"
#include "algorithms/registration/point_to_plane.hpp"
#include "core/error.hpp"

namespace tlsmon::registration {
namespace {

constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);

struct Plane {
    Eigen::Vector3d origin, u, v;  // points origin + a·u + b·v, a, b in [0, 1]
};

std::vector<Plane> site_planes() {
    return {
        {{-15, 30, 0}, {30, 0, 0}, {0, 12, 0}},    // ground in front of the pier
        {{0, 43.5, 0}, {18, 0, 0}, {0, 0, 0.4}},   // foundation's south face
        {{0, 43.5, 0}, {0, 10, 0}, {0, 0, 0.4}},   // foundation's west face
        {{22, 56, 0}, {0, 6, 0}, {0, 0, 2.5}},     // abutment's west face
        {{22, 56, 0}, {8, 0, 0}, {0, 0, 2.5}},     // abutment's south face
        {{-10, 60, 0}, {40, 0, 0}, {0, 20, 7.3}},  // the valley side (20°)
    };
}

struct Truth {
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
};

Truth drift(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(40 * kArcsec * n(rng), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(8 * kArcsec * n(rng), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(8 * kArcsec * n(rng), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    return {R, Eigen::Vector3d(0.002 * n(rng), 0.002 * n(rng), 0.002 * n(rng))};
}

// Pairs on the planes: the epoch point is the true point mapped back into the epoch's frame
// with noise along the normal (independent σ, plus one offset of σ_patch per 1 m cell); the
// reference point is another point of the same plane nearby.
std::vector<PointPlanePair> pairs_for(const Truth& T, std::mt19937_64& rng, int per_plane,
                                      double sigma, double sigma_patch) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> n(0.0, 1.0);
    std::vector<PointPlanePair> out;
    std::map<std::tuple<int, int, int, int>, double> patch;
    int index = 0;
    for (const Plane& p : site_planes()) {
        const Eigen::Vector3d normal = p.u.cross(p.v).normalized();
        for (int i = 0; i < per_plane; ++i) {
            const Eigen::Vector3d X = p.origin + u(rng) * p.u + u(rng) * p.v;
            PointPlanePair q;
            q.reference = X + 0.03 * (u(rng) - 0.5) * p.u.normalized() +
                          0.03 * (u(rng) - 0.5) * p.v.normalized();
            // The patch is the 1 m cell of the reference point on this plane (the fit's cell).
            const auto key =
                std::make_tuple(index, int(std::floor(q.reference.x())),
                                int(std::floor(q.reference.y())), int(std::floor(q.reference.z())));
            auto [it, inserted] = patch.try_emplace(key, 0.0);
            if (inserted) it->second = sigma_patch * n(rng);
            const Eigen::Vector3d measured = X + (sigma * n(rng) + it->second) * normal;
            q.epoch = T.R.transpose() * (measured - T.t);
            q.normal = normal;
            out.push_back(q);
        }
        ++index;
    }
    return out;
}

// (θ, t) error of an estimate against the truth.
Eigen::Matrix<double, 6, 1> error_of(const RigidTransform& T, const Truth& truth) {
    Eigen::Matrix<double, 6, 1> e;
    const Eigen::AngleAxisd d(T.rotation * truth.R.transpose());
    e.head<3>() = d.angle() * d.axis();
    e.tail<3>() = T.translation - truth.t;
    return e;
}

TEST(PointToPlane, RecoversTheTransformationExactlyWithoutNoise) {
    std::mt19937_64 rng(3);
    const Truth truth = drift(rng);
    const auto pairs = pairs_for(truth, rng, 300, 0.0, 0.0);
    const PointToPlaneFit f = fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), {});
    const auto e = error_of(f.transform, truth);
    EXPECT_LT(e.head<3>().norm(), 1e-9);
    EXPECT_LT(e.tail<3>().norm(), 1e-9);
    EXPECT_LT(f.rms, 1e-9);
}

// Over 200 draws: independent noise of 1 mm gives RMS(error/σ) near 1 for every parameter.
TEST(PointToPlane, CovarianceIsHonestForIndependentNoise) {
    std::mt19937_64 rng(5);
    Eigen::Matrix<double, 6, 1> q2 = Eigen::Matrix<double, 6, 1>::Zero();
    constexpr int draws = 200;
    for (int d = 0; d < draws; ++d) {
        const Truth truth = drift(rng);
        const auto pairs = pairs_for(truth, rng, 200, 0.001, 0.0);
        const PointToPlaneFit f = fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), {});
        const auto e = error_of(f.transform, truth);
        const auto S = f.transform.small_rotation_covariance;
        for (int k = 0; k < 6; ++k) q2(k) += e(k) * e(k) / S(k, k);
    }
    for (int k = 0; k < 6; ++k) {
        const double rms = std::sqrt(q2(k) / draws);
        std::printf("parameter %d: RMS(error/sigma) %.2f\n", k, rms);
        EXPECT_GT(rms, 0.8) << k;
        EXPECT_LT(rms, 1.2) << k;
    }
}

// Noise shared by 1 m patches (0.5 mm per patch beside 1 mm per point): s0²·N⁻¹ is
// optimistic (by up to 2.7 in σ on these planes); the reported covariance stays honest, and
// so does the cells' random-effects term alone, whose τ finds the patches' 0.5 mm.
TEST(PointToPlane, ClusteredCovarianceCoversNoiseSharedByPatches) {
    std::mt19937_64 rng(7);
    Eigen::Matrix<double, 6, 1> q2 = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Matrix<double, 6, 1> q2_independent = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Matrix<double, 6, 1> q2_cells = Eigen::Matrix<double, 6, 1>::Zero();
    constexpr int draws = 200;
    double inflation = 0, tau = 0;
    for (int d = 0; d < draws; ++d) {
        const Truth truth = drift(rng);
        const auto pairs = pairs_for(truth, rng, 400, 0.001, 0.0005);
        const PointToPlaneFit f = fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), {});
        const auto e = error_of(f.transform, truth);
        for (int k = 0; k < 6; ++k) {
            q2(k) += e(k) * e(k) / f.transform.small_rotation_covariance(k, k);
            q2_independent(k) += e(k) * e(k) / f.independent(k, k);
            q2_cells(k) += e(k) * e(k) / f.cell_effect(k, k);
        }
        inflation += f.inflation / draws;
        tau += f.cell_sigma / draws;
    }
    std::printf("mean inflation %.2f, mean cell sigma %.3f mm\n", inflation, 1e3 * tau);
    EXPECT_NEAR(tau, 0.0005, 0.0001);
    double worst_independent = 0;
    for (int k = 0; k < 6; ++k) {
        const double rms = std::sqrt(q2(k) / draws), rms_i = std::sqrt(q2_independent(k) / draws);
        const double rms_c = std::sqrt(q2_cells(k) / draws);
        std::printf("parameter %d: RMS(error/sigma) %.2f, independent %.2f, cells %.2f\n", k, rms,
                    rms_i, rms_c);
        EXPECT_GT(rms, 0.7) << k;
        EXPECT_LT(rms, 1.3) << k;
        EXPECT_GT(rms_c, 0.7) << k;
        EXPECT_LT(rms_c, 1.3) << k;
        worst_independent = std::max(worst_independent, rms_i);
    }
    EXPECT_GT(worst_independent, 2.0);
}

// The cells' random effect with pairs of unequal weight (the block faces' voxels hold 25
// times the ground's points, the abutment's 4 times; each pair's own noise σ/√p) and cells
// from one pair to dozens: the ANOVA estimator, with its expectation taken through the fit,
// finds the patches' τ² (0.242 against 0.25 mm² over the draws), and its covariance alone is
// honest. Each cell's mean residual counted alike (the estimator before) gave 0.147 mm² and a
// σ 2.4–2.6 times too small in κ, tx and ty, the faces' directions: the fit absorbs most of a
// heavy cell's offset, which the count C − 6 did not see.
TEST(PointToPlane, CellEffectIsUnbiasedWithUnequalWeights) {
    std::mt19937_64 rng(17);
    std::normal_distribution<double> n(0.0, 1.0);
    constexpr int draws = 300, per_plane = 300;
    constexpr double tau = 0.0005, sigma = 0.001;
    const std::vector<double> weight{1, 25, 25, 4, 4, 1};
    Eigen::Matrix<double, 6, 1> q2 = Eigen::Matrix<double, 6, 1>::Zero();
    double tau2 = 0;
    for (int d = 0; d < draws; ++d) {
        const Truth truth = drift(rng);
        auto pairs = pairs_for(truth, rng, per_plane, 0.0, tau);
        for (std::size_t i = 0; i < pairs.size(); ++i) {
            const double p = weight[i / per_plane];
            pairs[i].epoch +=
                truth.R.transpose() * pairs[i].normal * (sigma / std::sqrt(p) * n(rng));
            pairs[i].weight = p;
        }
        PointToPlaneParams params;
        params.outlier_k = 0;
        const PointToPlaneFit f = fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), params);
        const auto e = error_of(f.transform, truth);
        for (int k = 0; k < 6; ++k) q2(k) += e(k) * e(k) / f.cell_effect(k, k);
        tau2 += f.cell_sigma * f.cell_sigma / draws;
    }
    std::printf("mean tau^2 %.4f mm^2 (true %.4f)\n", 1e6 * tau2, 1e6 * tau * tau);
    EXPECT_NEAR(tau2, tau * tau, 0.06 * tau * tau);
    for (int k = 0; k < 6; ++k) {
        const double rms = std::sqrt(q2(k) / draws);
        std::printf("parameter %d: RMS(error/sigma) of the cells' random effect %.2f\n", k, rms);
        EXPECT_GT(rms, 0.8) << k;
        EXPECT_LT(rms, 1.2) << k;
    }
}

// The reference points are voxel means: noisy along their normal (1 mm here, beside the
// epoch's 1 mm), with no error common to a patch. The ground (z = 0), the foundation's and
// the abutment's faces (x = 0, x = 22, y = 56) lie on whole metres, on the faces of 1 m cells
// from the origin: each such surface's points fall into the cells on either side by the sign
// of their reference noise, whose mean residuals then carry that sign. The cells' random
// effect reads it as a common error of the cells (τ 0.67 mm) that cancels in the estimate,
// since both sides hold the same directions, and pads the σ of κ, tx and ty, which those faces
// hold, twice (RMS(error/σ) 0.45–0.48). With the grid's corner off the whole centimetres, as
// the ICP puts it (its voxel grid's), no cell face cuts a surface: τ 0.015 mm, RMS(error/σ)
// 0.91–0.97.
TEST(PointToPlane, ACellFaceInASurfaceMakesNoCommonErrorOfTheCells) {
    const auto run = [](const Eigen::Vector3d& origin) {
        std::mt19937_64 rng(19);
        std::normal_distribution<double> n(0.0, 1.0);
        constexpr int draws = 150;
        Eigen::Matrix<double, 6, 1> q2 = Eigen::Matrix<double, 6, 1>::Zero();
        double tau = 0;
        for (int d = 0; d < draws; ++d) {
            const Truth truth = drift(rng);
            auto pairs = pairs_for(truth, rng, 300, 0.001, 0.0);
            for (auto& p : pairs) p.reference += 0.001 * n(rng) * p.normal;
            PointToPlaneParams params;
            params.outlier_k = 0;
            params.cell_origin = origin;
            const PointToPlaneFit f =
                fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), params);
            const auto e = error_of(f.transform, truth);
            for (int k = 0; k < 6; ++k) q2(k) += e(k) * e(k) / f.cell_effect(k, k);
            tau += f.cell_sigma / draws;
        }
        Eigen::Matrix<double, 6, 1> rms = (q2 / draws).cwiseSqrt();
        std::printf("cells from (%.3f, %.3f, %.3f): mean tau %.3f mm, RMS(error/sigma)", origin.x(),
                    origin.y(), origin.z(), 1e3 * tau);
        for (int k = 0; k < 6; ++k) std::printf(" %.2f", rms(k));
        std::printf("\n");
        return std::make_pair(tau, rms);
    };
    const auto [tau_cut, rms_cut] = run(Eigen::Vector3d::Zero());
    EXPECT_GT(tau_cut, 0.0003);
    EXPECT_LT(rms_cut.minCoeff(), 0.7);
    const auto [tau_off, rms_off] = run(Eigen::Vector3d::Constant(0.005));
    EXPECT_LT(tau_off, 0.0001);
    for (int k = 0; k < 6; ++k) {
        EXPECT_GT(rms_off(k), 0.8) << k;
        EXPECT_LT(rms_off(k), 1.2) << k;
    }
}

// Surfaces of unequal noise (the ground and the valley side 4 mm, the block faces 0.5 mm), each
// pair weighted p = (1 mm/σ)²: s0² is the unit weight's variance, (1 mm)², the covariance stays
// honest, and the weighted estimate errs less than the unweighted one.
TEST(PointToPlane, WeightsFollowEachSurfacesNoise) {
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n(0.0, 1.0);
    constexpr int draws = 200, per_plane = 200;
    const std::vector<double> sigma{0.004, 0.0005, 0.0005, 0.0005, 0.0005, 0.004};
    Eigen::Matrix<double, 6, 1> q2 = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Matrix<double, 6, 1> se_weighted = q2, se_unweighted = q2;
    double s0 = 0;
    for (int d = 0; d < draws; ++d) {
        const Truth truth = drift(rng);
        auto pairs = pairs_for(truth, rng, per_plane, 0.0, 0.0);
        for (std::size_t i = 0; i < pairs.size(); ++i) {
            const double s = sigma[i / per_plane];
            pairs[i].epoch += truth.R.transpose() * pairs[i].normal * (s * n(rng));
            pairs[i].weight = 1e-6 / (s * s);
        }
        const PointToPlaneFit f = fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), {});
        for (auto& p : pairs) p.weight = 1.0;
        const PointToPlaneFit u = fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), {});
        const auto e = error_of(f.transform, truth), eu = error_of(u.transform, truth);
        for (int k = 0; k < 6; ++k) {
            q2(k) += e(k) * e(k) / f.transform.small_rotation_covariance(k, k);
            se_weighted(k) += e(k) * e(k);
            se_unweighted(k) += eu(k) * eu(k);
        }
        s0 += f.variance_factor / draws;
    }
    EXPECT_NEAR(s0, 1e-6, 0.1e-6);
    double gain = 0;
    for (int k = 0; k < 6; ++k) {
        const double rms = std::sqrt(q2(k) / draws);
        std::printf("parameter %d: RMS(error/sigma) %.2f, unweighted/weighted RMS error %.2f\n", k,
                    rms, std::sqrt(se_unweighted(k) / se_weighted(k)));
        EXPECT_GT(rms, 0.8) << k;
        EXPECT_LT(rms, 1.2) << k;
        gain = std::max(gain, std::sqrt(se_unweighted(k) / se_weighted(k)));
    }
    EXPECT_GT(gain, 1.2);  // 1.35 on this geometry; 1 when the weights are ignored
}

// The sandwich's Bell–McCaffrey degrees of freedom against their definition, built in full:
// G = (I − H)·blockdiag(X_c·N⁻¹·e_k), dof = (tr GᵀG)²/‖GᵀG‖²_F (X's rows √p·aᵀ).
TEST(PointToPlane, SandwichDegreesOfFreedomAreBellMcCaffreys) {
    std::mt19937_64 rng(13);
    const Truth truth = drift(rng);
    auto pairs = pairs_for(truth, rng, 15, 0.001, 0.0);
    for (std::size_t i = 0; i < pairs.size(); ++i) pairs[i].weight = 1.0 + double(i % 4);
    PointToPlaneParams params;
    params.cluster_size = 4.0;
    params.outlier_k = 0;
    const PointToPlaneFit f = fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), params);
    const Eigen::Matrix3d R = f.transform.rotation;
    const auto n = static_cast<Eigen::Index>(pairs.size());
    Eigen::MatrixXd X(n, 6);
    std::map<std::uint64_t, Eigen::Index> cell_of;
    std::vector<Eigen::Index> cell(pairs.size());
    for (Eigen::Index i = 0; i < n; ++i) {
        const auto& p = pairs[static_cast<std::size_t>(i)];
        X.row(i).head<3>() = ((R * p.epoch).cross(p.normal) * std::sqrt(p.weight)).transpose();
        X.row(i).tail<3>() = (p.normal * std::sqrt(p.weight)).transpose();
        const auto [it, added] =
            cell_of.try_emplace(cell_key(p.reference, params.cluster_size), cell_of.size());
        cell[static_cast<std::size_t>(i)] = it->second;
    }
    const auto C = static_cast<Eigen::Index>(cell_of.size());
    ASSERT_GT(C, 8);
    ASSERT_EQ(f.clusters, static_cast<std::size_t>(C));
    const Eigen::MatrixXd Ninv = (X.transpose() * X).inverse();
    const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(n, n) - X * Ninv * X.transpose();  // I − H
    for (int k = 0; k < 6; ++k) {
        const Eigen::VectorXd d = X * Ninv.col(k);
        Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, C);
        for (Eigen::Index i = 0; i < n; ++i) D(i, cell[static_cast<std::size_t>(i)]) = d(i);
        const Eigen::MatrixXd GG = D.transpose() * M * D;
        const double dof = GG.trace() * GG.trace() / GG.squaredNorm();
        std::printf("parameter %d: %.2f degrees of freedom of %td cells\n", k, dof, C);
        EXPECT_NEAR(f.clustered_dof(k), dof, 1e-6 * dof) << k;
        EXPECT_LT(f.clustered_dof(k), double(C)) << k;
    }
}

TEST(PointToPlane, TooFewPairsOrOnePlaneIsAnError) {
    std::mt19937_64 rng(9);
    const Truth truth = drift(rng);
    auto pairs = pairs_for(truth, rng, 2, 0.001, 0.0);
    pairs.resize(6);
    EXPECT_THROW(fit_point_to_plane(pairs, Eigen::Matrix4d::Identity(), {}), Error);
    // The ground alone does not hold x, y and the rotation about z.
    auto ground = pairs_for(truth, rng, 100, 0.001, 0.0);
    ground.resize(100);
    EXPECT_THROW(fit_point_to_plane(ground, Eigen::Matrix4d::Identity(), {}), Error);
}

// Two estimates of equal covariance half a millimetre and 2″ apart: the combination lies
// halfway, with half the variance.
TEST(PointToPlane, CombinationIsTheWeightedMean) {
    Covariance6 S = Covariance6::Zero();
    S.diagonal() << 4e-12, 4e-12, 9e-12, 1e-8, 1e-8, 4e-8;
    const RigidTransform a =
        rigid_transform_from(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.001, 0, 0), S);
    const Eigen::Matrix3d Rb = Eigen::AngleAxisd(2 * kArcsec, Eigen::Vector3d::UnitZ()).matrix();
    const RigidTransform b = rigid_transform_from(Rb, Eigen::Vector3d(0.0015, 0, 0), S);
    const RigidTransform c = combine_transforms(a, b);
    EXPECT_NEAR(c.translation.x(), 0.00125, 1e-12);
    EXPECT_NEAR(c.kappa, 1 * kArcsec, 1e-12);
    for (int k = 0; k < 6; ++k) {
        EXPECT_NEAR(c.small_rotation_covariance(k, k), 0.5 * S(k, k), 1e-6 * S(k, k)) << k;
    }
    // Unequal weights: the better one dominates, 4:1 in variance -> 0.8 of the way.
    Covariance6 S4 = 4.0 * S;
    const RigidTransform a4 =
        rigid_transform_from(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.001, 0, 0), S4);
    EXPECT_NEAR(combine_transforms(a4, b).translation.x(), 0.001 + 0.8 * 0.0005, 1e-12);
}

}  // namespace
}  // namespace tlsmon::registration
