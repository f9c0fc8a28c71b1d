#pragma once
// What an analyst asks the central database about the fleet (`tlsmon fleet`, docs/central.md):
// the sites and how current each is, every zone's newest value, one zone's series, alarm
// events. Results as rows of text (NULL absent), printed by the command.
#include <optional>
#include <string>

#include "central/pg_connection.hpp"

namespace tlsmon {

// name, location, epochs, newest epoch, forwarded (when the last batch arrived), entries.
PgResult fleet_sites(PgConnection& c);

// Every zone quantity's newest value of every site (tlsmon.zone_latest), optionally only
// those whose |value| is at least `min_abs`, of `site`, or of `quantity`.
struct LatestFilter {
    std::optional<double> min_abs;
    std::string site, quantity;
};
PgResult fleet_latest(PgConnection& c, const LatestFilter& filter);

// One zone quantity of one site over [from, to) (UTC seconds; absent: open).
PgResult fleet_series(PgConnection& c, const std::string& site, const std::string& zone,
                      const std::string& quantity, std::optional<std::int64_t> from,
                      std::optional<std::int64_t> to);

// Alarm events over [from, to), of one site or all (""), oldest first.
PgResult fleet_alarms(PgConnection& c, const std::string& site, std::optional<std::int64_t> from,
                      std::optional<std::int64_t> to);

}  // namespace tlsmon
