// ICP on stable regions (pipeline/icp_registration.hpp) on the simulator's `pier` preset with
// scanner drift (standing axis 60″, tilt 10″, translation σ 1.5 mm per axis) against the
// truth: for epoch i the exact map into epoch 0's frame is H₀⁻¹·Hᵢ (H = header_to_true,
// docs/simulator.md). The stable regions are the simulator's own (simulator/stable_ground.hpp,
// what `tlsmon simulate` writes). To stay fast, the ground and the blocks are rendered at a
// 0.05° step in the scan's lower band only, the targets in narrow windows at the preset's step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../simulator/narrow_window.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/icp_registration.hpp"
#include "simulator/render.hpp"
#include "simulator/stable_ground.hpp"
#include "tests/support/simulated_targets.hpp"
#include "tests/support/stable_band.hpp"

namespace tlsmon {
namespace {

sim::Site drifting_pier(std::uint64_t seed = 1) {
    sim::Site site = sim::preset_pier();
    site.drift.yaw_amplitude_arcsec = 60.0;
    site.drift.tilt_amplitude_arcsec = 10.0;
    site.drift.translation_sigma = 0.0015;
    site.atmosphere.enabled = false;  // no meteo here: nothing would correct a range scale
    site.noise.seed = seed;
    return site;
}

RegistrationConfig site_config(const sim::Site& site, IcpMode mode) {
    RegistrationConfig c = test::simulated_targets(site);
    c.icp.mode = mode;
    for (const auto& b : sim::stable_ground(site)) c.icp.regions.push_back({b.name, b.min, b.max});
    return c;
}

struct RenderedEpoch {
    std::vector<Scan> scans;
    Eigen::Affine3d header_to_true;
};

// The targets named in `visible` in narrow windows (first, so a target is fitted there), then
// the lower band of the scan (the ground, the blocks, the pier's foot) at 0.05°. The other
// targets are taken off the site: not there to be seen in any window.
RenderedEpoch render(sim::Site site, int epoch, double hours,
                     const std::vector<std::string>& visible) {
    std::erase_if(site.targets, [&](const sim::Target& t) {
        return std::find(visible.begin(), visible.end(), t.name) == visible.end();
    });
    RenderedEpoch out;
    const Eigen::Affine3d N = sim::nominal_pose(site.scanner);
    for (const auto& t : site.targets) {
        if (std::find(visible.begin(), visible.end(), t.name) == visible.end()) continue;
        sim::Site one = site;
        sim::test::narrow_window(one.scanner, t.centre, 0.9);
        out.scans.push_back(sim::render_epoch(one, epoch, hours, 2).scan);
    }
    const sim::RenderedScan r =
        test::render_lower_band(site, sim::epoch_conditions(site, epoch, hours), 12.0);
    out.header_to_true = N * r.pose_error.transform() * N.inverse();
    out.scans.push_back(r.scan);
    return out;
}

// Points on the pier's south and west faces, every 2.5 m.
std::vector<Eigen::Vector3d> pier_points(const sim::Site& site) {
    std::vector<Eigen::Vector3d> p;
    for (double z = 0.0; z <= site.pier.height; z += 2.5) {
        for (double x = site.pier.x0; x <= site.pier.x1; x += 2.5)
            p.emplace_back(x, site.pier.y0, z);
        for (double y = site.pier.y0; y <= site.pier.y1; y += 2.5)
            p.emplace_back(site.pier.x0, y, z);
    }
    return p;
}

struct Scored {
    double max_error = 0;  // m, largest 3-D error over the pier's points
    double rms = 0;        // m
    Eigen::Vector3d top_error = Eigen::Vector3d::Zero();  // at the pier's top corner
    Eigen::Vector3d top_sigma = Eigen::Vector3d::Zero();
};

Scored score(const registration::RigidTransform& T, const Eigen::Affine3d& H0,
             const Eigen::Affine3d& Hi, const std::vector<Eigen::Vector3d>& pier) {
    Scored s;
    for (const auto& P : pier) {
        const Eigen::Vector3d e = T.apply(Hi.inverse() * P) - H0.inverse() * P;
        s.rms += e.squaredNorm();
        s.max_error = std::max(s.max_error, e.norm());
    }
    s.rms = std::sqrt(s.rms / pier.size());
    const Eigen::Vector3d x = Hi.inverse() * pier.back();
    s.top_error = T.apply(x) - H0.inverse() * pier.back();
    s.top_sigma = registration::registration_covariance_at(T, x).diagonal().cwiseSqrt();
    return s;
}

void print(const char* what, const Scored& s) {
    std::printf(
        "%s: pier max %.3f mm, RMS %.3f mm; top corner error (%.3f, %.3f, %.3f) mm, "
        "σ (%.3f, %.3f, %.3f) mm\n",
        what, 1e3 * s.max_error, 1e3 * s.rms, 1e3 * s.top_error.x(), 1e3 * s.top_error.y(),
        1e3 * s.top_error.z(), 1e3 * s.top_sigma.x(), 1e3 * s.top_sigma.y(), 1e3 * s.top_sigma.z());
}

const std::vector<std::string> kTwoTargets = {"T1", "T6"};

// Only two targets visible: the targets alone are refused as too few; the ICP fallback on the
// stable regions recovers the pose to within its σ and 2 mm at the pier, and says so.
TEST(IcpRegistration, FallbackRecoversThePoseWithTwoTargets) {
    const sim::Site site = drifting_pier();
    const RegistrationConfig config = site_config(site, IcpMode::fallback);
    const RenderedEpoch e0 = render(site, 0, 0.0, kTwoTargets);
    const ReferenceTargets reference = measure_reference_targets(config, e0.scans);
    const StableSurface surface = build_stable_surface(config.icp, e0.scans);
    std::printf("reference surface: %zu points in the regions, %zu with normals\n", surface.cropped,
                surface.sample.points.size());
    const RenderedEpoch e1 = render(site, 1, 6.5, kTwoTargets);
    RegistrationResult r = register_epoch(config, reference, e1.scans, {});
    ASSERT_EQ(r.tested.status, registration::RegistrationStatus::too_few_targets);
    apply_icp(config, surface, e1.scans, {}, r);
    ASSERT_TRUE(r.icp);
    std::printf("%s\n", icp_quality(*r.icp).dump().c_str());
    if (r.icp->transform) {
        print("ICP alone",
              score(*r.icp->transform, e0.header_to_true, e1.header_to_true, pier_points(site)));
    }
    ASSERT_TRUE(r.accepted()) << r.tested.reason << " " << r.gate;
    EXPECT_EQ(registration_method(r), "icp");
    EXPECT_EQ(r.icp->role, "fallback");
    EXPECT_TRUE(r.icp->used);
    EXPECT_NE(r.icp->targets_status.find("too_few_targets"), std::string::npos);
    const Scored s =
        score(*r.tested.transform, e0.header_to_true, e1.header_to_true, pier_points(site));
    print("fallback", s);
    EXPECT_LE(s.max_error, 0.002);
    // Within 2σ in 3-D (the share of components within 2σ over many epochs is the next test's).
    EXPECT_LE(s.top_error.norm(), 2.0 * s.top_sigma.norm());
    // The drift it removed was far larger than what is left.
    const Scored none = score(registration::RigidTransform{}, e0.header_to_true, e1.header_to_true,
                              pier_points(site));
    print("unregistered", none);
    EXPECT_GT(none.max_error, 5.0 * s.max_error);
}

// Several series (noise and drift jitter seeded apart), a reference and two later epochs each:
// the share of the error's components at the pier's top corner within the fallback's 2σ, and
// RMS(error/σ) (the reference's own errors are one draw per series): 0.65 here, with the
// cells' τ by their weight (0.35 when each cell's mean residual counted alike, a σ padded at
// 0.05°; docs/registration.md, "The cells' τ by their weight"). The lower bound holds the σ
// from being padded again.
TEST(IcpRegistration, FallbackSigmaIsHonestOverSeveralEpochs) {
    constexpr int series = 3;
    int within = 0, components = 0;
    double sum_q2 = 0, worst = 0;
    for (int k = 0; k < series; ++k) {
        const sim::Site site = drifting_pier(301 + k);
        const RegistrationConfig config = site_config(site, IcpMode::fallback);
        const RenderedEpoch e0 = render(site, 0, 0.0, kTwoTargets);
        const ReferenceTargets reference = measure_reference_targets(config, e0.scans);
        const StableSurface surface = build_stable_surface(config.icp, e0.scans);
        for (int i = 1; i <= 2; ++i) {
            const RenderedEpoch ei = render(site, i, 2.0 * k + 6.5 * i, kTwoTargets);
            RegistrationResult r = register_epoch(config, reference, ei.scans, {});
            apply_icp(config, surface, ei.scans, {}, r);
            ASSERT_TRUE(r.accepted())
                << "series " << k << " epoch " << i << ": " << r.tested.reason << " " << r.gate;
            const Scored s =
                score(*r.tested.transform, e0.header_to_true, ei.header_to_true, pier_points(site));
            std::printf("series %d epoch %d: inflation %.2f, ", k, i, r.icp->inflation);
            print("fallback", s);
            worst = std::max(worst, s.max_error);
            for (int c = 0; c < 3; ++c) {
                within += std::fabs(s.top_error(c)) <= 2.0 * s.top_sigma(c);
                sum_q2 += s.top_error(c) * s.top_error(c) / (s.top_sigma(c) * s.top_sigma(c));
                ++components;
            }
        }
    }
    const double rms_q = std::sqrt(sum_q2 / components);
    std::printf("fallback: worst pier error %.3f mm; within 2 sigma %d/%d; RMS(error/sigma) %.2f\n",
                1e3 * worst, within, components, rms_q);
    EXPECT_LE(worst, 0.002);
    EXPECT_GE(within, static_cast<int>(std::ceil(0.8 * components)));
    EXPECT_LT(rms_q, 1.5);
    EXPECT_GT(rms_q, 0.45);
}

// All six targets: an accepted target registration refined by the ICP is combined only when
// the two agree, and the refined error at the pier is not worse than the targets' alone
// (beyond a tenth of a millimetre).
TEST(IcpRegistration, RefinementDoesNotMakeAGoodTargetRegistrationWorse) {
    std::vector<std::string> all;
    for (int k = 1; k <= 6; ++k) all.push_back("T" + std::to_string(k));
    for (int k = 0; k < 2; ++k) {
        const sim::Site site = drifting_pier(401 + k);
        const RegistrationConfig config = site_config(site, IcpMode::refine);
        const RenderedEpoch e0 = render(site, 0, 0.0, all);
        const ReferenceTargets reference = measure_reference_targets(config, e0.scans);
        const StableSurface surface = build_stable_surface(config.icp, e0.scans);
        const RenderedEpoch e1 = render(site, 1, 3.0 + 5.0 * k, all);
        RegistrationResult r = register_epoch(config, reference, e1.scans, {});
        ASSERT_TRUE(r.accepted()) << r.tested.reason << " " << r.gate;
        const Scored targets =
            score(*r.tested.transform, e0.header_to_true, e1.header_to_true, pier_points(site));
        apply_icp(config, surface, e1.scans, {}, r);
        ASSERT_TRUE(r.icp);
        std::printf("%s\n", icp_quality(*r.icp).dump().c_str());
        ASSERT_TRUE(r.accepted());
        const Scored refined =
            score(*r.tested.transform, e0.header_to_true, e1.header_to_true, pier_points(site));
        print("targets", targets);
        print(registration_method(r).c_str(), refined);
        EXPECT_EQ(registration_method(r), r.icp->used ? "targets+icp" : "targets");
        EXPECT_LE(refined.max_error, targets.max_error + 0.0001);
        EXPECT_LE(refined.max_error, 0.001);
    }
}

// The structure moves (every point of the pier shifted by 50 mm towards the scanner and 30 mm
// sideways, as no pier ever should): the ICP's result is the same to the last bit, because no
// point of the pier is inside a stable region. The control: a box over the pier's foot lets
// the same movement pull the registration away, unless a check zone covers it.
TEST(IcpRegistration, PointsOfTheStructureNeverEnterTheIcp) {
    const sim::Site site = drifting_pier(7);
    RegistrationConfig config = site_config(site, IcpMode::fallback);
    const RenderedEpoch e0 = render(site, 0, 0.0, kTwoTargets);
    const RenderedEpoch e1 = render(site, 1, 4.0, kTwoTargets);
    const auto& p = site.pier;
    const auto on_pier = [&](const Eigen::Vector3d& x) {
        return x.x() > p.x0 - 0.1 && x.x() < p.x1 + 0.1 && x.y() > p.y0 - 0.1 &&
               x.y() < p.y1 + 0.1 && x.z() > 0.3;
    };
    std::vector<Scan> moved = e1.scans;
    std::size_t pier_points_moved = 0;
    for (auto& scan : moved) {
        for (auto& x : scan.xyz) {
            if (on_pier(x)) {
                x += Eigen::Vector3d(0.03, -0.05, 0.0);
                ++pier_points_moved;
            }
        }
    }
    ASSERT_GT(pier_points_moved, 1000u);
    const auto run = [&](const RegistrationConfig& c, const std::vector<Scan>& scans) {
        const StableSurface surface = build_stable_surface(c.icp, e0.scans);
        // Every point ICP takes lies inside a region.
        for (const auto& x : points_in_stable_regions(c.icp, scans, Eigen::Matrix4d::Identity())) {
            bool inside = false, excluded = false;
            for (const auto& r : c.icp.regions) inside = inside || r.contains(x);
            for (const auto& r : c.icp.excluded) excluded = excluded || r.contains(x);
            EXPECT_TRUE(inside && !excluded);
        }
        IcpMeasurement m = measure_icp(c, surface, scans, Eigen::Matrix4d::Identity());
        EXPECT_TRUE(m.transform);
        return m.transform ? m.transform->matrix() : Eigen::Matrix4d::Identity();
    };
    const Eigen::Matrix4d still = run(config, e1.scans);
    const Eigen::Matrix4d shifted = run(config, moved);
    EXPECT_EQ((still - shifted).cwiseAbs().maxCoeff(), 0.0);

    // The control: a region over the foundation including the pier's foot (3 m of it).
    RegistrationConfig careless = config;
    careless.icp.regions.push_back(
        {"foot", {p.x0 - 1.0, p.y0 - 1.0, 0.0}, {p.x1 + 1.0, p.y1 + 1.0, 3.0}});
    const Eigen::Matrix4d a = run(careless, e1.scans);
    const Eigen::Matrix4d b = run(careless, moved);
    const Eigen::Vector3d top(p.x0, p.y0, p.height);
    const double pulled =
        ((a - b).topLeftCorner<3, 3>() * top + (a - b).topRightCorner<3, 1>()).norm();
    std::printf("a region over the pier's foot: the movement pulls the pier's top by %.2f mm\n",
                1e3 * pulled);
    EXPECT_GT(pulled, 0.0005);

    // The same box as a check zone ([[zone]] no_change, config.cpp): its points leave the
    // regions, and the movement pulls nothing again.
    RegistrationConfig checked = careless;
    checked.icp.excluded.push_back(careless.icp.regions.back());
    EXPECT_EQ((run(checked, e1.scans) - run(checked, moved)).cwiseAbs().maxCoeff(), 0.0);
}

// An unchanged scan keeps its datum: the ICP of the real pump-room scan (shared data) onto
// itself gave κ 12.4″ and tx -0.17 mm. Onto an identical copy it must give the identity.
TEST(IcpRegistration, AnUnchangedScanKeepsItsDatum) {
    const std::vector<Scan> scans =
        read_scans(std::filesystem::path(TLSMON_DATA_DIR) / "ptx/pumpA_from_e57.ptx");
    RegistrationConfig c;
    c.icp.mode = IcpMode::fallback;
    c.icp.voxel_size = 0.05;  // a small room
    c.icp.regions.push_back({"room", {-3, -5.4, -1.6}, {1.8, -0.7, 1.9}});
    const StableSurface surface = build_stable_surface(c.icp, scans);
    const IcpMeasurement m = measure_icp(c, surface, scans, Eigen::Matrix4d::Identity());
    ASSERT_TRUE(m.transform) << m.refused;
    EXPECT_EQ(m.refused, "");
    const auto& T = *m.transform;
    constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);
    EXPECT_LT(std::abs(T.omega) / kArcsec, 0.1);
    EXPECT_LT(std::abs(T.phi) / kArcsec, 0.1);
    EXPECT_LT(std::abs(T.kappa) / kArcsec, 0.1);
    EXPECT_LT(T.translation.norm(), 1e-5);
}

// A real scan moved rigidly is found whole wherever the voxel grid falls on it. The pump-room
// scan moved by (2, -3, 6) mm and 72″ about z, the room placed at four offsets against the
// grid (fractions of a voxel): cut once, where the scanner had put it, each epoch voxel held
// another part of the room than its reference voxel, and the adjustment came out 27″ to 101″
// and 0.34 to 1.28 mm off, by the offset. Cut again where the adjustment puts it, the epoch's
// voxels hold the reference's parts at the solution (docs/registration.md, "ICP on stable
// regions", step 4).
TEST(IcpRegistration, AMovedRealScanIsFoundWholeWhereverTheGridFalls) {
    const Scan pump =
        read_scans(std::filesystem::path(TLSMON_DATA_DIR) / "ptx/pumpA_from_e57.ptx").at(0);
    const Eigen::Affine3d movement =
        Eigen::Translation3d(0.002, -0.003, 0.006) *
        Eigen::AngleAxisd(0.02 * 3.141592653589793 / 180, Eigen::Vector3d::UnitZ());
    constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);
    const std::vector<Eigen::Vector3d> offsets{
        {0, 0, 0}, {0.019, 0.031, 0.025}, {0.035, 0.015, 0.005}, {0.0085, 0.0425, 0.0445}};
    for (const Eigen::Vector3d& offset : offsets) {
        SCOPED_TRACE("room offset (" + std::to_string(offset.x()) + ", " +
                     std::to_string(offset.y()) + ", " + std::to_string(offset.z()) + ") m");
        const Eigen::Affine3d place{Eigen::Translation3d(offset)};
        const auto placed = [&](const Eigen::Affine3d& motion) {
            Scan s = pump;
            s.pose = place * motion * s.pose;
            for (auto& p : s.xyz) p = place * motion * p;
            return std::vector<Scan>{s};
        };
        RegistrationConfig c;
        c.icp.mode = IcpMode::fallback;
        c.icp.voxel_size = 0.05;
        c.icp.regions.push_back({"room", Eigen::Vector3d(-3, -5.4, -1.6) + offset,
                                 Eigen::Vector3d(1.8, -0.7, 1.9) + offset});
        const StableSurface surface =
            build_stable_surface(c.icp, placed(Eigen::Affine3d::Identity()));
        const IcpMeasurement m =
            measure_icp(c, surface, placed(movement), Eigen::Matrix4d::Identity());
        ASSERT_TRUE(m.transform) << m.refused;
        // Epoch -> reference: the placed room's movement undone.
        const Eigen::Affine3d truth = place * movement.inverse() * place.inverse();
        const Eigen::Affine3d error = Eigen::Affine3d(m.transform->matrix()) * truth.inverse();
        const double angle = Eigen::AngleAxisd(error.rotation()).angle() / kArcsec;
        EXPECT_LT(angle, 1.0) << angle << "″ off";
        EXPECT_LT(error.translation().norm(), 2e-5)
            << 1e3 * error.translation().norm() << " mm off";
    }
}

}  // namespace
}  // namespace tlsmon
