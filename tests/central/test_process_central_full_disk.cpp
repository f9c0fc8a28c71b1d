// The central database's disk full (docs/central.md, "What happens when"): the partitions the
// site's next batch needs live in a tablespace on a 4 MB tmpfs (mounting needs root, as in
// CI), which a file then fills. The forwarder's batch is refused by the server ("No space left
// on device"), nothing is marked sent, the site database keeps committing epochs and raises
// system.central_forward; once the file is removed the backlog arrives whole and once, and
// the alarm clears.
#include <gtest/gtest.h>
#include <pwd.h>
#include <unistd.h>

#include "daemon/central_forwarder.hpp"
#include "daemon/system_alarm_watch.hpp"
#include "tests/support/central_fixtures.hpp"
#include "tests/support/small_tmpfs.hpp"

namespace tlsmon::test {
namespace {

std::string forward_alarm(const fs::path& db) {
    const e2e::json r = e2e::sql(db,
                                 "SELECT s.state AS state FROM alarm_states s JOIN alarm_rules r ON"
                                 " r.id = s.rule_id WHERE r.name = 'system.central_forward'");
    return r.empty() ? "" : r.at(0).at("state").get<std::string>();
}

int pending(const fs::path& db) {
    return e2e::sql(db, "SELECT count(*) AS n FROM outbox").at(0).at("n");
}

std::string last_error(const fs::path& db) {
    const e2e::json r = e2e::sql(db, "SELECT ifnull(last_error, '') AS e FROM central_forward");
    return r.empty() ? "" : r.at(0).at("e").get<std::string>();
}

TEST(CentralDatabase, AFullDiskRefusesTheBatchAndTheBacklogArrivesOnceThereIsRoom) {
    Central central;
    const fs::path small = central.dir / "small";
    SmallTmpfs tmpfs(small, "4m");
    ASSERT_TRUE(tmpfs.mounted()) << "mounting a tmpfs needs root: " << tmpfs.error();
    if (const passwd* pg = ::getpwnam("postgres"); pg && ::geteuid() == 0) {
        ASSERT_EQ(::chown(small.c_str(), pg->pw_uid, pg->pw_gid), 0);  // the server's user
    }
    // Every partition created from now on (the site's months) in the small tablespace.
    central.pg.psql("CREATE TABLESPACE small LOCATION '" + small.string() + "'", "postgres");
    central.pg.psql("ALTER DATABASE tlsmon SET default_tablespace = small", "postgres");

    SiteDatabase site;
    store_system_alarm_rules(site.db);  // as the daemon does at start
    fill_file_system(small / "filler");
    CentralConfig config;
    config.enabled = true;
    config.url = central.pg.url(site_role("a"));
    config.password_file = central.password_file("a");
    config.poll = 0.2;
    config.retry_initial = 0.2;
    config.retry_max = 0.4;
    config.alarm_after = 0.5;
    const int queued = pending(site.path());
    ASSERT_EQ(queued, 18);
    {
        CentralForwarder forwarder(config, site.path(), "a");
        ASSERT_TRUE(wait_until([&] { return forward_alarm(site.path()) == "unack"; }, 30))
            << last_error(site.path());
        EXPECT_NE(last_error(site.path()).find("No space left on device"), std::string::npos)
            << last_error(site.path());
        // Refused whole: nothing arrived, nothing was marked sent; the site goes on.
        EXPECT_EQ(central.pg.psql("SELECT count(*) FROM tlsmon.zone_results"), "0\n");
        site.commit(3, parse_utc("2027-02-01T00:30:00Z"), 0.004);
        forwarder.wake();
        EXPECT_GE(pending(site.path()), queued + 6);  // and the alarm's own events

        fs::remove(small / "filler");
        ASSERT_TRUE(wait_until([&] { return pending(site.path()) == 0; }, 30))
            << last_error(site.path());
        ASSERT_TRUE(wait_until([&] { return forward_alarm(site.path()) != "unack"; }, 30));
    }
    EXPECT_EQ(forward_alarm(site.path()), "rtn_unack");
    // Four epochs, each once; the results in the small tablespace's partitions.
    EXPECT_EQ(central.pg.psql("SELECT count(*), count(DISTINCT (zone, sha256)) FROM"
                              " tlsmon.zone_results"),
              "8|8\n");
    EXPECT_EQ(central.pg.psql("SELECT count(*) FROM tlsmon.epochs"), "4\n");
    EXPECT_EQ(central.pg.psql("SELECT DISTINCT t.spcname FROM pg_class c JOIN pg_tablespace t ON"
                              " t.oid = c.reltablespace JOIN pg_inherits i ON i.inhrelid ="
                              " c.oid WHERE i.inhparent = 'tlsmon.zone_results'::regclass"),
              "small\n");
}

}  // namespace
}  // namespace tlsmon::test
