#pragma once
// The part of an epoch database that belongs to a time window, as a database of the same
// schema (`tlsmon export --bundle`, docs/export.md): an analyst opens it with `tlsmon query
// --db`, `tlsmon export --db` or any SQLite tool.
#include <cstdint>
#include <filesystem>

#include "storage/series_reader.hpp"

namespace tlsmon {

struct WindowExtract {
    std::filesystem::path path;
    int schema_version = 0;
    std::int64_t epochs = 0;     // kept: the window's and those the current state names
    std::int64_t campaigns = 0;  // acquired in the window
    std::int64_t bytes = 0;
};

// A consistent copy of `source` (backup_database) reduced to:
// - the epochs acquired in `window`, and those the site's current state names: the reference
//   epoch (and the references of stable areas and campaigns), the epochs that set the
//   alarm states and the target exclusions; with every row of any table tied to them by an
//   `epoch_id` column (results, series, registrations, arrays, models, meteo, stages);
// - the system and alarm events, and the notifications, of the window;
// - the campaigns acquired in the window, with their rows (`campaign_id`);
// - the reference cache entries of kept reference epochs; the site (stations, zones,
//   quantities, alarm rules) whole.
// Then foreign_key_check must find nothing (a table tied to epochs some other way would be
// caught here) and the file is vacuumed. Throws StorageError; `destination` must not exist,
// and is removed again when the reduction fails.
WindowExtract extract_window(const std::filesystem::path& source,
                             const std::filesystem::path& destination, const TimeRange& window);

}  // namespace tlsmon
