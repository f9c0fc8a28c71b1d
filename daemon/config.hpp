#pragma once
// The daemon's configuration: plain structs whose member initialisers are the defaults,
// filled from a TOML file and validated in one place. daemon/config_keys.cpp declares each
// key once (name, type, range, meaning) for the reader, describe() and the reference in
// docs/configuration.md; tests hold etc/tlsmon.toml and the docs to these declarations.
// A choice made by name in the file is an enum here. Relative paths are resolved against the folder
// of the configuration file, so a checkout runs with its own etc/tlsmon.toml.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/toml_fields.hpp"
#include "daemon/ingest_files.hpp"
#include "daemon/modbus/modbus_config.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/epoch_pipeline.hpp"

namespace tlsmon {

struct StationConfig {
    std::string name = "station";
};

struct PathsConfig {
    std::filesystem::path ingest = "ingest";          // where the scanner drops its exports
    std::filesystem::path archive = "archive";        // processed files (archive = "move")
    std::filesystem::path quarantine = "quarantine";  // unreadable files + <name>.reason.txt
    std::filesystem::path database = "tlsmon.sqlite";
};

struct IngestConfig {
    // File name extensions (without the dot, compared case-insensitively) taken as scans.
    std::vector<std::string> extensions = scan_extensions();  // one per format of the table
    double stable_seconds = 10.0;             // size and mtime unchanged this long -> complete
    double rescan_interval = 60.0;            // full folder scan (inotify misses network shares)
    double max_growing = 3600.0;              // a file still growing after this is reported
    ArchiveMode archive = ArchiveMode::move;  // to paths.archive, or keep in place
    std::string reference_epoch;              // "" = first accepted epoch; else file name or sha256
    // Where an epoch's acquisition time comes from, first available wins.
    std::vector<TimeSource> acquisition_time = {TimeSource::scan, TimeSource::file_name,
                                                TimeSource::mtime};
    double retry_initial = 5.0;  // back-off after a database/disk failure, doubling ...
    double retry_max = 300.0;    // ... up to this
};

// The lowest level logged.
enum class LogLevel { trace, debug, info, warn, error, critical, off };

// Whether the log goes to the systemd journal: when started by systemd, always, or never.
enum class JournaldMode { automatic, on, off };

struct LoggingConfig {
    LogLevel level = LogLevel::info;
    std::filesystem::path file;                // optional rotating log file ("" = none)
    std::int64_t max_size = 10 * 1024 * 1024;  // bytes per log file before rotating
    int max_files = 5;                         // rotated files kept
    JournaldMode journald = JournaldMode::automatic;
};

struct DaemonConfig {
    double status_interval = 60.0;  // how often the systemd STATUS line is refreshed
};

// A named part of the structure; for now an axis-aligned box in the project frame.
struct ZoneConfig {
    std::string name;
    std::array<double, 3> min{};
    std::array<double, 3> max{};
};

// [alarm]: the system alarms' parameters, and the [[alarm.rule]] tables (docs/alarms.md).
struct AlarmConfig {
    double cadence = 900;         // the scanner's interval between scans, seconds
    double stale_factor = 3;      // system.stale after stale_factor x cadence without an epoch
    double disk_free_min = 0.05;  // system.disk_nearly_full below this free share
    std::vector<AlarmRuleSpec> rules;
};

struct Config {
    std::filesystem::path file;  // the configuration file read ("" for built-in defaults)
    StationConfig station;
    PathsConfig paths;
    IngestConfig ingest;
    MeteoConfig meteo;
    LoggingConfig logging;
    DaemonConfig daemon;
    CoverageConfig coverage;          // the pipeline's stages, in their order
    RegistrationConfig registration;  // targets: the [[target]] tables
    IcpConfig icp;  // [registration] icp_* keys; regions: the [[stable_region]] tables
    ModbusConfig modbus;
    AlarmConfig alarm;
    std::vector<ZoneConfig> zones;
};

// Reads, resolves and validates; throws ConfigError "file:line:col: key 'a.b': what".
Config load_config(const std::filesystem::path& path);
// The same from text; relative paths resolve against `base_dir`.
Config parse_config(std::string_view text, const std::string& source_name,
                    const std::filesystem::path& base_dir);

// The pipeline's part of the configuration.
PipelineConfig pipeline_config(const Config& config);

// The effective configuration as TOML lines ("ingest.stable_seconds = 10"), one per key.
std::vector<std::string> describe(const Config& config);

}  // namespace tlsmon
