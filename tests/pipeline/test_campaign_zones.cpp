// A campaign's zone values (pipeline/campaign_zones.hpp) against values worked by hand: the
// median of the C2C vectors along the zone's design normal (sign as M3C2: outward positive),
// its LoD95 from the median's sampling variance and each segment's registration σ along the
// normal at the zone's points, and what is left out.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "pipeline/campaign_zones.hpp"

namespace tlsmon {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 200 points near the plane y = 0 (20 × 10, 0.1 m apart) about `origin`; each point's distance
// along +y is 4 mm plus −2, −1, 0, 1, 2 mm in turn (40 of each): median 4 mm, MAD 1 mm.
struct Face {
    CampaignPoints points;
    Face() {
        points.origin = {100, 200.5, 10};
        for (const char* name :
             {"x_m", "y_m", "z_m", "segment", "c2c_dx_m", "c2c_dy_m", "c2c_dz_m"})
            points.arrays.push_back({name, {}});
        for (int i = 0; i < 200; ++i)
            add(0.1 * (i % 20), 0.1 * (i / 20), 0, 0.004 + 0.001 * (i % 5 - 2));
    }
    // A point at (x, d, z) from the origin, d outward (+y) of the reference's surface (the
    // plane y = 0 there): its C2C vector points back, −d·y, with a small component along the
    // face that a distance along the normal must ignore.
    void add(double x, double z, int segment, double d) {
        const double v[7] = {x, d, z, double(segment), 0.0005, -d, 0};
        for (int k = 0; k < 7; ++k) points.arrays[std::size_t(k)].values.push_back(float(v[k]));
    }
};

ZoneShape face_zone(const std::string& name, bool with_normal = true) {
    ZoneShape z = box_zone(name, {99.9, 200.4, 9.9}, {102.1, 200.6, 11.1});
    if (with_normal) z.normal = Eigen::Vector3d(0, 1, 0);
    return z;
}

CampaignSegmentRow segment(std::int64_t id, const std::string& outcome,
                           const Eigen::Vector3d& centroid,
                           std::array<std::optional<double>, 6> sigmas) {
    CampaignSegmentRow s;
    s.segment = id;
    s.outcome = outcome;
    for (int k = 0; k < 3; ++k) s.centroid[std::size_t(k)] = centroid(k);
    s.sigmas = sigmas;
    return s;
}

TEST(CampaignZones, MedianAlongTheNormalWithTheMediansAndTheSegmentsSigma) {
    Face face;
    // Left out: a segment that was not registered, points without a C2C, points outside.
    for (int i = 0; i < 20; ++i) face.add(0.1 * i, 0.55, 1, 0.05);
    for (int i = 0; i < 5; ++i) face.add(0.1 * i, 0.25, 0, kNaN);
    for (int i = 0; i < 30; ++i) face.add(5 + 0.03 * i, 0.25, 0, 0.5);
    // The grid's mean is (100.95, 200.5, 10.45) (and 4 mm); the centroid 1 m below it: the lever
    // arm r = (0, 0, 1), r × n = (−1, 0, 0), so σ along n = √(σ_rx² + σ_ty²) (σ_tx does not reach
    // along y; σ_tz is unobserved).
    const Eigen::Vector3d centroid(100.95, 200.5, 9.45);
    const std::vector<CampaignSegmentRow> segments{
        segment(0, "registered", centroid, {2e-4, 1e-3, 1e-3, 3e-3, 5e-4, std::nullopt}),
        segment(1, "unobserved", centroid, {})};
    const auto rows = campaign_zone_results(face.points, segments,
                                            {face_zone("face"), face_zone("no normal", false)}, 30);
    ASSERT_EQ(rows.size(), 1u);  // no direction to measure along: no row
    const ZoneResult& r = rows[0];
    EXPECT_EQ(r.zone, "face");
    EXPECT_EQ(r.quantity, "campaign_c2c_median_m");
    EXPECT_EQ(r.n, 200);
    EXPECT_NEAR(r.value, 0.004, 1e-7);  // float32 storage
    const double median_sigma = std::sqrt(std::numbers::pi / 2) * 1.4826 * 0.001 / std::sqrt(200.0);
    const double expected =
        1.96 * std::sqrt(median_sigma * median_sigma + 2e-4 * 2e-4 + 5e-4 * 5e-4);
    ASSERT_TRUE(r.uncertainty);
    EXPECT_NEAR(*r.uncertainty, expected, 1e-6);
    EXPECT_TRUE(r.significant);  // 4 mm against an LoD95 of about 1.1 mm
    // (Its 1 m cells — two on the face, one outside it — have the same median but one: the
    // segment is rigid, nothing is added for its shape.)
}

TEST(CampaignZones, ASegmentThatIsNotRigidAddsTheSpreadOfItsCells) {
    // A face 6 m long in six 1 m cells of 100 points, each cell offset by 0, +2, −2, +4, −4,
    // 0 mm (the SLAM's drift went on while the face was seen), each point ±2, ±1, 0 mm about
    // it. The cells' medians spread with a MAD of 2 mm; each median's own sampling variance is
    // (√(π/2)·1.4826·1 mm)²/100. The zone on the +4 mm cell: its value 4 mm, its σ² the
    // median's sampling variance plus the segment's non-rigidity, (1.4826·2 mm)² less it.
    Face face;
    for (auto& a : face.points.arrays) a.values.clear();
    const double offset[6] = {0, 0.002, -0.002, 0.004, -0.004, 0};
    for (int i = 0; i < 600; ++i) {
        const int column = i % 60, row = i / 60;
        face.add(0.1 * column, 0.1 * row, 0, offset[column / 10] + 0.001 * (i % 5 - 2));
    }
    ZoneShape cell = box_zone("cell", {102.95, 200.4, 9.9}, {103.95, 200.6, 11.1});
    cell.normal = Eigen::Vector3d(0, 1, 0);
    const auto rows = campaign_zone_results(
        face.points, {segment(0, "registered", {103, 200.5, 10.45}, {})}, {cell}, 30);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].n, 100);
    EXPECT_NEAR(rows[0].value, 0.004, 1e-7);
    const double sampling = std::pow(std::sqrt(std::numbers::pi / 2) * 1.4826 * 0.001, 2) / 100;
    const double nonrigid = std::pow(1.4826 * 0.002, 2) - sampling;
    EXPECT_NEAR(*rows[0].uncertainty, 1.96 * std::sqrt(sampling + nonrigid), 1e-6);
    EXPECT_FALSE(rows[0].significant);  // 4 mm inside the segment's own waviness (5.8 mm)
}

TEST(CampaignZones, SegmentsWeightedByTheirShareAndTooFewPointsGiveNoRow) {
    Face face;
    // Half the points in a second registered segment: var = (½σ₀)² + (½σ₂)² along n, with
    // translation σ only (the lever arm does not matter).
    auto& seg = face.points.arrays[3].values;
    for (std::size_t i = 0; i < seg.size(); ++i) seg[i] = float(i < 100 ? 0 : 2);
    const Eigen::Vector3d c(101, 200.5, 10.5);
    const std::vector<CampaignSegmentRow> segments{
        segment(0, "registered", c, {std::nullopt, std::nullopt, std::nullopt, 0, 0.004, 0}),
        segment(2, "registered", c, {std::nullopt, std::nullopt, std::nullopt, 0, 0.002, 0})};
    auto rows = campaign_zone_results(face.points, segments, {face_zone("face")}, 30);
    ASSERT_EQ(rows.size(), 1u);
    const double median_sigma = std::sqrt(std::numbers::pi / 2) * 1.4826 * 0.001 / std::sqrt(200.0);
    const double expected =
        1.96 * std::sqrt(median_sigma * median_sigma + 0.002 * 0.002 + 0.001 * 0.001);
    EXPECT_NEAR(*rows[0].uncertainty, expected, 1e-6);
    EXPECT_FALSE(rows[0].significant);  // 4 mm inside an LoD95 of about 4.4 mm

    EXPECT_TRUE(campaign_zone_results(face.points, segments, {face_zone("face")}, 201).empty());
    EXPECT_EQ(campaign_zone_results(face.points, segments, {face_zone("face")}, 200).size(), 1u);
    EXPECT_TRUE(campaign_zone_results(CampaignPoints{}, segments, {face_zone("face")}, 1).empty());
}

}  // namespace
}  // namespace tlsmon
