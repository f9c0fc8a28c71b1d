// `tlsmon fleet sites|status|query series|query alarms --central URL` (docs/central.md): the
// central database's view of every site, printed as the site's `tlsmon query` prints its own.
#include <iostream>
#include <map>

#include "central/fleet_queries.hpp"
#include "cli/commands.hpp"

namespace tlsmon {

namespace {

// Columns whose text is a number or a flag; every other is text.
enum class Kind { text, integer, real, flag };
const std::map<std::string, Kind> kKinds{{"epochs", Kind::integer},   {"entries", Kind::integer},
                                         {"n", Kind::integer},        {"value", Kind::real},
                                         {"uncertainty", Kind::real}, {"significant", Kind::flag}};

Cell cell(const std::optional<std::string>& text, Kind kind) {
    if (!text) return {};
    switch (kind) {
        case Kind::integer:
            return std::stoll(*text);
        case Kind::real:
            return std::stod(*text);
        case Kind::flag:
            return *text == "t";
        case Kind::text:
            break;
    }
    return *text;
}

// The values of `value` and `uncertainty` are in the unit of their quantity (`rounded_as`).
Table table_of(const PgResult& r, const std::string& quantity) {
    Table t;
    t.columns = r.columns;
    std::vector<Kind> kinds;
    for (const auto& c : r.columns) {
        const auto k = kKinds.find(c);
        kinds.push_back(k == kKinds.end() ? Kind::text : k->second);
        t.rounded_as.push_back((c == "value" || c == "uncertainty") ? quantity : "");
    }
    for (const auto& row : r.rows) {
        std::vector<Cell> cells;
        for (std::size_t i = 0; i < row.size(); ++i) cells.push_back(cell(row[i], kinds[i]));
        t.rows.push_back(std::move(cells));
    }
    return t;
}

std::optional<std::int64_t> bound(const std::string& text) {
    if (text.empty()) return std::nullopt;
    return time_bound(text, now_utc());
}

}  // namespace

int run_fleet(const FleetOptions& o) {
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
        print(std::cout, table_of(r, quantity), o.read.format);
    });
}

}  // namespace tlsmon
