// `tlsmon status`: last epoch, backlog, failures, alarm summary, database size.
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

std::vector<std::pair<std::string, Cell>> status_fields(const EpochDatabase& db,
                                                        const StatusSummary& s) {
    std::vector<std::pair<std::string, Cell>> f;
    f.emplace_back("database", db.path().string());
    f.emplace_back("database_bytes", s.database_bytes);
    f.emplace_back("schema_version", static_cast<std::int64_t>(s.schema_version));
    for (const auto& [status, count] : s.epochs_by_status) {
        f.emplace_back("epochs_" + std::string(to_string(status)), count);
    }
    f.emplace_back("backlog", s.backlog);
    f.emplace_back("oldest_pending", optional_time_cell(s.oldest_pending));
    f.emplace_back("reference_epoch", optional_cell(s.reference_epoch));
    if (s.last_done) {
        f.emplace_back("last_epoch", s.last_done->id);
        f.emplace_back("last_epoch_acquired", format_utc(s.last_done->acquired));
        f.emplace_back("last_epoch_total_ms", optional_cell(s.last_done->timings.total_ms));
    } else {
        f.emplace_back("last_epoch", std::monostate{});
    }
    if (s.last_failure) {
        f.emplace_back("last_failure", s.last_failure->id);
        f.emplace_back("last_failure_status", std::string(to_string(s.last_failure->status)));
        f.emplace_back("last_failure_reason", s.last_failure->reason);
    } else {
        f.emplace_back("last_failure", std::monostate{});
    }
    f.emplace_back("alarms_active", s.alarms_active);
    f.emplace_back("alarms_unacknowledged", s.alarms_unacknowledged);
    // Every rule not in its normal state: "P3 settlement: unack H since ...; ..." as text,
    // [{"rule", "state", "level", "since"}] as JSON.
    Structured active{"", ""};
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const auto& a : s.alarm_states) {
        if (a.state == "normal") continue;
        active.text += (active.text.empty() ? "" : "; ") + a.rule + ": " + a.state;
        if (!a.level.empty()) active.text += " " + a.level;
        active.text += " since " + format_utc(a.since);
        list.push_back({{"rule", a.rule},
                        {"state", a.state},
                        {"level", a.level},
                        {"since", format_utc(a.since)}});
    }
    active.json = list.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
    f.emplace_back("alarm_states", structured_cell(std::move(active)));
    return f;
}

}  // namespace

int run_status(const ReadOptions& options) {
    return run_reporting_errors("status", [&] {
        const auto db = open_for_reading(options);
        print_fields(std::cout, status_fields(db, db.series().status_summary()), options.format);
    });
}

}  // namespace tlsmon
