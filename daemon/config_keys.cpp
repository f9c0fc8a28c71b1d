#include "daemon/config_keys.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace tlsmon {

namespace {

constexpr std::array<Named<ArchiveMode>, 2> kArchiveModes{{
    {ArchiveMode::move, "move"},
    {ArchiveMode::keep, "keep"},
}};
constexpr std::array<Named<AtmosphereCorrection>, 2> kAtmosphereCorrections{{
    {AtmosphereCorrection::measured_air, "measured_air"},
    {AtmosphereCorrection::off, "off"},
}};
constexpr std::array<Named<M3c2Statistic>, 2> kM3c2Statistics{{
    {M3c2Statistic::mean, "mean"},
    {M3c2Statistic::median, "median"},
}};
constexpr std::array<Named<KeypointSegments>, 2> kKeypointSegments{{
    {KeypointSegments::zones, "zones"},
    {KeypointSegments::bands, "bands"},
}};
constexpr std::array<Named<IcpMode>, 4> kIcpModes{{
    {IcpMode::off, "off"},
    {IcpMode::refine, "refine"},
    {IcpMode::fallback, "fallback"},
    {IcpMode::both, "both"},
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
constexpr std::array<Named<WordOrder>, 2> kWordOrders{{
    {WordOrder::abcd, "ABCD"},
    {WordOrder::cdab, "CDAB"},
}};
constexpr std::array<Named<JournaldMode>, 3> kJournaldModes{{
    {JournaldMode::automatic, "auto"},
    {JournaldMode::on, "on"},
    {JournaldMode::off, "off"},
}};

// A member of one section of Config: Config::ingest, then IngestConfig::stable_seconds.
template <class S, class T>
struct Member {
    S Config::*section;
    T S::*field;
    T& of(Config& c) const { return c.*section.*field; }
    const T& of(const Config& c) const { return c.*section.*field; }
};

// "ingest.stable_seconds" -> a ConfigKey with its section and name filled in.
ConfigKey key(std::string_view dotted, std::string type, std::string range, std::string help) {
    const auto dot = dotted.find('.');
    return ConfigKey{std::string(dotted.substr(0, dot)),
                     std::string(dotted.substr(dot + 1)),
                     std::move(type),
                     std::move(range),
                     std::move(help),
                     {},
                     {}};
}

// "a" and "b" -> "a, b"; an empty part is left out.
std::string joined(std::initializer_list<std::string> parts) {
    std::string out;
    for (const auto& p : parts) {
        if (!p.empty()) out += (out.empty() ? "" : ", ") + p;
    }
    return out;
}

// 86400 -> "1 d", 3600 -> "1 h", 0.1 -> "0.1 s": a duration as the docs write it.
std::string duration_text(double seconds) {
    for (const auto& [unit, size] : {std::pair{"d", 86400.0}, {"h", 3600.0}, {"min", 60.0}}) {
        if (seconds >= size && std::fmod(seconds, size) == 0.0) {
            return toml_number(seconds / size) + " " + unit;
        }
    }
    return toml_number(seconds) + " s";
}

template <class Names>
std::string names_in_backticks(const Names& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "`" : ", `") + std::string(n.name) + "`";
    return out;
}

template <class S, class T>
Member<S, T> at(S Config::*section, T S::*field) {
    return {section, field};
}

template <class S>
ConfigKey text(Member<S, std::string> m, std::string_view dotted, std::string rule,
               std::string help) {
    ConfigKey k = key(dotted, "string", std::move(rule), std::move(help));
    k.read = [m, name = k.name](TomlFields& t, Config& c) { t.get(name, m.of(c)); };
    k.value = [m](const Config& c) { return toml_string(m.of(c)); };
    return k;
}

// A path; relative ones are resolved in config.cpp once the section is read.
template <class S>
ConfigKey path(Member<S, std::filesystem::path> m, std::string_view dotted, std::string rule,
               std::string help) {
    ConfigKey k = key(dotted, "path", std::move(rule), std::move(help));
    k.read = [m, name = k.name](TomlFields& t, Config& c) { t.get(name, m.of(c)); };
    k.value = [m](const Config& c) { return toml_string(m.of(c).string()); };
    return k;
}

// A path that may be "" (none).
template <class S>
ConfigKey optional_path(Member<S, std::filesystem::path> m, std::string_view dotted,
                        std::string help) {
    ConfigKey k = key(dotted, "path", "", std::move(help));
    k.read = [m, name = k.name](TomlFields& t, Config& c) {
        std::string text = m.of(c).string();
        t.get(name, text);
        m.of(c) = text;
    };
    k.value = [m](const Config& c) { return toml_string(m.of(c).string()); };
    return k;
}

template <class S>
ConfigKey flag(Member<S, bool> m, std::string_view dotted, std::string help) {
    ConfigKey k = key(dotted, "boolean", "`true`, `false`", std::move(help));
    k.read = [m, name = k.name](TomlFields& t, Config& c) { t.get(name, m.of(c)); };
    k.value = [m](const Config& c) { return std::string(m.of(c) ? "true" : "false"); };
    return k;
}

template <class S>
ConfigKey names(Member<S, std::vector<std::string>> m, std::string_view dotted, std::string rule,
                std::string help) {
    ConfigKey k = key(dotted, "array of strings", std::move(rule), std::move(help));
    k.read = [m, name = k.name](TomlFields& t, Config& c) { t.get(name, m.of(c)); };
    k.value = [m](const Config& c) {
        std::string out = "[";
        for (const auto& v : m.of(c)) out += (out.size() > 1 ? ", " : "") + toml_string(v);
        return out + "]";
    };
    return k;
}

template <class S>
ConfigKey seconds(Member<S, double> m, std::string_view dotted, double min, double max,
                  std::string rule, std::string help) {
    ConfigKey k = key(dotted, "duration",
                      joined({duration_text(min) + " .. " + duration_text(max), std::move(rule)}),
                      std::move(help));
    k.read = [m, name = k.name, min, max](TomlFields& t, Config& c) {
        t.get_seconds(name, m.of(c), min, max);
    };
    k.value = [m](const Config& c) { return toml_number(m.of(c)); };
    return k;
}

// A real number in [min, max] with its unit.
template <class S>
ConfigKey number(Member<S, double> m, std::string_view dotted, double min, double max,
                 std::string unit, std::string help) {
    std::string range = toml_number(min) + " .. " + toml_number(max);
    if (!unit.empty()) range += " " + unit;
    ConfigKey k = key(dotted, "number", std::move(range), std::move(help));
    k.read = [m, name = k.name, min, max](TomlFields& t, Config& c) {
        t.get(name, m.of(c), min, max);
    };
    k.value = [m](const Config& c) { return toml_number(m.of(c)); };
    return k;
}

template <class S, class T>
ConfigKey integer(Member<S, T> m, std::string_view dotted, std::int64_t min, std::int64_t max,
                  std::string unit, std::string help) {
    std::string range = std::to_string(min) + " .. " + std::to_string(max);
    if (!unit.empty()) range += " " + unit;
    ConfigKey k = key(dotted, "integer", std::move(range), std::move(help));
    k.read = [m, name = k.name, min, max](TomlFields& t, Config& c) {
        t.get(name, m.of(c), static_cast<T>(min), static_cast<T>(max));
    };
    k.value = [m](const Config& c) { return std::to_string(m.of(c)); };
    return k;
}

template <class S, class E, std::size_t N>
ConfigKey choice(Member<S, E> m, std::string_view dotted, const std::array<Named<E>, N>& choices,
                 std::string help) {
    ConfigKey k = key(dotted, "string", names_in_backticks(choices), std::move(help));
    k.read = [m, name = k.name, &choices](TomlFields& t, Config& c) {
        t.get_choice(name, m.of(c), choices);
    };
    k.value = [m, &choices](const Config& c) {
        return toml_string(std::string(name_of(m.of(c), choices)));
    };
    return k;
}

template <class S, class E, std::size_t N>
ConfigKey choices(Member<S, std::vector<E>> m, std::string_view dotted,
                  const std::array<Named<E>, N>& choices, std::string help) {
    ConfigKey k = key(dotted, "array of strings",
                      "each of " + names_in_backticks(choices) + ", no repeats", std::move(help));
    k.read = [m, name = k.name, &choices](TomlFields& t, Config& c) {
        t.get_choices(name, m.of(c), choices);
    };
    k.value = [m, &choices](const Config& c) {
        std::string out = "[";
        for (const E v : m.of(c)) {
            out += (out.size() > 1 ? ", " : "") + toml_string(std::string(name_of(v, choices)));
        }
        return out + "]";
    };
    return k;
}

// [m3c2] normal_radii: lengths in metres, at least one.
ConfigKey m3c2_radii() {
    ConfigKey k = key("m3c2.normal_radii", "array of numbers", "1 to 10 radii, each 0.001 .. 100 m",
                      "The normal scales D/2 of Lague 2013, as radii: at each core point the "
                      "normal is taken at the radius where the reference is most planar "
                      "(docs/m3c2.md).");
    k.read = [](TomlFields& t, Config& c) {
        std::vector<double> v = c.m3c2.normal_radii;
        t.get("normal_radii", v);
        if (v.empty() || v.size() > 10) t.fail("normal_radii", "expected 1 to 10 radii");
        for (double r : v) {
            if (!(r >= 0.001 && r <= 100)) {
                t.fail("normal_radii", "radius " + toml_number(r) + " is outside 0.001 .. 100 m");
            }
        }
        c.m3c2.normal_radii = v;
    };
    k.value = [](const Config& c) {
        std::string out = "[";
        for (double r : c.m3c2.normal_radii) out += (out.size() > 1 ? ", " : "") + toml_number(r);
        return out + "]";
    };
    return k;
}

// [m3c2] orientation: "scanner" or [x, y, z].
ConfigKey m3c2_orientation() {
    ConfigKey k = key("m3c2.orientation", "string or array of 3 numbers",
                      "`\"scanner\"` or a non-zero `[x, y, z]`",
                      "Which way the normals point, and so the sign of a distance: `scanner` = "
                      "towards the reference scan's position (positive = towards the scanner); "
                      "a vector v = the side with n · v ≥ 0 (e.g. `[0, 0, 1]`: up).");
    k.read = [](TomlFields& t, Config& c) {
        if (!t.has("orientation")) {
            std::string ignored;
            t.get("orientation", ignored);  // absent: the default stands, the key is known
            return;
        }
        if (t.is_array("orientation")) {
            std::vector<double> v;
            t.get("orientation", v);
            if (v.size() != 3) t.fail("orientation", "expected \"scanner\" or [x, y, z]");
            c.m3c2.orient_to_scanner = false;
            c.m3c2.orientation = Eigen::Vector3d(v[0], v[1], v[2]);
            return;
        }
        std::string text;
        t.get("orientation", text);
        if (text != "scanner") t.fail("orientation", "expected \"scanner\" or [x, y, z]");
        c.m3c2.orient_to_scanner = true;
    };
    k.value = [](const Config& c) {
        if (c.m3c2.orient_to_scanner) return std::string("\"scanner\"");
        const auto& v = c.m3c2.orientation;
        return "[" + toml_number(v.x()) + ", " + toml_number(v.y()) + ", " + toml_number(v.z()) +
               "]";
    };
    return k;
}

std::vector<ConfigKey> declare_keys() {
    using C = Config;
    constexpr double day = 86400.0;
    return {
        text(at(&C::station, &StationConfig::name), "station.name", "non-empty, no `/`",
             "The scanner station; recorded with every epoch. The simulator names its files "
             "`<name>_YYYYMMDDTHHMMSSZ.ptx`."),

        path(at(&C::paths, &PathsConfig::ingest), "paths.ingest", "",
             "Folder the scanner exports into; watched (not recursively)."),
        path(at(&C::paths, &PathsConfig::archive), "paths.archive",
             "apart from `ingest`: neither inside the other",
             "Processed scans are moved here when `ingest.archive = \"move\"`. A name already "
             "taken gets the first 12 hex digits of the sha256 added."),
        path(at(&C::paths, &PathsConfig::quarantine), "paths.quarantine",
             "apart from `ingest` and `archive`",
             "Files that could not be read, each with `<name>.reason.txt`."),
        path(at(&C::paths, &PathsConfig::database), "paths.database",
             "not in `ingest`, `archive` or `quarantine`",
             "The SQLite epoch database (created and migrated at start)."),

        names(at(&C::ingest, &IngestConfig::extensions), "ingest.extensions",
              "letters/digits, no dot, no repeats; case-insensitive",
              "File name extensions taken as scans (`laz` is listed so that a compressed LAS "
              "export is quarantined with a clear reason instead of being ignored). Hidden "
              "names (`.x`), `*.part`, `*.tmp`, `*.partial` and `*~` are always ignored."),
        seconds(at(&C::ingest, &IngestConfig::stable_seconds), "ingest.stable_seconds", 0, day, "",
                "A file is complete when it is not open for writing (its last inotify event was "
                "close-after-write or moved-in; a file found only by a folder scan counts as "
                "closed) and its size and mtime have not changed for this long."),
        seconds(at(&C::ingest, &IngestConfig::rescan_interval), "ingest.rescan_interval", 0.1, day,
                "", "Full scan of the folder besides inotify (network shares, lost events)."),
        seconds(at(&C::ingest, &IngestConfig::max_growing), "ingest.max_growing", 1, 30 * day,
                "> `stable_seconds`",
                "A file not complete after this long is logged once and recorded as a "
                "`file_growing` system event; it is still not processed while it grows."),
        choice(at(&C::ingest, &IngestConfig::archive), "ingest.archive", kArchiveModes,
               "`move`: processed files go to `paths.archive`; a second copy of a known scan is "
               "deleted. `keep`: files stay where they are; copies are left and logged."),
        text(at(&C::ingest, &IngestConfig::reference_epoch), "ingest.reference_epoch",
             "file name (no folder) or 64 lower-case hex digits",
             "The reference epoch (epoch 0 of the analyses). Empty: the first epoch accepted. "
             "Otherwise the epoch whose file name or sha256 matches, once it is accepted. Set "
             "once; never changed afterwards."),
        choices(at(&C::ingest, &IngestConfig::acquisition_time), "ingest.acquisition_time",
                kTimeSources,
                "Where an epoch's acquisition time comes from, first available wins: `scan` = "
                "the file's own header (E57 `acquisitionStart`, read from its XML section "
                "only), `file_name` = a `YYYYMMDDTHHMMSSZ` stamp in the name (UTC), `mtime` = "
                "the file's modification time. If none is available, mtime is used. Pending "
                "epochs are processed in acquisition-time order."),
        seconds(at(&C::ingest, &IngestConfig::max_clock_ahead), "ingest.max_clock_ahead", 0,
                30 * day, "",
                "A scan whose acquisition time lies further ahead of the daemon's clock is "
                "quarantined with the reason, never recorded as an epoch (a scanner clock or a "
                "file name that is wrong would make every later scan look late to the alarm "
                "rules)."),
        integer(at(&C::ingest, &IngestConfig::max_file_size), "ingest.max_file_size", 1024,
                std::int64_t{1} << 42, "bytes",
                "A larger file is quarantined unread, with the reason; so is a file larger than "
                "the memory available when it is taken (MemAvailable). Files are read whole."),
        seconds(at(&C::ingest, &IngestConfig::retry_initial), "ingest.retry_initial", 0.1, 3600, "",
                "After a disk-full or database error, the epoch stays pending and processing "
                "pauses this long, doubling after each further failure ..."),
        seconds(at(&C::ingest, &IngestConfig::retry_max), "ingest.retry_max", 0.1, day,
                ">= `retry_initial`", "... up to this."),

        seconds(at(&C::meteo, &MeteoConfig::wait_seconds), "meteo.wait_seconds", 0, day, "",
                "How long a new scan waits for its meteo sidecar `<scan stem>.meteo.csv` "
                "(docs/formats.md), counted from when the scan was recorded (so also across a "
                "restart). Epochs are processed in acquisition order: later scans wait behind "
                "it; files keep being taken meanwhile. Without a sidecar by then the epoch is "
                "processed without meteo, with a warning and a `meteo_missing` system event. "
                "0: no waiting, and no event (a site without a weather station); a sidecar "
                "already there is still used."),
        seconds(at(&C::meteo, &MeteoConfig::max_time_offset_seconds),
                "meteo.max_time_offset_seconds", 0, day, "",
                "The sidecar's row nearest the acquisition time is used if it lies within this; "
                "otherwise the sidecar is rejected (quarantined, `meteo_rejected` event) and the "
                "epoch is processed without meteo."),
        seconds(at(&C::meteo, &MeteoConfig::orphan_seconds), "meteo.orphan_seconds", 1, 30 * day,
                "",
                "A complete sidecar whose scan has not arrived after this long is moved to "
                "`paths.quarantine` with its reason and a `meteo_orphan` system event."),

        choice(at(&C::logging, &LoggingConfig::level), "logging.level", kLogLevels,
               "Lowest level logged."),
        optional_path(at(&C::logging, &LoggingConfig::file), "logging.file",
                      "Optional log file, rotated by size. Empty: none."),
        integer(at(&C::logging, &LoggingConfig::max_size), "logging.max_size", 4096,
                std::int64_t{1} << 40, "bytes", "Bytes per log file before it rotates."),
        integer(at(&C::logging, &LoggingConfig::max_files), "logging.max_files", 1, 1000, "",
                "Rotated files kept."),
        choice(at(&C::logging, &LoggingConfig::journald), "logging.journald", kJournaldModes,
               "`auto`: log to the systemd journal (with priorities) when started by systemd "
               "(`$JOURNAL_STREAM` or `$INVOCATION_ID` set), else to stderr. `on`: always the "
               "journal. `off`: always stderr."),

        seconds(at(&C::daemon, &DaemonConfig::status_interval), "daemon.status_interval", 1, day,
                "", "How often the systemd `STATUS=` line is refreshed."),

        number(at(&C::coverage, &CoverageConfig::margin), "coverage.margin", 0, 1000, "m",
               "The reference epoch's bounding box is grown by this on every side before the "
               "share of an epoch's points inside it is counted."),
        number(at(&C::coverage, &CoverageConfig::min_inside_share), "coverage.min_inside_share", 0,
               1, "",
               "An epoch with a smaller share of its points inside the grown box is rejected "
               "before any analysis (the scanner turned, the scan is cut short, a file of "
               "another station). 0: never rejected; the share is stored either way."),

        number(at(&C::registration, &RegistrationConfig::search_radius),
               "registration.search_radius", 0.05, 5, "m",
               "A target's points are taken within this of its predicted centre (its centre in "
               "the reference epoch), through the scan grid's angular window."),
        number(at(&C::registration, &RegistrationConfig::centre_sigma_floor),
               "registration.centre_sigma_floor", 0, 0.01, "m",
               "Added as σ² per coordinate to every fitted centre's covariance: the fit's σ is "
               "only its random part; what a centre repeats to beyond it (the footprint, the "
               "silhouette's mixed returns) is 0.05–0.1 mm (docs/registration.md)."),
        integer(at(&C::registration, &RegistrationConfig::min_targets), "registration.min_targets",
                3, 100, "",
                "Usable targets that must remain after outliers are excluded; fewer: rejected."),
        number(at(&C::registration, &RegistrationConfig::max_rms), "registration.max_rms", 0, 1,
               "m", "Quality gate: RMS of the used targets' residual lengths."),
        number(at(&C::registration, &RegistrationConfig::max_sigma_angle_arcsec),
               "registration.max_sigma_angle_arcsec", 0, 3600, "″",
               "Quality gate: σ of each of ω, φ, κ."),
        number(at(&C::registration, &RegistrationConfig::max_sigma_translation),
               "registration.max_sigma_translation", 0, 1, "m",
               "Quality gate: σ of each of tx, ty, tz."),
        number(at(&C::registration, &RegistrationConfig::global_alpha), "registration.global_alpha",
               1e-6, 0.5, "",
               "Significance level of the global test of the variance factor. An epoch that "
               "fails it while every target passes its outlier test is accepted with the "
               "covariance scaled by s0² (`accepted_scaled`), unless the hard limit below is "
               "exceeded (docs/registration.md, \"Global test policy\")."),
        number(at(&C::registration, &RegistrationConfig::global_reject_alpha),
               "registration.global_reject_alpha", 1e-9, 0.5, "",
               "The variance factor's hard limit χ²(r, 1 − this)/r: above it an epoch that "
               "fails the global test is rejected; at most `global_alpha` (equal: every failed "
               "global test is rejected)."),
        number(at(&C::registration, &RegistrationConfig::target_alpha), "registration.target_alpha",
               1e-9, 0.5, "", "Significance level of each target's outlier test (Baarda's α0)."),
        choice(at(&C::registration, &RegistrationConfig::atmosphere), "registration.atmosphere",
               kAtmosphereCorrections,
               "`measured_air`: when the epoch has meteo values, every range (target centres, "
               "and the points handed to later stages) is corrected from the scanner's "
               "setting below to the measured air, IAG 1999 group refractivity "
               "(core/group_refractivity.hpp); the reference epoch with its own meteo. "
               "Without meteo for the epoch or the reference, nothing is corrected and the "
               "registration row says so. `off`: never corrected."),
        number(at(&C::registration, &RegistrationConfig::scanner_wavelength_nm),
               "registration.scanner_wavelength_nm", 300, 2000, "nm",
               "The scanner's carrier wavelength."),
        number(at(&C::registration, &RegistrationConfig::scanner_temperature_c),
               "registration.scanner_temperature_c", -60, 60, "°C",
               "Air temperature of the scanner's atmospheric setting."),
        number(at(&C::registration, &RegistrationConfig::scanner_pressure_hpa),
               "registration.scanner_pressure_hpa", 300, 1200, "hPa",
               "Air pressure of the scanner's atmospheric setting."),
        number(at(&C::registration, &RegistrationConfig::scanner_humidity_pct),
               "registration.scanner_humidity_pct", 0, 100, "%",
               "Relative humidity of the scanner's atmospheric setting."),
        choice(at(&C::icp, &IcpConfig::mode), "registration.icp", kIcpModes,
               "Point-to-plane ICP on the `[[stable_region]]` tables only, never on the "
               "structure (docs/registration.md). `refine`: after an accepted target "
               "registration, combined with it by weights when the two agree. `fallback`: in "
               "place of the targets when fewer than `min_targets` are usable (or they lie on a "
               "line), from the identity, the epoch accepted if the ICP passes the `icp_*` "
               "limits and the σ limits above. `both`: either. `off`: targets only. The row's "
               "`method` says which was used."),
        number(at(&C::icp, &IcpConfig::max_correspondence_distance),
               "registration.icp_max_correspondence_distance", 0.001, 1, "m",
               "ICP pairs an epoch point with the nearest reference point within this."),
        integer(at(&C::icp, &IcpConfig::max_iterations), "registration.icp_max_iterations", 1, 1000,
                "", "ICP iterations at most; not converged by then: refused."),
        number(at(&C::icp, &IcpConfig::voxel_size), "registration.icp_voxel_size", 0.01, 2, "m",
               "Both clouds are thinned to one centroid per voxel of this side; the reference's "
               "normals come from its centroids within three voxels."),
        number(at(&C::icp, &IcpConfig::min_overlap), "registration.icp_min_overlap", 0, 1, "",
               "Quality gate: share of the epoch's thinned stable points that found a pair "
               "(the fitness)."),
        integer(at(&C::icp, &IcpConfig::min_points), "registration.icp_min_points", 7, 10000000, "",
                "Quality gate: pairs at least."),
        number(at(&C::icp, &IcpConfig::max_rms), "registration.icp_max_rms", 0, 0.1, "m",
               "Quality gate: RMS of the point-to-plane distances."),
        number(at(&C::icp, &IcpConfig::cluster_size), "registration.icp_cluster_size", 0.1, 100,
               "m",
               "The ICP's covariance lets the residuals within cells of this side be correlated "
               "(cluster-robust, docs/registration.md)."),
        number(at(&C::icp, &IcpConfig::sigma_factor), "registration.icp_sigma_factor", 1, 10, "",
               "The ICP's σ is multiplied by this for what no residual shows (the footprint on "
               "grazing ground, the grid's phase); 2 is honest on the simulator "
               "(docs/registration.md)."),
        flag(at(&C::m3c2, &M3c2Config::enabled), "m3c2.enabled",
             "Run M3C2 (docs/m3c2.md) for every epoch against the reference epoch, at core "
             "points inside the zones; without any `[[zone]]` it does not run."),
        number(at(&C::m3c2, &M3c2Config::core_spacing), "m3c2.core_spacing", 0.001, 100, "m",
               "Core points: the reference's points inside the zones, one per cube of this edge "
               "(the one nearest the cube's centre; none within half of it of another). Taken "
               "once, with the reference epoch."),
        m3c2_radii(),
        number(at(&C::m3c2, &M3c2Config::cylinder_radius), "m3c2.cylinder_radius", 0.001, 100, "m",
               "Radius of the projection cylinder (d/2 of Lague 2013)."),
        number(at(&C::m3c2, &M3c2Config::max_depth), "m3c2.max_depth", 0.001, 100, "m",
               "Half-length of the cylinder along the normal: the largest change measured."),
        integer(at(&C::m3c2, &M3c2Config::min_points), "m3c2.min_points", 2, 1000000, "",
                "Points each cloud needs in a cylinder; fewer: no distance at that core point "
                "(NaN, not counted in the zone's values)."),
        m3c2_orientation(),
        choice(at(&C::m3c2, &M3c2Config::statistic), "m3c2.statistic", kM3c2Statistics,
               "Per cylinder: `mean` with the standard deviation, or `median` with the "
               "interquartile range as the spread (robust to stray points)."),
        number(at(&C::m3c2, &M3c2Config::max_roughness), "m3c2.max_roughness", 0.0001, 100, "m",
               "A core point whose reference cylinder spreads more than this along the normal "
               "(the roughness σ1 of Lague 2013; the IQR with `median`) holds an edge or a "
               "corner: no distance there (NaN, not counted in the zone's values)."),
        number(at(&C::m3c2, &M3c2Config::registration_error), "m3c2.registration_error", 0, 1, "m",
               "The LoD's registration term (reg of Lague 2013, eq. 1) when there is no "
               "registration (no `[[target]]`). With a registration it is not used: each core "
               "point gets the registration's σ along its normal."),
        integer(at(&C::m3c2, &M3c2Config::threads), "m3c2.threads", 0, 256, "",
                "Threads of the stage; 0: every core."),
        flag(at(&C::keypoints, &KeypointConfig::enabled), "keypoints.enabled",
             "Run the keypoint displacement method (docs/keypoints.md) for every epoch against "
             "the reference epoch: movement along the surface, which M3C2 does not see. With "
             "`segments = \"zones\"` it needs at least one `[[zone]]`; an epoch without a "
             "structured scan (PTX, gridded E57) is not measured by it."),
        text(at(&C::keypoints, &KeypointConfig::detector), "keypoints.detector",
             "`akaze`, `kaze`, `sift`, `brisk`, `orb`",
             "Keypoint detector in the intensity images. `akaze` keeps a pier epoch within 10 s "
             "on 2 cores; `kaze` (the Hessian response of the case study's SURF) takes about "
             "three times as long for the same accuracy (docs/keypoints.md)."),
        text(at(&C::keypoints, &KeypointConfig::descriptor), "keypoints.descriptor",
             "`brisk`, `sift`, `orb`; `kaze`/`akaze` on their own detector only",
             "Keypoint descriptor; binary ones are matched by Hamming distance."),
        flag(at(&C::keypoints, &KeypointConfig::clahe), "keypoints.clahe",
             "Equalise the 8-bit intensity image (CLAHE) before detection and description."),
        number(at(&C::keypoints, &KeypointConfig::window_deg), "keypoints.window_deg", 0.0001, 5,
               "°",
               "Matching window: an epoch keypoint is a candidate for a reference keypoint "
               "within this angle of it; the nearest descriptor wins."),
        flag(at(&C::keypoints, &KeypointConfig::refine), "keypoints.refine",
             "Refine each match by least-squares matching of the reference's intensity patch "
             "around the keypoint's nearest pixel (docs/keypoints.md): the detector's sub-pixel "
             "position follows the pixel lattice, which moves over the surface as the scanner "
             "drifts."),
        integer(at(&C::keypoints, &KeypointConfig::patch_radius), "keypoints.patch_radius", 2, 50,
                "px", "The refinement's patch: (2 · radius + 1)² pixels."),
        number(at(&C::keypoints, &KeypointConfig::ratio), "keypoints.ratio", 0, 1, "",
               "Lowe's ratio test among the candidates (best < ratio · second best); 0: off."),
        flag(at(&C::keypoints, &KeypointConfig::mutual), "keypoints.mutual",
             "Keep a match only when it is also the epoch keypoint's best in the reference."),
        number(at(&C::keypoints, &KeypointConfig::mad_k), "keypoints.mad_k", 0.5, 10, "",
               "Outlier filters: a match is removed when a quantity lies farther than "
               "k · 1.4826 · MAD from the segment's median (the method's k = 2)."),
        integer(at(&C::keypoints, &KeypointConfig::min_matches), "keypoints.min_matches", 3,
                1000000, "", "Matches a segment needs after the filters; fewer: undefined."),
        number(at(&C::keypoints, &KeypointConfig::max_incidence_deg), "keypoints.max_incidence_deg",
               0, 90, "°",
               "`segments = \"zones\"`: a match whose beam meets the zone's wall (its plane "
               "fitted to the reference's points) at a larger angle to the normal is not used: "
               "a grazing wall's image is stretched along the beam and its keypoints do not "
               "repeat (the simulated pier's west face, 87°). 90: every match."),
        number(at(&C::keypoints, &KeypointConfig::max_sample_spacing),
               "keypoints.max_sample_spacing", 0.0001, 1, "m",
               "A segment the scan samples coarser than this (the median over its matches of "
               "range × angular step) is undefined: its intensity image is aliased and the "
               "sub-pixel positions follow the scan's lattice (docs/keypoints.md, "
               "\"Sampling\"). About the beam's footprint at the structure's range."),
        choice(at(&C::keypoints, &KeypointConfig::segments), "keypoints.segments",
               kKeypointSegments,
               "`zones`: one displacement per `[[zone]]` (the zones M3C2 uses), detection "
               "confined to them. `bands`: per band of the vertical angle, zones named "
               "`keypoint_band_<lo>_<hi>`, detection in the whole image."),
        number(at(&C::keypoints, &KeypointConfig::band_width_deg), "keypoints.band_width_deg", 0.1,
               180, "°", "Width of the vertical-angle bands (`segments = \"bands\"`)."),
        number(at(&C::keypoints, &KeypointConfig::registration_error),
               "keypoints.registration_error", 0, 1, "m",
               "The LoD's registration term when there is no registration (no `[[target]]`). "
               "With a registration each segment gets the registration's σ at its centroid in "
               "the worst direction."),
        names(at(&C::keypoints, &KeypointConfig::model_quantities), "keypoints.model_quantities",
              "keypoint displacement quantities, no repeats",
              "The zone quantities the displacement model d(t, z) is refitted for each epoch, "
              "over every segment and epoch so far (`tlsmon query keypoint-models`)."),
        flag(at(&C::modbus, &ModbusConfig::enabled), "modbus.enabled",
             "Run the Modbus TCP server for SCADA (docs/modbus.md)."),
        text(at(&C::modbus, &ModbusConfig::address), "modbus.address", "an IPv4 address",
             "Address the server listens on; `0.0.0.0`: every interface."),
        integer(at(&C::modbus, &ModbusConfig::port), "modbus.port", 1, 65535, "",
                "TCP port (Modbus: 502, which needs privileges; the demo uses 1502)."),
        integer(at(&C::modbus, &ModbusConfig::unit_id), "modbus.unit_id", 0, 255, "",
                "Unit identifier answered; requests for another unit are dropped."),
        choice(at(&C::modbus, &ModbusConfig::word_order), "modbus.word_order", kWordOrders,
               "Order of the two registers of a 32-bit value (float32, uint32): `ABCD` = high "
               "word first, `CDAB` = low word first. Bytes within a register are always "
               "big-endian."),
        integer(at(&C::modbus, &ModbusConfig::max_clients), "modbus.max_clients", 1, 256, "",
                "Connections served at once; a further one is closed at once."),
        seconds(at(&C::modbus, &ModbusConfig::idle_timeout), "modbus.idle_timeout", 1, day, "",
                "A client that sends no complete request for this long is disconnected."),
        names(at(&C::modbus, &ModbusConfig::allowlist), "modbus.allowlist", "IPv4 addresses",
              "Client addresses allowed to connect; empty: any client."),
        flag(at(&C::modbus, &ModbusConfig::writable_coils), "modbus.writable_coils",
             "Whether SCADA may acknowledge alarms by writing the acknowledge coils; `false`: "
             "every write is answered with an exception."),
        names(at(&C::modbus, &ModbusConfig::quantities), "modbus.quantities",
              "1 to 8 quantity names a stage writes, no repeats; append only",
              "The quantities of each zone shown in the input registers; the position in this "
              "list is the quantity's slot in the zone's block, so add new ones at the end."),
        seconds(at(&C::modbus, &ModbusConfig::stale_seconds), "modbus.stale_seconds", 1, 30 * day,
                "",
                "A zone value whose epoch was acquired longer ago than this is flagged stale in "
                "its quality word."),
        seconds(at(&C::modbus, &ModbusConfig::snapshot_interval), "modbus.snapshot_interval", 0.1,
                3600, "",
                "The registers are rebuilt from the database after each epoch and at least "
                "this often."),

        seconds(at(&C::alarm, &AlarmConfig::cadence), "alarm.cadence", 60, day, "",
                "The scanner's interval between scans, for the `system.stale` alarm."),
        number(at(&C::alarm, &AlarmConfig::stale_factor), "alarm.stale_factor", 1, 1000, "",
               "`system.stale` is raised when no new epoch was acquired for this many "
               "`cadence` intervals."),
        number(at(&C::alarm, &AlarmConfig::disk_free_min), "alarm.disk_free_min", 0, 0.5, "",
               "`system.disk_nearly_full` is raised when the free share of the database's "
               "file system falls below this (cleared 0.01 above it). The alarm rules are "
               "the `[[alarm.rule]]` tables (docs/alarms.md)."),
    };
}

}  // namespace

const std::vector<ConfigKey>& config_keys() {
    static const std::vector<ConfigKey> keys = declare_keys();
    return keys;
}

std::vector<std::string> config_sections() {
    std::vector<std::string> out;
    for (const auto& k : config_keys()) {
        if (out.empty() || out.back() != k.section) out.push_back(k.section);
    }
    return out;
}

std::string reference_table(const std::string& section) {
    const Config defaults;
    std::string out = "| key | type | default | range | meaning |\n|---|---|---|---|---|\n";
    for (const auto& k : config_keys()) {
        if (k.section != section) continue;
        out += "| `" + k.name + "` | " + k.type + " | `" + k.value(defaults) + "` | " + k.range +
               " | " + k.help + " |\n";
    }
    return out;
}

std::string toml_string(const std::string& s) {
    std::string out = "\"";
    for (char ch : s) {
        if (ch == '"' || ch == '\\') out += '\\';
        out += ch;
    }
    return out + '"';
}

std::string toml_number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

}  // namespace tlsmon
