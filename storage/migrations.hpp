#pragma once
// Private to storage/: the schema version of an open connection and the migrations.
#include "storage/connection.hpp"

namespace tlsmon {

// Highest migration recorded in the file (0 for a new file).
int applied_version(Connection& c);
// A StorageError when the file is newer than this binary knows.
void check_not_newer(Connection& c, int version);
// Applies every migration above `applied`; writes nothing when the file is up to date.
void migrate(Connection& c, int applied);

}  // namespace tlsmon
