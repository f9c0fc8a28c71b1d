#pragma once
// Private to storage/: the epochs the database's current state names, wherever they lie in
// time — the reference epoch, every epoch a row names as its reference (reference_epoch_id
// columns), the epochs of the alarms' standing state and of targets' exclusions. A window
// extract keeps them so it stays consistent; the retention policy never thins them.
#include <SQLiteCpp/SQLiteCpp.h>

#include <string>
#include <vector>

namespace tlsmon {

// The tables of `db` with a column `column`, by name.
std::vector<std::string> tables_with_column(SQLite::Database& db, const std::string& column);

// A SELECT of one column: the ids of those epochs (a UNION, no NULLs).
std::string epochs_named_by_state(SQLite::Database& db);

// The same for the epochs the retention and archive policies never thin: those the state
// names, every epoch of an alarm event (an alarm state change or an operator's action on
// it), and the pinned ones.
std::string protected_epochs(SQLite::Database& db);

}  // namespace tlsmon
