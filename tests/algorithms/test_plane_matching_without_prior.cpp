// The datum-independent plane matching (algorithms/registration/plane_matching_without_prior.hpp)
// on the synthetic site of tests/support/synthetic_planes.hpp seen from a station that was
// knocked: 0.2 m away and turned by 5° about the standing axis (plus the usual drift), the
// epoch's planes shuffled. Without any prior it must find the heading and the translation
// closely enough for the datum-dependent matching to pair every plane with its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <numeric>
#include <random>

#include "algorithms/registration/plane_matching.hpp"
#include "algorithms/registration/plane_matching_without_prior.hpp"
#include "tests/support/synthetic_planes.hpp"

namespace tlsmon::registration {
namespace {

using namespace tlsmon::test::synthetic_planes;

constexpr double kDegree = std::numbers::pi / 180.0;

struct KnockedEpoch {
    std::vector<FittedPlane> reference, epoch;
    std::vector<std::size_t> truth;  // epoch[k] is reference[truth[k]]
    Eigen::Affine3d station;         // epoch frame → reference frame
};

KnockedEpoch knocked(std::mt19937& rng, const Eigen::Affine3d& knock) {
    const auto site = site_planes();
    KnockedEpoch k;
    k.station = knock * drift(rng);
    const Eigen::Affine3d I = Eigen::Affine3d::Identity();
    std::vector<FittedPlane> seen;
    for (const SitePlane& s : site) {
        k.reference.push_back(fit_plane(sample(s, I, I, rng), kSigma));
        seen.push_back(fit_plane(sample(s, I, k.station.inverse(), rng), kSigma));
    }
    k.truth.resize(seen.size());
    std::iota(k.truth.begin(), k.truth.end(), 0);
    std::shuffle(k.truth.begin(), k.truth.end(), rng);
    for (const auto i : k.truth) k.epoch.push_back(seen[i]);
    return k;
}

TEST(PlaneMatchingWithoutPrior, AKnockedStationIsFoundAndEveryPlanePairedWithItsOwn) {
    // Over 20 seeds, in both directions of the turn.
    std::mt19937 rng(77);
    for (int trial = 0; trial < 20; ++trial) {
        const double turn = (trial % 2 ? 5.0 : -5.0) * kDegree;
        const Eigen::Affine3d knock = Eigen::Translation3d(0.14, -0.14, 0.01) *
                                      Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ());
        const KnockedEpoch k = knocked(rng, knock);

        // The identity, the datum-dependent matching's prior for a fixed station, is useless.
        EXPECT_LT(match_planes(k.reference, k.epoch, RigidTransform{}).size(), 4u);

        const auto m = match_planes_without_prior(k.reference, k.epoch);
        ASSERT_TRUE(m) << "trial " << trial;
        EXPECT_NEAR(m->heading, turn, 0.5 * kDegree) << "trial " << trial;
        EXPECT_GE(m->support, 10u);
        const Eigen::AngleAxisd rotation_error(m->approximate.rotation *
                                               k.station.rotation().transpose());
        EXPECT_LT(rotation_error.angle(), 0.01 * kDegree) << "trial " << trial;
        EXPECT_LT((m->approximate.translation - k.station.translation()).norm(), 0.005);

        const auto matches = match_planes(k.reference, k.epoch, m->approximate);
        EXPECT_EQ(matches.size(), k.reference.size());
        for (const PlaneMatch& p : matches) EXPECT_EQ(k.truth[p.epoch], p.reference);
    }
}

TEST(PlaneMatchingWithoutPrior, EitherSignFindsAnyHeadingWhenTheNormalsHaveNoSide) {
    // A campaign's frame: any heading and tens of metres away; the epoch's normals turned to
    // either side at random (an unstructured cloud has no scanner for them to face).
    std::mt19937 rng(79);
    for (int trial = 0; trial < 10; ++trial) {
        const double turn = (-170.0 + 37.0 * trial) * kDegree;
        const Eigen::Affine3d frame = Eigen::Translation3d(-23.0 + trial, 41.0, 0.7) *
                                      Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ());
        KnockedEpoch k = knocked(rng, frame);
        std::bernoulli_distribution flip(0.5);
        for (auto& e : k.epoch)
            if (flip(rng)) e.normal = -e.normal;

        PriorFreeMatchingParams p;
        p.either_sign = true;
        const auto m = match_planes_without_prior(k.reference, k.epoch, p);
        ASSERT_TRUE(m) << "trial " << trial;
        EXPECT_GT(m->support, m->runner_up) << "trial " << trial;
        const Eigen::AngleAxisd rotation_error(m->approximate.rotation *
                                               k.station.rotation().transpose());
        EXPECT_LT(rotation_error.angle(), 0.01 * kDegree) << "trial " << trial;
        EXPECT_LT((m->approximate.translation - k.station.translation()).norm(), 0.005)
            << "trial " << trial;
    }
}

TEST(PlaneMatchingWithoutPrior, NoHeadingWithoutVerticalFacesAndNothingFromTooFewPlanes) {
    std::mt19937 rng(78);
    const KnockedEpoch k =
        knocked(rng, Eigen::Translation3d(0.2, 0, 0) *
                         Eigen::AngleAxisd(5 * kDegree, Eigen::Vector3d::UnitZ()));
    // The ground, the foundation's top and the deck's underside: horizontal all.
    std::vector<FittedPlane> flat_ref, flat_epoch;
    for (std::size_t j = 0; j < k.epoch.size(); ++j) {
        if (std::fabs(k.epoch[j].normal.z()) > 0.95) flat_epoch.push_back(k.epoch[j]);
    }
    for (const auto& r : k.reference) {
        if (std::fabs(r.normal.z()) > 0.95) flat_ref.push_back(r);
    }
    ASSERT_GE(flat_ref.size(), 3u);
    EXPECT_FALSE(match_planes_without_prior(flat_ref, flat_epoch));
    const std::vector<FittedPlane> three(k.epoch.begin(), k.epoch.begin() + 3);
    EXPECT_FALSE(match_planes_without_prior(k.reference, three));
}

}  // namespace
}  // namespace tlsmon::registration
