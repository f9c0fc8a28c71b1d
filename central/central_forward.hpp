#pragma once
// One batch of a site's outbox to the central database (docs/central.md): one call of
// tlsmon.forward(source, entries), committed by the server before it returns, so the site
// marks the entries sent only after the central commit. A batch sent again (the site crashed
// between the two) changes nothing: every central row is keyed by what it is at the site.
#include <span>
#include <string>

#include "central/pg_connection.hpp"
#include "storage/central_outbox.hpp"

namespace tlsmon {

// The entries as the JSON array tlsmon.forward() takes: [{"seq":…,"kind":…,"p":payload}, …].
std::string forward_batch_json(std::span<const OutboxEntry> entries);

// Sends the entries (in seq order) as site database `source`; returns the highest seq the
// central database has committed for it.
std::int64_t forward_batch(PgConnection& c, const std::string& source,
                           std::span<const OutboxEntry> entries);

}  // namespace tlsmon
