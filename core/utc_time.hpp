#pragma once
// Time in one form everywhere: UTC seconds since 1970-01-01T00:00:00Z, with ISO-8601 text
// as stored in the epoch database and printed by `tlsmon query|events|status`, and the one
// clock the project reads.
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace tlsmon {

using UtcSeconds = std::int64_t;

// The wall clock, whole UTC seconds.
UtcSeconds now_utc();

// GPS time (seconds since 1980-01-06T00:00:00Z, no leap seconds; E57 dateTimeValue, LAS
// GPS time) <-> UTC seconds since 1970. GPS runs ahead of UTC by the leap seconds inserted
// since 1980 (IERS Bulletin C), 18 s since 2017-01-01.
double gps_to_utc(double gps_seconds);
double utc_to_gps(double utc_seconds);

// "2026-03-01T12:15:00Z".
std::string format_utc(UtcSeconds t);
// Accepts "2026-03-01", "2026-03-01T12:15", "2026-03-01T12:15:00", with an optional "Z" or
// "+hh:mm"/"-hh:mm" offset (converted to UTC), and a space instead of "T". Anything else is
// an Error naming the text.
UtcSeconds parse_utc(std::string_view text);

}  // namespace tlsmon
