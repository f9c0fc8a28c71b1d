#include "config/central_config.hpp"

#include <algorithm>
#include <array>

#include "core/redacted_url.hpp"

namespace tlsmon {

namespace {

// libpq's sslmode values (PostgreSQL 15 manual, §34.19.1).
constexpr std::array<const char*, 7> kSslModes{"",        "disable",   "allow",      "prefer",
                                               "require", "verify-ca", "verify-full"};

}  // namespace

std::vector<SectionKey<CentralConfig>> central_keys() {
    using K = Keys<CentralConfig>;
    return {
        K::flag(&CentralConfig::enabled, "enabled",
                "Forward this site's epochs, registrations, zone results and events to the "
                "central PostgreSQL of `url` (docs/central.md); switched on, the site's history "
                "so far is forwarded first."),
        K::flag(&CentralConfig::forward_arrays, "forward_arrays",
                "Forward each epoch's per-core-point arrays (M3C2 distances, LoD95, …) too, from "
                "the epochs committed while it is on; they are large (4 bytes per core point "
                "and quantity), so a fleet usually forwards only the zone series."),
        K::text(&CentralConfig::url, "url", "libpq URI or key=value, without a password",
                "The central database as this site's role reaches it, e.g. "
                "`postgresql://tlsmon_site_a12@central.example.org/tlsmon`."),
        K::optional_path(&CentralConfig::password_file, "password_file",
                         "The site role's password, the file's first line; empty: libpq's "
                         "PGPASSFILE or ~/.pgpass."),
        K::text(&CentralConfig::sslmode, "sslmode",
                "empty, `disable`, `allow`, `prefer`, `require`, `verify-ca`, `verify-full`",
                "TLS to the server (libpq's sslmode); `verify-full` checks the certificate and "
                "the host name; empty: the URL's or libpq's default."),
        K::optional_path(&CentralConfig::sslrootcert, "sslrootcert",
                         "Certificates that sign the server's (libpq's sslrootcert); empty: "
                         "libpq's default."),
        K::integer(&CentralConfig::batch_size, "batch_size", 1, 50000, "entries",
                   "Outbox entries sent in one call (one transaction of the central database)."),
        K::seconds(&CentralConfig::poll, "poll", 0.1, 3600, "",
                   "How often an empty outbox is looked at; a committed epoch wakes the "
                   "forwarder at once."),
        K::seconds(&CentralConfig::retry_initial, "retry_initial", 0.1, 3600, "",
                   "Wait after a failed call before the next; doubles with each failure."),
        K::seconds(&CentralConfig::retry_max, "retry_max", 1, 86400, "",
                   "Longest wait between calls."),
        K::seconds(&CentralConfig::alarm_after, "alarm_after", 0, 30 * 86400.0, "",
                   "Forwarding failing for this long raises the system alarm "
                   "`system.central_forward`; 0: at the first failure."),
    };
}

void check_central(TomlFields& t, CentralConfig& c, const std::filesystem::path& base) {
    if (c.enabled && c.url.empty()) t.fail("url", "forwarding is enabled but no url is given");
    if (url_has_password(c.url))
        t.fail("url", "holds a password; put it in password_file (it must never be logged)");
    if (std::find(kSslModes.begin(), kSslModes.end(), c.sslmode) == kSslModes.end())
        t.fail("sslmode", "expected disable, allow, prefer, require, verify-ca or verify-full");
    if (c.retry_max < c.retry_initial)
        t.fail("retry_max", "must be at least central.retry_initial");
    for (auto* p : {&c.password_file, &c.sslrootcert})
        if (!p->empty() && p->is_relative()) *p = base / *p;
}

}  // namespace tlsmon
