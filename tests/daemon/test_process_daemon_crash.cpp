// Crash safety: the daemon killed with SIGKILL at random moments while 20 simulated epochs
// arrive, restarted each time, ends with exactly the database of an uninterrupted run.
#include <gtest/gtest.h>

#include <iostream>
#include <map>
#include <random>

#include "tests/support/daemon_harness.hpp"

namespace tlsmon::test {
namespace {

// What must not depend on interruptions: everything but timings, times of the rows and
// paths (keyed by content).
struct Outcome {
    UtcSeconds acquired;
    std::int64_t size;
    EpochStatus status;
    std::string reason;
    std::optional<std::int64_t> points;
    bool operator==(const Outcome&) const = default;
};

void PrintTo(const Outcome& o, std::ostream* os) {
    *os << "{acquired " << o.acquired << ", size " << o.size << ", " << to_string(o.status)
        << ", points " << o.points.value_or(-1) << ", reason '" << o.reason << "'}";
}

// Reasons name the file; the two runs use different folders.
std::string without(std::string text, const std::string& folder) {
    for (auto at = text.find(folder); at != std::string::npos; at = text.find(folder)) {
        text.replace(at, folder.size(), "<site>");
    }
    return text;
}

std::map<std::string, Outcome> outcomes(const Site& site) {
    std::map<std::string, Outcome> out;
    for (const auto& e : site.open_db().series().epochs_in_range({})) {
        EXPECT_FALSE(out.count(e.sha256)) << "epoch twice: " << e.sha256;
        out[e.sha256] = Outcome{e.acquired, e.file_size, e.status,
                                without(e.reason, site.root.string()), e.point_count};
    }
    return out;
}

std::string reference_sha(const Site& site) {
    const auto db = site.open_db();
    const auto ref = db.epochs().reference();
    return ref ? db.epochs().find(*ref)->sha256 : "";
}

TEST(DaemonCrash, KilledTenTimesEqualsUninterruptedRun) {
    // 20 epochs of the small preset, one of them corrupted (truncated) so that a failed
    // epoch and its quarantine move are part of the comparison too.
    const TempDir scans_dir("crash-scans");
    const fs::path& scans = scans_dir.path();
    const auto sim = shell(std::string(TLSMON_BINARY) +
                           " simulate --preset small --epochs 20 --out " + scans.string());
    ASSERT_EQ(sim.status, 0) << sim.output;
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(scans)) {
        if (f.path().extension() == ".ptx") files.push_back(f.path());
    }
    std::sort(files.begin(), files.end());
    ASSERT_EQ(files.size(), 20u);
    {
        const std::string text = read_file(files[7]);
        write_file(files[7], text.substr(0, text.size() / 3));
    }

    Site calm("crash-calm");
    for (const auto& f : files) fs::copy_file(f, calm.ingest() / f.filename());
    DaemonProcess once(calm.config(), calm.log(), true);
    ASSERT_EQ(once.wait(120), 0) << read_file(calm.log());
    const auto expected = outcomes(calm);
    ASSERT_EQ(expected.size(), 20u);

    // The same files arriving two at a time while the daemon is killed -9 at random moments.
    Site site("crash-killed");
    std::mt19937 random(20261121);
    std::uniform_int_distribution<int> pause_ms(150, 1100);
    std::size_t copied = 0;
    for (int kill = 0; kill < 10; ++kill) {
        for (int k = 0; k < 2 && copied < files.size(); ++k, ++copied) {
            // Complete files appear by rename, like a scanner's export.
            const fs::path tmp =
                site.ingest() / ("." + files[copied].filename().native() + ".part");
            fs::copy_file(files[copied], tmp);
            fs::rename(tmp, site.ingest() / files[copied].filename());
        }
        DaemonProcess daemon(site.config(), site.log());
        std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms(random)));
        daemon.signal(SIGKILL);
        EXPECT_EQ(daemon.wait(5), -2);
    }
    DaemonProcess last(site.config(), site.log(), true);
    ASSERT_EQ(last.wait(120), 0) << read_file(site.log());

    // How often a kill landed mid-epoch (for the record; the moments are random).
    const std::string log = read_file(site.log());
    int interrupted = 0, finished_moves = 0;
    for (auto at = log.find("started ("); at != std::string::npos;
         at = log.find("started (", at + 1)) {
        interrupted += log.compare(log.find("); ", at) + 3, 2, "0 ") != 0;
    }
    for (auto at = log.find("before the restart"); at != std::string::npos;
         at = log.find("before the restart", at + 1)) {
        ++finished_moves;
    }
    std::cout << "restarts that found an epoch in processing: " << interrupted
              << ", archive moves finished after a restart: " << finished_moves << '\n';

    EXPECT_EQ(outcomes(site), expected);
    EXPECT_EQ(reference_sha(site), reference_sha(calm));
    const auto check = shell("sqlite3 " + site.database().string() + " 'PRAGMA integrity_check'");
    EXPECT_EQ(check.output, "ok\n");
    // Every file ended where the uninterrupted run put it: 19 archived, 1 quarantined, the
    // ingest folder holds only the simulator's truth files.
    std::size_t archived = 0, quarantined = 0, left = 0;
    for (const auto& f : fs::directory_iterator(site.root / "archive"))
        archived += f.is_regular_file();
    for (const auto& f : fs::directory_iterator(site.root / "quarantine")) {
        quarantined += f.path().extension() == ".ptx";
    }
    for (const auto& f : fs::directory_iterator(site.ingest()))
        left += f.path().extension() == ".ptx";
    EXPECT_EQ(archived, 19u);
    EXPECT_EQ(quarantined, 1u);
    EXPECT_EQ(left, 0u);
}

TEST(DaemonCrash, SigtermDuringBacklogStopsQuicklyLeavingEpochsDoneOrPending) {
    Site site("sigterm");
    const auto sim = shell(std::string(TLSMON_BINARY) +
                           " simulate --preset small --epochs 12 --out " + site.ingest().string());
    ASSERT_EQ(sim.status, 0) << sim.output;
    DaemonProcess daemon(site.config(), site.log());
    ASSERT_TRUE(wait_until(
        [&] {
            const auto s = site.open_db().series().status_summary();
            return s.epochs_by_status.at(EpochStatus::done) >= 2;
        },
        20))
        << read_file(site.log());
    const auto asked = std::chrono::steady_clock::now();
    daemon.signal(SIGTERM);
    ASSERT_EQ(daemon.wait(5), 0);
    const double stop_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
    EXPECT_LT(stop_s, 2.0) << "one epoch of the small preset at most, then stop";
    const auto s = site.open_db().series().status_summary();
    EXPECT_EQ(s.epochs_by_status.at(EpochStatus::processing), 0);
    EXPECT_EQ(
        s.epochs_by_status.at(EpochStatus::done) + s.epochs_by_status.at(EpochStatus::pending), 12);
    EXPECT_GT(s.epochs_by_status.at(EpochStatus::pending), 0) << "stopped before the end";
    // The rest is taken after a restart.
    DaemonProcess again(site.config(), site.log(), true);
    ASSERT_EQ(again.wait(60), 0);
    EXPECT_EQ(site.open_db().series().status_summary().epochs_by_status.at(EpochStatus::done), 12);
}

}  // namespace
}  // namespace tlsmon::test
