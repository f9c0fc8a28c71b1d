// Shared by the reading commands: database location, time options, output formats.
#include "cli/query_output.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <span>
#include <string_view>

#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/text_escape.hpp"
#include "core/toml_fields.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

std::filesystem::path database_path(const ReadOptions& options) {
    if (!options.db.empty()) return options.db;
    if (options.config.empty()) throw Error("give the database with --db PATH or --config FILE");
    return load_config(options.config).paths.database;
}

EpochDatabase open_for_reading(const ReadOptions& options) {
    return EpochDatabase::open(database_path(options), EpochDatabase::Mode::read_only);
}

EpochDatabase open_for_writing(const std::string& db, const std::string& config) {
    const auto path = database_path(ReadOptions{db, config, OutputFormat::table, "", ""});
    if (!std::filesystem::exists(path)) throw Error("no epoch database " + path.string());
    return EpochDatabase::open(path, EpochDatabase::Mode::read_write);
}

std::string cli_actor(const std::string& by) {
    if (!by.empty()) return by;
    const char* user = std::getenv("USER");
    return user && *user ? std::string("cli:") + user : "cli";
}

UtcSeconds time_bound(const std::string& text, UtcSeconds now) {
    if (text == "now") return now;
    if (text.starts_with('-')) {
        try {
            return now - std::llround(parse_duration_seconds(text.substr(1)));
        } catch (const ConfigError& e) {
            throw Error("time '" + text + "': " + e.what());
        }
    }
    return parse_utc(text);
}

TimeRange time_range(const ReadOptions& options) {
    TimeRange range;
    const UtcSeconds now = now_utc();
    const auto bound = [&](const char* argument, const std::string& text) {
        try {
            return time_bound(text, now);
        } catch (const Error& e) {
            throw Error(std::string(argument) + ": " + e.what());
        }
    };
    if (!options.from.empty()) range.from = bound("--from", options.from);
    if (!options.to.empty()) range.to = bound("--to", options.to);
    if (range.from && range.to && *range.from > *range.to) {
        throw Error("--from " + options.from + " is after --to " + options.to);
    }
    return range;
}

Cell structured_cell(Structured value) {
    return std::make_shared<const Structured>(std::move(value));
}

Cell optional_cell(const std::optional<double>& v) {
    return v ? Cell(*v) : Cell();
}
Cell optional_cell(const std::optional<std::int64_t>& v) {
    return v ? Cell(*v) : Cell();
}
Cell optional_time_cell(const std::optional<UtcSeconds>& t) {
    return t ? Cell(format_utc(*t)) : Cell();
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
    char buf[400];  // a fixed-point double needs at most 309 digits before the point
    const auto written =
        decimals ? std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, *decimals)
                 : std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
    std::string text(buf, written.ptr);
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
        std::string operator()(const StructuredCell& s) const {
            return escape_control_characters(s->text);
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
        nlohmann::ordered_json operator()(const StructuredCell& s) const {
            return nlohmann::ordered_json::parse(s->json);
        }
    } visitor;
    return std::visit(visitor, c);
}

// A JSON string literal; bytes that are not UTF-8 (a Latin-1 file name) become U+FFFD
// instead of an exception.
std::string json_string(const std::string& s) {
    // Printable ASCII without a quote or backslash is its own JSON text (a time, a status):
    // the common case, without a JSON value per cell (a year of one series has 105,000).
    if (std::all_of(s.begin(), s.end(),
                    [](char c) { return c >= 0x20 && c < 0x7F && c != '"' && c != '\\'; }))
        return '"' + s + '"';
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
    } else if (const auto* structured = std::get_if<StructuredCell>(&c)) {
        buf += (*structured)->json;
    } else {
        buf += cell_text(c, {}, OutputFormat::json);  // integer or true/false
    }
}

}  // namespace

RowPrinter::RowPrinter(std::ostream& out, std::vector<std::string> columns,
                       std::vector<std::string> rounded_as, OutputFormat format)
    : out_(out), columns_(std::move(columns)), format_(format) {
    rounding_.resize(columns_.size());
    for (std::size_t i = 0; i < columns_.size(); ++i) {
        const bool own = i >= rounded_as.size() || rounded_as[i].empty();
        rounding_[i] = own ? columns_[i] : rounded_as[i];
    }
    buf_.reserve(kBlock + 4096);
    if (format_ == OutputFormat::json) {
        for (const auto& c : columns_) keys_.push_back(json_string(c) + ": ");
        buf_ += '[';
    } else if (format_ == OutputFormat::csv) {
        for (std::size_t i = 0; i < columns_.size(); ++i) {
            if (i) buf_ += ',';
            buf_ += csv_field(columns_[i]);
        }
        end_line();
    } else {
        width_.assign(columns_.size(), 0);
        for (const auto& c : columns_) add_cell_text(c);
    }
}

void RowPrinter::row(std::span<const Cell> cells) {
    if (format_ == OutputFormat::json) {
        if (rows_) buf_ += ',';
        end_line();
        buf_ += "  {";
        for (std::size_t i = 0; i < columns_.size(); ++i) {
            if (i) buf_ += ", ";
            buf_ += keys_[i];
            append_json(buf_, cells[i]);
        }
        buf_ += '}';
    } else if (format_ == OutputFormat::csv) {
        for (std::size_t i = 0; i < columns_.size(); ++i) {
            if (i) buf_ += ',';
            buf_ += csv_field(cell_text(cells[i], rounding_[i], format_));
        }
        end_line();
    } else {
        for (std::size_t i = 0; i < columns_.size(); ++i) {
            add_cell_text(cell_text(cells[i], rounding_[i], format_));
        }
    }
    ++rows_;
}

// A table's cells are kept as text, each ended by a NUL (escaped text holds none), in
// blocks of 1 MiB: no object per cell, and no copy of the whole when it grows.
void RowPrinter::add_cell_text(std::string_view text) {
    const std::size_t column = cells_ % columns_.size();
    width_[column] = std::max(width_[column], text.size());
    if (text_.empty() || text_.back().size() + text.size() + 1 > text_.back().capacity()) {
        text_.emplace_back().reserve(std::max(kTextBlock, text.size() + 1));
    }
    text_.back() += text;
    text_.back() += '\0';
    ++cells_;
}

void RowPrinter::finish() {
    if (format_ == OutputFormat::json) {
        if (rows_) end_line();
        buf_ += ']';
        end_line();
    } else if (format_ == OutputFormat::table) {
        const std::size_t columns = columns_.size();
        std::size_t k = 0;
        for (const auto& block : text_) {
            for (std::size_t at = 0; at < block.size(); ++k) {
                const std::size_t end = block.find('\0', at);
                const auto c = std::string_view(block).substr(at, end - at);
                at = end + 1;
                buf_ += c;
                const std::size_t i = k % columns;
                if (i + 1 < columns) {
                    buf_.append(width_[i] - c.size() + 2, ' ');
                } else {
                    end_line();
                }
            }
        }
    }
    flush();
}

void RowPrinter::end_line() {
    buf_ += '\n';
    if (buf_.size() >= kBlock) flush();
}

void RowPrinter::flush() {
    out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
}

void print(std::ostream& out, const Table& table, OutputFormat format) {
    RowPrinter printer(out, table.columns, table.rounded_as, format);
    for (const auto& row : table.rows) printer.row(row);
    printer.finish();
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
