// `tlsmon run` end to end: the real binary on real and simulated scans, checked in the
// SQLite epoch database it writes.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include "tests/support/daemon_harness.hpp"

namespace tlsmon::test {
namespace {

const fs::path kData = TLSMON_DATA_DIR;

std::vector<Epoch> all_epochs(const Site& site) {
    return site.open_db().series().epochs_in_range({});  // by acquisition time
}

const Epoch* by_name(const std::vector<Epoch>& epochs, const std::string& name) {
    for (const auto& e : epochs) {
        if (fs::path(e.file_path).filename() == name) return &e;
    }
    return nullptr;
}

bool has_event(const Site& site, const std::string& kind, const std::string& text) {
    if (!fs::exists(site.database())) return false;  // the daemon has not created it yet
    for (const auto& e : site.open_db().series().events({})) {
        if (e.kind == kind && e.message.find(text) != std::string::npos) return true;
    }
    return false;
}

TEST(DaemonIngest, OnceTakesFilesInAcquisitionOrderOnceEach) {
    Site site("once");
    const fs::path in = site.ingest();
    fs::copy_file(kData / "ptx/no-color.ptx", in / "small_20260601T061500Z.ptx");
    fs::copy_file(kData / "ptx/complex-transform.ptx", in / "small_20260601T060000Z.ptx");
    fs::copy_file(kData / "ptx/no-color.ptx", in / "copy-of-first.ptx");  // same bytes
    {  // a truncated real scan: the reader's error names file and line
        std::string text = read_file(kData / "ptx/pumpA_from_e57.ptx");
        std::ofstream(in / "small_20260601T063000Z.ptx") << text.substr(0, text.size() / 2);
    }
    std::ofstream(in / "small_20260601T064500Z.ptx").flush();  // empty
    std::ofstream(in / ".small_20260601T070000Z.ptx.part") << "partial";
    std::ofstream(in / "notes.txt.bak") << "not a scan";

    DaemonProcess daemon(site.config(), site.log(), /*once=*/true);
    ASSERT_EQ(daemon.wait(60), 0) << read_file(site.log());

    const auto epochs = all_epochs(site);
    ASSERT_EQ(epochs.size(), 4u) << read_file(site.log());
    // The same bytes under two names are one epoch, under the name with the time stamp.
    const std::string e1_name = "small_20260601T061500Z.ptx";
    const Epoch* e1 = by_name(epochs, e1_name);
    const Epoch* e0 = by_name(epochs, "small_20260601T060000Z.ptx");
    const Epoch* bad = by_name(epochs, "small_20260601T063000Z.ptx");
    const Epoch* empty = by_name(epochs, "small_20260601T064500Z.ptx");
    ASSERT_TRUE(e0 && e1 && bad && empty) << read_file(site.log());
    EXPECT_EQ(e0->acquired, 1780293600);  // 2026-06-01T06:00:00Z from the file name
    EXPECT_EQ(e0->status, EpochStatus::done);
    EXPECT_EQ(e0->point_count, 4);  // INVENTORY: 4 valid points of 12 cells
    EXPECT_EQ(e1->status, EpochStatus::done);
    EXPECT_EQ(e1->point_count, 15);  // INVENTORY: no-color.ptx, 15 points
    EXPECT_EQ(bad->status, EpochStatus::failed);
    EXPECT_NE(bad->reason.find("small_20260601T063000Z.ptx:"), std::string::npos) << bad->reason;
    EXPECT_EQ(empty->status, EpochStatus::failed);
    EXPECT_NE(empty->reason.find("empty"), std::string::npos) << empty->reason;
    ASSERT_TRUE(site.open_db().epochs().reference());
    EXPECT_EQ(*site.open_db().epochs().reference(), e0->id);
    // Processed in acquisition order: the log's "epoch N done/failed" lines, mapped to the
    // epochs' acquisition times, never go back in time.
    std::vector<std::int64_t> order;
    std::istringstream log(read_file(site.log()));
    for (std::string line; std::getline(log, line);) {
        const auto at = line.find(" epoch ");
        if (at == std::string::npos) continue;
        std::istringstream words(line.substr(at + 7));
        EpochId id = 0;
        std::string what;
        if (!(words >> id >> what) || (what != "done:" && what != "failed:")) continue;
        for (const auto& e : epochs) {
            if (e.id == id) order.push_back(e.acquired);
        }
    }
    ASSERT_EQ(order.size(), 4u) << read_file(site.log());
    EXPECT_TRUE(std::is_sorted(order.begin(), order.end()));

    // Files: done -> archive, failed -> quarantine with the reason, duplicate removed,
    // temporary and foreign names untouched.
    EXPECT_TRUE(fs::exists(site.root / "archive/small_20260601T060000Z.ptx"));
    EXPECT_TRUE(fs::exists(site.root / "archive" / e1_name));
    EXPECT_FALSE(fs::exists(in / "copy-of-first.ptx"));
    EXPECT_FALSE(fs::exists(in / "small_20260601T061500Z.ptx"));
    EXPECT_EQ(e1->archive_path, (site.root / "archive" / e1_name).string());
    const fs::path reason = site.root / "quarantine/small_20260601T063000Z.ptx.reason.txt";
    ASSERT_TRUE(fs::exists(reason));
    EXPECT_NE(read_file(reason).find(bad->reason), std::string::npos);
    EXPECT_TRUE(fs::exists(in / ".small_20260601T070000Z.ptx.part"));
    EXPECT_TRUE(fs::exists(in / "notes.txt.bak"));
    EXPECT_TRUE(has_event(site, "epoch_failed", "small_20260601T064500Z.ptx"));

    // A second run over the archive's copies is idempotent: no new epochs.
    fs::copy_file(site.root / "archive/small_20260601T060000Z.ptx", in / "again.ptx");
    DaemonProcess again(site.config(), site.log(), true);
    ASSERT_EQ(again.wait(60), 0);
    EXPECT_EQ(all_epochs(site).size(), 4u);
    EXPECT_FALSE(fs::exists(in / "again.ptx"));
}

TEST(DaemonIngest, LiveSimulatorRealtimeSlowCopyDuplicateAndQueries) {
    Site site("live");
    DaemonProcess daemon(site.config(), site.log());
    // Migrated, not only created: a reader refuses a database still at schema version 0.
    ASSERT_TRUE(wait_until([&] { return has_event(site, "start", "tlsmon started"); }, 10));
    const std::string sim =
        std::string(TLSMON_BINARY) + " simulate --preset small --out " + site.ingest().string();
    // Three scans appearing complete (temporary name, then rename) every 0.7 s, and
    // meanwhile `tlsmon query` reading the database the daemon writes.
    std::atomic<bool> querying{true};
    std::atomic<int> queries{0}, query_failures{0};
    std::string failure;
    std::thread reader_thread([&] {
        while (querying) {
            const auto r = shell(std::string(TLSMON_BINARY) + " query epochs --db " +
                                 site.database().string() + " --format csv");
            ++queries;
            if (r.status != 0) {
                ++query_failures;
                failure = r.output;
            }
        }
    });
    struct Join {
        std::atomic<bool>& flag;
        std::thread& thread;
        ~Join() {
            flag = false;
            if (thread.joinable()) thread.join();
        }
    } join{querying, reader_thread};
    auto r = shell(sim + " --epochs 3 --realtime 0.7");
    ASSERT_EQ(r.status, 0) << r.output;
    // Two more written slowly under their final name (1.5 s each, chunks 75 ms apart while
    // stable_seconds is 0.3 s: only the close tells the file is complete); another noise
    // seed, so that their bytes differ from the first three.
    r = shell(sim + " --epochs 2 --slow-copy 1.5 --seed 99 --start 2026-06-01T06:45:00Z");
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_TRUE(wait_until(
        [&] {
            const auto s = site.open_db().series().status_summary();
            return s.epochs_by_status.at(EpochStatus::done) == 5;
        },
        30))
        << read_file(site.log());
    // The same scan copied in again is no new epoch.
    fs::copy_file(site.root / "archive/small_20260601T061500Z.ptx", site.ingest() / "dup.ptx");
    ASSERT_TRUE(wait_until([&] { return !fs::exists(site.ingest() / "dup.ptx"); }, 10));
    querying = false;
    reader_thread.join();

    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(5), 0) << "SIGTERM must stop the daemon within 5 s";

    const auto epochs = all_epochs(site);
    ASSERT_EQ(epochs.size(), 5u);
    for (std::size_t i = 0; i < epochs.size(); ++i) {
        EXPECT_EQ(epochs[i].status, EpochStatus::done);
        EXPECT_EQ(epochs[i].acquired, 1780293600 + 900 * static_cast<std::int64_t>(i));
        EXPECT_GT(epochs[i].point_count.value_or(0), 80000);
        if (i) {
            EXPECT_GT(epochs[i].id, epochs[i - 1].id);  // taken in acquisition order
        }
    }
    EXPECT_EQ(site.open_db().epochs().reference(), epochs.front().id);
    EXPECT_TRUE(has_event(site, "stop", "5 epoch(s) done"));
    EXPECT_NE(read_file(site.log()).find("dup.ptx: same content as epoch"), std::string::npos);
    EXPECT_GT(queries.load(), 3);
    EXPECT_EQ(query_failures.load(), 0) << failure;
}

TEST(DaemonIngest, GrowingAndUnreadableFilesAreRecorded) {
    Site site("bad", "", "max_growing = \"1s\"\n");
    // Root reads every file: run the daemon as `nobody` so the permission is real.
    const bool root = ::getuid() == 0;
    const uid_t nobody = 65534;
    if (root) {
        ASSERT_EQ(shell("chown -R 65534:65534 " + site.root.string()).status, 0);
    }
    const fs::path locked = site.ingest() / "small_20260601T060000Z.ptx";
    fs::copy_file(kData / "ptx/no-color.ptx", locked);
    ::chmod(locked.c_str(), 0);
    if (root) {
        ASSERT_EQ(::chown(locked.c_str(), 0, 0), 0);
    }

    DaemonProcess daemon(site.config(), site.log(), false,
                         root ? std::optional<uid_t>(nobody) : std::nullopt);
    ASSERT_TRUE(wait_until([&] { return has_event(site, "start", "tlsmon started"); }, 20))
        << read_file(site.log());
    // A file that keeps growing for 3 s (appended every 100 ms, kept open); max_growing is
    // 1 s, so it is reported while it still grows.
    const fs::path growing = site.ingest() / "small_20260601T061500Z.ptx";
    {
        std::ofstream out(growing);
        for (int i = 0; i < 30; ++i) {
            out << "0 0 0 0.5\n" << std::flush;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            if (i == 25) {
                EXPECT_TRUE(has_event(site, "file_growing", growing.filename().string()))
                    << read_file(site.log());
                EXPECT_FALSE(by_name(all_epochs(site), growing.filename().string()))
                    << "a growing file must not become an epoch";
            }
        }
    }
    ASSERT_TRUE(
        wait_until([&] { return site.open_db().series().epochs_in_range({}).size() == 2; }, 10))
        << read_file(site.log());
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(5), 0);

    const auto epochs = all_epochs(site);
    const Epoch* unreadable = by_name(epochs, locked.filename().string());
    ASSERT_TRUE(unreadable);
    EXPECT_EQ(unreadable->status, EpochStatus::failed);
    EXPECT_NE(unreadable->reason.find("Permission denied"), std::string::npos)
        << unreadable->reason;
    EXPECT_TRUE(has_event(site, "unreadable", locked.filename().string()));
    const Epoch* grown = by_name(epochs, growing.filename().string());
    ASSERT_TRUE(grown);
    EXPECT_EQ(grown->status, EpochStatus::failed);  // its content is no PTX header
    int growing_events = 0;
    for (const auto& e : site.open_db().series().events({}, std::string("file_growing"))) {
        growing_events += e.message.find(growing.filename().string()) != std::string::npos;
    }
    EXPECT_EQ(growing_events, 1) << "reported once";
}

TEST(DaemonIngest, SighupReloadsAndKeepsOldConfigWhenInvalid) {
    Site site("reload");
    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until([&] { return has_event(site, "start", "tlsmon started"); }, 10));
    const std::string good = read_file(site.config());
    std::ofstream(site.config()) << good << "[logging]\nlevel = \"loud\"\n";
    daemon.signal(SIGHUP);
    ASSERT_TRUE(wait_until([&] { return has_event(site, "config_reload", "reload failed"); }, 10))
        << read_file(site.log());
    EXPECT_TRUE(has_event(site, "config_reload", "key 'logging.level'"));
    EXPECT_TRUE(daemon.running());
    std::ofstream(site.config()) << good << "[logging]\nlevel = \"debug\"\n";
    daemon.signal(SIGHUP);
    ASSERT_TRUE(
        wait_until([&] { return has_event(site, "config_reload", "configuration reloaded"); }, 10));
    fs::copy_file(kData / "ptx/no-color.ptx", site.ingest() / "after-reload.ptx");
    ASSERT_TRUE(wait_until(
        [&] {
            const auto e = all_epochs(site);
            return e.size() == 1 && e[0].status == EpochStatus::done;
        },
        10))
        << read_file(site.log());
    daemon.signal(SIGINT);
    EXPECT_EQ(daemon.wait(5), 0);
}

// An empty file on SIGHUP was accepted and silently dropped every zone, rule and target.
// A reload that removes some says so, one event each; one that removes every one of a
// kind is refused (a restart applies it on purpose).
TEST(DaemonIngest, SighupThatRemovesZonesSaysSoAndAnEmptyFileIsRefused) {
    const std::string zones =
        "[[zone]]\nname = \"pier\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
        "[[zone]]\nname = \"deck\"\nmin = [0, 0, 2]\nmax = [1, 1, 3]\n";
    Site site("reloadzones", zones);
    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until([&] { return has_event(site, "start", "tlsmon started"); }, 10));
    const std::string full = read_file(site.config());
    std::ofstream(site.config()) << "";
    daemon.signal(SIGHUP);
    ASSERT_TRUE(wait_until([&] { return has_event(site, "config_reload", "reload refused"); }, 10))
        << read_file(site.log());
    EXPECT_TRUE(has_event(site, "config_reload",
                          "it has no [[zone]] table, and the running "
                          "configuration has 2"));
    EXPECT_TRUE(has_event(site, "config_reload", "restart tlsmon to apply"));
    EXPECT_FALSE(has_event(site, "config_reload", "configuration reloaded"));
    // One zone fewer: applied, and said.
    std::string one = full;
    one.erase(one.find("[[zone]]\nname = \"deck\""));
    std::ofstream(site.config()) << one << "\n[meteo]\nwait_seconds = 0\n";
    daemon.signal(SIGHUP);
    ASSERT_TRUE(
        wait_until([&] { return has_event(site, "config_reload", "configuration reloaded"); }, 10))
        << read_file(site.log());
    EXPECT_TRUE(has_event(site, "config_reload", "reload removes zone 'deck'"));
    EXPECT_FALSE(has_event(site, "config_reload", "reload removes zone 'pier'"));
    EXPECT_TRUE(daemon.running());
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(5), 0);
}

TEST(DaemonIngest, SighupToNewArchiveAndQuarantineFoldersCreatesThem) {
    Site site("newfolders");
    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until([&] { return has_event(site, "start", "tlsmon started"); }, 10));
    std::string text = read_file(site.config());
    text.replace(text.find("archive = \"archive\""), 19, "archive = \"new/archive\"");
    text.replace(text.find("quarantine = \"quarantine\""), 25, "quarantine = \"new/quar\"");
    std::ofstream(site.config()) << text;
    daemon.signal(SIGHUP);
    ASSERT_TRUE(
        wait_until([&] { return has_event(site, "config_reload", "configuration reloaded"); }, 10))
        << read_file(site.log());
    fs::copy_file(kData / "ptx/no-color.ptx", site.ingest() / "good.ptx");
    std::ofstream(site.ingest() / "empty.ptx").flush();
    ASSERT_TRUE(wait_until([&] { return all_epochs(site).size() == 2; }, 10))
        << read_file(site.log());
    // Each epoch's row is written before its file moves (pipeline/epoch_pipeline.cpp): wait
    // for both moves, not only the first, or a loaded machine sees the second one pending.
    ASSERT_TRUE(wait_until(
        [&] {
            return !fs::exists(site.ingest() / "good.ptx") &&
                   !fs::exists(site.ingest() / "empty.ptx");
        },
        10))
        << read_file(site.log());
    EXPECT_EQ(read_file(site.root / "new/archive/good.ptx"), read_file(kData / "ptx/no-color.ptx"));
    EXPECT_TRUE(fs::exists(site.root / "new/quar/empty.ptx"));
    EXPECT_TRUE(fs::exists(site.root / "new/quar/empty.ptx.reason.txt"));
    EXPECT_FALSE(fs::exists(site.ingest() / "empty.ptx"));
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(5), 0);
}

TEST(DaemonIngest, IngestFolderDeletedAndCreatedAgainIsWatchedAgain) {
    Site site("recreated");
    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until([&] { return has_event(site, "start", "tlsmon started"); }, 10));
    fs::remove_all(site.ingest());
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    fs::create_directories(site.ingest());
    std::this_thread::sleep_for(std::chrono::seconds(2));  // a rescan (every 1 s) in between
    // Written slowly, pausing longer than stable_seconds (0.3 s) while the file is open:
    // only inotify tells that it is still being written.
    const std::string text = read_file(kData / "ptx/no-color.ptx");
    {
        std::ofstream out(site.ingest() / "slow.ptx");
        const std::size_t chunk = text.size() / 4 + 1;
        for (std::size_t at = 0; at < text.size(); at += chunk) {
            out << text.substr(at, chunk) << std::flush;
            std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        }
    }
    ASSERT_TRUE(wait_until(
        [&] {
            const auto e = all_epochs(site);
            return !e.empty() && e.back().status != EpochStatus::pending &&
                   e.back().status != EpochStatus::processing;
        },
        10))
        << read_file(site.log());
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(5), 0);
    const auto epochs = all_epochs(site);
    ASSERT_EQ(epochs.size(), 1u) << read_file(site.log());
    EXPECT_EQ(epochs[0].status, EpochStatus::done) << epochs[0].reason;
    EXPECT_EQ(epochs[0].point_count, 15);
}

TEST(DaemonIngest, ConfiguredReferenceEpochWinsOverTheFirst) {
    Site site("reference", "", "reference_epoch = \"small_20260601T061500Z.ptx\"\n");
    fs::copy_file(kData / "ptx/complex-transform.ptx",
                  site.ingest() / "small_20260601T060000Z.ptx");
    fs::copy_file(kData / "ptx/no-color.ptx", site.ingest() / "small_20260601T061500Z.ptx");
    DaemonProcess once(site.config(), site.log(), true);
    ASSERT_EQ(once.wait(60), 0) << read_file(site.log());
    const auto epochs = all_epochs(site);
    const Epoch* named = by_name(epochs, "small_20260601T061500Z.ptx");
    ASSERT_TRUE(named);
    EXPECT_EQ(site.open_db().epochs().reference(), named->id);
}

int count_events(const Site& site, const std::string& kind, const std::string& text) {
    int n = 0;
    for (const auto& e : site.open_db().series().events({}, kind)) {
        n += e.message.find(text) != std::string::npos;
    }
    return n;
}

std::string truncated_ptx() {
    const std::string text = read_file(kData / "ptx/pumpA_from_e57.ptx");
    return text.substr(0, text.size() / 2);
}

// A symbolic link in the ingest folder is never followed nor read, whether it was there
// before the start or appears while the daemon runs: it is reported once (a `symlink`
// system event per link) and left where it is.
TEST(DaemonIngest, SymlinksAreNeverFollowedAndReportedOnce) {
    Site site("symlinks");
    const fs::path in = site.ingest();
    const fs::path outside = site.root / "outside.ptx";  // a valid scan outside the folder
    fs::copy_file(kData / "ptx/no-color.ptx", outside);
    fs::create_symlink(outside, in / "small_20260601T060000Z.ptx");  // there before the start
    fs::create_symlink("/etc", in / "etc.ptx");                      // a folder
    fs::create_symlink(site.root / "missing.ptx", in / "dangling.ptx");
    // Neither a link nor a file: a FIFO (reading it would block) and a folder.
    ASSERT_EQ(::mkfifo((in / "pipe_20260601T060000Z.ptx").c_str(), 0600), 0);
    fs::create_directory(in / "folder.ptx");

    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until([&] { return has_event(site, "start", "tlsmon started"); }, 20))
        << read_file(site.log());
    fs::create_symlink(outside, in / "small_20260601T061500Z.ptx");  // while running
    fs::copy_file(kData / "ptx/complex-transform.ptx", in / "real.ptx");
    ASSERT_TRUE(wait_until(
        [&] {
            const auto e = all_epochs(site);
            const Epoch* real = by_name(e, "real.ptx");
            return real && real->status == EpochStatus::done;
        },
        30))
        << read_file(site.log());
    ASSERT_TRUE(
        wait_until([&] { return has_event(site, "symlink", "small_20260601T061500Z.ptx"); }, 10))
        << read_file(site.log());
    // Several rescans (every 1 s) later: still reported once, never taken.
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(10), 0);

    const auto epochs = all_epochs(site);
    EXPECT_EQ(epochs.size(), 1u) << read_file(site.log());
    for (const char* link :
         {"small_20260601T060000Z.ptx", "etc.ptx", "dangling.ptx", "small_20260601T061500Z.ptx"}) {
        EXPECT_TRUE(fs::is_symlink(fs::symlink_status(in / link))) << link << " left in place";
        EXPECT_EQ(count_events(site, "symlink", (in / link).string()), 1) << link;
    }
    EXPECT_EQ(read_file(outside), read_file(kData / "ptx/no-color.ptx"));
    EXPECT_EQ(count_events(site, "not_a_file",
                           (in / "pipe_20260601T060000Z.ptx").string() + " is a FIFO (named pipe)"),
              1);
    EXPECT_EQ(count_events(site, "not_a_file", (in / "folder.ptx").string() + " is a folder"), 1);
    EXPECT_TRUE(fs::is_fifo(in / "pipe_20260601T060000Z.ptx"));
    EXPECT_FALSE(fs::exists(site.root / "quarantine/small_20260601T060000Z.ptx.reason.txt"));
    EXPECT_TRUE(!fs::exists(site.root / "quarantine") || fs::is_empty(site.root / "quarantine"));
}

// The daemon (re)starts while a writer holds a half-written scan open and pauses longer
// than stable_seconds: the file is waited for, and taken whole once the writer closes it.
TEST(DaemonIngest, StartWhileAWriterHoldsTheFileOpenWaitsForIt) {
    Site site("openwriter");
    const std::string text = read_file(kData / "ptx/no-color.ptx");
    const fs::path file = site.ingest() / "small_20260601T060000Z.ptx";
    // The writer's descriptor is close-on-exec: the daemon started below must not inherit it.
    const int out = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    ASSERT_GE(out, 0);
    const auto write_part = [&](const std::string& part) {
        ASSERT_EQ(::write(out, part.data(), part.size()), static_cast<ssize_t>(part.size()));
    };
    write_part(text.substr(0, text.size() / 2));
    fs::copy_file(kData / "ptx/complex-transform.ptx",
                  site.ingest() / "small_20260601T054500Z.ptx");

    DaemonProcess daemon(site.config(), site.log());
    // The other scan found by the same first folder scan is taken: so was the open file,
    // had it been judged by its stable size alone.
    ASSERT_TRUE(wait_until(
        [&] {
            const Epoch* other = by_name(all_epochs(site), "small_20260601T054500Z.ptx");
            return other && other->status == EpochStatus::done;
        },
        30))
        << read_file(site.log());
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // 5 x stable_seconds
    EXPECT_FALSE(by_name(all_epochs(site), file.filename().string()))
        << "a file open for writing must not become an epoch\n"
        << read_file(site.log());
    EXPECT_TRUE(fs::exists(file));

    write_part(text.substr(text.size() / 2));
    ::close(out);
    ASSERT_TRUE(wait_until(
        [&] {
            const Epoch* e = by_name(all_epochs(site), file.filename().string());
            return e && e->status != EpochStatus::pending && e->status != EpochStatus::processing;
        },
        30))
        << read_file(site.log());
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(10), 0);
    const Epoch* e = by_name(all_epochs(site), file.filename().string());
    ASSERT_TRUE(e);
    EXPECT_EQ(e->status, EpochStatus::done) << e->reason;
    EXPECT_EQ(e->point_count, 15);
    EXPECT_EQ(all_epochs(site).size(), 2u);
    EXPECT_TRUE(fs::exists(site.root / "archive" / file.filename()));
}

// Empty files all have the same sha256, as have copies of one broken file: none of them is
// a duplicate to delete; each is quarantined with its reason.
TEST(DaemonIngest, EmptyAndBrokenCopiesAreQuarantinedNotRemovedAsDuplicates) {
    Site site("emptycopies");
    const fs::path in = site.ingest();
    for (const char* name : {"a.ptx", "b.ptx", "c.ptx"}) std::ofstream(in / name).flush();
    std::ofstream(in / "broken1.ptx") << truncated_ptx();
    std::ofstream(in / "broken2.ptx") << truncated_ptx();
    DaemonProcess daemon(site.config(), site.log(), /*once=*/true);
    ASSERT_EQ(daemon.wait(60), 0) << read_file(site.log());

    const fs::path q = site.root / "quarantine";
    for (const char* name : {"a.ptx", "b.ptx", "c.ptx"}) {
        EXPECT_FALSE(fs::exists(in / name)) << name;
        ASSERT_TRUE(fs::exists(q / name)) << name << "\n" << read_file(site.log());
        EXPECT_NE(read_file(q / (std::string(name) + ".reason.txt")).find("empty"),
                  std::string::npos)
            << name;
    }
    for (const char* name : {"broken1.ptx", "broken2.ptx"}) {
        EXPECT_FALSE(fs::exists(in / name)) << name;
        ASSERT_TRUE(fs::exists(q / name)) << name << "\n" << read_file(site.log());
        EXPECT_NE(read_file(q / (std::string(name) + ".reason.txt")).find("broken1.ptx:"),
                  std::string::npos)
            << name << ": the reason of the first copy's epoch";
    }
    EXPECT_EQ(all_epochs(site).size(), 2u);  // one per content
    EXPECT_EQ(count_events(site, "quarantine", (in / "b.ptx").string()), 1);
    EXPECT_EQ(count_events(site, "quarantine", (in / "broken2.ptx").string()), 1);
}

// Two copies of one scan arriving together: the copy whose name carries the time stamp
// becomes the epoch (its acquisition time from the name, not mtime), the other is removed
// and named in the `duplicate` system event.
TEST(DaemonIngest, DuplicateCopiesArrivingTogetherKeepTheTimeStampedName) {
    Site site("dupstamp");
    const fs::path in = site.ingest();
    fs::copy_file(kData / "ptx/no-color.ptx", in / "a-copy.ptx");  // first alphabetically
    fs::copy_file(kData / "ptx/no-color.ptx", in / "small_20260601T061500Z.ptx");
    const auto old = fs::file_time_type::clock::now() - std::chrono::hours(24 * 144);
    fs::last_write_time(in / "a-copy.ptx", old);
    fs::last_write_time(in / "small_20260601T061500Z.ptx", old);
    DaemonProcess daemon(site.config(), site.log(), /*once=*/true);
    ASSERT_EQ(daemon.wait(60), 0) << read_file(site.log());

    const auto epochs = all_epochs(site);
    ASSERT_EQ(epochs.size(), 1u);
    EXPECT_EQ(fs::path(epochs[0].file_path).filename(), "small_20260601T061500Z.ptx");
    EXPECT_EQ(epochs[0].acquired, 1780294500);
    EXPECT_EQ(epochs[0].status, EpochStatus::done);
    EXPECT_TRUE(fs::exists(site.root / "archive/small_20260601T061500Z.ptx"));
    EXPECT_FALSE(fs::exists(in / "a-copy.ptx"));
    EXPECT_EQ(count_events(site, "duplicate", (in / "a-copy.ptx").string()), 1)
        << read_file(site.log());
}

// Removing a second copy of a known scan is recorded as a system event naming the file
// and the epoch.
TEST(DaemonIngest, RemovedDuplicateIsASystemEvent) {
    Site site("dupevent");
    fs::copy_file(kData / "ptx/no-color.ptx", site.ingest() / "small_20260601T060000Z.ptx");
    DaemonProcess first(site.config(), site.log(), /*once=*/true);
    ASSERT_EQ(first.wait(60), 0) << read_file(site.log());
    ASSERT_EQ(all_epochs(site).size(), 1u);
    const EpochId id = all_epochs(site)[0].id;
    fs::copy_file(site.root / "archive/small_20260601T060000Z.ptx", site.ingest() / "again.ptx");
    DaemonProcess second(site.config(), site.log(), /*once=*/true);
    ASSERT_EQ(second.wait(60), 0) << read_file(site.log());
    EXPECT_FALSE(fs::exists(site.ingest() / "again.ptx"));
    bool found = false;
    for (const auto& e : site.open_db().series().events({}, std::string("duplicate"))) {
        if (e.message.find((site.ingest() / "again.ptx").string()) == std::string::npos) continue;
        found = true;
        EXPECT_EQ(e.epoch, id);
        EXPECT_NE(e.message.find("epoch " + std::to_string(id)), std::string::npos) << e.message;
    }
    EXPECT_TRUE(found) << read_file(site.log());
}

// A file name with a newline and other control characters cannot forge a log record or a
// line of a reason file: they are escaped (\n, \r, \t, \xNN).
TEST(DaemonIngest, ControlCharactersInFileNamesAreEscapedInLogsAndReasonFiles) {
    TempDir logs("escapelog");
    const fs::path log_file = logs / "tlsmon.log";
    Site site("escape", "[logging]\nfile = \"" + log_file.string() + "\"\n");
    const std::string name =
        "x\n2026-06-01T06:00:00.000+0000 critical forged\r\t\x1b[2J\x7f\xc2\x9b\xff.ptx";
    const std::string escaped =
        "x\\n2026-06-01T06:00:00.000+0000 critical forged\\r\\t\\x1b[2J\\x7f\\xc2\\x9b\\xff.ptx";
    std::ofstream(site.ingest() / name) << truncated_ptx();
    DaemonProcess daemon(site.config(), site.log(), /*once=*/true);
    ASSERT_EQ(daemon.wait(60), 0) << read_file(site.log());

    for (const fs::path& log : {site.log(), log_file}) {
        const std::string text = read_file(log);
        EXPECT_NE(text.find(escaped), std::string::npos) << log << "\n" << text;
        EXPECT_EQ(text.find("\n2026-06-01T06:00:00.000+0000 critical forged"), std::string::npos)
            << log;
        for (const char c : {'\r', '\t', '\x1b', '\x7f'}) {
            EXPECT_EQ(text.find(c), std::string::npos) << log << ": byte " << int(c);
        }
        EXPECT_EQ(text.find("\xc2\x9b"), std::string::npos) << log;
    }
    const fs::path reason = site.root / "quarantine" / (name + ".reason.txt");
    ASSERT_TRUE(fs::exists(reason)) << read_file(site.log());
    const std::string text = read_file(reason);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;
    EXPECT_EQ(text.find('\x1b'), std::string::npos) << text;
    EXPECT_NE(text.find("file: " + (site.ingest() / escaped).string() + "\n"), std::string::npos)
        << text;
    // What the analyst reads: `tlsmon events` and `tlsmon query epochs`, table and CSV,
    // escape them as the log does (JSON escapes its own).
    for (const std::string command : {"events", "query epochs"}) {
        for (const std::string format : {"table", "csv"}) {
            const auto r = shell(std::string(TLSMON_BINARY) + " " + command + " --db " +
                                 site.database().string() + " --format " + format);
            ASSERT_EQ(r.status, 0) << r.output;
            EXPECT_NE(r.output.find(escaped), std::string::npos) << command << " " << format;
            for (const char c : {'\r', '\t', '\x1b', '\x7f'}) {
                EXPECT_EQ(r.output.find(c), std::string::npos)
                    << command << " " << format << ": byte " << int(c);
            }
            EXPECT_EQ(r.output.find("\n2026-06-01T06:00:00.000+0000 critical forged"),
                      std::string::npos)
                << command << " " << format;
        }
    }
}

TEST(DaemonIngest, BadConfigurationExitsWithTheKey) {
    Site site("badconfig", "[ingest]\nstable_seconds = 3\n");  // [ingest] twice: TOML error
    const auto r =
        shell(std::string(TLSMON_BINARY) + " run --once --config " + site.config().string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("site.toml:"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace tlsmon::test
