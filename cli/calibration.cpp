// `tlsmon calibration --db DB [--truth DIR] [--from T] [--to T]`: whether each method's own σ /
// LoD95 covers its true error (or a check zone's zero change) at the nominal rate
// (report/calibration.hpp, docs/calibration.md), per method and part, with the Wilson interval of
// each coverage and a verdict.
#include "report/calibration.hpp"

#include <fmt/format.h>

#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"

namespace tlsmon {

namespace {

Table calibration_table(const std::vector<report::CoverageRow>& rows) {
    Table t{{"method", "part", "n", "unit", "bias", "rms", "max_abs", "rms_sigma", "cover68_pct",
             "band68_pct", "verdict68", "cover95_pct", "band95_pct", "verdict95"},
            {}};
    // Lengths in mm, angles in µrad: one unit per row, named in its own column.
    for (const auto& r : rows) {
        const bool blank = r.blank_numbers();
        const auto number = [&](double v) { return blank ? Cell() : Cell(r.display_scale() * v); };
        const auto band = [](const report::ShareInterval& b) {
            return Cell(fmt::format("{:.1f}-{:.1f}", 100 * b.lower, 100 * b.upper));
        };
        t.rows.push_back({r.method, r.part, static_cast<std::int64_t>(r.n),
                          blank ? Cell() : Cell(std::string(r.angle() ? "urad" : "mm")),
                          number(r.error.bias), number(r.error.rms), number(r.error.max_abs),
                          number(r.rms_sigma), 100 * r.coverage68(), band(r.band68),
                          std::string(to_string(r.verdict68)), 100 * r.coverage95(), band(r.band95),
                          std::string(to_string(r.verdict95))});
    }
    // bias … rms_sigma in the row's unit: three decimals, as millimetres
    t.rounded_as = {"", "", "", "", "_mm", "_mm", "_mm", "_mm"};
    return t;
}

}  // namespace

int run_calibration(const CalibrationOptions& o) {
    return run_reporting_errors("calibration", [&] {
        const auto truth = o.truth.empty() ? std::vector<report::TruthEpoch>()
                                           : report::read_truth_folder(o.truth);
        const auto db = open_for_reading(o.read);
        const report::RunData run = report::read_run(
            db, time_range(o.read),
            o.truth.empty() ? report::ZoneSeries::check_zones : report::ZoneSeries::all);
        const auto rows = report::calibration(report::analyse(run, truth, o.truth));
        if (rows.empty() && o.truth.empty())
            throw Error(
                "nothing to check without a truth: no check zone ([[zone]] no_change = true) "
                "has a value with an LoD, no accepted epoch used four targets or more, and none "
                "joined two independent "
                "estimates (registration.method with targets and planes or stable areas, or "
                "registration.icp = \"refine\"), whose agreement tests need none; give the "
                "simulator's truth with --truth DIR");
        if (rows.empty())
            throw Error(
                "no scored figure: the database holds no accepted epoch or zone value "
                "with an uncertainty at a time of the truth files in " +
                o.truth);
        print(std::cout, calibration_table(rows), o.read.format);
    });
}

}  // namespace tlsmon
