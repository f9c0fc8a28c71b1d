// Shared by the reading commands: database location, time options, output formats.
#include "daemon/query_output.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/text_escape.hpp"
#include "core/utc_time.hpp"
#include "daemon/config.hpp"

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

// Shortest text that reads back to the same double; plain decimals (0.0001, not 1e-04)
// unless that takes more than 24 characters.
std::string number_text(double v) {
    std::array<char, 24> fixed{};
    const auto f =
        std::to_chars(fixed.data(), fixed.data() + fixed.size(), v, std::chars_format::fixed);
    if (f.ec == std::errc()) return std::string(fixed.data(), f.ptr);
    std::array<char, 32> buf{};
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), r.ptr);
}

// Text for a terminal or a CSV file: a file name with a newline or ESC[31m can neither
// start a row nor colour the analyst's terminal (escaped as in the log; JSON escapes its
// own control characters).
std::string cell_text(const Cell& c) {
    struct {
        std::string operator()(std::monostate) const { return ""; }
        std::string operator()(const std::string& s) const { return escape_control_characters(s); }
        std::string operator()(std::int64_t i) const { return std::to_string(i); }
        std::string operator()(double d) const { return number_text(d); }
        std::string operator()(bool b) const { return b ? "true" : "false"; }
    } visitor;
    return std::visit(visitor, c);
}

nlohmann::ordered_json cell_json(const Cell& c) {
    struct {
        nlohmann::ordered_json operator()(std::monostate) const { return nullptr; }
        nlohmann::ordered_json operator()(const std::string& s) const { return s; }
        nlohmann::ordered_json operator()(std::int64_t i) const { return i; }
        nlohmann::ordered_json operator()(double d) const { return d; }
        nlohmann::ordered_json operator()(bool b) const { return b; }
    } visitor;
    return std::visit(visitor, c);
}

// RFC 4180: quote a field holding a comma, quote or line break; double inner quotes.
std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char ch : s) {
        if (ch == '"') out += '"';
        out += ch;
    }
    return out + '"';
}

void print_csv_line(std::ostream& out, const std::vector<std::string>& fields) {
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i) out << ',';
        out << csv_field(fields[i]);
    }
    out << '\n';
}

}  // namespace

namespace {

// A JSON string literal; bytes that are not UTF-8 (a Latin-1 file name) become U+FFFD
// instead of an exception.
std::string json_string(const std::string& s) {
    return nlohmann::ordered_json(s).dump(-1, ' ', false,
                                          nlohmann::ordered_json::error_handler_t::replace);
}

void append_json(std::string& buf, const Cell& c) {
    if (const auto* d = std::get_if<double>(&c)) {
        buf += std::isfinite(*d) ? number_text(*d) : "null";  // JSON has no NaN/Inf
    } else if (const auto* s = std::get_if<std::string>(&c)) {
        buf += json_string(*s);
    } else if (std::holds_alternative<std::monostate>(c)) {
        buf += "null";
    } else {
        buf += cell_text(c);  // integer or true/false
    }
}

void append_csv_line(std::string& buf, const std::vector<std::string>& fields, std::size_t first,
                     std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
        if (i) buf += ',';
        buf += csv_field(fields[first + i]);
    }
    buf += '\n';
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
        for (const auto& c : row) text.push_back(cell_text(c));
    }
    const std::size_t lines = table.rows.size() + 1;
    if (format == OutputFormat::csv) {
        for (std::size_t l = 0; l < lines; ++l) append_csv_line(buf, text, l * columns, columns);
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
    if (format == OutputFormat::csv) print_csv_line(out, {"key", "value"});
    std::size_t width = 0;
    for (const auto& f : fields) width = std::max(width, f.first.size());
    for (const auto& [key, value] : fields) {
        if (format == OutputFormat::csv) {
            print_csv_line(out, {key, cell_text(value)});
        } else {
            out << escape_control_characters(key) << std::string(width - key.size() + 2, ' ')
                << cell_text(value) << '\n';
        }
    }
}

}  // namespace tlsmon
