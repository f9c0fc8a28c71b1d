#pragma once
// UTC seconds <-> ISO-8601 text, as stored in the epoch database and printed by
// `tlsmon query|events|status`.
#include <string>
#include <string_view>

#include "storage/epoch_database.hpp"

namespace tlsmon {

// "2026-03-01T12:15:00Z".
std::string format_utc(UtcSeconds t);
// Accepts "2026-03-01", "2026-03-01T12:15", "2026-03-01T12:15:00", with an optional "Z" or
// "+hh:mm"/"-hh:mm" offset (converted to UTC), and a space instead of "T". Anything else is
// an Error naming the text.
UtcSeconds parse_utc(std::string_view text);

}  // namespace tlsmon
