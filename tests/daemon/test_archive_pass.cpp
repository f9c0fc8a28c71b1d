// One pass of the archive policy (daemon/archive_pass.hpp) on real files and a real SQLite
// file: scans thinned by age with the protected ones kept, kept scans re-encoded as E57 and
// read back equal, the space freed equal to what the folder lost, deletions an interrupted
// pass recorded finished by the next, and real scans re-encoded (a real pump-room scan) or,
// when E57 cannot hold them (a pose with a scale), kept as they were ingested.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "daemon/archive_pass.hpp"
#include "daemon/scan_reencoding.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/archive_series.hpp"
#include "tests/support/map_series.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;
constexpr UtcSeconds kDay = 86400;
constexpr double kResolution = 1e-5;

std::int64_t folder_bytes(const fs::path& folder) {
    std::int64_t total = 0;
    for (const auto& f : fs::directory_iterator(folder))
        total += static_cast<std::int64_t>(f.file_size());
    return total;
}

// The largest distance between the points of two reads of one file.
double max_distance(const std::vector<Scan>& a, const std::vector<Scan>& b) {
    EXPECT_EQ(a.size(), b.size());
    double worst = 0;
    for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
        EXPECT_EQ(a[k].size(), b[k].size());
        for (std::size_t i = 0; i < std::min(a[k].size(), b[k].size()); ++i)
            worst = std::max(worst, (a[k].xyz[i] - b[k].xyz[i]).norm());
    }
    return worst;
}

class ArchivePass : public ::testing::Test {
  protected:
    void SetUp() override {
        fs::create_directories(archive_);
        fs::create_directories(dir_ / "quarantine");
    }

    // `days` x 4 epochs from kSeriesStart, each with its PTX in the archive.
    void add_series(int days, const std::set<int>& alarm_at = {}) {
        ids_ = test::write_archive_series(db_, archive_, days * 4, 4, test::kSeriesStart, alarm_at);
    }

    std::string archive_path(EpochId id) { return db_.epochs().find(id)->archive_path.value(); }

    ArchivePolicy policy(ScanReencoding reencode) {
        ArchivePolicy p;
        p.enabled = true;
        p.keep_all_days = 2;
        p.keep_daily_days = 6;
        p.reencode = reencode;
        p.e57_resolution = kResolution;
        p.batch_scans = 7;
        return p;
    }

    test::TempDir dir_;
    fs::path archive_ = dir_ / "archive";
    fs::path database_ = dir_ / "epochs.sqlite";
    EpochDatabase db_ = EpochDatabase::open(database_, Mode::read_write);
    std::vector<EpochId> ids_;
};

TEST_F(ArchivePass, RemovesThinnedScansKeepsProtectedOnesAndReencodesTheKept) {
    add_series(12, {5});  // 48 epochs; epoch index 5 raised an alarm
    db_.retention().pin(ids_[9], "test", "", 0);
    // A failed epoch's file in quarantine: never the archive policy's.
    const fs::path quarantined = dir_ / "quarantine" / "broken.ptx";
    write_ptx(test::archive_grid_scan(99), quarantined);
    const auto failed = db_.epochs()
                            .insert({sha256_file(quarantined), test::kSeriesStart + 1,
                                     dir_ / "ingest/broken.ptx", 1, std::nullopt})
                            .id;
    db_.epochs().claim(failed);
    db_.epochs().fail(failed, "test", quarantined.string());

    std::map<EpochId, std::vector<Scan>> before;
    for (const auto id : ids_) before[id] = read_scans(archive_path(id));
    const std::int64_t size_before = folder_bytes(archive_);

    const auto r = run_archive_pass(db_, policy(ScanReencoding::e57), archive_);
    // Now = day 11.75. Young (>= 9.75): 9; daily (days 6..9's firsts): 4; weekly (days 0..5:
    // Thu 1 Jan, Mon 5 Jan): 2; protected besides: the alarm's and the pinned epoch.
    EXPECT_EQ(r.plan.tiers.kept_young, 9);
    EXPECT_EQ(r.plan.tiers.kept_daily, 4);
    EXPECT_EQ(r.plan.tiers.kept_weekly, 2);
    EXPECT_EQ(r.plan.tiers.kept_protected, 2);
    EXPECT_EQ(r.plan.scans, 48);
    EXPECT_EQ(r.scans_removed, 48 - 9 - 4 - 2 - 2);
    // Kept past the young tier, less the reference: 4 + 2 + 2 - 1.
    EXPECT_EQ(r.scans_reencoded, 7);
    EXPECT_TRUE(r.errors.empty()) << r.errors.front();
    EXPECT_FALSE(r.stopped);
    // What the pass says it freed is what the folder lost.
    EXPECT_EQ(r.bytes_freed, size_before - folder_bytes(archive_));
    EXPECT_LT(r.reencoded_bytes_after * 2, r.reencoded_bytes_before);

    std::set<EpochId> removed;
    for (const auto& s : r.plan.remove) removed.insert(s.id);
    for (const auto id : ids_) {
        const fs::path file = archive_path(id);
        const auto record = db_.archive().record(id);
        if (removed.count(id)) {
            EXPECT_FALSE(fs::exists(file)) << file;
            ASSERT_TRUE(record);
            EXPECT_EQ(record->action, "removed");
        } else if (record) {
            EXPECT_EQ(record->action, "reencoded");
            EXPECT_EQ(file.extension(), ".e57");
            EXPECT_FALSE(fs::exists(record->original_path));
            EXPECT_EQ(record->sha256_after, sha256_file(file));
            EXPECT_LE(max_distance(before[id], read_scans(file)),
                      0.5 * std::sqrt(3.0) * kResolution + 1e-9);
        } else {
            EXPECT_EQ(file.extension(), ".ptx");  // young, or the reference
            EXPECT_EQ(sha256_file(file), db_.epochs().find(id)->sha256);
        }
    }
    EXPECT_FALSE(removed.count(ids_[0]));  // the reference
    EXPECT_FALSE(removed.count(ids_[5]));  // the alarm's
    EXPECT_FALSE(removed.count(ids_[9]));  // pinned
    EXPECT_EQ(archive_path(ids_[0]), (archive_ / "scan_0.ptx").string());
    EXPECT_TRUE(fs::exists(quarantined));
    EXPECT_EQ(test::sql_count(database_,
                              "SELECT count(*) FROM system_events WHERE kind = 'archive_thinned'"),
              (r.scans_removed + 6) / 7);
    EXPECT_EQ(test::sql_count(
                  database_, "SELECT count(*) FROM system_events WHERE kind = 'archive_reencoded'"),
              1);

    // A second pass finds nothing to do.
    const auto again = run_archive_pass(db_, policy(ScanReencoding::e57), archive_);
    EXPECT_EQ(again.scans_removed + again.scans_reencoded + again.deletions_finished, 0);
    EXPECT_EQ(again.bytes_freed, 0);
    EXPECT_EQ(again.plan.scans, 48 - r.scans_removed);
}

TEST_F(ArchivePass, FinishesWhatAnInterruptedPassRecorded) {
    add_series(12);
    const auto p = policy(ScanReencoding::e57);
    // Killed after the removals' commit, before a file was deleted; and after an E57 was
    // written but before it was recorded.
    const auto plan = db_.archive().plan(archive_, p);
    ASSERT_EQ(db_.archive().record_removed(plan.remove, now_utc()).size(), plan.remove.size());
    ASSERT_FALSE(plan.reencode.empty());
    const fs::path leftover = fs::path(plan.reencode.front().path).replace_extension(".e57");
    write_ptx(test::archive_grid_scan(1000), leftover);  // any bytes: no epoch holds this file
    for (const auto& s : plan.remove) ASSERT_TRUE(fs::exists(s.path));

    const auto r = run_archive_pass(db_, p, archive_);
    EXPECT_EQ(r.deletions_finished, static_cast<std::int64_t>(plan.remove.size()));
    EXPECT_EQ(r.scans_removed, 0);
    for (const auto& s : plan.remove) EXPECT_FALSE(fs::exists(s.path)) << s.path;
    EXPECT_EQ(r.scans_reencoded, static_cast<std::int64_t>(plan.reencode.size()));
    // The leftover was replaced by the E57 written from the scan itself.
    EXPECT_EQ(archive_path(plan.reencode.front().id), leftover.string());
    EXPECT_LE(max_distance(
                  read_scans(leftover),
                  {test::archive_grid_scan(static_cast<int>(plan.reencode.front().id - ids_[0]))}),
              0.5 * std::sqrt(3.0) * kResolution + 2e-6);  // + the PTX's 1 µm decimals
    EXPECT_TRUE(r.errors.empty());
}

TEST_F(ArchivePass, KeepsAScanE57CannotHoldAsItWasIngested) {
    // A real PTX whose first scan's pose scales z by 2: E57 has no place for a scale.
    test::prepare_archive_site(db_);
    write_ptx(test::archive_grid_scan(0), archive_ / "reference.ptx");
    test::add_archived_epoch(db_, test::kSeriesStart, archive_ / "reference.ptx");
    const fs::path real = archive_ / "multiple-and-transform.ptx";
    fs::copy_file(fs::path(TLSMON_DATA_DIR) / "ptx/multiple-and-transform.ptx", real);
    fs::permissions(real, fs::perms::owner_write, fs::perm_options::add);
    const auto id = test::add_archived_epoch(db_, test::kSeriesStart + 5 * kDay, real);
    write_ptx(test::archive_grid_scan(2), archive_ / "newest.ptx");
    test::add_archived_epoch(db_, test::kSeriesStart + 10 * kDay, archive_ / "newest.ptx");
    const std::string sha = sha256_file(real);

    auto p = policy(ScanReencoding::e57);
    p.keep_daily_days = 30;
    const auto r = run_archive_pass(db_, p, archive_);
    EXPECT_EQ(r.scans_reencoded, 0);
    ASSERT_EQ(r.errors.size(), 1u);
    EXPECT_NE(r.errors[0].find("multiple-and-transform.ptx: re-encoding as E57 failed"),
              std::string::npos)
        << r.errors[0];
    EXPECT_EQ(sha256_file(real), sha);
    EXPECT_EQ(archive_path(id), real.string());
    EXPECT_FALSE(fs::exists(archive_ / "multiple-and-transform.e57"));
    EXPECT_FALSE(fs::exists(archive_ / "multiple-and-transform.e57.part"));
    const auto record = db_.archive().record(id);
    ASSERT_TRUE(record);
    EXPECT_EQ(record->action, "not_reencoded");
    EXPECT_EQ(test::sql_count(database_,
                              "SELECT count(*) FROM system_events WHERE kind ="
                              " 'archive_not_reencoded'"),
              1);
    // Not tried again.
    EXPECT_TRUE(run_archive_pass(db_, p, archive_).errors.empty());
}

TEST(ScanReencoding, ARealScanAsE57IsAThirdOfItsPtxAndReadsBackWithinTheResolution) {
    test::TempDir dir;
    const fs::path ptx = dir / "pumpA.ptx";
    fs::copy_file(fs::path(TLSMON_DATA_DIR) / "ptx/pumpA_from_e57.ptx", ptx);
    const auto written = reencode_as_e57(ptx, sha256_file(ptx), kResolution);
    EXPECT_EQ(written.path, dir / "pumpA.e57");
    const auto ptx_bytes = static_cast<std::int64_t>(fs::file_size(ptx));
    EXPECT_EQ(written.bytes, static_cast<std::int64_t>(fs::file_size(written.path)));
    EXPECT_LT(written.bytes * 3, ptx_bytes) << written.bytes << " of " << ptx_bytes;
    std::printf("pumpA: PTX %lld bytes, E57 %lld bytes\n", static_cast<long long>(ptx_bytes),
                static_cast<long long>(written.bytes));
    const auto a = read_scans(ptx), b = read_scans(written.path);
    ASSERT_EQ(b.size(), 1u);
    EXPECT_EQ(b[0].size(), 155201u);
    EXPECT_LE(max_distance(a, b), 0.5 * std::sqrt(3.0) * kResolution + 1e-9);
    EXPECT_EQ(a[0].rgb, b[0].rgb);
    ASSERT_TRUE(b[0].grid);
    EXPECT_EQ(a[0].grid->row, b[0].grid->row);
    EXPECT_EQ(a[0].grid->column, b[0].grid->column);
    // Another content than the epoch's is refused, and nothing is written.
    fs::remove(written.path);
    EXPECT_THROW(reencode_as_e57(ptx, std::string(64, '0'), kResolution), Error);
    EXPECT_FALSE(fs::exists(written.path));
}

}  // namespace
}  // namespace tlsmon
