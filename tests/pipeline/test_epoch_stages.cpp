// The stages of the epoch pipeline against the reference epoch: the first accepted epoch
// becomes the reference, a later epoch is analysed against it with the reference's products
// reused, an epoch a stage cannot analyse is stored `rejected` with the stage's reason (not
// `failed`), and a reference whose scan is gone still serves from the cache.
#include <gtest/gtest.h>

#include "pipeline_site.hpp"

namespace tlsmon::test {
namespace {

TEST(EpochStages, FirstEpochIsTheReferenceAndLaterEpochsReuseItsProducts) {
    PipelineSite site;
    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, 0.01);
    ReferenceCache cache(*site.db);
    EXPECT_EQ(site.process(e0, cache), EpochOutcome::done);
    EXPECT_EQ(site.db->epochs().reference(), e0.id);
    EXPECT_EQ(cache.counters().built, 1);
    EXPECT_EQ(site.process(e1, cache), EpochOutcome::done);
    EXPECT_EQ(cache.counters().built, 1);
    EXPECT_EQ(cache.counters().from_memory, 1);
    EXPECT_EQ(site.db->epochs().find(e1.id)->status, EpochStatus::done);
    const auto stages = site.db->series().stages(e1.id);
    ASSERT_EQ(stages.size(), 2u);
    EXPECT_EQ(stages[0].stage, "coverage");
    EXPECT_GE(stages[0].ms, 0.0);
    EXPECT_EQ(stages[0].rejected, "");
    EXPECT_EQ(stages[0].note, "100.0 % of the points inside the reference extent");
    // No target, no ICP: the epoch says that nothing registered it.
    EXPECT_EQ(stages[1].stage, "registration");
    EXPECT_EQ(stages[1].note.rfind("not registered: no [[target]] and no ICP fallback", 0), 0u)
        << stages[1].note;
    EXPECT_EQ(site.db->registrations().of_epoch(e1.id)->method, "unregistered");
    EXPECT_EQ(site.db->registrations().of_epoch(e0.id)->method, "reference");
}

TEST(EpochStages, AnEpochOutsideTheReferenceExtentIsRejectedWithTheReason) {
    PipelineSite site;
    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    // Half of the grid beyond the reference's box + 1 m margin: 9 of 21 columns inside.
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, 0.0, {7.0, 0.0, 0.0});
    ReferenceCache cache(*site.db);
    ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
    EXPECT_EQ(site.process(e1, cache), EpochOutcome::rejected);
    const Epoch stored = *site.db->epochs().find(e1.id);
    EXPECT_EQ(stored.status, EpochStatus::rejected);
    EXPECT_NE(stored.reason.find("42.9 % of the points lie within the reference epoch's extent"),
              std::string::npos)
        << stored.reason;
    const auto stages = site.db->series().stages(e1.id);
    ASSERT_EQ(stages.size(), 1u);
    EXPECT_EQ(stages[0].rejected, stored.reason);
    ASSERT_TRUE(stored.archive_path);  // the file was fine: archived, not quarantined
    EXPECT_TRUE(fs::exists(*stored.archive_path));
    const auto events = site.db->series().events({}, std::string("epoch_rejected"));
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].epoch, e1.id);
}

TEST(EpochStages, ReferenceScanGoneServesFromTheCacheAndRejectsWithoutIt) {
    PipelineSite site;
    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, 0.001);
    const Epoch e2 = site.add_epoch("e2.xyz", 3000, 0.002);
    {
        ReferenceCache cache(*site.db);
        ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
    }
    fs::remove(*site.db->epochs().find(e0.id)->archive_path);
    site.restart();
    {
        ReferenceCache cache(*site.db);
        EXPECT_EQ(site.process(e1, cache), EpochOutcome::done);
        EXPECT_EQ(cache.counters().from_database, 1);
    }
    site.db->reference_cache().clear("coverage.extent");
    ReferenceCache cache(*site.db);
    EXPECT_EQ(site.process(e2, cache), EpochOutcome::rejected);
    const Epoch stored = *site.db->epochs().find(e2.id);
    EXPECT_NE(
        stored.reason.find("coverage: the reference epoch's scan is needed and cannot be read"),
        std::string::npos)
        << stored.reason;
}

TEST(EpochStages, NoReferenceYetRejectsUntilTheNamedReferenceIsProcessed) {
    PipelineSite site;
    site.config.reference_epoch = "ref.xyz";
    const Epoch early = site.add_epoch("early.xyz", 1000);
    const Epoch ref = site.add_epoch("ref.xyz", 2000, 0.001);
    ReferenceCache cache(*site.db);
    EXPECT_EQ(site.process(early, cache), EpochOutcome::rejected);
    EXPECT_NE(site.db->epochs().find(early.id)->reason.find("no reference epoch yet"),
              std::string::npos);
    EXPECT_EQ(site.process(ref, cache), EpochOutcome::done);
    EXPECT_EQ(site.db->epochs().reference(), ref.id);
}

}  // namespace
}  // namespace tlsmon::test
