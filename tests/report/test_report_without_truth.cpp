// The report of a run without a truth (a real site): nothing is scored, and the report holds
// the run's own figures — the registration's residuals and σ, each zone's latest value with
// its LoD95 and range, how often each alarm rose.
#include <gtest/gtest.h>

#include <string>

#include "report/analysis.hpp"
#include "report/output.hpp"

namespace tlsmon::report {
namespace {

RunData three_epochs() {
    RunData run;
    run.database = "site.sqlite";
    run.reference = 1;
    for (int i = 0; i < 3; ++i) {
        RunEpoch e;
        e.epoch.id = i + 1;
        e.epoch.acquired = 1'000'000 + 900 * i;
        e.epoch.status = EpochStatus::done;
        RegistrationRow r;
        r.accepted = true;
        r.parameters = std::array<double, 6>{};
        r.target_count = 5 - i;
        r.rms_m = 0.0004 * i;  // 0, 0.4, 0.8 mm
        e.registration = r;
        e.zone_sigmas.push_back({"top", 0.0003 * (i + 1)});
        run.epochs.push_back(e);
    }
    RunZone zone;
    zone.id = 1;
    zone.name = "top";
    zone.box = ZoneBox{{2.0, 44.5, 30.0}, {17.0, 45.5, 40.0}};
    zone.series["m3c2_median_m"] = {
        {1, 1'000'000, 0.0, 0.002, 50, false, "targets", true, std::nullopt},
        {2, 1'000'900, -0.0031, 0.002, 50, true, "targets", true, std::nullopt},
        {3, 1'001'800, 0.0062, 0.0025, 50, true, "targets", true, std::nullopt}};
    run.zones.push_back(zone);
    run.rules.push_back({1, "step", "top", "m3c2_median_m", "{}", true});
    run.alarm_events.push_back({1'001'800, "step", "raise", "alarm", 0.0062, 3, "", "rule"});
    return run;
}

TEST(ReportWithoutTruth, NothingIsScoredAndTheRunsOwnFiguresAreReported) {
    const RunReport r = analyse(three_epochs(), {}, "");
    EXPECT_FALSE(r.scored);
    EXPECT_EQ(r.registration_top_error.n, 0u);
    ASSERT_EQ(r.zones.size(), 1u);
    EXPECT_FALSE(r.zones[0].face);  // no pier to lie on without a truth
    ASSERT_EQ(r.zones[0].quantities.size(), 1u);
    EXPECT_TRUE(r.zones[0].quantities[0].displacement);
    EXPECT_EQ(r.zones[0].quantities[0].error.n, 0u);
    ASSERT_EQ(r.alarms.size(), 1u);
    EXPECT_EQ(r.alarms[0].raises, 1);
    EXPECT_EQ(r.alarms[0].false_alarms, 0);  // not a false alarm: nothing says so

    const std::string md = markdown(r, {}, {});
    EXPECT_EQ(md.rfind("# tlsmon run\n", 0), 0u) << md;
    EXPECT_EQ(md.find("truth"), std::string::npos) << md;
    EXPECT_NE(md.find("Reference epoch: epoch 1."), std::string::npos) << md;
    // Residual RMS of the accepted epochs besides the reference: 0.4 and 0.8 mm, median the
    // upper one of two; the zone σ 0.6 and 0.9 mm.
    EXPECT_NE(md.find("| targets' residual RMS (mm) | 2 | 0.800 | 0.800 |"), std::string::npos)
        << md;
    EXPECT_NE(md.find("| largest σ at a zone, 3-D (mm) | 2 | 0.900 | 0.900 |"), std::string::npos)
        << md;
    EXPECT_NE(md.find("Targets used per accepted epoch: 3–4."), std::string::npos) << md;
    // Latest +6.2 mm ± 2.5, range −3.1 to +6.2 mm, significant in 2 of 3 epochs.
    EXPECT_NE(md.find("| m3c2_median_m | 3 | +6.200 | 2.500 | -3.100 | +6.200 | 67 % |"),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("- **step** (m3c2_median_m in zone top): raised 1 time(s)."),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("  - epoch 3: raise alarm (+6.20 mm)"), std::string::npos) << md;
}

}  // namespace
}  // namespace tlsmon::report
