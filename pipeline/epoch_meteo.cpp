#include "pipeline/epoch_meteo.hpp"

#include <cerrno>

#include "formats/format_error.hpp"
#include "formats/meteo_csv.hpp"
#include "pipeline/sha256.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

std::optional<MeteoSidecar> read_epoch_meteo(const fs::path& sidecar, const Epoch& epoch,
                                             const MeteoConfig& config) {
    MeteoSidecar m;
    m.epoch = epoch.id;
    m.file_name = sidecar.filename().string();
    std::error_code size_error;
    const auto size = fs::file_size(sidecar, size_error);
    if (!size_error && size > static_cast<std::uintmax_t>(kMaxMeteoSidecarBytes)) {
        m.outcome = MeteoOutcome::rejected;
        m.sha256 = sha256_text("too large\n" + m.file_name + "\n" + std::to_string(size));
        m.reason = sidecar.string() + ": " + std::to_string(size) +
                   " bytes, more than a meteo sidecar holds (16 MiB): not read";
        return m;
    }
    HashedBytes content;
    try {
        content = read_file_hashed(sidecar);
    } catch (const FileAccessError& e) {
        if (e.error_number() == ENOENT) return std::nullopt;
        // No content to hash: identified by its name, as an unreadable scan is.
        m.outcome = MeteoOutcome::rejected;
        m.sha256 = sha256_text("unreadable\n" + m.file_name);
        m.reason = e.what();
        return m;
    }
    m.sha256 = content.sha256;
    try {
        const auto rows = parse_meteo_csv(content.bytes, sidecar);
        const MeteoRow& row =
            nearest_meteo_row(rows, epoch.acquired, config.max_time_offset_seconds, sidecar);
        m.outcome = MeteoOutcome::used;
        m.values = MeteoValues{row.time_utc, static_cast<std::int64_t>(row.line),
                               row.air_temperature_c, row.pressure_hpa, row.relative_humidity_pct};
    } catch (const FormatError& e) {
        m.outcome = MeteoOutcome::rejected;
        m.reason = e.what();
    }
    return m;
}

std::vector<SectionKey<MeteoConfig>> meteo_keys() {
    using K = Keys<MeteoConfig>;
    constexpr double day = 86400.0;
    return {
        K::seconds(&MeteoConfig::wait_seconds, "wait_seconds", 0, day, "",
                   "How long a new scan waits for its meteo sidecar `<scan stem>.meteo.csv` "
                   "(docs/formats.md), counted from when the scan was recorded (so also across a "
                   "restart). Epochs are processed in acquisition order: later scans wait behind "
                   "it; files keep being taken meanwhile. Without a sidecar by then the epoch is "
                   "processed without meteo, with a warning and a `meteo_missing` system event. "
                   "0: no waiting, and no event (a site without a weather station); a sidecar "
                   "already there is still used."),
        K::seconds(
            &MeteoConfig::max_time_offset_seconds, "max_time_offset_seconds", 0, day, "",
            "The sidecar's row nearest the acquisition time is used if it lies within this; "
            "otherwise the sidecar is rejected (quarantined, `meteo_rejected` event) and the "
            "epoch is processed without meteo."),
        K::seconds(&MeteoConfig::orphan_seconds, "orphan_seconds", 1, 30 * day, "",
                   "A complete sidecar whose scan has not arrived after this long is moved to "
                   "`paths.quarantine` with its reason and a `meteo_orphan` system event."),
    };
}

}  // namespace tlsmon
