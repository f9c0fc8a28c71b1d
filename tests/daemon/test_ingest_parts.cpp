// The small pieces of ingest with known answers: scan names, acquisition time from a file
// name, SHA-256 (FIPS 180-4 test vectors), free names in the archive.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <fstream>

#include "daemon/ingest_files.hpp"
#include "daemon/watcher.hpp"
#include "formats/e57_writer.hpp"
#include "pipeline/epoch_files.hpp"
#include "pipeline/sha256.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

TEST(IngestParts, ScanNames) {
    const std::vector<std::string> ext = {"ptx", "e57"};
    EXPECT_TRUE(is_scan_name("pier_20260601T061500Z.ptx", ext));
    EXPECT_TRUE(is_scan_name("SCAN.PTX", ext));
    EXPECT_TRUE(is_scan_name("a.e57", ext));
    EXPECT_FALSE(is_scan_name(".pier.ptx.part", ext));
    EXPECT_FALSE(is_scan_name(".hidden.ptx", ext));
    EXPECT_FALSE(is_scan_name("pier.ptx.part", ext));
    EXPECT_FALSE(is_scan_name("pier.ptx~", ext));
    EXPECT_FALSE(is_scan_name("pier.las", ext));
    EXPECT_FALSE(is_scan_name("pier", ext));
    EXPECT_FALSE(is_scan_name("pier.truth.json", ext));
}

TEST(IngestParts, TimeFromFileName) {
    EXPECT_EQ(time_from_file_name("small_20260601T061500Z.ptx"), 1780294500);
    EXPECT_EQ(time_from_file_name("19700101T000000Z.e57"), 0);
    EXPECT_EQ(time_from_file_name("x_20240229T235959Z_y.ptx"), 1709251199);  // leap day
    EXPECT_FALSE(time_from_file_name("x_20230229T000000Z.ptx"));             // no 29 Feb in 2023
    EXPECT_FALSE(time_from_file_name("x_20260601T256000Z.ptx"));
    EXPECT_FALSE(time_from_file_name("x_20260601T0615Z.ptx"));
    EXPECT_FALSE(time_from_file_name("scan.ptx"));
}

TEST(IngestParts, AcquisitionTimePrecedence) {
    // An E57 whose header says 2026-06-01T06:00:00.5Z, named as if taken on 2020-01-01.
    const test::TempDir d;
    const fs::path file = d / "pier_20200101T000000Z.e57";
    Scan scan;
    scan.xyz = {{1, 2, 3}, {4, 5, 6}};
    scan.acquired_utc = 1780293600.5;
    write_e57(file, {scan});
    std::string used;
    EXPECT_EQ(
        acquisition_time(file, {TimeSource::scan, TimeSource::file_name, TimeSource::mtime}, used),
        1780293600);
    EXPECT_EQ(used, "scan");
    EXPECT_EQ(acquisition_time(file, {TimeSource::file_name, TimeSource::scan}, used), 1577836800);
    EXPECT_EQ(used, "file_name");
    EXPECT_EQ(acquisition_time(file, {TimeSource::mtime}, used), *file_mtime(file));
    EXPECT_EQ(used, "mtime");
    // A PTX has no header time: "scan" is skipped.
    const fs::path ptx = d / "pier_20260601T061500Z.ptx";
    fs::copy_file(fs::path(TLSMON_DATA_DIR) / "ptx/no-color.ptx", ptx);
    EXPECT_EQ(acquisition_time(ptx, {TimeSource::scan, TimeSource::file_name}, used), 1780294500);
    EXPECT_EQ(used, "file_name");
}

TEST(IngestParts, Sha256KnownAnswers) {
    // FIPS 180-4 examples ("abc" and the empty message).
    EXPECT_EQ(sha256_text("abc"),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256_text(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    const test::TempDir d;
    const fs::path f = d / "a";
    // Larger than the 1 MiB read buffer: the file is read in two parts and must give the
    // digest of the same bytes in memory.
    test::write_file(f, std::string(2000000, 'a'));
    EXPECT_EQ(sha256_file(f), sha256_text(std::string(2000000, 'a')));
    test::write_file(f, std::string(1000000, 'a'));
    EXPECT_EQ(sha256_file(f), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    fs::remove(f);
    EXPECT_THROW(sha256_file(f), FileAccessError);
}

TEST(IngestParts, FreeNameNeverOverwrites) {
    const test::TempDir dir;
    const fs::path& d = dir.path();
    EXPECT_EQ(free_name(d, "a.ptx", "0123"), d / "a.ptx");
    test::write_file(d / "a.ptx", "1");
    EXPECT_EQ(free_name(d, "a.ptx", "0123"), d / "a.0123.ptx");
    test::write_file(d / "a.0123.ptx", "2");
    EXPECT_EQ(free_name(d, "a.ptx", "0123"), d / "a.0123-2.ptx");
}

// A file whose close event was lost when the inotify queue overflowed is complete once its
// size and mtime are stable, as a file found by a scan.
TEST(IngestParts, WatcherAfterQueueOverflowTakesAFileWhoseCloseWasLost) {
    const test::TempDir d;
    IngestConfig config;
    config.stable_seconds = 0;
    FolderWatcher watcher(d.path(), config);
    const auto now = std::chrono::steady_clock::now();
    std::vector<GrowingFile> growing;
    {
        std::ofstream scan(d / "scan.ptx");
        scan << "written" << std::flush;
        watcher.read_events(now);  // IN_CREATE, IN_MODIFY: being written
        EXPECT_TRUE(watcher.take_complete(now, growing).empty());
        // More events than the queue holds (fs.inotify.max_queued_events, 16384 by
        // default), alternating between two files so that they are not merged.
        std::ifstream limit("/proc/sys/fs/inotify/max_queued_events");
        int max_events = 16384;
        limit >> max_events;
        std::ofstream a(d / "a.txt"), b(d / "b.txt");
        for (int i = 0; i < max_events; ++i) {
            a << 'x' << std::flush;
            b << 'x' << std::flush;
        }
    }  // the close of scan.ptx is lost
    watcher.read_events(now);
    const auto complete = watcher.take_complete(now + std::chrono::seconds(1), growing);
    ASSERT_EQ(complete.size(), 1u);
    EXPECT_EQ(complete[0], d / "scan.ptx");
}

std::vector<fs::path> paths_of(const std::vector<NotAFile>& entries) {
    std::vector<fs::path> paths;
    for (const auto& e : entries) paths.push_back(e.path);
    std::sort(paths.begin(), paths.end());
    return paths;
}

// A symbolic link is never a candidate (never polled, never handed out); it is reported
// once, and again only when the link is replaced.
TEST(IngestParts, WatcherReportsSymlinksOnceAndNeverTracksThem) {
    const test::TempDir d;
    test::write_file(d / "target.ptx.bak", "bytes outside the scan names");
    IngestConfig config;
    config.stable_seconds = 0;
    FolderWatcher watcher(d.path(), config);
    fs::create_symlink(d / "target.ptx.bak", d / "link.ptx");
    fs::create_symlink("/etc", d / "etc.ptx");
    const auto now = std::chrono::steady_clock::now();
    watcher.read_events(now);  // IN_CREATE of both links
    watcher.rescan(now);
    std::vector<GrowingFile> growing;
    EXPECT_TRUE(watcher.take_complete(now + std::chrono::seconds(1), growing).empty());
    EXPECT_FALSE(watcher.has_candidates());
    EXPECT_EQ(watcher.until_next_check(now), std::chrono::hours(1));
    EXPECT_EQ(paths_of(watcher.take_not_files()),
              (std::vector<fs::path>{d / "etc.ptx", d / "link.ptx"}));
    watcher.rescan(now + std::chrono::seconds(2));
    EXPECT_TRUE(watcher.take_not_files().empty()) << "reported once";
    fs::remove(d / "link.ptx");
    fs::create_symlink("/etc/passwd", d / "link.ptx");
    watcher.read_events(now + std::chrono::seconds(3));
    watcher.rescan(now + std::chrono::seconds(3));
    const auto again = watcher.take_not_files();
    ASSERT_EQ(again.size(), 1u);
    EXPECT_EQ(again[0].path, d / "link.ptx");
    EXPECT_EQ(again[0].kind, "symbolic link");
}

// A FIFO or a folder with a scan's name was ignored without a word: each is reported once,
// by what it is, and never tracked (reading a FIFO would block the daemon).
TEST(IngestParts, WatcherReportsFifosAndFoldersOnceAndNeverTracksThem) {
    const test::TempDir d;
    IngestConfig config;
    config.stable_seconds = 0;
    FolderWatcher watcher(d.path(), config);
    ASSERT_EQ(::mkfifo((d / "pipe.ptx").c_str(), 0600), 0);
    fs::create_directory(d / "folder.ptx");
    const auto now = std::chrono::steady_clock::now();
    watcher.read_events(now);
    watcher.rescan(now);
    std::vector<GrowingFile> growing;
    EXPECT_TRUE(watcher.take_complete(now + std::chrono::seconds(1), growing).empty());
    EXPECT_FALSE(watcher.has_candidates());
    auto entries = watcher.take_not_files();
    std::sort(entries.begin(), entries.end(),
              [](const NotAFile& a, const NotAFile& b) { return a.path < b.path; });
    ASSERT_EQ(entries.size(), 2u);
    EXPECT_EQ(entries[0].path, d / "folder.ptx");
    EXPECT_EQ(entries[0].kind, "folder");
    EXPECT_EQ(entries[1].path, d / "pipe.ptx");
    EXPECT_EQ(entries[1].kind, "FIFO (named pipe)");
    watcher.rescan(now + std::chrono::seconds(2));
    EXPECT_TRUE(watcher.take_not_files().empty()) << "reported once";
}

// Files are opened without following a symbolic link: the hash never reads the target.
TEST(IngestParts, Sha256NeverFollowsASymlink) {
    const test::TempDir d;
    test::write_file(d / "target", "secret");
    fs::create_symlink(d / "target", d / "link.ptx");
    try {
        sha256_file(d / "link.ptx");
        FAIL() << "a symbolic link was followed";
    } catch (const FileAccessError& e) {
        EXPECT_EQ(e.error_number(), ELOOP);
    }
    EXPECT_THROW(read_file_hashed(d / "link.ptx"), FileAccessError);
}

// A file some process still has open for writing is not complete, however long its size
// stays the same (found by a folder scan, e.g. after a restart, no close event comes first).
TEST(IngestParts, WatcherWaitsForAFileOpenForWriting) {
    const test::TempDir d;
    IngestConfig config;
    config.stable_seconds = 0.5;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<GrowingFile> growing;
    std::ofstream out(d / "scan.ptx");
    out << "half a scan" << std::flush;
    EXPECT_TRUE(held_open_for_writing(d / "scan.ptx"));
    EXPECT_TRUE(held_open_for_writing_by_proc(d / "scan.ptx"));
    FolderWatcher watcher(d.path(), config);
    watcher.rescan(t0);
    EXPECT_TRUE(watcher.take_complete(t0 + std::chrono::seconds(1), growing).empty());
    EXPECT_TRUE(watcher.take_complete(t0 + std::chrono::seconds(5), growing).empty());
    out.close();
    EXPECT_FALSE(held_open_for_writing(d / "scan.ptx"));
    EXPECT_FALSE(held_open_for_writing_by_proc(d / "scan.ptx"));
    // A reader is no writer.
    std::ifstream reader(d / "scan.ptx");
    EXPECT_FALSE(held_open_for_writing_by_proc(d / "scan.ptx"));
    watcher.read_events(t0 + std::chrono::seconds(5));  // the close
    const auto complete = watcher.take_complete(t0 + std::chrono::seconds(10), growing);
    ASSERT_EQ(complete.size(), 1u);
    EXPECT_EQ(complete[0], d / "scan.ptx");
}

}  // namespace
}  // namespace tlsmon
