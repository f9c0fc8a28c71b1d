// Disk full: the database lives on a small tmpfs that the test fills up. The daemon must
// log it, record a system event (once the disk has room again), retry with back-off and
// lose no epoch.
#include <gtest/gtest.h>

#include <iostream>

#include "daemon_harness.hpp"
#include "tests/support/small_tmpfs.hpp"

namespace tlsmon::test {
namespace {

const fs::path kData = TLSMON_DATA_DIR;

TEST(DaemonDiskFull, EpochsWaitAndAreProcessedWhenSpaceReturns) {
    Site site("diskfull");
    const fs::path db_folder = site.root / "db";
    const SmallTmpfs tmpfs(db_folder, "4m");
    if (!tmpfs.mounted()) {
        // Mounting needs root (CI runs the suite as root); elsewhere this cannot be tested
        // honestly, so it says so instead of passing.
        FAIL() << "cannot mount a tmpfs at " << db_folder << " (not root?): " << tmpfs.error();
    }

    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until(
        [&] {
            for (const auto& e : site.open_db().series().events({})) {
                if (e.kind == "start") return true;
            }
            return false;
        },
        10));
    const fs::path filler = db_folder / "filler";
    fill_file_system(filler);

    fs::copy_file(kData / "ptx/no-color.ptx", site.ingest() / "a_20260601T060000Z.ptx");
    fs::copy_file(kData / "ptx/complex-transform.ptx", site.ingest() / "ca_20260601T060000Z.ptx");
    // The database refuses while the disk is full: nothing processed, nothing lost.
    ASSERT_TRUE(
        wait_until([&] { return read_file(site.log()).find("full") != std::string::npos; }, 10))
        << read_file(site.log());
    std::this_thread::sleep_for(std::chrono::seconds(2));  // a few back-off rounds
    EXPECT_TRUE(daemon.running());
    EXPECT_TRUE(fs::exists(site.ingest() / "a_20260601T060000Z.ptx"));
    EXPECT_TRUE(fs::exists(site.ingest() / "ca_20260601T060000Z.ptx"));

    fs::remove(filler);
    ASSERT_TRUE(wait_until(
        [&] {
            const auto epochs = site.open_db().series().epochs_in_range({});
            return epochs.size() == 2 && epochs[0].status == EpochStatus::done &&
                   epochs[1].status == EpochStatus::done;
        },
        15))
        << read_file(site.log());
    bool recorded = false;
    for (const auto& e : site.open_db().series().events({}, std::string("disk_full"))) {
        recorded = recorded || e.message.find("full") != std::string::npos;
    }
    EXPECT_TRUE(recorded) << "a disk_full system event is written once there is room";
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(5), 0);
    const auto check = shell("sqlite3 " + site.database().string() + " 'PRAGMA integrity_check'");
    EXPECT_EQ(check.output, "ok\n");
    if (::testing::Test::HasFailure()) std::cout << read_file(site.log());
}

}  // namespace
}  // namespace tlsmon::test
