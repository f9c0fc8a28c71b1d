#pragma once
// The central database's answers as the site's `tlsmon query` tables (cli/query_output.hpp):
// counts as integers, values as reals in their quantity's unit, flags as booleans; printed by
// `tlsmon fleet` and served by `tlsmon fleet serve`.
#include <string>

#include "central/pg_connection.hpp"
#include "cli/query_output.hpp"

namespace tlsmon {

// `quantity` sets the rounding of the value and uncertainty columns ("" for none).
Table fleet_table(const PgResult& r, const std::string& quantity);

}  // namespace tlsmon
