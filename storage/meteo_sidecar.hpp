#pragma once
// A meteo sidecar (`<scan stem>.meteo.csv`, docs/formats.md) as the epoch database records
// it: which epoch it belongs to, what became of it, and for the epoch that used it the
// weather station's row nearest the acquisition time (docs/schema.md, "meteo_sidecars").
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

enum class MeteoOutcome {
    used,      // the epoch was processed with its row nearest the acquisition time
    rejected,  // malformed (or no row near enough): quarantined, the epoch went without
    unused,    // came after its epoch was processed (or its scan failed, or the epoch had one)
    orphan,    // no scan of its stem came in time: quarantined
};
std::string_view to_string(MeteoOutcome outcome);
// Throws StorageError for an unknown name.
MeteoOutcome meteo_outcome_from_string(std::string_view name);

// One row of the sidecar.
struct MeteoValues {
    UtcSeconds time = 0;    // the row's time_utc
    std::int64_t line = 0;  // its line in the file, 1-based
    double air_temperature_c = 0;
    double pressure_hpa = 0;
    double relative_humidity_pct = 0;
};

struct MeteoSidecar {
    std::optional<EpochId> epoch;  // absent only for an orphan
    MeteoOutcome outcome = MeteoOutcome::used;
    std::string file_name;              // as found beside the scan
    std::string sha256;                 // of its bytes
    std::optional<std::string> path;    // where it was moved; absent: left where it was
    std::string reason;                 // rejected, unused, orphan: why
    std::optional<MeteoValues> values;  // used: the row nearest the acquisition time
    UtcSeconds recorded = 0;            // when the row was written (set by storage)
};

}  // namespace tlsmon
