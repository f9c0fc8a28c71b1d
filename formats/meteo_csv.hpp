#pragma once
// The meteo sidecar of a scan: `<scan stem>.meteo.csv` beside the scan, the samples a site's
// weather station logged around the acquisition (docs/formats.md, "Meteo sidecar"). Comment
// lines (`#`), a header naming the columns in any order, one row per sample:
//   time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct
//   2026-06-01T05:55:00Z,14.2,1012.3,78.0
// Every error is a FormatError naming the file and the line.
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace tlsmon {

// One logged sample.
struct MeteoRow {
    std::int64_t time_utc = 0;  // UTC seconds since 1970
    double air_temperature_c = 0;
    double pressure_hpa = 0;
    double relative_humidity_pct = 0;
    std::uint64_t line = 0;  // where it stands in the file, 1-based
};

// "pier_20260601T060000Z.meteo.csv": the name of a sidecar (compared exactly, lower case).
bool is_meteo_sidecar_name(std::string_view file_name);
// The sidecar that belongs to `scan`: the same folder and stem, ".meteo.csv".
std::filesystem::path meteo_sidecar_of(const std::filesystem::path& scan);

// A sidecar is a few hundred lines; a larger file (a 64 GiB sparse file under a sidecar's
// name) is refused by its size, never read into memory or hashed.
inline constexpr std::int64_t kMaxMeteoSidecarBytes = std::int64_t{16} << 20;

// The rows of a sidecar, in file order; at least one. `file` names the file in errors.
std::vector<MeteoRow> parse_meteo_csv(std::string_view text, const std::filesystem::path& file);

// The row nearest `acquired` (the earlier one on a tie); a FormatError naming the nearest
// row's line when it is more than `max_offset_seconds` away.
const MeteoRow& nearest_meteo_row(const std::vector<MeteoRow>& rows, std::int64_t acquired,
                                  double max_offset_seconds, const std::filesystem::path& file);

}  // namespace tlsmon
