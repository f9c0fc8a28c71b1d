// `tlsmon fleet sites|status|query series|query alarms --central URL` (docs/central.md): the
// central database's view of every site, printed as the site's `tlsmon query` prints its own.
#include <iostream>
#include <map>

#include "central/fleet_queries.hpp"
#include "cli/commands.hpp"
#include "cli/fleet_table.hpp"

namespace tlsmon {

namespace {

std::optional<std::int64_t> bound(const std::string& text) {
    if (text.empty()) return std::nullopt;
    return time_bound(text, now_utc());
}

}  // namespace

int run_fleet(const FleetOptions& o) {
    if (o.action == "serve") return serve_fleet(o);
    return run_reporting_errors("fleet " + o.action, [&] {
        PgConnection c =
            PgConnection::open(command_target(o.central, o.password_file, "tlsmon fleet"));
        const auto from = bound(o.read.from);
        // --to is inclusive, as in `tlsmon query`.
        const auto to =
            o.read.to.empty() ? std::nullopt : std::optional<std::int64_t>(*bound(o.read.to) + 1);
        PgResult r;
        std::string quantity = o.quantity;
        if (o.action == "sites") {
            r = fleet_sites(c);
        } else if (o.action == "status") {
            r = fleet_latest(c, {o.min_abs, o.site, o.quantity});
        } else if (o.action == "series") {
            r = fleet_series(c, o.site, o.zone, o.quantity, from, to);
        } else {
            r = fleet_alarms(c, o.site, from, to);
            quantity.clear();
        }
        print(std::cout, fleet_table(r, quantity), o.read.format);
    });
}

}  // namespace tlsmon
