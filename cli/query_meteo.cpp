// `tlsmon query meteo`: the epochs of a time range with the meteo values each was processed
// with, and what became of every sidecar that came with it (docs/schema.md,
// "meteo_sidecars"), read-only.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

// One row per sidecar recorded for an epoch, in the order recorded; an epoch without any has
// one row with meteo "none".
Table meteo_table(const EpochDatabase& db, const std::vector<Epoch>& epochs) {
    Table t{
        {"epoch", "acquired", "status", "meteo", "time", "offset_s", "air_temperature_c",
         "pressure_hpa", "relative_humidity_pct", "line", "sidecar", "sha256", "path", "reason"},
        {}};
    t.rows.reserve(epochs.size());
    for (const auto& e : epochs) {
        const auto sidecars = db.meteo().of_epoch(e.id);
        if (sidecars.empty()) {
            std::vector<Cell> row{e.id, format_utc(e.acquired), std::string(to_string(e.status)),
                                  std::string("none")};
            row.resize(t.columns.size());
            t.rows.push_back(std::move(row));
            continue;
        }
        for (const auto& m : sidecars) {
            const auto& v = m.values;
            t.rows.push_back(
                {e.id, format_utc(e.acquired), std::string(to_string(e.status)),
                 std::string(to_string(m.outcome)), v ? Cell(format_utc(v->time)) : Cell(),
                 v ? Cell(static_cast<std::int64_t>(v->time - e.acquired)) : Cell(),
                 v ? Cell(v->air_temperature_c) : Cell(), v ? Cell(v->pressure_hpa) : Cell(),
                 v ? Cell(v->relative_humidity_pct) : Cell(), v ? Cell(v->line) : Cell(),
                 m.file_name, m.sha256, m.path ? Cell(*m.path) : Cell(), m.reason});
        }
    }
    return t;
}

}  // namespace

int run_query_meteo(const ReadOptions& options) {
    return run_reporting_errors("query meteo", [&] {
        const auto range = time_range(options);
        const auto db = open_for_reading(options);
        print(std::cout, meteo_table(db, db.series().epochs_in_range(range)), options.format);
    });
}

}  // namespace tlsmon
