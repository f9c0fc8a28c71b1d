#pragma once
// The central database's schema (docs/central.md): the numbered migrations of
// central/schema/, embedded at build time, applied in order by `tlsmon central migrate`.
#include <span>
#include <vector>

#include "central/pg_connection.hpp"
#include "storage/schema_migrations.hpp"

namespace tlsmon {

// In ascending version order.
std::span<const SchemaMigration> central_migrations();

// The highest migration applied to the database (0: none).
int central_schema_version(PgConnection& c);

// Applies every migration not yet recorded, each in its own transaction under an advisory
// lock (two migrating at once apply each once). Returns the versions applied now.
std::vector<int> migrate_central(PgConnection& c);

}  // namespace tlsmon
