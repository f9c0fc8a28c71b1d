// `tlsmon events`: system and alarm events in a time range, optionally of one kind.
#include <iostream>

#include "daemon/commands.hpp"
#include "daemon/query_output.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

void add_events_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("events", "List system and alarm events");
    auto options = std::make_shared<ReadOptions>();
    auto kind = std::make_shared<std::string>();
    add_read_options(cmd, *options, true);
    cmd->add_option("--kind", *kind, "Only events of this kind (e.g. disk_full, raise, ack)");
    cmd->callback([options, kind] {
        run_reporting_errors("events", [&] {
            const auto range = time_range(*options);
            const auto db = open_for_reading(*options);
            const auto events =
                db.series().events(range, kind->empty() ? std::nullopt : std::optional(*kind));
            Table t{{"time", "source", "level", "kind", "rule", "epoch", "message"}, {}};
            for (const auto& e : events) {
                t.rows.push_back({format_utc(e.time), e.source, e.level, e.kind, e.rule,
                                  optional_cell(e.epoch), e.message});
            }
            print(std::cout, t, output_format(*options));
        });
    });
}

}  // namespace tlsmon
