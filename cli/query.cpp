// `tlsmon query epochs|series`: the epochs of a time range, and the time series of one zone
// and quantity, read from the epoch database (read-only: safe while the daemon writes).
#include <fmt/format.h>

#include <algorithm>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

// "coverage 3.1 ms (99.8 % of the points inside ...); m3c2 812.0 ms": each stage that ran.
std::string stages_text(const std::vector<StageRun>& stages) {
    std::string out;
    for (const auto& s : stages) {
        if (!out.empty()) out += "; ";
        out += fmt::format("{} {:.1f} ms", s.stage, s.ms);
        if (!s.note.empty()) out += " (" + s.note + ")";
    }
    return out;
}

Table epochs_table(const EpochDatabase& db, const std::vector<Epoch>& epochs) {
    Table t{{"epoch", "acquired", "status", "points", "total_ms", "stages", "file", "size",
             "sha256", "reason"},
            {}};
    t.rows.reserve(epochs.size());
    for (const auto& e : epochs) {
        t.rows.push_back({e.id, format_utc(e.acquired), std::string(to_string(e.status)),
                          optional_cell(e.point_count), optional_cell(e.timings.total_ms),
                          stages_text(db.series().stages(e.id)),
                          e.archive_path.value_or(e.file_path), e.file_size, e.sha256, e.reason});
    }
    return t;
}

// The value's quality follows its epoch's registration: an unregistered epoch's value mixes
// the scanner's movement into the structure's (docs/registration.md).
std::string quality_of(const SeriesPoint& p) {
    if (p.datum == kUnregistered) return kUnregistered;
    return p.registration_accepted ? "accepted" : "degraded";
}

// One row of a series; the value and its uncertainty are in the quantity's unit, which its
// name ends with.
const std::vector<std::string> kSeriesColumns{"epoch", "acquired",    "value",   "uncertainty",
                                              "n",     "significant", "quality", "datum"};

void series_row(const SeriesPoint& p, std::vector<Cell>& row) {
    // A campaign quantity's point has no epoch: its datum names the campaign.
    const std::optional<std::int64_t> epoch =
        p.campaign ? std::nullopt : std::optional<std::int64_t>(p.epoch);
    row = {optional_cell(epoch),
           format_utc(p.acquired),
           p.value,
           optional_cell(p.uncertainty),
           p.n,
           p.significant,
           quality_of(p),
           p.campaign ? "campaign " + std::to_string(*p.campaign) : p.datum};
}

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s.empty() ? "none" : s;
}

// A misspelt zone or quantity is an error naming what exists, not an empty series.
void check_series_names(const EpochDatabase& db, const std::string& zone,
                        const std::string& quantity) {
    std::vector<std::string> zones;
    for (const auto& z : db.site().zones()) zones.push_back(z.first);
    if (std::find(zones.begin(), zones.end(), zone) == zones.end()) {
        throw Error("no zone '" + zone + "' in " + db.path().string() +
                    " (zones: " + joined(zones) + ")");
    }
    const auto quantities = db.series().quantities(zone);
    if (!quantities.empty() &&
        std::find(quantities.begin(), quantities.end(), quantity) == quantities.end()) {
        throw Error("zone '" + zone + "' has no quantity '" + quantity +
                    "' (quantities: " + joined(quantities) + ")");
    }
}

}  // namespace

int run_query_epochs(const ReadOptions& options) {
    return run_reporting_errors("query epochs", [&] {
        const auto range = time_range(options);
        const auto db = open_for_reading(options);
        print(std::cout, epochs_table(db, db.series().epochs_in_range(range)), options.format);
    });
}

int run_query_series(const SeriesOptions& o) {
    return run_reporting_errors("query series", [&] {
        const auto range = time_range(o.read);
        const auto db = open_for_reading(o.read);
        check_series_names(db, o.zone, o.quantity);
        // Printed as they are read: a year of one series is 35,040 rows.
        RowPrinter printer(std::cout, kSeriesColumns, {"", "", o.quantity, o.quantity},
                           o.read.format);
        std::vector<Cell> row;
        db.series().for_each_point(o.zone, o.quantity, range, [&](const SeriesPoint& p) {
            series_row(p, row);
            printer.row(row);
        });
        printer.finish();
    });
}

}  // namespace tlsmon
