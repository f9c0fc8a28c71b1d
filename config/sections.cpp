// The keys of the daemon's own sections ([station], [paths], [ingest], [logging], [daemon],
// [alarm], [retention], [archive]), declared beside their structs (config/config.hpp) as the
// stages' are beside theirs; config/keys.cpp collects them all.
#include <array>

#include "config/config.hpp"

namespace tlsmon {

namespace {

constexpr std::array<Named<ArchiveMode>, 2> kArchiveModes{{
    {ArchiveMode::move, "move"},
    {ArchiveMode::keep, "keep"},
}};
constexpr std::array<Named<ScanReencoding>, 2> kScanReencodings{{
    {ScanReencoding::none, "none"},
    {ScanReencoding::e57, "e57"},
}};
constexpr std::array<Named<TimeSource>, 3> kTimeSources{{
    {TimeSource::scan, "scan"},
    {TimeSource::file_name, "file_name"},
    {TimeSource::mtime, "mtime"},
}};
constexpr std::array<Named<LogLevel>, 7> kLogLevels{{
    {LogLevel::trace, "trace"},
    {LogLevel::debug, "debug"},
    {LogLevel::info, "info"},
    {LogLevel::warn, "warn"},
    {LogLevel::error, "error"},
    {LogLevel::critical, "critical"},
    {LogLevel::off, "off"},
}};
constexpr std::array<Named<JournaldMode>, 3> kJournaldModes{{
    {JournaldMode::automatic, "auto"},
    {JournaldMode::on, "on"},
    {JournaldMode::off, "off"},
}};

}  // namespace

std::vector<SectionKey<StationConfig>> station_keys() {
    using K = Keys<StationConfig>;
    return {
        K::text(&StationConfig::name, "name", "non-empty, no `/`",
                "The scanner station; recorded with every epoch. The simulator names its files "
                "`<name>_YYYYMMDDTHHMMSSZ.ptx`."),
        K::number(&StationConfig::range_sigma_a, "range_sigma_a", 0, 0.1, "m",
                  "The scanner's range noise σ_r = a + b·r, constant part (its data sheet; the "
                  "simulator's default). The registration on planes tests a block's planarity "
                  "against it; the keypoints' outlier filters never judge a spread below it."),
        K::number(&StationConfig::range_sigma_b_ppm, "range_sigma_b_ppm", 0, 1000, "ppm",
                  "The range noise's part proportional to the range."),
        K::number(&StationConfig::angular_sigma_arcsec, "angular_sigma_arcsec", 0, 100, "″",
                  "The σ of the beam's direction. The ICP on stable regions tells from it and "
                  "the range noise where ground is so grazing that the angular noise scatters a "
                  "scan row along its beams, and wants a plane's beams spread across the row by "
                  "three times it (docs/registration.md, \"ICP on stable regions\")."),
        K::text(&StationConfig::crs, "crs", "a system PROJ knows, or empty",
                "The coordinate system of the project frame (the reference's, which every result "
                "is in), e.g. `\"EPSG:25832\"` or a WKT: written into exported LAS files as "
                "their WKT record (docs/export.md). Empty: the frame is local, none is written."),
    };
}

std::vector<SectionKey<PathsConfig>> paths_keys() {
    using K = Keys<PathsConfig>;
    return {
        K::path(&PathsConfig::ingest, "ingest", "",
                "Folder the scanner exports into; watched (not recursively)."),
        K::path(&PathsConfig::archive, "archive", "apart from `ingest`: neither inside the other",
                "Processed scans are moved here when `ingest.archive = \"move\"`. A name already "
                "taken gets the first 12 hex digits of the sha256 added."),
        K::path(&PathsConfig::quarantine, "quarantine", "apart from `ingest` and `archive`",
                "Files that could not be read, each with `<name>.reason.txt`."),
        K::path(&PathsConfig::database, "database", "not in `ingest`, `archive` or `quarantine`",
                "The SQLite epoch database (created and migrated at start)."),
    };
}

std::vector<SectionKey<IngestConfig>> ingest_keys() {
    using K = Keys<IngestConfig>;
    constexpr double day = 86400.0;
    return {
        K::names(&IngestConfig::extensions, "extensions",
                 "letters/digits, no dot, no repeats; case-insensitive",
                 "File name extensions taken as scans (`laz` is listed so that a compressed LAS "
                 "export is quarantined with a clear reason instead of being ignored). Hidden "
                 "names (`.x`), `*.part`, `*.tmp`, `*.partial` and `*~` are always ignored."),
        K::seconds(&IngestConfig::stable_seconds, "stable_seconds", 0, day, "",
                   "A file is complete when it is not open for writing (its last inotify event was "
                   "close-after-write or moved-in; a file found only by a folder scan counts as "
                   "closed) and its size and mtime have not changed for this long."),
        K::seconds(&IngestConfig::rescan_interval, "rescan_interval", 0.1, day, "",
                   "Full scan of the folder besides inotify (network shares, lost events)."),
        K::seconds(&IngestConfig::max_growing, "max_growing", 1, 30 * day, "> `stable_seconds`",
                   "A file not complete after this long is logged once and recorded as a "
                   "`file_growing` system event; it is still not processed while it grows."),
        K::choice(&IngestConfig::archive, "archive", kArchiveModes,
                  "`move`: processed files go to `paths.archive`; a second copy of a known scan is "
                  "deleted. `keep`: files stay where they are; copies are left and logged."),
        K::text(&IngestConfig::reference_epoch, "reference_epoch",
                "file name (no folder) or 64 lower-case hex digits",
                "The reference epoch (epoch 0 of the analyses). Empty: the first epoch accepted. "
                "Otherwise the epoch whose file name or sha256 matches, once it is accepted. Set "
                "once; never changed afterwards."),
        K::choices(&IngestConfig::acquisition_time, "acquisition_time", kTimeSources,
                   "Where an epoch's acquisition time comes from, first available wins: `scan` = "
                   "the file's own header (E57 `acquisitionStart`, read from its XML section "
                   "only), `file_name` = a `YYYYMMDDTHHMMSSZ` stamp in the name (UTC), `mtime` = "
                   "the file's modification time. If none is available, mtime is used. Pending "
                   "epochs are processed in acquisition-time order."),
        K::seconds(&IngestConfig::max_clock_ahead, "max_clock_ahead", 0, 30 * day, "",
                   "A scan whose acquisition time lies further ahead of the daemon's clock is "
                   "quarantined with the reason, never recorded as an epoch (a scanner clock or a "
                   "file name that is wrong would make every later scan look late to the alarm "
                   "rules)."),
        K::integer(&IngestConfig::max_file_size, "max_file_size", 1024, std::int64_t{1} << 42,
                   "bytes",
                   "A larger file is quarantined unread, with the reason; so is a file larger than "
                   "the memory available when it is taken (MemAvailable). Files are read whole."),
        K::seconds(&IngestConfig::retry_initial, "retry_initial", 0.1, 3600, "",
                   "After a disk-full or database error, the epoch stays pending and processing "
                   "pauses this long, doubling after each further failure ..."),
        K::seconds(&IngestConfig::retry_max, "retry_max", 0.1, day, ">= `retry_initial`",
                   "... up to this."),
    };
}

std::vector<SectionKey<LoggingConfig>> logging_keys() {
    using K = Keys<LoggingConfig>;
    return {
        K::choice(&LoggingConfig::level, "level", kLogLevels, "Lowest level logged."),
        K::optional_path(&LoggingConfig::file, "file",
                         "Optional log file, rotated by size. Empty: none."),
        K::integer(&LoggingConfig::max_size, "max_size", 4096, std::int64_t{1} << 40, "bytes",
                   "Bytes per log file before it rotates."),
        K::integer(&LoggingConfig::max_files, "max_files", 1, 1000, "", "Rotated files kept."),
        K::choice(&LoggingConfig::journald, "journald", kJournaldModes,
                  "`auto`: log to the systemd journal (with priorities) when started by systemd "
                  "(`$JOURNAL_STREAM` or `$INVOCATION_ID` set), else to stderr. `on`: always the "
                  "journal. `off`: always stderr."),
    };
}

std::vector<SectionKey<DaemonConfig>> daemon_keys() {
    using K = Keys<DaemonConfig>;
    constexpr double day = 86400.0;
    return {
        K::seconds(&DaemonConfig::status_interval, "status_interval", 1, day, "",
                   "How often the systemd `STATUS=` line is refreshed."),
    };
}

std::vector<SectionKey<AlarmConfig>> alarm_keys() {
    using K = Keys<AlarmConfig>;
    constexpr double day = 86400.0;
    return {
        K::seconds(&AlarmConfig::cadence, "cadence", 60, day, "",
                   "The scanner's interval between scans, for the `system.stale` alarm."),
        K::number(&AlarmConfig::stale_factor, "stale_factor", 1, 1000, "",
                  "`system.stale` is raised when no new epoch was acquired for this many "
                  "`cadence` intervals."),
        K::number(&AlarmConfig::disk_free_min, "disk_free_min", 0, 0.5, "",
                  "`system.disk_nearly_full` is raised when the free share of the database's "
                  "file system falls below this (cleared 0.01 above it). The alarm rules are "
                  "the `[[alarm.rule]]` tables (docs/alarms.md)."),
    };
}

std::vector<SectionKey<RetentionPolicy>> retention_keys() {
    using K = Keys<RetentionPolicy>;
    constexpr double day = 86400.0;
    return {
        K::flag(&RetentionPolicy::enabled, "enabled",
                "Thin the per-core-point maps (M3C2 distances, LoD95, ...) of older epochs "
                "(docs/retention.md). Zone series, events and alarms are always kept; so are the "
                "maps of the reference epoch, of epochs with alarm events or standing alarm "
                "state, of epochs that excluded a target, and of pinned epochs "
                "(`tlsmon epochs pin N`). `false`: every map is kept and the database grows "
                "by every epoch."),
        K::number(&RetentionPolicy::keep_all_days, "keep_all_days", 1, 36500, "d",
                  "Every epoch's maps are kept while it is younger than this. Age counts from the "
                  "newest epoch's acquisition time, not the clock."),
        K::number(&RetentionPolicy::keep_daily_days, "keep_daily_days", 1, 36500,
                  "d, >= `keep_all_days`",
                  "Older than `keep_all_days`: only the first epoch of each UTC day keeps its "
                  "maps, until this age; older still: only the first of each ISO week."),
        K::integer(&RetentionPolicy::batch_epochs, "batch_epochs", 1, 10000, "",
                   "Epochs thinned per transaction (an epoch commit waits for at most one)."),
        K::integer(&RetentionPolicy::vacuum_pages, "vacuum_pages", 16, 1 << 20, "",
                   "Free pages given back to the file system per transaction (incremental "
                   "vacuum)."),
        K::seconds(&RetentionPolicy::interval, "interval", 60, 7 * day, "",
                   "Time between the daemon's retention passes (the first runs at start)."),
    };
}

std::vector<SectionKey<ArchivePolicy>> archive_keys() {
    using K = Keys<ArchivePolicy>;
    return {
        K::flag(&ArchivePolicy::enabled, "enabled",
                "Thin the scan files in `paths.archive` by age (docs/retention.md), in the "
                "retention thread every `retention.interval`. Never removed: the scans of the "
                "reference epoch, of epochs with alarm events or standing alarm state, of epochs "
                "that excluded a target, and of pinned epochs. Their results stay in the "
                "database. Needs `ingest.archive = \"move\"` (with `keep` the scans stay in the "
                "ingest folder, which the policy never touches). `false`: every scan is kept."),
        K::number(&ArchivePolicy::keep_all_days, "keep_all_days", 0, 36500, "d",
                  "Every scan is kept while its epoch is younger than this (age from the newest "
                  "epoch's acquisition time)."),
        K::number(&ArchivePolicy::keep_daily_days, "keep_daily_days", 0, 36500,
                  "d, >= `keep_all_days`",
                  "Then only the first scan of each UTC day, until this age; older still: the "
                  "first of each ISO week."),
        K::choice(&ArchivePolicy::reencode, "reencode", kScanReencodings,
                  "`e57`: a kept scan older than `keep_all_days` is rewritten as E57 (coordinates "
                  "as scaled integers of `e57_resolution`, bit-packed; grid, intensity in 12 "
                  "bits, colour, pose and time kept), read back and compared point by point "
                  "before the original is deleted. The scans the state names (the reference) "
                  "stay as they were ingested. `none`: scans are kept as ingested."),
        K::number(&ArchivePolicy::e57_resolution, "e57_resolution", 1e-6, 1e-3, "m",
                  "The step of the re-encoded coordinates: every point stays within "
                  "√3/2 of it (10 µm: far below any scanner's noise)."),
        K::integer(&ArchivePolicy::batch_scans, "batch_scans", 1, 10000, "",
                   "Scans removed per transaction."),
    };
}

}  // namespace tlsmon
