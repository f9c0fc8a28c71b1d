// `tlsmon central status`: how far this site's forwarding to the central database is
// behind (docs/central.md), from the site's own database; no connection to the central one.
#include <iostream>

#include "cli/commands.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

int run_central_status(const ReadOptions& options) {
    return run_reporting_errors("central status", [&] {
        const auto db = open_for_reading(options);
        const CentralForwardState s = db.central_outbox().state();
        const UtcSeconds now = now_utc();
        const std::optional<std::int64_t> lag =
            s.oldest_pending ? std::optional<std::int64_t>(now - *s.oldest_pending) : std::nullopt;
        print_fields(std::cout,
                     {{"enabled", s.enabled},
                      {"forward_arrays", s.forward_arrays},
                      {"source", s.database_id},
                      {"pending_entries", s.pending},
                      {"lag_s", optional_cell(lag)},
                      {"oldest_pending", optional_time_cell(s.oldest_pending)},
                      {"sent_upto", s.sent_upto},
                      {"sent_at", optional_time_cell(s.sent_at)},
                      {"failing_since", optional_time_cell(s.failing_since)},
                      {"last_error", s.last_error},
                      {"last_error_at", optional_time_cell(s.last_error_at)}},
                     options.format);
    });
}

}  // namespace tlsmon
