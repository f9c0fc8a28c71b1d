// The system alarms on a real SQLite file: observations through the state machine, stored as
// the rules system.* with events.
#include <gtest/gtest.h>

#include "daemon/system_alarm_watch.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

struct Fixture {
    test::TempDir dir;
    EpochDatabase db = EpochDatabase::open(dir / "e.sqlite", EpochDatabase::Mode::read_write);
    SystemAlarmConfig config;  // 900 s cadence, factor 3, 5 % free, 1 % deadband
    Fixture() { store_system_alarm_rules(db); }
    AlarmState state(const std::string& rule) const {
        for (const auto& s : db.alarms().states()) {
            if (s.rule == rule) return s;
        }
        return AlarmState{rule, "normal", "", 0, {}, {}, "", {}, "", {}};
    }
};

TEST(SystemAlarmWatch, DiskNearlyFullRaisesAndClearsAboveTheDeadband) {
    Fixture f;
    SystemObservation seen;
    seen.now = 1000;
    seen.disk_free_fraction = 0.04;
    EXPECT_EQ(observe_system_alarms(f.db, f.config, seen), 1);
    EXPECT_EQ(f.state("system.disk_nearly_full").state, "unack");
    EXPECT_EQ(f.state("system.disk_nearly_full").level, "alert");
    seen.now = 2000;
    seen.disk_free_fraction = 0.055;  // above 5 %, not above 6 %: still nearly full
    EXPECT_EQ(observe_system_alarms(f.db, f.config, seen), 0);
    seen.now = 3000;
    seen.disk_free_fraction = 0.07;
    EXPECT_EQ(observe_system_alarms(f.db, f.config, seen), 1);
    EXPECT_EQ(f.state("system.disk_nearly_full").state, "rtn_unack");
    const auto events = f.db.alarms().events(std::nullopt, "system.disk_nearly_full");
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].time, 1000);
    EXPECT_EQ(events[1].kind, "return");
    EXPECT_EQ(events[1].time, 3000);
}

TEST(SystemAlarmWatch, StaleRejectedAndDatabaseError) {
    Fixture f;
    SystemObservation seen;
    seen.now = 10000;
    seen.last_epoch_acquired = 10000 - 2700;  // exactly 3 x cadence: not yet stale
    seen.last_epoch_rejected = true;
    seen.database_error = true;
    EXPECT_EQ(observe_system_alarms(f.db, f.config, seen), 2);
    EXPECT_EQ(f.state("system.stale").state, "normal");
    EXPECT_EQ(f.state("system.registration_rejected").level, "warning");
    EXPECT_EQ(f.state("system.database_error").level, "alarm");
    SystemObservation later;
    later.now = 10001;
    later.last_epoch_acquired = 10000 - 2700;
    EXPECT_EQ(observe_system_alarms(f.db, f.config, later), 1);
    EXPECT_EQ(f.state("system.stale").state, "unack");
    // Fields not observed keep their condition.
    EXPECT_EQ(f.state("system.database_error").state, "unack");
}

}  // namespace
}  // namespace tlsmon
