#pragma once
// The central database's tests share these: a PostgreSQL cluster migrated with two sites
// ("a" and "b", each with its password file), and a site database with forwarding on and
// three committed epochs whose outbox is ready to send.
#include <sstream>
#include <string>
#include <vector>

#include "central/central_schema.hpp"
#include "central/central_sites.hpp"
#include "tests/storage/fake_sha256.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/postgres_cluster.hpp"

namespace tlsmon::test {

inline std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) out.push_back(l);
    return out;
}

struct Central {
    PostgresCluster pg;
    TempDir dir{"central"};
    CentralTarget admin;
    explicit Central(bool tls = false) : pg(tls) {
        admin.url = pg.url("postgres");
        admin.password_file = pg.admin_password_file();
        PgConnection c = PgConnection::open(admin);
        migrate_central(c);
        for (const char* site : {"a", "b"}) {
            write_text(password_file(site), std::string("pw-") + site + "\n");
            add_site(c, site, std::string("bridge ") + site, std::string("pw-") + site);
        }
    }
    fs::path password_file(const std::string& site) const { return dir / (site + ".pw"); }
    PgConnection as_site(const std::string& site) const {
        CentralTarget t;
        t.url = pg.url(site_role(site));
        t.password_file = password_file(site);
        return PgConnection::open(t);
    }
};

// A site database with forwarding on and three epochs 15 minutes apart, the last in the
// next month.
struct SiteDatabase {
    TempDir dir{"site"};
    EpochDatabase db = EpochDatabase::open(dir / "site.sqlite", EpochDatabase::Mode::read_write);
    SiteDatabase() {
        db.site().upsert_zone("pier", "{}");
        db.site().upsert_zone("deck", "{}");
        db.alarms().upsert_rule({0, "pier high", "pier", "m3c2_median_m", "{}", true});
        db.central_outbox().set_enabled(true);
        const UtcSeconds jan31 = parse_utc("2027-01-31T23:30:00Z");
        for (int k = 0; k < 3; ++k) commit(k, jan31 + 900 * k, 0.001 * k + 1.0 / 3e3);
    }
    void commit(int k, UtcSeconds t, double v) {
        const auto id = db.epochs().insert({fake_sha256(k + 1), t, "/ingest/s.ptx", 10, {}}).id;
        db.epochs().claim(id);
        EpochResults r;
        RegistrationRow reg;
        reg.method = "targets-helmert";
        reg.rms_m = 0.0007 + k * 1e-5;
        reg.accepted = true;
        reg.parameters = std::array<double, 6>{1e-6, 2e-6, 3e-6, 1e-3, 2e-3, 3e-3};
        reg.sigmas = std::array<double, 6>{1e-7, 1e-7, 1e-7, 1e-4, 1e-4, 1e-4};
        r.registration = reg;
        r.zone_results = {{"pier", "m3c2_median_m", v, 0.0011, 800, true},
                          {"deck", "m3c2_median_m", -v / 7, std::nullopt, 300, false}};
        r.alarm_events = {{t, "pier high", "raise", "alarm", v, id, "over 5 mm", "rule"}};
        r.system_events = {{t, "info", "epoch_done", "done", id}};
        db.results().commit(id, r);
    }
    fs::path path() const { return dir / "site.sqlite"; }
};

}  // namespace tlsmon::test
