// `tlsmon query registrations`: each epoch's registration onto the reference targets — the
// test's verdict, ω, φ, κ, tx, ty, tz with their σ, the quaternion, the variance factor, each
// target's use and residual, and the registration's σ at each zone (docs/schema.md,
// "registrations"), read-only.
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "cli/transformation_columns.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

// Each target's use and residual length: "T1 used 0.000040 m; T2 excluded_outlier 0.010020
// m; T3 not_found" as text, [{"target", "use", "residual_m"}] as JSON (null: not measured).
Structured target_summary(const std::vector<TargetObservation>& targets) {
    Structured out{"", ""};
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const auto& t : targets) {
        const std::string use = t.use.empty() ? t.status : t.use;
        const bool measured = t.status == "found" || t.status == "excluded";
        const double length = std::hypot(t.residual[0], t.residual[1], t.residual[2]);
        out.text += fmt::format("{}{} {}", out.text.empty() ? "" : "; ", t.target, use);
        if (measured) out.text += fmt::format(" {:.6f} m", length);
        list.push_back({{"target", t.target},
                        {"use", use},
                        {"residual_m", measured ? nlohmann::ordered_json(length) : nullptr}});
    }
    out.json = list.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
    return out;
}

// The registration's largest 3-D σ in each zone: "pier_top 0.000310 m; ..." as text,
// {"zone": σ} as JSON.
Structured zone_summary(const std::vector<RegistrationZoneSigma>& zones) {
    Structured out{"", ""};
    nlohmann::ordered_json object = nlohmann::ordered_json::object();
    for (const auto& z : zones) {
        out.text +=
            fmt::format("{}{} {:.6f} m", out.text.empty() ? "" : "; ", z.zone, z.max_sigma_3d_m);
        object[z.zone] = z.max_sigma_3d_m;
    }
    out.json = object.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
    return out;
}

Table registrations_table(const EpochDatabase& db, const std::vector<Epoch>& epochs) {
    Table t{{"epoch", "acquired", "status", "registration", "accepted", "method", "targets_used",
             "rms_m"},
            {}};
    t.columns.insert(t.columns.end(), kParameterColumns.begin(), kParameterColumns.end());
    t.columns.insert(t.columns.end(), kSigmaColumns.begin(), kSigmaColumns.end());
    t.columns.insert(t.columns.end(), {"qw", "qx", "qy", "qz", "variance_factor", "redundancy",
                                       "targets", "zone_sigma_3d_m", "reason"});
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
                              r->rms_m};
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
        row.push_back(structured_cell(target_summary(db.registrations().targets_of_epoch(e.id))));
        row.push_back(structured_cell(zone_summary(db.registrations().zone_sigmas_of_epoch(e.id))));
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
