// Registration on the scene's own planes (pipeline/registration_on_planes.hpp) on the
// simulator's `pier` preset with drift (standing axis 60″, tilt 10″, translation σ 1.5 mm)
// and no target used, against the truth: for epoch i the exact map into epoch 0's frame is
// H₀⁻¹·Hᵢ (docs/simulator.md). The scan's lower band (the floor, the valley side, the
// foundation, the abutment, the two retaining walls at an angle, the pier's foot) is
// rendered at 0.03°. Two series: in one the abutment is moved by 3 mm and tilted by 20″ from
// epoch 2 (the congruence test must leave its planes out and the datum must not follow it);
// in the other the scanner is knocked at epoch 1 (0.2 m and 5° about its standing axis; the
// header keeps the nominal pose), so that no prior fits and the matching without a prior
// must recover the registration. Then each series through the epoch pipeline into a real
// SQLite file: the registration row's method, the stored plane rows, the station change's
// event.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "algorithms/registration/registration_error.hpp"
#include "formats/ptx_writer.hpp"
#include "pipeline/icp_registration.hpp"
#include "pipeline/registration_on_planes.hpp"
#include "pipeline_site.hpp"
#include "simulator/render.hpp"

namespace tlsmon {
namespace {

constexpr int kMovedFrom = 2;  // the abutment's motion, in the first series
constexpr int kKnocked = 1;    // the station change, in the second

sim::Site drifting_pier() {
    sim::Site site = sim::preset_pier();
    site.drift.yaw_amplitude_arcsec = 60.0;
    site.drift.tilt_amplitude_arcsec = 10.0;
    site.drift.translation_sigma = 0.0015;
    site.atmosphere.enabled = false;
    site.noise.seed = 5;
    site.scanner.azimuth_step_deg = 0.03;
    site.scanner.elevation_step_deg = 0.03;
    site.scanner.elevation_max_deg = 12.0;
    return site;
}

sim::Site moving_abutment() {
    sim::Site site = drifting_pier();
    for (auto& b : site.terrain.blocks) {
        if (b.name != "A-north") continue;
        b.motion.from_epoch = kMovedFrom;
        b.motion.translation = {0.0012, -0.0025, -0.0012};  // 3.0 mm
        b.motion.rotation_arcsec = {14.0, 0.0, 14.0};       // 19.8″
    }
    return site;
}

sim::Site knocked_scanner() {
    sim::Site site = drifting_pier();
    site.events.station_change_epoch = kKnocked;
    site.events.station_shift = {0.16, -0.12, 0.0};  // 0.2 m
    site.events.station_turn_deg = 5.0;
    return site;
}

RegistrationConfig planes_config(const sim::Site& site) {
    RegistrationConfig c;
    c.method = RegistrationMethod::planes;
    const auto& p = site.pier;
    c.zones = {
        box_zone("pier_south_face", {p.x0, p.y0 - 0.5, 0}, {p.x1, p.y0 + 0.5, p.height}),
        box_zone("pier_west_face", {p.x0 - 0.5, p.y0 + 0.5, 0}, {p.x0 + 0.5, p.y1, p.height})};
    return c;
}

struct RenderedEpoch {
    std::vector<Scan> scans;
    Eigen::Affine3d header_to_true;
};

RenderedEpoch render(const sim::Site& site, int epoch) {
    const sim::RenderedScan r = sim::render_epoch(site, epoch, 2.0 * epoch, 2);
    const Eigen::Affine3d N = sim::nominal_pose(site.scanner);
    return {{r.scan}, N * r.pose_error.transform() * N.inverse()};
}

// The block whose box (as it stood) holds a point of the true frame, within 5 cm.
std::string block_at(const sim::Site& site, const Eigen::Vector3d& p) {
    for (const auto& b : site.terrain.blocks) {
        const Eigen::Vector3d q = b.pose(0).inverse() * p;
        if ((q.cwiseAbs().array() <= (0.5 * (b.hi - b.lo)).array() + 0.05).all()) return b.name;
    }
    return "";
}

// A series rendered once per test program.
struct Series {
    sim::Site site;
    std::vector<RenderedEpoch> epochs;
    Series(sim::Site s, int epochs_count) : site(std::move(s)) {
        for (int e = 0; e < epochs_count; ++e) epochs.push_back(render(site, e));
    }
};

const Series& moved_series() {
    static const Series s(moving_abutment(), kMovedFrom + 1);
    return s;
}

// Two epochs after the knock: the second is registered from the first one's pose.
const Series& knocked_series() {
    static const Series s(knocked_scanner(), kKnocked + 2);
    return s;
}

// Registers epoch `e` of the series onto epoch 0 (from the identity, a fixed station's prior) and
// checks the pier's error against the truth: RMS at points on its faces every 2.5 m, and each
// component at the foot and the top against the predicted σ.
RegistrationResult register_and_score(const Series& s, int e) {
    const auto config = planes_config(s.site);
    const ReferencePlanes reference = detect_scan_planes(config.planes, s.epochs[0].scans);
    RegistrationResult r;
    r.tested.status = registration::RegistrationStatus::too_few_targets;
    apply_planes(config, reference, s.epochs[e].scans, {}, r, registration::RigidTransform{});
    EXPECT_TRUE(r.accepted()) << r.tested.reason;
    EXPECT_EQ(registration_method(r), "planes");
    if (!r.accepted()) return r;
    const auto& T = *r.tested.transform;
    const Eigen::Affine3d& H0 = s.epochs[0].header_to_true;
    const Eigen::Affine3d& Hi = s.epochs[e].header_to_true;
    const auto& p = s.site.pier;
    double sum = 0;
    int n = 0;
    for (double z = 0.0; z <= p.height; z += 2.5) {
        for (double x = p.x0; x <= p.x1; x += 2.5, ++n) {
            const Eigen::Vector3d P(x, p.y0, z);
            sum += (T.apply(Hi.inverse() * P) - H0.inverse() * P).squaredNorm();
        }
    }
    const double rms = std::sqrt(sum / n);
    std::printf("epoch %d: %zu planes in the datum, %zu moved, pier RMS error %.3f mm\n", e,
                r.planes->in_datum, r.planes->moved, 1e3 * rms);
    EXPECT_LT(rms, 0.0005);
    for (const Eigen::Vector3d& P :
         {Eigen::Vector3d(p.x0, p.y0, 0.0), Eigen::Vector3d(p.x1, p.y0, p.height)}) {
        const Eigen::Vector3d x = Hi.inverse() * P;
        const Eigen::Vector3d error = T.apply(x) - H0.inverse() * P;
        const Eigen::Matrix3d S = registration::registration_covariance_at(T, x);
        for (int k = 0; k < 3; ++k) {
            EXPECT_LT(std::fabs(error(k)), 3.0 * std::sqrt(S(k, k)) + 1e-5)
                << "component " << k << " at " << P.transpose();
        }
    }
    return r;
}

// Every epoch of the series through the epoch pipeline into a real SQLite file, each done.
struct ProcessedSeries {
    test::PipelineSite ps;
    std::vector<EpochId> ids;
};

std::unique_ptr<ProcessedSeries> process(const Series& s) {
    auto out = std::make_unique<ProcessedSeries>();
    test::PipelineSite& ps = out->ps;
    ps.config.coverage.min_inside_share = 0.0;
    ps.config.registration = planes_config(s.site);
    // A site's targets stay listed when it changes to planes: they are not measured, not even
    // in the reference (which once rejected the reference as having too few targets).
    for (const auto& t : s.site.targets) {
        TargetConfig target;
        target.name = t.name;
        target.approximate = t.centre;
        ps.config.registration.targets.push_back(target);
    }
    for (const auto& z : ps.config.registration.zones) ps.db->site().upsert_zone(z.name, "{}");
    ReferenceCache cache(*ps.db);
    for (std::size_t e = 0; e < s.epochs.size(); ++e) {
        const auto file = ps.dir / "ingest" / ("pier_" + std::to_string(e) + ".ptx");
        {
            std::ofstream f(file, std::ios::binary);
            f << ptx_text(s.epochs[e].scans.front());
        }
        const EpochInsert ins = ps.db->epochs().insert(
            NewEpoch{sha256_file(file), 1780293600 + 900 * static_cast<std::int64_t>(e), file,
                     static_cast<std::int64_t>(std::filesystem::file_size(file)), std::nullopt});
        out->ids.push_back(ins.id);
        EXPECT_EQ(ps.process(*ps.db->epochs().find(ins.id), cache), EpochOutcome::done)
            << "epoch " << e;
    }
    return out;
}

TEST(RegistrationOnPlanes, ADriftedEpochIsRegisteredOnPlanesAlone) {
    const Series& s = moved_series();
    const RegistrationResult r = register_and_score(s, 1);
    ASSERT_TRUE(r.planes);
    // Floor, valley side, foundation, abutment and both walls: normals that span space.
    EXPECT_GE(r.planes->in_datum, 8u);
    EXPECT_EQ(r.planes->moved, 0u);
    bool west_wall = false;
    for (const auto& o : r.planes->matched) {
        const Eigen::Vector3d c = s.epochs[0].header_to_true * o.reference.centroid;
        if (block_at(s.site, c) == "W-west") west_wall = o.role == "datum";
        // The pier's faces are in zones: never in the datum, their change reported.
        if (!o.zone.empty()) {
            EXPECT_EQ(o.role, "monitored");
        }
    }
    EXPECT_TRUE(west_wall);
}

TEST(RegistrationOnPlanes, AMovedAbutmentLeavesTheDatumAndIsNamed) {
    const Series& s = moved_series();
    const RegistrationResult r = register_and_score(s, kMovedFrom);
    ASSERT_TRUE(r.planes);
    int on_abutment = 0;
    for (const auto& o : r.planes->matched) {
        const Eigen::Vector3d c = s.epochs[0].header_to_true * o.reference.centroid;
        const bool abutment = block_at(s.site, c) == "A-north";
        on_abutment += abutment;
        if (abutment) {
            EXPECT_EQ(o.role, "moved") << "plane " << o.plane << " at " << c.transpose();
        } else if (o.zone.empty()) {
            EXPECT_EQ(o.role, "datum") << "plane " << o.plane << " at " << c.transpose();
        }
    }
    EXPECT_GE(on_abutment, 2);
}

TEST(RegistrationOnPlanes, AKnockedScannerIsRegisteredWithoutAPriorAndNamedAStationChange) {
    const Series& s = knocked_series();
    const RegistrationResult r = register_and_score(s, kKnocked);
    ASSERT_TRUE(r.planes && r.planes->station_change) << r.tested.reason;
    EXPECT_NEAR(r.planes->station_change->shift_m, 0.2, 0.01);
    EXPECT_NEAR(r.planes->station_change->turn_deg, 5.0, 0.02);
    EXPECT_NE(r.tested.reason.find("station change"), std::string::npos) << r.tested.reason;
    EXPECT_EQ(r.planes->moved, 0u);
}

TEST(RegistrationOnPlanes, TheStageStoresTheMethodAndThePlanes) {
    const auto processed = process(moved_series());
    test::PipelineSite& ps = processed->ps;
    const std::vector<EpochId>& ids = processed->ids;
    auto& regs = ps.db->registrations();
    EXPECT_EQ(regs.of_epoch(ids[0])->method, "reference");
    EXPECT_TRUE(regs.planes_of_epoch(ids[0]).empty());
    for (int e = 1; e <= kMovedFrom; ++e) {
        const auto row = regs.of_epoch(ids[e]);
        ASSERT_TRUE(row);
        EXPECT_TRUE(row->accepted);
        EXPECT_EQ(row->method, "planes");
        EXPECT_EQ(row->target_count, 0);
        EXPECT_NE(row->quality_json.find("\"in_datum\""), std::string::npos);
        const auto planes = regs.planes_of_epoch(ids[e]);
        ASSERT_GE(planes.size(), 8u);
        int moved = 0, monitored = 0;
        for (const auto& p : planes) {
            moved += p.role == "moved";
            monitored += p.role == "monitored";
            if (p.role == "moved") {
                // The abutment's planes: changed by millimetres or arc seconds, significant.
                EXPECT_TRUE(p.significant);
                EXPECT_GT(p.statistic, p.critical);
                EXPECT_GT(p.sigma[2], 0.0);
            }
            if (p.role == "monitored") {
                EXPECT_FALSE(p.zone.empty());
            }
        }
        EXPECT_EQ(moved > 0, e >= kMovedFrom) << "epoch " << e;
        EXPECT_GE(monitored, 1);
        // The σ at the zones, from the planes' covariance.
        EXPECT_EQ(regs.zone_sigmas_of_epoch(ids[e]).size(), 2u);
    }
    EXPECT_TRUE(ps.db->series().events(TimeRange{}, std::string("station_change")).empty());
    // The south face's zone series: its plane (the zone's largest) as the plane rows have it,
    // the tilts in arc seconds, each with its LoD95 = 1.959964·σ.
    const auto shift = ps.db->series().points("pier_south_face", "plane_shift_m", {});
    const auto tilt = ps.db->series().points("pier_south_face", "plane_tilt_u_arcsec", {});
    ASSERT_EQ(shift.size(), std::size_t(kMovedFrom));
    ASSERT_EQ(tilt.size(), std::size_t(kMovedFrom));
    for (int k = 0; k < kMovedFrom; ++k) {
        const auto planes = regs.planes_of_epoch(ids[k + 1]);
        const PlaneRow* face = nullptr;
        for (const auto& p : planes) {
            if (p.zone == "pier_south_face" && (!face || p.plane < face->plane)) face = &p;
        }
        ASSERT_TRUE(face);
        EXPECT_DOUBLE_EQ(shift[k].value, face->change[2]);
        EXPECT_NEAR(*shift[k].uncertainty, 1.959964 * face->sigma[2], 1e-10);
        EXPECT_NEAR(tilt[k].value, face->change[0] * 206264.806, 1e-6);
        EXPECT_EQ(shift[k].significant, std::fabs(face->change[2]) > *shift[k].uncertainty);
        // The pier bends by millimetres over the day; its face is measured to a fraction.
        EXPECT_LT(std::fabs(shift[k].value), 0.02);
        EXPECT_GT(*shift[k].uncertainty, 0.0);
        EXPECT_LT(*shift[k].uncertainty, 0.001);
    }
}

TEST(RegistrationOnPlanes, TheStageRecordsOneStationChangeAndGoesOnFromTheNewPose) {
    const auto processed = process(knocked_series());
    test::PipelineSite& ps = processed->ps;
    const std::vector<EpochId>& ids = processed->ids;
    for (std::size_t e = 1; e < ids.size(); ++e) {
        const auto row = ps.db->registrations().of_epoch(ids[e]);
        ASSERT_TRUE(row);
        EXPECT_TRUE(row->accepted) << row->reason;
        EXPECT_EQ(row->method, "planes");
        // The quality record says which epoch was matched without a prior.
        EXPECT_EQ(row->quality_json.find("\"station_change\":null") == std::string::npos,
                  e == kKnocked)
            << row->quality_json;
    }
    // One event, at the knocked epoch: the next one starts from its accepted pose.
    const auto changes = ps.db->series().events(TimeRange{}, std::string("station_change"));
    ASSERT_EQ(changes.size(), 1u);
    EXPECT_EQ(changes[0].epoch, ids[kKnocked]);
    EXPECT_EQ(changes[0].level, "warning");
    EXPECT_NE(changes[0].message.find("0.20"), std::string::npos) << changes[0].message;
}

}  // namespace
}  // namespace tlsmon
