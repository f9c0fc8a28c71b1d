// ingest_file and process_epoch when the file of a pending epoch changes before it is
// processed: replaced by other content under the same name, or renamed. In-process, on real
// files and a real SQLite database.
#include <gtest/gtest.h>

#include <chrono>
#include <ctime>
#include <fstream>

#include "config/config.hpp"
#include "daemon/ingest.hpp"
#include "formats/e57_writer.hpp"
#include "pipeline/epoch_meteo.hpp"
#include "pipeline/epoch_pipeline.hpp"
#include "pipeline/sha256.hpp"
#include "tests/support/daemon_harness.hpp"
#include "tests/support/text_file.hpp"

namespace tlsmon::test {
namespace {

const fs::path kData = TLSMON_DATA_DIR;

struct PipelineSite {
    Site site{"pipefiles"};
    Config config = parse_config("[paths]\ningest = \"ingest\"\ndatabase = \"db/tlsmon.sqlite\"\n",
                                 "test.toml", site.root);
    EpochDatabase db = open();
    SystemEventLog events;
    IngestContext ctx{db, config, std::nullopt, events};
    PipelineConfig pipeline = pipeline_config(config);
    ReferenceCache cache{db};
    PipelineContext pipeline_ctx{db, pipeline, events, cache};

    EpochDatabase open() {
        fs::create_directories(config.paths.archive);
        fs::create_directories(config.paths.quarantine);
        fs::create_directories(config.paths.database.parent_path());
        return EpochDatabase::open(config.paths.database, EpochDatabase::Mode::read_write);
    }
    // Processes every pending epoch, as the daemon's backlog does.
    void process_backlog() {
        for (const Epoch& e : db.epochs().pending()) process_epoch(pipeline_ctx, e);
    }
    std::optional<Epoch> by_content(const fs::path& original) {
        return db.epochs().find_by_sha256(sha256_file(original));
    }
};

// Ingest reads and hashes a new scan once; the pipeline parses those bytes instead of
// reading the file again, unless the file changed since (then they are not this file's).
TEST(PipelineFiles, BytesReadAtIngestAreParsedWithoutReadingAgain) {
    PipelineSite s;
    const fs::path scan = s.site.ingest() / "small_20260601T060000Z.ptx";
    fs::copy_file(kData / "ptx/no-color.ptx", scan);
    HashedBytes bytes;
    s.ctx.new_epoch_bytes = &bytes;
    ASSERT_EQ(ingest_file(s.ctx, scan), IngestOutcome::new_epoch);
    EXPECT_EQ(bytes.sha256, sha256_file(scan));
    EXPECT_EQ(bytes.bytes.size(), fs::file_size(scan));
    const Epoch epoch = s.db.epochs().pending().at(0);
    EXPECT_EQ(process_epoch(s.pipeline_ctx, epoch, &bytes), EpochOutcome::done);
    EXPECT_TRUE(bytes.bytes.empty()) << "the ingest's bytes were not used";
    EXPECT_EQ(s.db.epochs().find(epoch.id)->point_count, 15);

    // A second scan whose file is touched after ingest: its bytes are left, the file is read.
    const fs::path other = s.site.ingest() / "small_20260601T061500Z.ptx";
    fs::copy_file(kData / "ptx/complex-transform.ptx", other);
    HashedBytes other_bytes;
    s.ctx.new_epoch_bytes = &other_bytes;
    ASSERT_EQ(ingest_file(s.ctx, other), IngestOutcome::new_epoch);
    fs::last_write_time(other, fs::last_write_time(other) + std::chrono::seconds(1));
    const Epoch second = s.db.epochs().pending().at(0);
    EXPECT_EQ(process_epoch(s.pipeline_ctx, second, &other_bytes), EpochOutcome::done);
    EXPECT_FALSE(other_bytes.bytes.empty());
    EXPECT_EQ(s.db.epochs().find(second.id)->point_count, 4);
}

TEST(PipelineFiles, FileReplacedUnderTheSameNameWhilePendingIsTwoEpochs) {
    PipelineSite s;
    const fs::path first = kData / "ptx/no-color.ptx";            // 15 points
    const fs::path second = kData / "ptx/complex-transform.ptx";  // 4 points
    const fs::path scan = s.site.ingest() / "small_20260601T060000Z.ptx";
    fs::copy_file(first, scan);
    ASSERT_EQ(ingest_file(s.ctx, scan), IngestOutcome::new_epoch);
    // The scanner exports again under the same name before the epoch was processed.
    fs::copy_file(second, scan, fs::copy_options::overwrite_existing);
    ASSERT_EQ(ingest_file(s.ctx, scan), IngestOutcome::new_epoch);
    s.process_backlog();

    const auto a = s.by_content(first);
    const auto b = s.by_content(second);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->status, EpochStatus::failed);
    EXPECT_NE(a->reason.find("replaced by other content"), std::string::npos) << a->reason;
    EXPECT_NE(a->point_count, 15) << "the first content is gone; it was never read";
    EXPECT_EQ(b->status, EpochStatus::done) << b->reason;
    EXPECT_EQ(b->point_count, 4) << "the second content's points, in its own epoch";
    ASSERT_TRUE(b->archive_path);
    EXPECT_EQ(read_file(*b->archive_path), read_file(second));
}

// After a restart the files still queued in the ingest folder are known by path, size and
// modification time, not read and hashed again (20 files took 5-10 s before anything was
// processed). Shown by changing the bytes behind the daemon's back, size and time kept: the
// file is not read, so it stays the queued epoch; the pipeline's own sha256 check catches
// such a change when it reads the file.
TEST(PipelineFiles, QueuedFileUnchangedSinceItWasRecordedIsNotReadAgain) {
    PipelineSite s;
    const fs::path scan = s.site.ingest() / "small_20260601T060000Z.ptx";
    fs::copy_file(kData / "ptx/no-color.ptx", scan);
    const auto written = fs::file_time_type::clock::now() - std::chrono::hours(1);
    fs::last_write_time(scan, written);
    EpochId first = 0;
    ASSERT_EQ(ingest_file(s.ctx, scan, &first), IngestOutcome::new_epoch);
    std::string bytes = read_file(scan);
    bytes[bytes.size() - 2] = bytes[bytes.size() - 2] == '1' ? '2' : '1';
    write_text(scan, bytes);
    fs::last_write_time(scan, written);
    EpochId again = 0;
    EXPECT_EQ(ingest_file(s.ctx, scan, &again), IngestOutcome::known);
    EXPECT_EQ(again, first);
    EXPECT_EQ(s.db.epochs().pending().size(), 1u) << "not hashed: no epoch for the new bytes";
    // Modified after it was recorded: read and hashed, a new epoch.
    fs::last_write_time(scan, fs::file_time_type::clock::now() + std::chrono::seconds(5));
    EXPECT_EQ(ingest_file(s.ctx, scan), IngestOutcome::new_epoch);
    EXPECT_EQ(s.db.epochs().pending().size(), 2u);
}

// A scan dated in the future (a scanner clock or a name gone wrong) would leave every later
// epoch "late" for the alarm rules: it is quarantined with the reason, never an epoch.
TEST(PipelineFiles, ScanAcquiredBeyondTheClockToleranceIsQuarantined) {
    PipelineSite s;
    const fs::path future = s.site.ingest() / "pier_20300101T000000Z.ptx";
    fs::copy_file(kData / "ptx/no-color.ptx", future);
    EXPECT_EQ(ingest_file(s.ctx, future), IngestOutcome::quarantined);
    EXPECT_TRUE(s.db.series().epochs_in_range({}).empty());
    EXPECT_FALSE(fs::exists(future));
    std::string reason;
    for (const auto& f : fs::directory_iterator(s.config.paths.quarantine)) {
        if (f.path().string().ends_with(".reason.txt")) reason = read_file(f.path());
    }
    EXPECT_NE(reason.find("acquired 2030-01-01T00:00:00Z (from file_name)"), std::string::npos)
        << reason;
    EXPECT_NE(reason.find("ingest.max_clock_ahead = 3600 s"), std::string::npos) << reason;
    // Within the tolerance: an epoch.
    const auto soon = std::chrono::system_clock::now() + std::chrono::minutes(30);
    const std::time_t t = std::chrono::system_clock::to_time_t(soon);
    char name[64];
    std::strftime(name, sizeof name, "pier_%Y%m%dT%H%M%SZ.ptx", std::gmtime(&t));
    fs::copy_file(kData / "ptx/complex-transform.ptx", s.site.ingest() / name);
    EXPECT_EQ(ingest_file(s.ctx, s.site.ingest() / name), IngestOutcome::new_epoch);
}

// A file larger than ingest.max_file_size (a 64 GiB sparse file renamed into the folder
// gave std::bad_alloc and blocked the queue) is quarantined unread, with the reason.
TEST(PipelineFiles, FileLargerThanTheLimitIsQuarantinedUnread) {
    PipelineSite s;
    const fs::path huge = s.site.ingest() / "huge.ptx";
    { std::ofstream(huge).put('1'); }
    fs::resize_file(huge, std::uint64_t{64} << 30);  // sparse: no disk taken
    EXPECT_EQ(ingest_file(s.ctx, huge), IngestOutcome::quarantined);
    EXPECT_FALSE(fs::exists(huge));
    std::string reason;
    for (const auto& f : fs::directory_iterator(s.config.paths.quarantine)) {
        if (f.path().string().ends_with(".reason.txt")) reason = read_file(f.path());
        if (f.path().filename() == "huge.ptx") fs::remove(f.path());
    }
    EXPECT_NE(reason.find("the file is 64.00 GiB (68719476736 bytes), larger than "
                          "ingest.max_file_size = 16.00 GiB; not read"),
              std::string::npos)
        << reason;
    bool event = false;
    for (const auto& e : s.db.series().events({}, std::string("quarantine"))) {
        event = event || e.message.find("huge.ptx: the file is 64.00 GiB") != std::string::npos;
    }
    EXPECT_TRUE(event);
    EXPECT_TRUE(s.db.series().epochs_in_range({}).empty());
}

// The same for a file under a meteo sidecar's name: refused by its size, never read whole
// (in the pipeline a std::bad_alloc was taken for a database error and retried for ever).
TEST(PipelineFiles, HugeMeteoSidecarIsRejectedUnread) {
    PipelineSite s;
    const fs::path scan = s.site.ingest() / "small_20260601T060000Z.ptx";
    fs::copy_file(kData / "ptx/no-color.ptx", scan);
    ASSERT_EQ(ingest_file(s.ctx, scan), IngestOutcome::new_epoch);
    const fs::path sidecar = s.site.ingest() / "small_20260601T060000Z.meteo.csv";
    { std::ofstream(sidecar).put('#'); }
    fs::resize_file(sidecar, std::uint64_t{8} << 30);
    const Epoch epoch = s.db.epochs().pending().at(0);
    const auto m = read_epoch_meteo(sidecar, epoch, s.config.meteo);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->outcome, MeteoOutcome::rejected);
    EXPECT_NE(m->reason.find("8589934592 bytes, more than a meteo sidecar holds"),
              std::string::npos)
        << m->reason;
    EXPECT_EQ(process_epoch(s.pipeline_ctx, epoch, nullptr, sidecar), EpochOutcome::done);
    EXPECT_FALSE(fs::exists(sidecar)) << "quarantined with its reason";
    for (const auto& f : fs::directory_iterator(s.config.paths.quarantine)) {
        if (f.path().extension() == ".csv") fs::remove(f.path());
    }
}

TEST(PipelineFiles, FileRenamedWhilePendingKeepsItsEpoch) {
    PipelineSite s;
    const fs::path first = kData / "ptx/no-color.ptx";
    const fs::path second = kData / "ptx/complex-transform.ptx";
    // Renamed after ingest, and the new name taken before the epoch is processed.
    const fs::path a = s.site.ingest() / "a.ptx";
    fs::copy_file(first, a);
    ASSERT_EQ(ingest_file(s.ctx, a), IngestOutcome::new_epoch);
    fs::rename(a, s.site.ingest() / "a-renamed.ptx");
    EXPECT_EQ(ingest_file(s.ctx, s.site.ingest() / "a-renamed.ptx"), IngestOutcome::known);
    EXPECT_TRUE(fs::exists(s.site.ingest() / "a-renamed.ptx")) << "not removed as a duplicate";
    // Renamed after ingest, processed (the file is gone) before the new name is taken.
    const fs::path b = s.site.ingest() / "b.ptx";
    fs::copy_file(second, b);
    ASSERT_EQ(ingest_file(s.ctx, b), IngestOutcome::new_epoch);
    fs::rename(b, s.site.ingest() / "b-renamed.ptx");
    s.process_backlog();
    EXPECT_EQ(s.by_content(second)->status, EpochStatus::failed);
    EXPECT_EQ(ingest_file(s.ctx, s.site.ingest() / "b-renamed.ptx"), IngestOutcome::known);
    s.process_backlog();

    for (const auto& [original, points, name] :
         {std::tuple{first, 15, "a-renamed.ptx"}, std::tuple{second, 4, "b-renamed.ptx"}}) {
        const auto e = s.by_content(original);
        ASSERT_TRUE(e);
        EXPECT_EQ(e->status, EpochStatus::done) << name << ": " << e->reason;
        EXPECT_EQ(e->point_count, points) << name;
        EXPECT_EQ(e->reason, "") << name;
        EXPECT_EQ(e->archive_path, (s.config.paths.archive / name).string());
        EXPECT_EQ(read_file(s.config.paths.archive / name), read_file(original)) << name;
    }
    EXPECT_EQ(s.db.series().epochs_in_range({}).size(), 2u);
}

// An E57 of 400 points whose rowIndex/columnIndex spread them over 40 000 × 40 000 cells (a
// damaged file, 14 KB): the grid's users would hold 1.6·10⁹ cells (6.3 GB and 46 s in
// `tlsmon m3c2` before the reader refused it). The epoch fails with the reason and the file is
// quarantined; the next scan is processed.
TEST(PipelineFiles, ScanWhoseGridIsFarLargerThanItsPointsFailsAndIsQuarantined) {
    PipelineSite s;
    Scan sparse;
    sparse.grid = ScanGrid{40'000, 40'000, {}, {}};
    for (std::uint32_t r = 0; r < 20; ++r)
        for (std::uint32_t c = 0; c < 20; ++c) {
            sparse.xyz.emplace_back(10.0, 0.01 * c, 0.01 * r);
            sparse.grid->row.push_back(r * 2000);
            sparse.grid->column.push_back(c * 2000);
        }
    const fs::path file = s.site.ingest() / "sparse_20260601T060000Z.e57";
    write_e57(file, {sparse}, {.coordinate_scale = 0.0});
    const std::string sha = sha256_file(file);
    ASSERT_EQ(ingest_file(s.ctx, file), IngestOutcome::new_epoch);
    const fs::path next = s.site.ingest() / "small_20260601T061500Z.ptx";
    fs::copy_file(kData / "ptx/no-color.ptx", next);
    ASSERT_EQ(ingest_file(s.ctx, next), IngestOutcome::new_epoch);
    s.process_backlog();

    const auto failed = s.db.epochs().find_by_sha256(sha);
    ASSERT_TRUE(failed);
    EXPECT_EQ(failed->status, EpochStatus::failed);
    const std::string why =
        "rowIndex/columnIndex spread 400 points over 38001 rows and 38001 columns, more than 32 "
        "cells a point: not a scanner's grid";
    EXPECT_NE(failed->reason.find(file.string()), std::string::npos) << failed->reason;
    EXPECT_NE(failed->reason.find(why), std::string::npos) << failed->reason;
    EXPECT_FALSE(fs::exists(file));
    std::string reason_file;
    for (const auto& f : fs::directory_iterator(s.config.paths.quarantine))
        if (f.path().string().ends_with(".reason.txt")) reason_file = read_file(f.path());
    EXPECT_NE(reason_file.find(why), std::string::npos) << reason_file;
    const auto done = s.by_content(kData / "ptx/no-color.ptx");
    ASSERT_TRUE(done);
    EXPECT_EQ(done->status, EpochStatus::done) << done->reason;
}

}  // namespace
}  // namespace tlsmon::test
