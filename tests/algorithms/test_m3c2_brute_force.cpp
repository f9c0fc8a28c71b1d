// M3C2 against a brute-force implementation written here straight from the definitions of
// docs/m3c2.md (every point of the cloud tested at every core point, no index, no batches):
// normals, radii, cylinder counts, statistics (with and without strays left out), distances
// and LoD agree to 1e-9 m on small clouds, whatever the number of threads and however the
// core points are batched.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "algorithms/m3c2/core_points.hpp"
#include "algorithms/m3c2/members.hpp"
#include "algorithms/m3c2/reference.hpp"
#include "core/error.hpp"

namespace tlsmon::test {
namespace {

using Eigen::Vector3d;
using namespace tlsmon::m3c2;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

struct BruteNormal {
    Vector3d normal = Vector3d::Constant(nan);
    double radius = nan;
};

BruteNormal brute_normal(const std::vector<Vector3d>& cloud, const Vector3d& c,
                         const std::vector<double>& radii, const Vector3d& v) {
    BruteNormal best;
    double best_planarity = -1;
    for (double r : radii) {
        std::vector<Vector3d> near;
        for (const auto& p : cloud)
            if ((p - c).norm() <= r) near.push_back(p);
        if (near.size() < 3) continue;
        Vector3d mean = Vector3d::Zero();
        for (const auto& p : near) mean += p - c;
        mean /= static_cast<double>(near.size());
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (const auto& p : near) cov += (p - c - mean) * (p - c - mean).transpose();
        cov /= static_cast<double>(near.size() - 1);
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
        const double planarity = (es.eigenvalues()[1] - es.eigenvalues()[0]) / es.eigenvalues()[2];
        if (planarity > best_planarity) {
            best_planarity = planarity;
            best.normal = es.eigenvectors().col(0);
            best.radius = r;
        }
    }
    if (best.normal.dot(v) < 0) best.normal = -best.normal;
    return best;
}

struct BruteSide {
    double centre = nan, spread = nan, roughness = nan;
    std::size_t n = 0;
    Vector3d lateral = Vector3d::Constant(nan);  // the points' mean offset across the axis
    double lateral_spread = nan;                 // their RMS distance from the axis
};

double quantile(const std::vector<double>& sorted, double q) {
    const double h = (sorted.size() - 1) * q;
    const std::size_t lo = static_cast<std::size_t>(h);
    const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (h - lo) * (sorted[hi] - sorted[lo]);
}

// The statistic of all of x: median and IQR, or mean and sample standard deviation.
BruteSide brute_statistic(std::vector<double> x, bool median) {
    BruteSide s;
    s.n = x.size();
    if (x.size() < 2) return s;
    if (median) {
        std::sort(x.begin(), x.end());
        s.centre = quantile(x, 0.5);
        s.spread = quantile(x, 0.75) - quantile(x, 0.25);
    } else {
        double sum = 0;
        for (double v : x) sum += v;
        s.centre = sum / x.size();
        double ss = 0;
        for (double v : x) ss += (v - s.centre) * (v - s.centre);
        s.spread = std::sqrt(ss / (x.size() - 1));
    }
    s.roughness = s.spread;
    return s;
}

// `stray_distance` (with the mean): the projections farther from their median than both it
// and 3.5 · 1.4826·MAD are left out, `clipped` counts them; more than a tenth of them: two
// surfaces, no centre and no spread. The roughness is the spread of all of them.
BruteSide brute_side(const std::vector<Vector3d>& cloud, const Vector3d& c, const Vector3d& n,
                     double radius, double depth, bool median, double stray_distance,
                     std::size_t& clipped) {
    std::vector<double> x;
    Vector3d across_sum = Vector3d::Zero();
    double across_squares = 0;
    for (const auto& p : cloud) {
        const double along = (p - c).dot(n);
        const Vector3d across = (p - c) - along * n;
        if (std::abs(along) <= depth && across.norm() <= radius) {
            x.push_back(along);
            across_sum += across;
            across_squares += across.squaredNorm();
        }
    }
    BruteSide all = brute_statistic(x, median);
    if (!x.empty()) {
        all.lateral = across_sum / double(x.size());
        all.lateral_spread = std::sqrt(across_squares / double(x.size()));
    }
    if (median || !std::isfinite(stray_distance) || x.empty()) return all;
    std::vector<double> sorted = x, deviation;
    std::sort(sorted.begin(), sorted.end());
    const double centre = quantile(sorted, 0.5);
    for (double v : x) deviation.push_back(std::abs(v - centre));
    std::sort(deviation.begin(), deviation.end());
    const double limit = std::max(stray_distance, 3.5 * 1.4826 * quantile(deviation, 0.5));
    std::vector<double> kept;
    for (double v : x)
        if (std::abs(v - centre) <= limit) kept.push_back(v);
    clipped += x.size() - kept.size();
    BruteSide s = brute_statistic(kept, median);
    if (double(x.size() - kept.size()) > 0.1 * double(x.size())) s.centre = s.spread = nan;
    s.roughness = all.roughness;
    s.lateral = all.lateral;
    s.lateral_spread = all.lateral_spread;
    return s;
}

// The compared points lie elsewhere across the axis than the reference's: their mean offsets
// more than max(0.2, 3.72·√((1/n1 + 1/n2)/2)) of the reference's RMS distance apart.
bool brute_partly_seen(const BruteSide& b1, const BruteSide& b2) {
    const double limit = std::max(0.2, 3.72 * std::sqrt(0.5 / b1.n + 0.5 / b2.n));
    return (b2.lateral - b1.lateral).norm() > limit * b1.lateral_spread;
}

// A wavy surface with a step and noise, and a compared epoch bulged and noisier.
std::vector<Vector3d> surface(int n, double bulge, double sigma, unsigned seed) {
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<Vector3d> points;
    for (int i = 0; i < n; ++i) {
        const double x = u(random), y = u(random);
        double z = 0.1 * std::sin(3 * x) + (x > 0.4 ? 0.15 : 0.0);
        z += bulge * std::exp(-(x * x + y * y) / 0.2) + noise(random);
        points.emplace_back(x + 100.0, y - 50.0, z + 20.0);  // away from the origin
    }
    return points;
}

struct Case {
    const char* name;
    bool median;
    Orientation orientation;
    double stray_distance = std::numeric_limits<double>::infinity();
};

void PrintTo(const Case& c, std::ostream* os) {
    *os << c.name;
}

class M3c2BruteForce : public ::testing::TestWithParam<Case> {};

TEST_P(M3c2BruteForce, EqualsTheDefinitions) {
    const Case& c = GetParam();
    const auto p1 = surface(3000, 0.0, 0.003, 11);
    const auto p2 = surface(2500, 0.02, 0.004, 12);
    const NormalParameters normals{{0.08, 0.15, 0.3}, c.orientation};
    const CylinderParameters cylinder{
        0.08, 0.25, c.median ? CylinderStatistic::median : CylinderStatistic::mean,
        c.stray_distance};
    // Some cylinders at the step are rougher than 1 cm: refused, strays or not.
    const DistanceParameters distance{4, 0.001, 0.01};
    auto cores = subsample(p1, 0.2);
    cores.push_back({100.0, -50.0, 30.0});  // far above the surface: no neighbours
    ASSERT_GT(cores.size(), 60u);

    const Reference r1 = prepare_reference(p1, cores, normals, cylinder, 1);
    const Reference r2 = prepare_reference(p1, cores, normals, cylinder, 2);
    const auto s1 = cylinder_sides(r1.cylinders, p2, 1), s2 = cylinder_sides(r2.cylinders, p2, 2);
    const auto d = distances(r2, s2, distance);

    std::size_t defined = 0, clipped = 0, rough = 0;
    for (std::size_t k = 0; k < cores.size(); ++k) {
        SCOPED_TRACE(k);
        // The same bits with one thread or two.
        EXPECT_EQ(r1.normals()[k].allFinite(), r2.normals()[k].allFinite());
        if (r1.normals()[k].allFinite()) {
            EXPECT_EQ(r1.normals()[k], r2.normals()[k]);
        }
        EXPECT_EQ(s1[k].count, s2[k].count);
        if (!std::isnan(s1[k].centre)) {
            EXPECT_EQ(s1[k].centre, s2[k].centre);
        }

        const Vector3d v = c.orientation.kind == Orientation::Kind::vector
                               ? c.orientation.value
                               : Vector3d(c.orientation.value - cores[k]);
        const BruteNormal bn = brute_normal(p1, cores[k], normals.radii, v);
        if (!bn.normal.allFinite()) {
            EXPECT_FALSE(r2.normals()[k].allFinite());
            EXPECT_TRUE(std::isnan(r2.normal_radius[k]));
            EXPECT_TRUE(std::isnan(d[k].distance));
            continue;
        }
        EXPECT_EQ(r2.normal_radius[k], bn.radius);
        EXPECT_LT((r2.normals()[k] - bn.normal).norm(), 1e-9);
        const auto b1 = brute_side(p1, cores[k], bn.normal, cylinder.radius, cylinder.max_depth,
                                   c.median, c.stray_distance, clipped);
        const auto b2 = brute_side(p2, cores[k], bn.normal, cylinder.radius, cylinder.max_depth,
                                   c.median, c.stray_distance, clipped);
        EXPECT_EQ(r2.reference_side[k].count, b1.n);
        EXPECT_EQ(s2[k].count, b2.n);
        if (b1.n >= 2) {
            EXPECT_NEAR(r2.reference_side[k].roughness, b1.roughness, 1e-9);
        }
        if (b1.n >= 1 && b2.n >= 1) {
            EXPECT_LT((r2.reference_side[k].lateral - b1.lateral).norm(), 1e-9);
            EXPECT_NEAR(s2[k].lateral_spread, b2.lateral_spread, 1e-9);
        }
        if (b1.n < distance.min_points || b2.n < distance.min_points || std::isnan(b1.centre) ||
            std::isnan(b2.centre) || !(b1.roughness <= distance.max_reference_spread) ||
            brute_partly_seen(b1, b2)) {
            rough += b1.roughness > distance.max_reference_spread;
            EXPECT_TRUE(std::isnan(d[k].distance));
            EXPECT_FALSE(d[k].significant);
            continue;
        }
        ++defined;
        EXPECT_NEAR(r2.reference_side[k].centre, b1.centre, 1e-9);
        EXPECT_NEAR(r2.reference_side[k].spread, b1.spread, 1e-9);
        EXPECT_NEAR(s2[k].spread, b2.spread, 1e-9);
        EXPECT_NEAR(d[k].distance, b2.centre - b1.centre, 1e-9);
        const double lod =
            1.96 * (std::sqrt(b1.spread * b1.spread / b1.n + b2.spread * b2.spread / b2.n) +
                    distance.registration_error);
        EXPECT_NEAR(d[k].lod, lod, 1e-9);
        if (std::abs(std::abs(d[k].distance) - lod) > 1e-9) {
            EXPECT_EQ(d[k].significant, std::abs(b2.centre - b1.centre) > lod);
        }
    }
    EXPECT_GT(defined, cores.size() / 2);
    EXPECT_GT(rough, 0u);  // the step's cylinders
    // The mean leaves strays out (the cylinders across the step hold the other level); the
    // median ignores them.
    EXPECT_EQ(clipped > 0, std::isfinite(c.stray_distance) && !c.median) << clipped;
}

INSTANTIATE_TEST_SUITE_P(
    Statistics, M3c2BruteForce,
    ::testing::Values(Case{"mean_up", false, Orientation::along({0, 0, 1})},
                      Case{"median_up", true, Orientation::along({0, 0, 1})},
                      Case{"mean_scanner", false, Orientation::towards({101, -49, 21})},
                      Case{"median_down", true, Orientation::along({0.2, 0.1, -1})},
                      Case{"mean_strays", false, Orientation::along({0, 0, 1}), 0.005},
                      Case{"median_ignores_strays", true, Orientation::along({0, 0, 1}), 0.005}),
    [](const auto& info) { return std::string(info.param.name); });

// Batches of core points (a tiny member budget) give the same members as one batch, and the
// members are exactly the points within the radius, ascending; points left out (an edge
// point's mark, pipeline/m3c2_stage.hpp) are no core point's member, in one pass and in
// batches alike.
TEST(M3c2Members, BatchesGiveTheSameMembersAsTheDefinition) {
    const auto cloud = surface(4000, 0.0, 0.003, 21);
    const auto cores = subsample(cloud, 0.15);
    const double radius = 0.2;
    const RegionIndex index = RegionIndex::spheres(cores, radius, 0.1);
    std::vector<std::uint8_t> every_third(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) every_third[i] = i % 3 == 1;
    for (const auto& left_out : {std::vector<std::uint8_t>{}, every_third})
        for (const bool single_pass : {true, false})
            for (std::size_t budget : {std::size_t{1}, std::size_t{500}, kMemberBudget}) {
                std::vector<std::vector<std::uint32_t>> members(cores.size());
                for_each_core_with_members(
                    cloud, index, cores.size(),
                    [&](std::uint32_t k, const Vector3d& p) {
                        return (p - cores[k]).norm() <= radius;
                    },
                    [&](std::size_t k, std::span<const std::uint32_t> m) {
                        members[k].assign(m.begin(), m.end());
                    },
                    2, budget, single_pass, left_out);
                std::size_t found = 0;
                for (std::size_t k = 0; k < cores.size(); ++k) {
                    std::vector<std::uint32_t> expected;
                    for (std::uint32_t i = 0; i < cloud.size(); ++i)
                        if ((left_out.empty() || !left_out[i]) &&
                            (cloud[i] - cores[k]).norm() <= radius)
                            expected.push_back(i);
                    ASSERT_EQ(members[k], expected) << "core " << k << ", budget " << budget;
                    found += expected.size();
                }
                EXPECT_GT(found, 1000u);  // the test sees members, not empty sets
            }
    std::vector<std::uint8_t> wrong(cloud.size() - 1);
    EXPECT_THROW(
        for_each_core_with_members(
            cloud, index, cores.size(), [](std::uint32_t, const Vector3d&) { return true; },
            [](std::size_t, std::span<const std::uint32_t>) {}, 1, kMemberBudget, true, wrong),
        Error);
}

// The reference's normals and sides, and an epoch's sides, with points marked as left out are
// those of the cloud without them, to the bit: the stage marks a scan's edge points instead of
// copying the rest.
TEST(M3c2BruteForceLeftOut, MarkedPointsGiveWhatTheirRemovalGives) {
    const auto p1 = surface(3000, 0.0, 0.003, 31);
    const auto p2 = surface(2500, 0.02, 0.004, 32);
    const NormalParameters normals{{0.08, 0.15, 0.3}, Orientation{}};
    const CylinderParameters cylinder{0.08, 0.25, CylinderStatistic::median};
    const auto cores = subsample(p1, 0.2);
    auto mark = [](const std::vector<Vector3d>& cloud, std::vector<Vector3d>& kept) {
        std::vector<std::uint8_t> left_out(cloud.size());
        for (std::size_t i = 0; i < cloud.size(); ++i) {
            left_out[i] = cloud[i].x() > 100.3 && cloud[i].x() < 100.5;  // across the step
            if (!left_out[i]) kept.push_back(cloud[i]);
        }
        return left_out;
    };
    std::vector<Vector3d> kept1, kept2;
    const auto out1 = mark(p1, kept1), out2 = mark(p2, kept2);
    ASSERT_LT(kept1.size() + 200, p1.size());
    const Reference marked = prepare_reference(p1, cores, normals, cylinder, 2, {}, out1);
    const Reference removed = prepare_reference(kept1, cores, normals, cylinder, 2);
    const Reference all = prepare_reference(p1, cores, normals, cylinder, 2);
    const auto side_marked = cylinder_sides(marked.cylinders, p2, 2, out2);
    const auto side_removed = cylinder_sides(removed.cylinders, kept2, 2);
    std::size_t differs = 0;
    for (std::size_t k = 0; k < cores.size(); ++k) {
        SCOPED_TRACE(k);
        EXPECT_EQ(marked.normals()[k].allFinite(), removed.normals()[k].allFinite());
        if (marked.normals()[k].allFinite()) {
            EXPECT_EQ(marked.normals()[k], removed.normals()[k]);
        }
        EXPECT_EQ(marked.reference_side[k].count, removed.reference_side[k].count);
        EXPECT_EQ(side_marked[k].count, side_removed[k].count);
        if (side_marked[k].count > 0) {
            EXPECT_EQ(side_marked[k].centre, side_removed[k].centre);
        }
        differs += marked.reference_side[k].count != all.reference_side[k].count;
    }
    EXPECT_GT(differs, 5u);  // the strip mattered
}

}  // namespace
}  // namespace tlsmon::test
