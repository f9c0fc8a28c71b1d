// Every epoch states its datum. A site without [[target]] tables ran no registration at
// all, not even the configured ICP fallback on its stable regions, and said nothing: the
// real pump-room scan (shared data) moved by (2, -3, +6) mm and 0.02° gave its floor
// +6 mm, significant, and raised the alarm. Here, on that scan and the same movement, in
// process on a real SQLite file: without any registration the epoch is `unregistered`
// and raises nothing; with the ICP fallback on a stable region and no target, the ICP
// registers it and the floor moves by less than 0.1 mm.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <iostream>
#include <numbers>

#include "config/config.hpp"
#include "daemon/ingest.hpp"
#include "daemon/modbus/modbus_snapshot.hpp"
#include "formats/ptx_writer.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/alarm_evaluation.hpp"
#include "pipeline/epoch_pipeline.hpp"
#include "tests/support/daemon_harness.hpp"

namespace tlsmon::test {
namespace {

const fs::path kPump = fs::path(TLSMON_DATA_DIR) / "ptx/pumpA_from_e57.ptx";

// The room's floor lies at z = -1.9 m; everything above it up to the ceiling (walls, pipes,
// the pump) is the stable region: the whole room moved with the scanner.
const std::string kSite =
    "[paths]\ningest = \"ingest\"\ndatabase = \"db/tlsmon.sqlite\"\n"
    "[keypoints]\nenabled = false\n"
    "[[zone]]\nname = \"floor\"\nmin = [-2.4, -4.8, -2.0]\nmax = [1.2, -1.1, -1.75]\n"
    "[alarm]\n[[alarm.rule]]\nname = \"floor moves\"\nzone = \"floor\"\n"
    "quantity = \"m3c2_median_m\"\nalarm = { high = 0.003, low = -0.003 }\n";
const std::string kIcp =
    "[registration]\nicp = \"fallback\"\nicp_voxel_size = 0.05\nicp_min_overlap = "
    "0.2\nmax_sigma_angle_arcsec = 120\n"
    "[[stable_region]]\nname = \"room\"\nmin = [-3, -5.4, -1.6]\nmax = [1.8, -0.7, 1.9]\n";

// The scanner's movement of the issue: (2, -3, +6) mm and 0.02° about z.
const Eigen::Affine3d kMovement =
    Eigen::Translation3d(0.002, -0.003, 0.006) *
    Eigen::AngleAxisd(0.02 * std::numbers::pi / 180, Eigen::Vector3d::UnitZ());

struct DatumSite {
    explicit DatumSite(const std::string& extra)
        : config(parse_config(kSite + extra, "site.toml", site.root)) {
        fs::create_directories(config.paths.archive);
        fs::create_directories(config.paths.quarantine);
        fs::create_directories(config.paths.database.parent_path());
        db.emplace(EpochDatabase::open(config.paths.database, EpochDatabase::Mode::read_write));
        for (const auto& z : config.zones) db->site().upsert_zone(z.name, "{}");
        store_alarm_rules(*db, config.alarm.rules);
    }
    // The reference (the pump scan as it is), then the scan moved as the issue moved it.
    void run() {
        fs::copy_file(kPump, site.ingest() / "pump_20260601T060000Z.ptx");
        Scan moved = read_scans(kPump).at(0);
        moved.pose = kMovement * moved.pose;
        for (auto& p : moved.xyz) p = kMovement * p;
        write_ptx(moved, site.ingest() / "pump_20260601T061500Z.ptx");
        SystemEventLog events;
        IngestContext ingest{*db, config, std::nullopt, events};
        for (const char* f : {"pump_20260601T060000Z.ptx", "pump_20260601T061500Z.ptx"}) {
            ASSERT_EQ(ingest_file(ingest, site.ingest() / f), IngestOutcome::new_epoch);
        }
        const PipelineConfig pipeline = pipeline_config(config);
        ReferenceCache cache(*db);
        PipelineContext ctx{*db, pipeline, events, cache};
        for (const Epoch& e : db->epochs().pending()) {
            ASSERT_EQ(process_epoch(ctx, e), EpochOutcome::done);
        }
    }
    SeriesPoint floor() const {
        const auto points = db->series().points("floor", "m3c2_median_m", {});
        EXPECT_EQ(points.size(), 2u);
        return points.back();
    }
    std::string alarm_state() const {
        for (const auto& s : db->alarms().states()) {
            if (s.rule == "floor moves") return s.state;
        }
        return "normal";
    }

    Site site{"datum"};
    Config config;
    std::optional<EpochDatabase> db;
};

TEST(DatumWithoutTargets, AnUnregisteredEpochSaysSoAndRaisesNoAlarm) {
    DatumSite s("");
    s.run();
    const auto epochs = s.db->series().epochs_in_range({});
    ASSERT_EQ(epochs.size(), 2u);
    const auto reference = s.db->registrations().of_epoch(epochs[0].id);
    ASSERT_TRUE(reference);
    EXPECT_EQ(reference->method, "reference");
    EXPECT_TRUE(reference->accepted);
    const auto moved = s.db->registrations().of_epoch(epochs[1].id);
    ASSERT_TRUE(moved) << "every epoch states its datum";
    EXPECT_EQ(moved->method, "unregistered");
    EXPECT_FALSE(moved->accepted);
    EXPECT_NE(moved->reason.find("no [[target]] and no ICP fallback"), std::string::npos);
    // The value is what M3C2 measured (the scanner's movement in it), flagged as such.
    const SeriesPoint floor = s.floor();
    EXPECT_NEAR(floor.value, 0.006, 0.001);
    std::cout << fmt::format("unregistered: floor M3C2 median {:+.2f} mm, significant {}\n",
                             1e3 * floor.value, floor.significant);
    EXPECT_EQ(floor.datum, "unregistered");
    EXPECT_EQ(s.alarm_state(), "normal") << "an unregistered epoch raises no alarm";
    // On Modbus: the unregistered bit of the quality word, not "degraded".
    ModbusConfig modbus;
    modbus.quantities = {"m3c2_median_m"};
    const MapInputs inputs = modbus_map_inputs(&*s.db, {"floor"}, modbus);
    const ModbusSnapshot snapshot = read_modbus_snapshot(*s.db, inputs, modbus, epochs[1].acquired);
    ASSERT_EQ(snapshot.values.size(), 1u);
    EXPECT_TRUE(snapshot.values[0].unregistered);
    EXPECT_FALSE(snapshot.values[0].registration_degraded);
}

TEST(DatumWithoutTargets, IcpFallbackOnStableRegionsRunsWithoutAnyTarget) {
    DatumSite s(kIcp);
    s.run();
    const auto epochs = s.db->series().epochs_in_range({});
    ASSERT_EQ(epochs.size(), 2u);
    const auto moved = s.db->registrations().of_epoch(epochs[1].id);
    ASSERT_TRUE(moved);
    EXPECT_EQ(moved->method, "icp") << moved->reason;
    EXPECT_TRUE(moved->accepted) << moved->reason;
    ASSERT_TRUE(moved->parameters && moved->sigmas);
    const auto& p = *moved->parameters;
    const auto& sd = *moved->sigmas;
    SCOPED_TRACE(
        fmt::format("κ {:.2f}″ ± {:.2f}, t ({:.3f}, {:.3f}, {:.3f}) ± ({:.3f}, {:.3f}, "
                    "{:.3f}) mm, ω {:.2f}″ ± {:.2f}, φ {:.2f}″ ± {:.2f}",
                    p[2] * 206264.8, sd[2] * 206264.8, 1e3 * p[3], 1e3 * p[4], 1e3 * p[5],
                    1e3 * sd[3], 1e3 * sd[4], 1e3 * sd[5], p[0] * 206264.8, sd[0] * 206264.8,
                    p[1] * 206264.8, sd[1] * 206264.8));
    // The ICP found the movement back (epoch -> reference: the inverse of kMovement), every
    // angle to 1″ and the translation to 0.02 mm. Cut once, where the scanner had put it, it
    // stopped on its way (κ 24″ and tz 0.83 mm RMS over ten phases of the voxel grid); cut
    // again where the adjustment puts it, it does not (docs/registration.md, "ICP on stable
    // regions", step 4). Not against its own σ: the moved scan carries the reference's own
    // noise, so the residuals vanish at the solution.
    const Eigen::Affine3d back = kMovement.inverse();
    const Eigen::Matrix3d R = back.rotation();  // about z only: ω = φ = 0
    const double truth[6] = {0.0,
                             0.0,
                             std::atan2(R(1, 0), R(0, 0)),
                             back.translation().x(),
                             back.translation().y(),
                             back.translation().z()};
    for (int k = 0; k < 3; ++k)
        EXPECT_LT(std::abs(p[k] - truth[k]) * 206264.8, 1.0) << "angle " << k;
    for (int k = 3; k < 6; ++k) EXPECT_LT(std::abs(p[k] - truth[k]), 2e-5) << "parameter " << k;
    const SeriesPoint floor = s.floor();
    EXPECT_LT(std::abs(floor.value), 1e-4) << "the floor did not move";
    ASSERT_TRUE(floor.uncertainty);
    // Nor significantly (before the epoch was cut again, 0.33 mm against an LoD95 of 0.43 mm).
    EXPECT_LT(std::abs(floor.value), *floor.uncertainty) << "nor significantly";
    std::cout << fmt::format(
        "ICP without targets: κ {:.2f}″ ± {:.2f} (true {:.2f}″), ω {:.2f}″, φ {:.2f}″, t off by "
        "({:.4f}, {:.4f}, {:.4f}) mm, floor M3C2 median {:+.3f} mm, LoD95 {:.2f} mm\n",
        p[2] * 206264.8, sd[2] * 206264.8, truth[2] * 206264.8, p[0] * 206264.8, p[1] * 206264.8,
        1e3 * (p[3] - truth[3]), 1e3 * (p[4] - truth[4]), 1e3 * (p[5] - truth[5]),
        1e3 * floor.value, 1e3 * floor.uncertainty.value_or(0));
    EXPECT_EQ(floor.datum, "icp");
    EXPECT_EQ(s.alarm_state(), "normal");
}

}  // namespace
}  // namespace tlsmon::test
