// Shared by the reading commands: database location, time options, output formats.
#include "cli/query_output.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <span>
#include <string_view>

#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/text_escape.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

EpochDatabase open_for_reading(const ReadOptions& options) {
    std::filesystem::path path = options.db;
    if (path.empty()) {
        if (options.config.empty())
            throw Error("give the database with --db PATH or --config FILE");
        path = load_config(options.config).paths.database;
    }
    return EpochDatabase::open(path, EpochDatabase::Mode::read_only);
}

TimeRange time_range(const ReadOptions& options) {
    TimeRange range;
    if (!options.from.empty()) range.from = parse_utc(options.from);
    if (!options.to.empty()) range.to = parse_utc(options.to);
    if (range.from && range.to && *range.from > *range.to) {
        throw Error("--from " + options.from + " is after --to " + options.to);
    }
    return range;
}

Cell optional_cell(const std::optional<double>& v) {
    return v ? Cell(*v) : Cell();
}
Cell optional_cell(const std::optional<std::int64_t>& v) {
    return v ? Cell(*v) : Cell();
}

namespace {

// The decimals a table shows for a column, from the unit its name ends with (lengths to
// the micrometre, times to the millisecond, weather to its sensors' resolution); none for a
// column without a unit: six significant digits then.
std::optional<int> table_decimals(std::string_view column) {
    static constexpr std::pair<std::string_view, int> kUnits[] = {
        {"_m", 6},   {"_mm", 3},  {"_ms", 1},  {"_s", 3},         {"_deg", 6}, {"_c", 2},
        {"_hpa", 1}, {"_pct", 1}, {"_ppm", 2}, {"_m_per_day", 6}, {"_px", 2},  {"_arcsec", 2}};
    for (const auto& [suffix, decimals] : kUnits)
        if (column.ends_with(suffix)) return decimals;
    return std::nullopt;
}

// A number for a person: rounded to its column's resolution, no "-0".
std::string table_number(double v, std::string_view column) {
    if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
    const auto decimals = table_decimals(column);
    std::string text = decimals ? fmt::format("{:.{}f}", v, *decimals) : fmt::format("{:.6g}", v);
    if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
    return text;
}

// Text for a terminal or a CSV file: a file name with a newline or ESC[31m can neither
// start a row nor colour the analyst's terminal (escaped as in the log; JSON escapes its
// own control characters). Numbers at full precision in CSV, rounded in a table.
std::string cell_text(const Cell& c, std::string_view column, OutputFormat format) {
    if (const auto* d = std::get_if<double>(&c))
        return format == OutputFormat::table ? table_number(*d, column) : csv_number(*d);
    struct {
        std::string operator()(std::monostate) const { return ""; }
        std::string operator()(const std::string& s) const { return escape_control_characters(s); }
        std::string operator()(std::int64_t i) const { return std::to_string(i); }
        std::string operator()(double d) const { return csv_number(d); }
        std::string operator()(bool b) const { return b ? "true" : "false"; }
        std::string operator()(const Structured& s) const {
            return escape_control_characters(s.text);
        }
    } visitor;
    return std::visit(visitor, c);
}

nlohmann::ordered_json cell_json(const Cell& c) {
    struct {
        nlohmann::ordered_json operator()(std::monostate) const { return nullptr; }
        nlohmann::ordered_json operator()(const std::string& s) const { return s; }
        nlohmann::ordered_json operator()(std::int64_t i) const { return i; }
        nlohmann::ordered_json operator()(double d) const { return d; }  // NaN: null
        nlohmann::ordered_json operator()(bool b) const { return b; }
        nlohmann::ordered_json operator()(const Structured& s) const {
            return nlohmann::ordered_json::parse(s.json);
        }
    } visitor;
    return std::visit(visitor, c);
}

// A JSON string literal; bytes that are not UTF-8 (a Latin-1 file name) become U+FFFD
// instead of an exception.
std::string json_string(const std::string& s) {
    return nlohmann::ordered_json(s).dump(-1, ' ', false,
                                          nlohmann::ordered_json::error_handler_t::replace);
}

void append_json(std::string& buf, const Cell& c) {
    if (const auto* d = std::get_if<double>(&c)) {
        buf += std::isfinite(*d) ? csv_number(*d) : "null";  // JSON has no NaN/Inf
    } else if (const auto* s = std::get_if<std::string>(&c)) {
        buf += json_string(*s);
    } else if (std::holds_alternative<std::monostate>(c)) {
        buf += "null";
    } else if (const auto* structured = std::get_if<Structured>(&c)) {
        buf += structured->json;
    } else {
        buf += cell_text(c, {}, OutputFormat::json);  // integer or true/false
    }
}

}  // namespace

// Everything is formatted into one buffer and written once: a year of 15-minute epochs is
// 35,040 rows.
void print(std::ostream& out, const Table& table, OutputFormat format) {
    const std::size_t columns = table.columns.size();
    std::string buf;
    buf.reserve(table.rows.size() * 100 + 256);
    if (format == OutputFormat::json) {
        std::vector<std::string> keys;
        for (const auto& c : table.columns) keys.push_back(json_string(c) + ": ");
        buf += '[';
        for (std::size_t r = 0; r < table.rows.size(); ++r) {
            buf += r ? ",\n  {" : "\n  {";
            for (std::size_t i = 0; i < columns; ++i) {
                if (i) buf += ", ";
                buf += keys[i];
                append_json(buf, table.rows[r][i]);
            }
            buf += '}';
        }
        buf += table.rows.empty() ? "]\n" : "\n]\n";
        out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        return;
    }
    std::vector<std::string> text;  // header, then the rows, row-major
    text.reserve((table.rows.size() + 1) * columns);
    for (const auto& c : table.columns) text.push_back(c);
    for (const auto& row : table.rows) {
        for (std::size_t i = 0; i < columns; ++i) {
            const bool own = i >= table.rounded_as.size() || table.rounded_as[i].empty();
            text.push_back(cell_text(row[i], own ? table.columns[i] : table.rounded_as[i], format));
        }
    }
    const std::size_t lines = table.rows.size() + 1;
    if (format == OutputFormat::csv) {
        for (std::size_t l = 0; l < lines; ++l)
            append_csv_line(buf, std::span(text).subspan(l * columns, columns));
        out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        return;
    }
    std::vector<std::size_t> width(columns, 0);
    for (std::size_t k = 0; k < text.size(); ++k) {
        width[k % columns] = std::max(width[k % columns], text[k].size());
    }
    for (std::size_t l = 0; l < lines; ++l) {
        for (std::size_t i = 0; i < columns; ++i) {
            const auto& cell = text[l * columns + i];
            buf += cell;
            if (i + 1 < columns) buf.append(width[i] - cell.size() + 2, ' ');
        }
        buf += '\n';
    }
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

void print_fields(std::ostream& out, const std::vector<std::pair<std::string, Cell>>& fields,
                  OutputFormat format) {
    if (format == OutputFormat::json) {
        nlohmann::ordered_json object = nlohmann::ordered_json::object();
        for (const auto& [key, value] : fields) object[key] = cell_json(value);
        out << object.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << '\n';
        return;
    }
    std::string buf;
    if (format == OutputFormat::csv) buf = "key,value\n";
    std::size_t width = 0;
    for (const auto& f : fields) width = std::max(width, f.first.size());
    for (const auto& [key, value] : fields) {
        const std::string text = cell_text(value, key, format);
        if (format == OutputFormat::csv) {
            buf += csv_line(std::vector<std::string>{key, text});
        } else {
            buf += escape_control_characters(key) + std::string(width - key.size() + 2, ' ') +
                   text + '\n';
        }
    }
    out << buf;
}

}  // namespace tlsmon
