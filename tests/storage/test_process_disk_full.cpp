// A full disk surfacing as StorageError::disk_full, on a real 2 MiB tmpfs (needs root), and
// the interrupted epoch retried once there is room again.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "fake_sha256.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/small_tmpfs.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;

EpochResults one_zone(double value) {
    EpochResults r;
    r.zone_results = {{"deck", "m3c2_mean_m", value, 0.002, 50, false}};
    return r;
}

TEST(DiskFull, SurfacesAsDiskFullAndTheEpochCanBeRetried) {
    // Like the daemon's disk-full tests, this one needs root to mount the tmpfs; without it
    // it fails rather than skips, so a run that did not test disk-full never looks green.
    ASSERT_EQ(::geteuid(), 0u) << "mounting a tmpfs needs root (CI runs as root)";
    test::TempDir dir;
    // A real full file system: a 2 MiB tmpfs mounted for the test (room for the schema, a
    // first commit and its WAL, and the retry once the filler is gone).
    test::SmallTmpfs fs(dir / "mnt", "2m");
    ASSERT_TRUE(fs.mounted()) << "mount tmpfs: " << fs.error();
    const auto path = dir / "mnt" / "e.sqlite";
    const auto filler = dir / "mnt" / "filler";
    int done = 0;
    EpochId stuck = 0;
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        db.site().upsert_zone("deck", "{}");
        // Each commit (a 200 KB array) is far larger than an epoch's row and its counters (a
        // few pages). The first commit's cost on this file system is measured, then the
        // filler leaves half of it: the next insert and claim fit, their commit does not, so
        // it is a commit that meets the full disk, whatever the schema's own size.
        std::size_t free_before = 0;
        bool full = false;
        for (int i = 0; i < 100 && !full; ++i) {
            if (i == 1) {
                const auto left = std::filesystem::space(dir / "mnt").available;
                const auto commit_cost = free_before - left;
                ASSERT_GT(left, commit_cost / 2) << "the first commit took " << commit_cost;
                test::write_file(filler, std::string(left - commit_cost / 2, '\0'));
            }
            if (i == 0) free_before = std::filesystem::space(dir / "mnt").available;
            const auto id =
                db.epochs()
                    .insert({test::fake_sha256(i + 1), 1000 + i, "/i/s.ptx", 1, std::nullopt})
                    .id;
            ASSERT_TRUE(db.epochs().claim(id));
            auto r = one_zone(0.001 * i);
            r.core_point_arrays = {{"m3c2_distance_m", std::vector<float>(50000, 0.001f * i)}};
            try {
                db.results().commit(id, r);
                ++done;
            } catch (const StorageError& e) {
                EXPECT_TRUE(e.disk_full()) << e.what();
                EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos);
                full = true;
                stuck = id;
            }
        }
        ASSERT_TRUE(full) << "the 2 MiB file system never filled";
        EXPECT_GT(done, 0);
        EXPECT_EQ(db.epochs().find(stuck)->status, EpochStatus::processing);
        EXPECT_FALSE(db.series().core_point_array(stuck, "m3c2_distance_m"));
    }
    // Space comes back (the operator cleans up); the daemon restarts and retries the epoch.
    std::filesystem::remove(filler);
    auto db = EpochDatabase::open(path, Mode::read_write);
    EXPECT_EQ(db.epochs().recover_interrupted(), 1);
    ASSERT_TRUE(db.epochs().claim(stuck));
    auto r = one_zone(0.5);
    r.core_point_arrays = {{"m3c2_distance_m", std::vector<float>(50000, 0.5f)}};
    db.results().commit(stuck, r);
    EXPECT_EQ(db.series().points("deck", "m3c2_mean_m", {}).size(),
              static_cast<std::size_t>(done + 1));
    SQLite::Database raw(path.string(), SQLite::OPEN_READONLY);
    EXPECT_EQ(raw.execAndGet("PRAGMA integrity_check").getString(), "ok");
}

}  // namespace
}  // namespace tlsmon
