// The registration stage inside the epoch pipeline, on the simulator's `pier` preset with
// drift: the targets' windows are rendered and written as multi-scan PTX files (one scan per
// window), processed with process_epoch against a real SQLite file, and what the database
// holds is checked against the simulator's truth: the knocked target (10 mm, from epoch 2)
// is left out of epoch 2, excluded as moved when epoch 3 confirms it (the default
// confirm_exclusion_epochs = 2) and stays excluded; an epoch where only two targets remain usable
// is rejected with the reason and a system event; the registration's σ at a configured zone is
// stored for every accepted epoch.
#include <gtest/gtest.h>

#include <fstream>

#include "../simulator/narrow_window.hpp"
#include "formats/ptx_writer.hpp"
#include "pipeline_site.hpp"
#include "simulator/drift.hpp"
#include "simulator/render.hpp"

namespace tlsmon {
namespace {

sim::Site knocked_pier() {
    sim::Site site = sim::preset_pier();
    site.drift.yaw_amplitude_arcsec = 60.0;
    site.drift.tilt_amplitude_arcsec = 10.0;
    site.drift.translation_sigma = 0.0015;
    site.atmosphere.enabled = false;
    site.events.knocked_target = 0;  // T1
    site.events.knocked_epoch = 2;
    site.events.knocked_displacement = {0.0, 0.010, 0.0};
    return site;
}

// The epoch's target windows as one multi-scan PTX, leaving out the targets in `skip`.
std::string ptx_of_windows(const sim::Site& site, int epoch, const std::set<std::string>& skip) {
    std::string out;
    for (const auto& t : site.targets) {
        if (skip.count(t.name)) continue;
        sim::Site one = site;
        sim::test::narrow_window(one.scanner, t.centre, 0.9);
        out += ptx_text(sim::render_epoch(one, epoch, 1.5 * epoch, 2).scan);
    }
    return out;
}

TEST(RegistrationStage, KnockedTargetStaysExcludedAndTwoTargetsAreRejected) {
    const sim::Site site = knocked_pier();
    test::PipelineSite ps;
    ps.config.coverage.min_inside_share = 0.0;
    for (const auto& t : site.targets) {
        TargetConfig g;
        g.name = t.name;
        g.kind =
            t.kind == sim::Target::Kind::sphere ? TargetKind::sphere : TargetKind::checkerboard;
        g.approximate = t.centre + Eigen::Vector3d(-0.01, 0.02, 0.005);
        ps.config.registration.targets.push_back(g);
    }
    ps.config.registration.zones.push_back(
        box_zone("pier_south_face", Eigen::Vector3d(2, 44.5, 0), Eigen::Vector3d(17, 45.5, 40)));
    ReferenceCache cache(*ps.db);
    std::vector<EpochOutcome> outcomes;
    std::vector<EpochId> ids;
    for (int e = 0; e < 5; ++e) {
        // Epoch 4: only T1..T3 in the file, T1 still excluded: two usable targets.
        std::set<std::string> skip;
        if (e == 4) {
            for (std::size_t k = 3; k < site.targets.size(); ++k) skip.insert(site.targets[k].name);
        }
        const auto file = ps.dir / "ingest" / ("pier_" + std::to_string(e) + ".ptx");
        {
            std::ofstream f(file, std::ios::binary);
            f << ptx_of_windows(site, e, skip);
        }
        const EpochInsert ins = ps.db->epochs().insert(
            NewEpoch{sha256_file(file), 1780293600 + 900 * e, file,
                     static_cast<std::int64_t>(std::filesystem::file_size(file)), std::nullopt});
        ids.push_back(ins.id);
        outcomes.push_back(ps.process(*ps.db->epochs().find(ins.id), cache));
    }
    EXPECT_EQ(outcomes[0], EpochOutcome::done);
    EXPECT_EQ(outcomes[1], EpochOutcome::done);
    EXPECT_EQ(outcomes[2], EpochOutcome::done);
    EXPECT_EQ(outcomes[3], EpochOutcome::done);
    EXPECT_EQ(outcomes[4], EpochOutcome::rejected);

    auto& regs = ps.db->registrations();
    // Epoch 2: T1 moved by 10 mm (its apparent movement in the reference frame), excluded.
    const auto t2 = regs.targets_of_epoch(ids[2]);
    const auto n = site.targets.size();
    ASSERT_EQ(t2.size(), n);
    EXPECT_EQ(t2[0].target, "T1");
    EXPECT_EQ(t2[0].use, "excluded_outlier");
    EXPECT_FALSE(t2[0].used);
    EXPECT_NEAR(std::hypot(t2[0].residual[0], t2[0].residual[1], t2[0].residual[2]), 0.010, 0.001);
    const auto r2 = regs.of_epoch(ids[2]);
    ASSERT_TRUE(r2);
    EXPECT_TRUE(r2->accepted);
    EXPECT_EQ(r2->target_count, static_cast<std::int64_t>(n) - 1);
    ASSERT_TRUE(r2->parameters && r2->sigmas && r2->quaternion);
    // Epoch 3: tested again, it fails again and is excluded as moved from then on, by epoch 3.
    const auto t3 = regs.targets_of_epoch(ids[3]);
    EXPECT_EQ(t3[0].status, "found");
    EXPECT_EQ(t3[0].use, "excluded_outlier");
    EXPECT_EQ(regs.of_epoch(ids[3])->target_count, static_cast<std::int64_t>(n) - 1);
    EXPECT_EQ(regs.excluded_targets(), std::set<std::string>{"T1"});
    const auto exclusions = regs.exclusions();
    ASSERT_EQ(exclusions.size(), 1u);
    EXPECT_EQ(exclusions[0].epoch, ids[3]);
    // What the daemon reads for each epoch: T1's run of failed tests before it.
    EXPECT_TRUE(regs.outlier_runs(1780293600 + 900 * 2, 10).empty());
    EXPECT_EQ(regs.outlier_runs(1780293600 + 900 * 3, 10), (std::map<std::string, int>{{"T1", 1}}));
    EXPECT_EQ(regs.outlier_runs(1780293600 + 900 * 4, 10), (std::map<std::string, int>{{"T1", 2}}));
    EXPECT_EQ(regs.outlier_runs(1780293600 + 900 * 4, 1), (std::map<std::string, int>{{"T1", 1}}));
    // Epoch 4: excluded, not tested.
    const auto t4 = regs.targets_of_epoch(ids[4]);
    EXPECT_EQ(t4[0].status, "excluded");
    EXPECT_EQ(t4[0].use, "not_usable");
    // The registration's σ at the pier face: stored per accepted epoch, and of the size the
    // layout allows (docs/registration.md: ≈ 1 mm at 50 m for centres of 0.1 mm).
    const auto z3 = regs.zone_sigmas_of_epoch(ids[3]);
    ASSERT_EQ(z3.size(), 1u);
    EXPECT_GT(z3[0].max_sigma_3d_m, 0.0001);
    EXPECT_LT(z3[0].max_sigma_3d_m, 0.003);
    // Epoch 4: two usable targets: rejected, the reason says so, no zone σ.
    const auto e4 = ps.db->epochs().find(ids[4]);
    EXPECT_NE(e4->reason.find("too few"), std::string::npos) << e4->reason;
    const auto r4 = regs.of_epoch(ids[4]);
    ASSERT_TRUE(r4);
    EXPECT_FALSE(r4->accepted);
    EXPECT_TRUE(regs.zone_sigmas_of_epoch(ids[4]).empty());
    // Re-surveyed: offered again.
    EXPECT_EQ(regs.mark_resurveyed("T1", 1780300000), 1);
    EXPECT_TRUE(regs.excluded_targets().empty());
}

// A target is excluded as moved when it has failed its outlier test in `confirm` consecutive
// epochs, this one included; otherwise it is only left out of this epoch.
TEST(RegistrationStage, AnOutlierIsExcludedAsMovedOnceConsecutiveEpochsConfirmIt) {
    const std::map<std::string, int> runs{{"T2", 1}, {"T3", 3}};
    const auto split = [&](int confirm) {
        RegistrationResult r;
        r.newly_excluded = {"T1", "T2", "T3"};
        confirm_exclusions(r, runs, confirm);
        return std::pair(r.newly_excluded, r.outliers);
    };
    using Names = std::vector<std::string>;
    EXPECT_EQ(split(1), std::pair(Names{"T1", "T2", "T3"}, Names{}));
    EXPECT_EQ(split(2), std::pair(Names{"T2", "T3"}, Names{"T1"}));
    EXPECT_EQ(split(4), std::pair(Names{"T3"}, Names{"T1", "T2"}));
    EXPECT_EQ(split(5), std::pair(Names{}, Names{"T1", "T2", "T3"}));
}

}  // namespace
}  // namespace tlsmon
