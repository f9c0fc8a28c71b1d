// A rendered scan written as PTX and read back through read_ptx: grid, empty cells, and
// coordinates consistent with the scene geometry within the measurement noise.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "formats/ptx_reader.hpp"
#include "formats/ptx_writer.hpp"
#include "simulator/render.hpp"
#include "simulator/terrain.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Within 1 m (horizontally) of a target: its mast or stand, not the ground.
bool near_a_target(const Site& site, const Eigen::Vector3d& p) {
    for (const Target& t : site.targets) {
        if ((p - t.centre).head<2>().norm() < 1.0) return true;
    }
    return false;
}

// On a face of a stable block (foundation, abutment), to 1e-5 m.
bool on_a_block(const Site& site, const Eigen::Vector3d& p) {
    for (const Block& b : site.terrain.blocks) {
        const Eigen::Vector3d lo = b.lo.array() - 1e-5, hi = b.hi.array() + 1e-5;
        if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
        if (((p - b.lo).cwiseAbs().array() < 1e-5).any() ||
            ((p - b.hi).cwiseAbs().array() < 1e-5).any()) {
            return true;
        }
    }
    return false;
}

Scan render_and_read_back(const Site& site, int epoch, double hours, const std::string& name) {
    const RenderedScan r = render_epoch(site, epoch, hours);
    const tlsmon::test::TempDir dir;
    const auto path = dir / name;
    write_ptx(r.scan, path);
    std::vector<Scan> scans = read_ptx(path);
    EXPECT_EQ(scans.size(), 1u);
    return std::move(scans.at(0));
}

TEST(SimulatorReadBack, SmallPresetHasTheExpectedGridAndCells) {
    const Site site = preset_small();
    const RenderedScan r = render_epoch(site, 0, 0.0);
    const tlsmon::test::TempDir dir;
    const auto path = dir / "grid.ptx";
    write_ptx(r.scan, path);
    const Scan back = read_ptx(path).at(0);

    // 62..95° at 0.1° and −8..46° at 0.1°.
    ASSERT_TRUE(back.grid);
    EXPECT_EQ(back.grid->columns, 331u);
    EXPECT_EQ(back.grid->rows, 541u);
    ASSERT_EQ(back.size(), r.scan.size());
    EXPECT_GT(back.size(), 50'000u);
    EXPECT_LT(back.size(), back.grid->cells());  // sky cells are empty
    for (std::size_t i = 0; i < back.size(); ++i) {
        ASSERT_EQ(back.grid->row[i], r.scan.grid->row[i]);
        ASSERT_EQ(back.grid->column[i], r.scan.grid->column[i]);
        ASSERT_LT((back.xyz[i] - r.scan.xyz[i]).norm(), 2e-6);  // 6 decimals in the file
        ASSERT_NEAR(back.intensity[i], r.scan.intensity[i], 1e-6);
    }
    EXPECT_TRUE(back.pose.isApprox(r.scan.pose));
}

TEST(SimulatorReadBack, SkyAbovePierIsEmptyAndPierBelowTopIsHit) {
    const Site site = preset_small();
    const Scan back = render_and_read_back(site, 0, 0.0, "sky.ptx");
    const ScanGrid& g = *back.grid;
    std::vector<char> filled(g.cells(), 0);
    for (std::size_t i = 0; i < back.size(); ++i) filled[g.column[i] * g.rows + g.row[i]] = 1;

    // The column looking at the centre of the south face.
    const Pier& p = site.pier;
    const double az = std::atan2(p.y0, 0.5 * (p.x0 + p.x1)) / kDeg;
    const auto column =
        static_cast<std::uint32_t>(std::lround((site.scanner.azimuth_max_deg - az) / 0.1));
    const double top_el =
        std::atan2(p.height - site.scanner.position.z(), std::hypot(0.5 * (p.x0 + p.x1), p.y0)) /
        kDeg;  // ≈ 40.1°
    int sky = 0, pier = 0;
    for (std::uint32_t row = 0; row < g.rows; ++row) {
        const double el = site.scanner.elevation_min_deg + row * 0.1;
        const bool hit = filled[column * g.rows + row];
        if (el > top_el + 0.3) {
            EXPECT_FALSE(hit) << "row " << row << " elevation " << el;
            ++sky;
        } else if (el > 0.0 && el < top_el - 0.3) {
            EXPECT_TRUE(hit) << "row " << row << " elevation " << el;
            ++pier;
        }
    }
    EXPECT_GT(sky, 40);
    EXPECT_GT(pier, 300);
}

// Ground points (beams well below the horizon, where nothing but the ground is) lie on
// z = 0 within the noise: σ_z² = (σ_r sin e)² + (ρ σ_angle)², σ_r = a + b·r.
TEST(SimulatorReadBack, GroundPointsLieOnTheGroundWithinTheNoise) {
    Site site = preset_small();
    site.drift.enabled = false;                 // the header pose is then the true pose
    site.noise.model = Noise::Model::constant;  // σ_r = a + b·r as below
    site.beam.footprint = false;                // no footprint range bias on the grazing ground
    const Scan back = render_and_read_back(site, 0, 0.0, "ground.ptx");
    const Eigen::Vector3d o = site.scanner.position;
    const double sa = site.noise.angular_arcsec * kDeg / 3600.0;
    std::size_t n = 0, within3 = 0;
    double sum = 0.0, sum_sq = 0.0;
    for (std::size_t i = 0; i < back.size(); ++i) {
        const double el = site.scanner.elevation_min_deg + back.grid->row[i] * 0.1;
        if (el > -2.5) continue;  // targets and the pier foot are above −2°
        if (near_a_target(site, back.xyz[i])) continue;  // masts and stands reach lower
        const Eigen::Vector3d d = back.xyz[i] - o;
        const double r = d.norm();
        const double sr = site.noise.range_a + site.noise.range_b_ppm * 1e-6 * r;
        const double s = std::hypot(sr * std::sin(el * kDeg), r * sa);
        const double z = back.xyz[i].z() / s;
        ++n;
        sum += z;
        sum_sq += z * z;
        if (std::abs(z) <= 3.0) ++within3;
        ASSERT_LT(std::abs(z), 6.0) << "point " << i << " z = " << back.xyz[i].z();
    }
    ASSERT_GT(n, 10'000u);
    const double mean = sum / n, sd = std::sqrt(sum_sq / n - mean * mean);
    EXPECT_NEAR(mean, 0.0, 0.05);
    EXPECT_NEAR(sd, 1.0, 0.1);  // the noise is as large as the model says, not smaller
    EXPECT_GT(static_cast<double>(within3) / n, 0.99);
}

// A scanner set up with a heading: the PTX header carries a real rotation, and the points
// read back through it land on the true scene (the writer's row-vector matrix and axes
// agree with the reader's).
TEST(SimulatorReadBack, HeaderRotationTakesPointsToTheProjectFrame) {
    Site site = preset_small();
    site.noise.enabled = false;
    site.drift.enabled = false;
    site.deformation.enabled = false;
    site.atmosphere.enabled = false;  // no atmospheric range scale
    site.beam.footprint = false;      // exact ranges: one thin ray per cell
    site.scanner.heading_deg = 30.0;  // the same window, seen from a turned instrument
    site.scanner.azimuth_min_deg -= 30.0;
    site.scanner.azimuth_max_deg -= 30.0;
    const Scan back = render_and_read_back(site, 0, 0.0, "heading.ptx");
    const Eigen::Matrix3d r = back.pose.linear();
    EXPECT_NEAR(std::atan2(r(1, 0), r(0, 0)) / kDeg, 30.0, 1e-6);
    std::size_t ground = 0, face = 0, block = 0;
    for (const auto& p : back.xyz) {
        if (std::abs(p.z() - terrain_height(site.terrain, p.y())) < 1e-5) ++ground;
        if (on_a_block(site, p)) ++block;
        if (std::abs(p.y() - site.pier.y0) < 1e-5 && p.x() > site.pier.x0 && p.x() < site.pier.x1) {
            ++face;
        }
    }
    // Nearly every point is on the terrain, a stable block or the south face (the rest: the
    // grazing west face, the targets and their supports).
    EXPECT_GT(ground, 5'000u);
    EXPECT_GT(face, 30'000u);
    EXPECT_GT(block, 500u);
    EXPECT_GT(ground + face + block, back.size() * 95 / 100);
}

}  // namespace
}  // namespace tlsmon::sim
