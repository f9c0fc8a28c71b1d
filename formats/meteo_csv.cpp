#include "formats/meteo_csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

#include "core/text_escape.hpp"
#include "core/utc_time.hpp"
#include "formats/format_error.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kSuffix = ".meteo.csv";

// The columns a sidecar must name, and the physical range of each value. A value outside
// it is a station's error code (-999, 9999) or a broken sensor, not weather.
enum Column { time_utc, air_temperature, pressure, humidity, kColumns };
struct ColumnSpec {
    std::string_view name;
    double min, max;
    std::string_view unit;
};
constexpr std::array<ColumnSpec, kColumns> kSpecs{{
    {"time_utc", 0, 0, ""},
    {"air_temperature_c", -80, 70, "°C"},
    {"pressure_hpa", 300, 1100, "hPa"},
    {"relative_humidity_pct", 0, 100, "%"},
}};

std::string_view trimmed(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
        s.remove_suffix(1);
    }
    return s;
}

std::vector<std::string_view> fields_of(std::string_view line) {
    std::vector<std::string_view> out;
    for (;;) {
        const auto comma = line.find(',');
        out.push_back(trimmed(line.substr(0, comma)));
        if (comma == std::string_view::npos) return out;
        line.remove_prefix(comma + 1);
    }
}

// A value from the file as an error quotes it: at most 40 bytes, control characters escaped.
std::string quoted(std::string_view v) {
    constexpr std::size_t limit = 40;
    if (v.size() <= limit) return escape_control_characters(v);
    return escape_control_characters(v.substr(0, limit)) + "...";
}

bool is_digit(char c) {
    return c >= '0' && c <= '9';
}

// Exactly "YYYY-MM-DDTHH:MM:SSZ": the station's clock in UTC, whole seconds.
std::int64_t parse_time(std::string_view v, const fs::path& file, std::uint64_t line) {
    constexpr std::string_view form = "YYYY-MM-DDTHH:MM:SSZ";
    bool shape = v.size() == form.size();
    for (std::size_t i = 0; shape && i < form.size(); ++i) {
        const char f = form[i];
        shape = (f >= 'A' && f <= 'Y' && f != 'T') ? is_digit(v[i]) : v[i] == f;
    }
    if (!shape) {
        const bool has_zone = v.size() > 19 && (v[19] == '+' || v[19] == '-');
        const std::string what = has_zone || (v.size() == 19 && v.find('T') == 10)
                                     ? "is not UTC"
                                     : "is not an ISO 8601 UTC time";
        throw_at_line(file, line,
                      "time_utc '" + quoted(v) + "' " + what +
                          ": expected YYYY-MM-DDTHH:MM:SSZ (UTC, with Z)");
    }
    try {
        return parse_utc(v);
    } catch (const Error& e) {
        throw_at_line(file, line, "time_utc: " + std::string(e.what()));
    }
}

double parse_number(std::string_view v, const ColumnSpec& spec, const fs::path& file,
                    std::uint64_t line) {
    const std::string column = "column '" + std::string(spec.name) + "'";
    if (v.empty()) throw_at_line(file, line, column + ": empty value");
    const char* begin = v.data() + (v.front() == '+' ? 1 : 0);
    double x = 0;
    const auto [end, ec] = std::from_chars(begin, v.data() + v.size(), x);
    if (ec != std::errc() || end != v.data() + v.size() || !std::isfinite(x)) {
        throw_at_line(file, line, column + ": not a number: '" + quoted(v) + "'");
    }
    if (x < spec.min || x > spec.max) {
        throw_at_line(file, line,
                      column + ": " + std::string(v) + " " + std::string(spec.unit) +
                          " is outside " + std::to_string(static_cast<int>(spec.min)) + " .. " +
                          std::to_string(static_cast<int>(spec.max)) + " " +
                          std::string(spec.unit));
    }
    return x;
}

std::string expected_header() {
    std::string out;
    for (const auto& s : kSpecs) out += (out.empty() ? "" : ",") + std::string(s.name);
    return out;
}

}  // namespace

bool is_meteo_sidecar_name(std::string_view name) {
    return name.size() > kSuffix.size() && name.front() != '.' && name.ends_with(kSuffix);
}

fs::path meteo_sidecar_of(const fs::path& scan) {
    return scan.parent_path() / (scan.stem().string() + std::string(kSuffix));
}

std::vector<MeteoRow> parse_meteo_csv(std::string_view text, const fs::path& file) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte-order mark
    std::optional<std::array<std::size_t, kColumns>> where;       // field index of each column
    std::size_t header_fields = 0;
    std::uint64_t header_line = 0;
    std::vector<MeteoRow> rows;
    std::uint64_t number = 0;
    while (!text.empty()) {
        const auto eol = text.find('\n');
        const std::string_view line = trimmed(text.substr(0, eol));
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        ++number;
        if (line.empty() || line.front() == '#') continue;
        const auto fields = fields_of(line);
        if (!where) {
            std::array<std::size_t, kColumns> at{};
            at.fill(fields.size());
            for (std::size_t i = 0; i < fields.size(); ++i) {
                if (fields[i].empty()) {
                    throw_at_line(file, number,
                                  "header column " + std::to_string(i + 1) + " has no name");
                }
                for (std::size_t c = 0; c < kColumns; ++c) {
                    if (fields[i] != kSpecs[c].name) continue;
                    if (at[c] != fields.size()) {
                        throw_at_line(
                            file, number,
                            "header names column '" + std::string(kSpecs[c].name) + "' twice");
                    }
                    at[c] = i;
                }
            }
            for (std::size_t c = 0; c < kColumns; ++c) {
                if (at[c] == fields.size()) {
                    throw_at_line(file, number,
                                  "the header has no column '" + std::string(kSpecs[c].name) +
                                      "' (expected a header line naming " + expected_header() +
                                      ", in any order; found '" + quoted(line) + "')");
                }
            }
            where = at;
            header_fields = fields.size();
            header_line = number;
            continue;
        }
        if (fields.size() != header_fields) {
            throw_at_line(file, number,
                          "the row has " + std::to_string(fields.size()) +
                              " fields, the header on line " + std::to_string(header_line) +
                              " names " + std::to_string(header_fields));
        }
        const auto& at = *where;
        const std::string_view time = fields[at[time_utc]];
        if (time.empty()) throw_at_line(file, number, "column 'time_utc': empty value");
        MeteoRow row;
        row.time_utc = parse_time(time, file, number);
        row.air_temperature_c =
            parse_number(fields[at[air_temperature]], kSpecs[air_temperature], file, number);
        row.pressure_hpa = parse_number(fields[at[pressure]], kSpecs[pressure], file, number);
        row.relative_humidity_pct =
            parse_number(fields[at[humidity]], kSpecs[humidity], file, number);
        row.line = number;
        rows.push_back(row);
    }
    if (!where) {
        throw_format_error(file, "no header line (expected " + expected_header() +
                                     ", after optional # comment lines)");
    }
    if (rows.empty()) throw_at_line(file, header_line, "no rows after the header");
    return rows;
}

const MeteoRow& nearest_meteo_row(const std::vector<MeteoRow>& rows, std::int64_t acquired,
                                  double max_offset_seconds, const fs::path& file) {
    if (rows.empty()) throw_format_error(file, "no rows");
    const MeteoRow* best = &rows.front();
    const auto offset = [acquired](const MeteoRow& r) { return std::llabs(r.time_utc - acquired); };
    for (const auto& r : rows) {
        const auto d = offset(r), b = offset(*best);
        if (d < b || (d == b && r.time_utc < best->time_utc)) best = &r;
    }
    if (static_cast<double>(offset(*best)) > max_offset_seconds) {
        throw_at_line(file, best->line,
                      "the nearest row (" + format_utc(best->time_utc) + ") is " +
                          std::to_string(offset(*best)) + " s from the acquisition time " +
                          format_utc(acquired) + ", more than the " +
                          std::to_string(static_cast<long long>(max_offset_seconds)) +
                          " s allowed (meteo.max_time_offset_seconds)");
    }
    return *best;
}

}  // namespace tlsmon
