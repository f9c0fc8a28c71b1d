// The report's reading of the simulator's truth and its scoring, on cases worked by hand:
// the displacement field of docs/simulator.md ("Deformation") integrated over a zone, the
// face a zone box lies on, the registration error of a transformation known to be off by a
// millimetre, and the detection latency of a step alarm.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "report/analysis.hpp"
#include "report/truth.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::report {
namespace {

// A pier 15 x 7 x 40 m, top displaced by `top`, optionally stepped at z 30–40 m by
// (0, −20, 0) mm; the scanner pose off by `pose`.
TruthEpoch truth(int epoch, const Eigen::Vector3d& top, bool stepped,
                 const Eigen::Affine3d& pose = Eigen::Affine3d::Identity()) {
    TruthEpoch t;
    t.epoch = epoch;
    t.time_unix = 1'000'000 + 900 * epoch;
    t.header_to_true = pose;
    t.pier = {2.0, 17.0, 45.0, 52.0, 40.0};
    t.deformation_enabled = true;
    t.exponent = 2.0;
    t.top_displacement = top;
    if (stepped) t.step = StepEvent{2, 30.0, 40.0, {0.0, -0.020, 0.0}};
    t.samples = {{"south_face_z30", {9.5, 45.0, 30.0}, {}}, {"top_centre", {9.5, 48.5, 40.0}, {}}};
    return t;
}

TEST(ReportTruth, DisplacementFollowsTheCantileverProfileAndTheStep) {
    const TruthEpoch t = truth(5, {0.002, 0.004, -0.001}, true);
    // u_h = top_h (z/H)², u_z = top_z z/H; the step inside [30, 40] m only.
    const Eigen::Vector3d at20 = true_displacement(t, {9.5, 45.0, 20.0});
    EXPECT_NEAR(at20.x(), 0.002 * 0.25, 1e-15);
    EXPECT_NEAR(at20.y(), 0.004 * 0.25, 1e-15);
    EXPECT_NEAR(at20.z(), -0.001 * 0.5, 1e-15);
    const Eigen::Vector3d at35 = true_displacement(t, {9.5, 45.0, 35.0});
    EXPECT_NEAR(at35.y(), 0.004 * 0.765625 - 0.020, 1e-15);
}

TEST(ReportTruth, ZoneTruthIsTheChangeSinceTheReferenceAlongTheOutwardNormal) {
    const TruthEpoch ref = truth(0, {0.001, 0.001, 0.0}, false);
    const TruthEpoch e = truth(8, {0.001, 0.005, 0.0}, true);
    const auto face = zone_face(ref.pier, {{2.0, 44.5, 30.0}, {17.0, 45.5, 40.0}});
    ASSERT_TRUE(face.has_value());
    EXPECT_EQ(face->face, "south");
    EXPECT_EQ(face->normal, Eigen::Vector3d(0, -1, 0));
    // Δu_y(z) = 0.004 (z/40)² − 0.020; along −y: 0.020 − 0.004 (z/40)².
    // Mean over z in [30, 40]: mean of z² = (40³ − 30³)/(3·10) = 1233.33…; median at z = 35.
    const ZoneTruth z = zone_truth(ref, e, *face);
    EXPECT_NEAR(z.normal_mean, 0.020 - 0.004 * (37000.0 / 30.0) / 1600.0, 2e-7);
    EXPECT_NEAR(z.normal_median, 0.020 - 0.004 * 0.765625, 2e-7);
    EXPECT_NEAR(z.mean_vector.x(), 0.0, 1e-15);
}

TEST(ReportTruth, ZoneFaceIsTheFaceTheBoxIsASlabAcross) {
    const PierBox pier{2.0, 17.0, 45.0, 52.0, 40.0};
    // The simulator's south-face zone reaches past the corner into the west face's plane.
    const auto south = zone_face(pier, {{2.0, 44.5, 0.0}, {17.0, 45.5, 40.0}});
    ASSERT_TRUE(south);
    EXPECT_EQ(south->face, "south");
    EXPECT_DOUBLE_EQ(south->z_max, 40.0);
    const auto west = zone_face(pier, {{1.5, 45.0, 0.0}, {2.5, 52.0, 40.0}});
    ASSERT_TRUE(west);
    EXPECT_EQ(west->face, "west");
    EXPECT_EQ(west->normal, Eigen::Vector3d(-1, 0, 0));
    EXPECT_FALSE(zone_face(pier, {{-5.0, 0.0, 0.0}, {-4.0, 10.0, 5.0}}));  // off the pier
}

TEST(ReportTruth, AFileThatIsNotATruthFileIsNamedWithItsKey) {
    test::TempDir dir;
    std::ofstream(dir.path() / "a.truth.json") << R"({"format": "tlsmon-simulator-truth/1"})";
    try {
        read_truth_folder(dir.path());
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("a.truth.json: key 'epoch' missing"),
                  std::string::npos)
            << e.what();
    }
}

TEST(ReportAnalysis, RegistrationErrorAndStepLatencyAgainstTheTruth) {
    // The scanner's pose drifts by a yaw of 30″; the stored transformation undoes it but is
    // 1 mm off in x: the error is (1, 0, 0) mm at every pier point.
    const Eigen::Affine3d yaw(Eigen::AngleAxisd(30.0 / 206264.806, Eigen::Vector3d::UnitZ()));
    std::vector<TruthEpoch> t = {truth(0, {0, 0, 0}, false), truth(1, {0, 0, 0}, false, yaw),
                                 truth(2, {0, 0, 0}, true, yaw), truth(3, {0, 0, 0}, true)};
    RunData run;
    run.reference = 1;
    for (int i = 0; i < 4; ++i) {
        RunEpoch e;
        e.epoch.id = i + 1;
        e.epoch.acquired = t[static_cast<std::size_t>(i)].time_unix;
        e.epoch.status = EpochStatus::done;
        RegistrationRow r;
        r.accepted = true;
        r.parameters = std::array<double, 6>{};
        Eigen::Affine3d T = t[static_cast<std::size_t>(i)].header_to_true.value();
        if (i > 0) T.translation().x() += 0.001;
        for (int k = 0; k < 16; ++k)
            r.transform[static_cast<std::size_t>(k)] = T.matrix()(k / 4, k % 4);
        e.registration = r;
        run.epochs.push_back(e);
    }
    RunZone zone;
    zone.id = 3;
    zone.name = "top";
    zone.box = ZoneBox{{2.0, 44.5, 30.0}, {17.0, 45.5, 40.0}};
    for (int i = 0; i < 4; ++i) {
        zone.series["m3c2_median_m"].push_back({i + 1, t[static_cast<std::size_t>(i)].time_unix,
                                                i >= 2 ? 0.0205 : 0.0005, 0.002, 50, i >= 2,
                                                "targets", true, std::nullopt});
    }
    run.zones.push_back(zone);
    run.rules.push_back({1, "step", "top", "m3c2_median_m", "{}", true});
    run.alarm_events.push_back({t[1].time_unix, "step", "raise", "alarm", 0.006, 2, "", "rule"});
    run.alarm_events.push_back({t[3].time_unix, "step", "raise", "alarm", 0.02, 4, "", "rule"});

    const RunReport r = analyse(run, t, "truth");
    ASSERT_EQ(r.registration.size(), 4u);
    EXPECT_TRUE(r.registration[0].is_reference);
    EXPECT_NEAR(r.registration[0].max_error.value(), 0.0, 1e-12);
    for (std::size_t i = 1; i < 4; ++i) {
        EXPECT_NEAR(r.registration[i].top_error->x(), 0.001, 1e-9);
        EXPECT_NEAR(r.registration[i].top_error->norm(), 0.001, 1e-9);
    }
    EXPECT_EQ(r.registration_top_error.n, 3u);
    EXPECT_NEAR(r.registration_top_error.rms, 0.001, 1e-9);

    // The zone: truth 0 before the step, 20 mm − 0 after; values 0.5 mm above it.
    ASSERT_EQ(r.zones.size(), 1u);
    ASSERT_EQ(r.zones[0].quantities.size(), 1u);
    const auto& q = r.zones[0].quantities[0];
    EXPECT_EQ(q.error.n, 4u);
    EXPECT_NEAR(q.error.bias, 0.0005, 1e-6);
    EXPECT_NEAR(q.error.max_abs, 0.0005, 1e-6);
    EXPECT_TRUE(r.zones[0].step_zone);

    // Raised once before the step (epoch 1: false) and at epoch 3, one after the step at 2.
    ASSERT_EQ(r.alarms.size(), 1u);
    EXPECT_EQ(r.alarms[0].false_alarms, 1);
    EXPECT_EQ(r.alarms[0].latency_epochs, 1);
    // Named by the database's epoch ids, as `tlsmon alarms history` names them.
    EXPECT_EQ(r.epoch_id.at(3), 4);
    ASSERT_EQ(r.alarms[0].events.size(), 2u);
    EXPECT_EQ(r.alarms[0].events[1].rfind("epoch 4: raise alarm", 0), 0u) << r.alarms[0].events[1];
}

TEST(ReportAnalysis, SummaryOfErrors) {
    const ErrorSummary s = summarise({1.0, -3.0, 2.0});
    EXPECT_DOUBLE_EQ(s.bias, 0.0);
    EXPECT_DOUBLE_EQ(s.rms, std::sqrt(14.0 / 3.0));
    EXPECT_DOUBLE_EQ(s.max_abs, 3.0);
    EXPECT_EQ(summarise({}).n, 0u);
}

}  // namespace
}  // namespace tlsmon::report
