#pragma once
// The meteo sidecar of an epoch (`<scan stem>.meteo.csv`, docs/formats.md): read once,
// hashed, and reduced to the weather station's row nearest the acquisition time, which the
// stages get in EpochInput::meteo and the epoch's commit stores (docs/pipeline.md, "Meteo").
#include <filesystem>
#include <optional>

#include "core/config_key.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// The [meteo] section of the configuration.
struct MeteoConfig {
    // How long a new scan waits for its sidecar (from when the scan was recorded). 0: no
    // waiting; a sidecar already there is used, a missing one is not reported.
    double wait_seconds = 120.0;
    // The row used must lie within this of the acquisition time.
    double max_time_offset_seconds = 300.0;
    // A sidecar whose scan has not come after this long goes to quarantine.
    double orphan_seconds = 86400.0;
};

// The sidecar as `epoch` uses it: outcome `used` with the row nearest its acquisition time,
// or `rejected` with the reason (the parser's message, naming file and line). `path` is
// left empty: where the file goes is decided with the epoch's archive. nullopt when the file
// is gone.
std::optional<MeteoSidecar> read_epoch_meteo(const std::filesystem::path& sidecar,
                                             const Epoch& epoch, const MeteoConfig& config);

// The keys of [meteo] (core/config_key.hpp).
std::vector<SectionKey<MeteoConfig>> meteo_keys();

}  // namespace tlsmon
