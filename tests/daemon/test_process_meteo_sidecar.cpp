// `tlsmon run` pairing scans with their meteo sidecars `<stem>.meteo.csv`: the real binary,
// a real SQLite file, sidecars written here with known values. The waits are short so the
// whole file runs in a few seconds.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/support/daemon_harness.hpp"

namespace tlsmon::test {
namespace {

using Clock = std::chrono::steady_clock;

const std::string kHeader = "time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct\n";

// A three-point PTX scan; `k` makes its content (and so its epoch) distinct.
std::string scan_text(int k) {
    return "3\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"
           "10.000 0.000 2.000 0.5\n10.100 0.000 2.000 0.5\n10.200 0.000 2." +
           std::to_string(100 + k) + " 0.5\n";
}

// Complete files appear by rename, as an export does.
void put(const fs::path& file, const std::string& text) {
    const fs::path tmp = file.parent_path() / ("." + file.filename().string() + ".part");
    write_file(tmp, text);
    fs::rename(tmp, file);
}

std::string sha256_of(const fs::path& file) {
    return shell("sha256sum " + file.string()).output.substr(0, 64);
}

std::vector<Epoch> epochs_of(const Site& site) {
    return site.open_db().series().epochs_in_range({});
}

std::optional<Epoch> only_epoch(const Site& site) {
    const auto all = epochs_of(site);
    if (all.size() != 1) return std::nullopt;
    return all.front();
}

bool epoch_finished(const Site& site, std::size_t count) {
    if (!fs::exists(site.database())) return false;
    const auto all = epochs_of(site);
    if (all.size() != count) return false;
    for (const auto& e : all) {
        if (e.status == EpochStatus::pending || e.status == EpochStatus::processing) return false;
    }
    return true;
}

std::vector<EventRow> events_of(const Site& site, const std::string& kind) {
    std::vector<EventRow> out;
    for (const auto& e : site.open_db().series().events({}, kind)) out.push_back(e);
    return out;
}

// 06:10 .. 06:16, one row a minute; the row of 06:15:00 (line 7) is the one nearest the
// acquisition time of "small_20260601T061500Z" and carries values no other row has.
const std::string kSidecar = "# station WS-12 on the abutment\n" + kHeader +
                             "2026-06-01T06:10:00Z,13.8,1012.9,80.1\n"
                             "2026-06-01T06:11:00Z,13.9,1012.8,80.0\n"
                             "2026-06-01T06:12:00Z,14.0,1012.7,79.4\n"
                             "2026-06-01T06:13:00Z,14.1,1012.6,79.0\n"
                             "2026-06-01T06:15:00Z,14.7,1011.3,76.2\n"
                             "2026-06-01T06:16:00Z,14.8,1011.2,76.0\n";
const std::string kStem = "small_20260601T061500Z";

void expect_used_row_of_0615(const MeteoSidecar& m, const std::string& sha) {
    EXPECT_EQ(m.outcome, MeteoOutcome::used);
    ASSERT_TRUE(m.values);
    EXPECT_EQ(m.values->time, 1780294500);  // 2026-06-01T06:15:00Z
    EXPECT_EQ(m.values->line, 7);
    EXPECT_EQ(m.values->air_temperature_c, 14.7);
    EXPECT_EQ(m.values->pressure_hpa, 1011.3);
    EXPECT_EQ(m.values->relative_humidity_pct, 76.2);
    EXPECT_EQ(m.file_name, kStem + ".meteo.csv");
    EXPECT_EQ(m.sha256, sha);
}

TEST(MeteoSidecar, BeforeItsScanIsUsedWithTheValuesOfTheFile) {
    Site site("meteo-before", "", "", "wait_seconds = 20\n");
    const fs::path sidecar = site.ingest() / (kStem + ".meteo.csv");
    put(sidecar, kSidecar);
    const std::string sha = sha256_of(sidecar);
    DaemonProcess daemon(site.config(), site.log());
    std::this_thread::sleep_for(std::chrono::milliseconds(700));  // the sidecar is complete
    put(site.ingest() / (kStem + ".ptx"), scan_text(0));
    ASSERT_TRUE(wait_until([&] { return epoch_finished(site, 1); }, 15)) << read_file(site.log());
    // The sidecar is moved after its epoch is processed (its record first, then the move: a
    // stop in between finishes the move at the next start).
    ASSERT_TRUE(wait_until([&] { return !fs::exists(sidecar); }, 5)) << read_file(site.log());

    const auto epoch = only_epoch(site);
    ASSERT_TRUE(epoch);
    EXPECT_EQ(epoch->status, EpochStatus::done);
    EXPECT_EQ(epoch->point_count, 3);
    const auto meteo = site.open_db().meteo().of_epoch(epoch->id);
    ASSERT_EQ(meteo.size(), 1u);
    expect_used_row_of_0615(meteo[0], sha);
    // Archived beside its scan, byte for byte.
    const fs::path archived = site.root / "archive" / (kStem + ".meteo.csv");
    EXPECT_EQ(meteo[0].path, archived.string());
    EXPECT_EQ(read_file(archived), kSidecar);
    EXPECT_TRUE(fs::exists(site.root / "archive" / (kStem + ".ptx")));
    EXPECT_TRUE(events_of(site, "meteo_missing").empty());

    // `tlsmon query meteo` shows the values as the file wrote them.
    const auto q = shell(std::string(TLSMON_BINARY) + " query meteo --format csv --db " +
                         site.database().string());
    ASSERT_EQ(q.status, 0) << q.output;
    EXPECT_EQ(q.output.substr(0, q.output.find('\n')),
              "epoch,acquired,status,meteo,time,offset_s,air_temperature_c,pressure_hpa,"
              "relative_humidity_pct,line,sidecar,sha256,path,reason");
    EXPECT_NE(q.output.find("1,2026-06-01T06:15:00Z,done,used,2026-06-01T06:15:00Z,0,14.7,1011.3,"
                            "76.2,7," +
                            kStem + ".meteo.csv," + sha + "," + archived.string() + ",\n"),
              std::string::npos)
        << q.output;
}

TEST(MeteoSidecar, AfterItsScanWithinTheWaitIsPaired) {
    Site site("meteo-after", "", "", "wait_seconds = 20\n");
    DaemonProcess daemon(site.config(), site.log());
    put(site.ingest() / (kStem + ".ptx"), scan_text(0));
    ASSERT_TRUE(wait_until([&] { return fs::exists(site.database()) && only_epoch(site); }, 10))
        << read_file(site.log());
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    EXPECT_EQ(only_epoch(site)->status, EpochStatus::pending) << "waits for its sidecar";
    const fs::path sidecar = site.ingest() / (kStem + ".meteo.csv");
    put(sidecar, kSidecar);
    const std::string sha = sha256_of(sidecar);
    const auto put_at = Clock::now();
    ASSERT_TRUE(wait_until([&] { return epoch_finished(site, 1); }, 15)) << read_file(site.log());
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - put_at).count(), 5.0)
        << "taken once the sidecar is complete, not at the end of the wait";
    const auto meteo = site.open_db().meteo().of_epoch(only_epoch(site)->id);
    ASSERT_EQ(meteo.size(), 1u);
    expect_used_row_of_0615(meteo[0], sha);
}

TEST(MeteoSidecar, NoneComesTheEpochIsDoneAfterTheWaitAndSaysSo) {
    Site site("meteo-none", "", "", "wait_seconds = 2\n");
    DaemonProcess daemon(site.config(), site.log());
    put(site.ingest() / (kStem + ".ptx"), scan_text(0));
    const auto put_at = Clock::now();
    ASSERT_TRUE(wait_until([&] { return epoch_finished(site, 1); }, 15)) << read_file(site.log());
    const double took = std::chrono::duration<double>(Clock::now() - put_at).count();
    // The wait counts whole seconds from the recorded discovery: between 1 and 2 s after it.
    EXPECT_GE(took, 1.0);
    EXPECT_LT(took, 4.5);
    const auto epoch = only_epoch(site);
    EXPECT_EQ(epoch->status, EpochStatus::done);
    EXPECT_TRUE(site.open_db().meteo().of_epoch(epoch->id).empty());
    const auto missing = events_of(site, "meteo_missing");
    ASSERT_EQ(missing.size(), 1u);
    EXPECT_EQ(missing[0].level, "warning");
    EXPECT_EQ(missing[0].epoch, epoch->id);
    EXPECT_NE(missing[0].message.find(kStem + ".meteo.csv within meteo.wait_seconds = 2 s"),
              std::string::npos)
        << missing[0].message;
    EXPECT_NE(read_file(site.log()).find("processed without meteo"), std::string::npos);
}

TEST(MeteoSidecar, MalformedIsQuarantinedNamingItsLineAndTheEpochIsDone) {
    Site site("meteo-bad", "", "", "wait_seconds = 20\nmax_time_offset_seconds = 120\n");
    struct Bad {
        std::string stem, text, where;
    };
    const Bad bad[] = {
        {"small_20260601T060000Z",
         "# station WS-12\ntime_utc;air_temperature_c;pressure_hpa;relative_humidity_pct\n",
         ".meteo.csv:2: the header has no column 'time_utc'"},
        {"small_20260601T061500Z",
         kHeader + "2026-06-01T06:14:00Z,14.2,1012.3,78.0\n2026-06-01T06:15:00Z,14.2,10l2.3,78\n",
         ".meteo.csv:3: column 'pressure_hpa': not a number: '10l2.3'"},
        {"small_20260601T063000Z", kHeader + "2026-06-01T08:30:00+02:00,14.2,1012.3,78.0\n",
         ".meteo.csv:2: time_utc '2026-06-01T08:30:00+02:00' is not UTC"},
        {"small_20260601T064500Z",
         kHeader + "2026-06-01T06:40:00Z,14.2,1012.3,78.0\n2026-06-01T06:42:00Z,14.2,1012.3,78\n",
         ".meteo.csv:3: the nearest row (2026-06-01T06:42:00Z) is 180 s from the acquisition "
         "time 2026-06-01T06:45:00Z"},
    };
    for (std::size_t k = 0; k < std::size(bad); ++k) {
        put(site.ingest() / (bad[k].stem + ".meteo.csv"), bad[k].text);
        put(site.ingest() / (bad[k].stem + ".ptx"), scan_text(static_cast<int>(k)));
    }
    DaemonProcess once(site.config(), site.log(), true);
    ASSERT_EQ(once.wait(30), 0) << read_file(site.log());

    const auto epochs = epochs_of(site);
    ASSERT_EQ(epochs.size(), std::size(bad));
    const auto rejected = events_of(site, "meteo_rejected");
    EXPECT_EQ(rejected.size(), std::size(bad));
    for (std::size_t k = 0; k < std::size(bad); ++k) {
        const auto& e = epochs[k];  // by acquisition time, as `bad` is
        const std::string name = bad[k].stem + ".meteo.csv";
        const std::string where = (site.ingest() / bad[k].stem).string() + bad[k].where;
        EXPECT_EQ(e.status, EpochStatus::done) << name;
        EXPECT_EQ(e.point_count, 3) << name;
        EXPECT_TRUE(fs::exists(site.root / "archive" / (bad[k].stem + ".ptx"))) << name;
        const auto meteo = site.open_db().meteo().of_epoch(e.id);
        ASSERT_EQ(meteo.size(), 1u) << name;
        EXPECT_EQ(meteo[0].outcome, MeteoOutcome::rejected) << name;
        EXPECT_FALSE(meteo[0].values) << name;
        EXPECT_EQ(meteo[0].reason.substr(0, where.size()), where);
        // Quarantined as it was, with its reason; nothing of it is lost.
        const fs::path q = site.root / "quarantine" / name;
        EXPECT_EQ(meteo[0].path, q.string());
        EXPECT_EQ(read_file(q), bad[k].text);
        EXPECT_NE(read_file(q.string() + ".reason.txt").find("reason: " + where), std::string::npos)
            << name;
        bool evented = false;
        for (const auto& ev : rejected) {
            evented |= ev.epoch == e.id && ev.message.find(where) != std::string::npos;
        }
        EXPECT_TRUE(evented) << name;
    }
    EXPECT_TRUE(fs::is_empty(site.ingest()));
}

TEST(MeteoSidecar, KilledWhileWaitingPairsOnceAfterTheRestart) {
    Site site("meteo-restart", "", "", "wait_seconds = 30\n");
    {
        DaemonProcess daemon(site.config(), site.log());
        put(site.ingest() / (kStem + ".ptx"), scan_text(0));
        ASSERT_TRUE(wait_until([&] { return fs::exists(site.database()) && only_epoch(site); }, 10))
            << read_file(site.log());
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        daemon.signal(SIGKILL);
        ASSERT_EQ(daemon.wait(5), -2);
    }
    EXPECT_EQ(only_epoch(site)->status, EpochStatus::pending);
    const fs::path sidecar = site.ingest() / (kStem + ".meteo.csv");
    put(sidecar, kSidecar);
    const std::string sha = sha256_of(sidecar);
    const auto restart = Clock::now();
    DaemonProcess once(site.config(), site.log(), true);
    ASSERT_EQ(once.wait(30), 0) << read_file(site.log());
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - restart).count(), 10.0)
        << "the sidecar is there: no waiting for the rest of wait_seconds";
    // A second start finds nothing left to do.
    DaemonProcess again(site.config(), site.log(), true);
    ASSERT_EQ(again.wait(30), 0) << read_file(site.log());

    const auto epoch = only_epoch(site);
    ASSERT_TRUE(epoch);
    EXPECT_EQ(epoch->status, EpochStatus::done);
    const auto meteo = site.open_db().meteo().of_epoch(epoch->id);
    ASSERT_EQ(meteo.size(), 1u);
    expect_used_row_of_0615(meteo[0], sha);
    EXPECT_TRUE(fs::is_empty(site.ingest()));
    std::size_t archived = 0;
    for (const auto& f : fs::directory_iterator(site.root / "archive"))
        archived += f.is_regular_file();
    EXPECT_EQ(archived, 2u);
    EXPECT_TRUE(events_of(site, "meteo_missing").empty());
}

TEST(MeteoSidecar, LateIsArchivedUnusedAndAnOrphanQuarantinedNeitherIsAScan) {
    // "csv" among the scan extensions: a sidecar is still never taken as a scan.
    Site site("meteo-late", "", "extensions = [\"ptx\", \"csv\"]\n",
              "wait_seconds = 1\norphan_seconds = 1\n");
    DaemonProcess daemon(site.config(), site.log());
    put(site.ingest() / (kStem + ".ptx"), scan_text(0));
    ASSERT_TRUE(wait_until([&] { return epoch_finished(site, 1); }, 15)) << read_file(site.log());
    const fs::path late = site.ingest() / (kStem + ".meteo.csv");
    put(late, kSidecar);
    const std::string late_sha = sha256_of(late);
    const fs::path orphan = site.ingest() / "small_20260601T073000Z.meteo.csv";
    put(orphan, kHeader + "2026-06-01T07:30:00Z,15.0,1010.0,70.0\n");
    ASSERT_TRUE(wait_until([&] { return fs::is_empty(site.ingest()); }, 15))
        << read_file(site.log());
    ASSERT_TRUE(wait_until([&] { return !events_of(site, "meteo_orphan").empty(); }, 5));

    const auto epoch = only_epoch(site);
    ASSERT_TRUE(epoch) << "no epoch of a .csv";
    const auto meteo = site.open_db().meteo().of_epoch(epoch->id);
    ASSERT_EQ(meteo.size(), 1u);
    EXPECT_EQ(meteo[0].outcome, MeteoOutcome::unused);
    EXPECT_FALSE(meteo[0].values) << "the epoch was processed without it";
    EXPECT_EQ(meteo[0].sha256, late_sha);
    EXPECT_NE(meteo[0].reason.find("came after epoch 1"), std::string::npos) << meteo[0].reason;
    EXPECT_EQ(read_file(site.root / "archive" / late.filename()), kSidecar);
    const auto unused = events_of(site, "meteo_unused");
    ASSERT_EQ(unused.size(), 1u);
    EXPECT_EQ(unused[0].epoch, epoch->id);

    const fs::path quarantined = site.root / "quarantine" / orphan.filename();
    EXPECT_TRUE(fs::exists(quarantined));
    EXPECT_NE(read_file(quarantined.string() + ".reason.txt")
                  .find("no scan small_20260601T073000Z.* came within meteo.orphan_seconds = 1 s"),
              std::string::npos);
    const auto orphans = events_of(site, "meteo_orphan");
    ASSERT_EQ(orphans.size(), 1u);
    EXPECT_FALSE(orphans[0].epoch);
}

TEST(MeteoSidecar, TheSimulatorsSidecarsAreUsedRowForRow) {
    Site site("meteo-sim", "", "", "wait_seconds = 20\n");
    const auto sim = shell(std::string(TLSMON_BINARY) +
                           " simulate --preset small --epochs 2 --out " + site.ingest().string());
    ASSERT_EQ(sim.status, 0) << sim.output;
    // The rows at the acquisition times, as the simulator wrote them.
    std::vector<std::string> expected;
    for (const std::string stem : {"small_20260601T060000Z", "small_20260601T061500Z"}) {
        const std::string text = read_file(site.ingest() / (stem + ".meteo.csv"));
        const std::string time = stem.substr(6, 4) + "-" + stem.substr(10, 2) + "-" +
                                 stem.substr(12, 2) + "T" + stem.substr(15, 2) + ":" +
                                 stem.substr(17, 2) + ":" + stem.substr(19, 2) + "Z,";
        const auto at = text.find(time);
        ASSERT_NE(at, std::string::npos) << text;
        expected.push_back(text.substr(at, text.find('\n', at) - at));
    }
    DaemonProcess once(site.config(), site.log(), true);
    ASSERT_EQ(once.wait(60), 0) << read_file(site.log());
    const auto epochs = epochs_of(site);
    ASSERT_EQ(epochs.size(), 2u);
    for (std::size_t k = 0; k < epochs.size(); ++k) {
        EXPECT_EQ(epochs[k].status, EpochStatus::done);
        const auto meteo = site.open_db().meteo().of_epoch(epochs[k].id);
        ASSERT_EQ(meteo.size(), 1u);
        ASSERT_TRUE(meteo[0].values);
        const auto& v = *meteo[0].values;
        EXPECT_EQ(v.time, epochs[k].acquired);
        char row[128];
        std::snprintf(row, sizeof row, "%s,%.1f,%.1f,%.1f", format_utc(v.time).c_str(),
                      v.air_temperature_c, v.pressure_hpa, v.relative_humidity_pct);
        EXPECT_EQ(row, expected[k]);
    }
}

}  // namespace
}  // namespace tlsmon::test
