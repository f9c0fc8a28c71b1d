// `tlsmon query registrations`: each epoch's registration onto the reference targets — the
// test's verdict, ω, φ, κ, tx, ty, tz with their σ, the quaternion, the variance factor, each
// target's use and residual, and the registration's σ at each zone (docs/schema.md,
// "registrations"), read-only.
#include <fmt/format.h>

#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "cli/transformation_columns.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

// "T1 used 0.04 mm; T2 excluded_outlier 10.02 mm; ..." (residual lengths).
std::string target_summary(const std::vector<TargetObservation>& targets) {
    std::string out;
    for (const auto& t : targets) {
        const double len = std::hypot(t.residual[0], t.residual[1], t.residual[2]);
        out += fmt::format(
            "{}{} {} {}", out.empty() ? "" : "; ", t.target, t.use.empty() ? t.status : t.use,
            t.status == "found" || t.status == "excluded" ? fmt::format("{:.2f} mm", 1e3 * len)
                                                          : "(" + t.status + ")");
    }
    return out;
}

std::string zone_summary(const std::vector<RegistrationZoneSigma>& zones) {
    std::string out;
    for (const auto& z : zones) {
        out +=
            fmt::format("{}{} {:.2f} mm", out.empty() ? "" : "; ", z.zone, 1e3 * z.max_sigma_3d_m);
    }
    return out;
}

Table registrations_table(const EpochDatabase& db, const std::vector<Epoch>& epochs) {
    Table t{{"epoch", "acquired", "status", "registration", "accepted", "method", "targets_used",
             "rms_mm"},
            {}};
    t.columns.insert(t.columns.end(), kParameterColumns.begin(), kParameterColumns.end());
    t.columns.insert(t.columns.end(), kSigmaColumns.begin(), kSigmaColumns.end());
    t.columns.insert(t.columns.end(), {"qw", "qx", "qy", "qz", "variance_factor", "redundancy",
                                       "targets", "zone_sigma_3d", "reason"});
    for (const auto& e : epochs) {
        const auto r = db.registrations().of_epoch(e.id);
        if (!r) continue;
        std::vector<Cell> row{e.id,
                              format_utc(e.acquired),
                              std::string(to_string(e.status)),
                              r->status,
                              r->accepted,
                              r->method,
                              r->target_count,
                              1e3 * r->rms_m};
        const auto& unit = kParameterUnits;
        for (int k = 0; k < 6; ++k) {
            row.push_back(optional_cell(r->parameters
                                            ? std::optional<double>((*r->parameters)[k] * unit[k])
                                            : std::nullopt));
        }
        for (int k = 0; k < 6; ++k) {
            row.push_back(optional_cell(r->sigmas ? std::optional<double>((*r->sigmas)[k] * unit[k])
                                                  : std::nullopt));
        }
        for (int k = 0; k < 4; ++k) {
            row.push_back(optional_cell(r->quaternion ? std::optional<double>((*r->quaternion)[k])
                                                      : std::nullopt));
        }
        row.push_back(optional_cell(r->variance_factor));
        row.push_back(optional_cell(r->redundancy));
        row.push_back(target_summary(db.registrations().targets_of_epoch(e.id)));
        row.push_back(zone_summary(db.registrations().zone_sigmas_of_epoch(e.id)));
        row.push_back(r->reason);
        t.rows.push_back(std::move(row));
    }
    return t;
}

}  // namespace

int run_query_registrations(const ReadOptions& options) {
    return run_reporting_errors("query registrations", [&] {
        const auto range = time_range(options);
        const auto db = open_for_reading(options);
        print(std::cout, registrations_table(db, db.series().epochs_in_range(range)),
              options.format);
    });
}

}  // namespace tlsmon
