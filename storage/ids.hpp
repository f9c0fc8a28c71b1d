#pragma once
// Row ids of the epoch database, and the connection every store of storage/ works on.
#include <cstdint>

namespace tlsmon {

using EpochId = std::int64_t;
using StationId = std::int64_t;
using ZoneId = std::int64_t;
using AlarmRuleId = std::int64_t;
// Times are UtcSeconds (core/utc_time.hpp converts to ISO-8601).

// The one SQLite connection of an EpochDatabase; its definition (and all SQL) is private to
// storage/.
struct Connection;

}  // namespace tlsmon
