// `tlsmon events`: system and alarm events in a time range, optionally of one kind.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "core/utc_time.hpp"
#include "storage/alarm_store.hpp"

namespace tlsmon {

int run_events(const EventsOptions& o) {
    return run_reporting_errors("events", [&] {
        const auto range = time_range(o.read);
        const auto db = open_for_reading(o.read);
        const auto events =
            db.series().events(range, o.kind.empty() ? std::nullopt : std::optional(o.kind));
        Table t{{"time", "time_base", "source", "level", "kind", "rule", "epoch", "message"}, {}};
        for (const auto& e : events) {
            const std::string_view base =
                e.source == "alarm" ? alarm_event_time_base(e.rule, e.actor) : "system";
            t.rows.push_back({format_utc(e.time), std::string(base), e.source, e.level, e.kind,
                              e.rule, optional_cell(e.epoch), e.message});
        }
        print(std::cout, t, o.read.format);
    });
}

}  // namespace tlsmon
