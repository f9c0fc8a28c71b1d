#pragma once
// The [central] section of the configuration (docs/central.md): forwarding this site's results
// to a central PostgreSQL. Off by default; the site works alone either way.
//
//   [central]
//   enabled = true
//   url = "postgresql://tlsmon_site_a12@central.example.org:5432/tlsmon"
//   password_file = "/etc/tlsmon/central-password"
//   sslmode = "verify-full"
#include <filesystem>
#include <string>
#include <vector>

#include "core/config_key.hpp"

namespace tlsmon {

struct CentralConfig {
    bool enabled = false;
    bool forward_arrays = false;          // per-core-point arrays too (large)
    std::string url;                      // libpq URI or key=value; never with the password in it
    std::filesystem::path password_file;  // "" = libpq's PGPASSFILE or ~/.pgpass
    std::string sslmode;                  // "" = the URL's or libpq's default
    std::filesystem::path sslrootcert;    // "" = libpq's default (~/.postgresql/root.crt)
    int batch_size = 500;                 // outbox entries per call
    double poll = 5.0;                    // seconds between looks at an empty outbox
    double retry_initial = 5.0;           // after a failure, doubling ...
    double retry_max = 600.0;             // ... up to this
    double alarm_after = 900.0;           // failing this long raises system.central_forward
    bool operator==(const CentralConfig&) const = default;
};

std::vector<SectionKey<CentralConfig>> central_keys();

// The section as a whole: a URL when enabled, no password in it, a known sslmode; relative
// paths resolved against `base`. Each mistake is a ConfigError naming the key.
void check_central(TomlFields& t, CentralConfig& c, const std::filesystem::path& base);

}  // namespace tlsmon
