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

}  // namespace tlsmon
