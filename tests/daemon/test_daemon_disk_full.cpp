// Disk full: the database lives on a small tmpfs that the test fills up. The daemon must
// log it, record a system event (once the disk has room again), retry with back-off and
// lose no epoch.
#include <gtest/gtest.h>
#include <sys/mount.h>

#include <iostream>

#include "daemon_harness.hpp"

namespace tlsmon::test {
namespace {

const fs::path kData = TLSMON_DATA_DIR;

// Fills the file system holding `folder` with one file until write() fails.
void fill(const fs::path& file) {
    std::ofstream out(file, std::ios::binary);
    const std::string block(4096, 'x');
    while (out.write(block.data(), block.size())) out.flush();
}

TEST(DaemonDiskFull, EpochsWaitAndAreProcessedWhenSpaceReturns) {
    Site site("diskfull");
    const fs::path db_folder = site.root / "db";
    fs::create_directories(db_folder);
    if (::mount("tlsmon-test", db_folder.c_str(), "tmpfs", 0, "size=4m") != 0) {
        // Mounting needs root (CI runs the suite as root); elsewhere this cannot be tested
        // honestly, so it says so instead of passing.
        FAIL() << "cannot mount a tmpfs at " << db_folder << " (not root?): " << strerror(errno);
    }
    struct Unmount {
        fs::path at;
        ~Unmount() { ::umount2(at.c_str(), MNT_DETACH); }
    } unmount{db_folder};

    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until(
        [&] {
            for (const auto& e : site.open_db().events({})) {
                if (e.kind == "start") return true;
            }
            return false;
        },
        10));
    const fs::path filler = db_folder / "filler";
    fill(filler);

    fs::copy_file(kData / "ptx/no-color.ptx", site.ingest() / "a_20260601T060000Z.ptx");
    fs::copy_file(kData / "ptx/complex-transform.ptx", site.ingest() / "ca_20260601T060000Z.ptx");
    // The database refuses while the disk is full: nothing processed, nothing lost.
    ASSERT_TRUE(
        wait_until([&] { return read_text(site.log()).find("full") != std::string::npos; }, 10))
        << read_text(site.log());
    std::this_thread::sleep_for(std::chrono::seconds(2));  // a few back-off rounds
    EXPECT_TRUE(daemon.running());
    EXPECT_TRUE(fs::exists(site.ingest() / "a_20260601T060000Z.ptx"));
    EXPECT_TRUE(fs::exists(site.ingest() / "ca_20260601T060000Z.ptx"));

    fs::remove(filler);
    ASSERT_TRUE(wait_until(
        [&] {
            const auto epochs = site.open_db().epochs_in_range({});
            return epochs.size() == 2 && epochs[0].status == EpochStatus::done &&
                   epochs[1].status == EpochStatus::done;
        },
        15))
        << read_text(site.log());
    bool recorded = false;
    for (const auto& e : site.open_db().events({}, std::string("disk_full"))) {
        recorded = recorded || e.message.find("full") != std::string::npos;
    }
    EXPECT_TRUE(recorded) << "a disk_full system event is written once there is room";
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(5), 0);
    const auto check = shell("sqlite3 " + site.database().string() + " 'PRAGMA integrity_check'");
    EXPECT_EQ(check.output, "ok\n");
    if (::testing::Test::HasFailure()) std::cout << read_text(site.log());
}

}  // namespace
}  // namespace tlsmon::test
