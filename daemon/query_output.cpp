// Shared by the reading commands: database location, time options, output formats.
#include "daemon/query_output.hpp"

#include <array>
#include <charconv>
#include <nlohmann/json.hpp>

#include "daemon/config.hpp"
#include "storage/utc_time.hpp"

namespace tlsmon {

void add_read_options(CLI::App* cmd, ReadOptions& options, bool with_time_range) {
    auto* db = cmd->add_option("--db", options.db, "Epoch database (SQLite file)");
    auto* config = cmd->add_option("--config", options.config,
                                   "Configuration file naming the database (paths.database)");
    db->excludes(config);
    cmd->add_option("--format", options.format, "Output format")
        ->check(CLI::IsMember({"table", "csv", "json"}));
    if (with_time_range) {
        cmd->add_option("--from", options.from, "Start, ISO-8601 UTC (e.g. 2026-03-01T00:00Z)");
        cmd->add_option("--to", options.to, "End (inclusive), ISO-8601 UTC");
    }
}

EpochDatabase open_for_reading(const ReadOptions& options) {
    std::filesystem::path path = options.db;
    if (path.empty()) {
        if (options.config.empty())
            throw Error("give the database with --db PATH or --config FILE");
        path = load_config(options.config).paths.database;
    }
    return EpochDatabase::open(path, EpochDatabase::Mode::read_only);
}

OutputFormat output_format(const ReadOptions& options) {
    if (options.format == "csv") return OutputFormat::csv;
    if (options.format == "json") return OutputFormat::json;
    return OutputFormat::table;
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

std::string cell_text(const Cell& c) {
    struct {
        std::string operator()(std::monostate) const { return ""; }
        std::string operator()(const std::string& s) const { return s; }
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

void print(std::ostream& out, const Table& table, OutputFormat format) {
    if (format == OutputFormat::json) {
        auto rows = nlohmann::ordered_json::array();
        for (const auto& row : table.rows) {
            nlohmann::ordered_json object = nlohmann::ordered_json::object();
            for (std::size_t i = 0; i < table.columns.size(); ++i) {
                object[table.columns[i]] = cell_json(row[i]);
            }
            rows.push_back(std::move(object));
        }
        out << rows.dump(2) << '\n';
        return;
    }
    std::vector<std::vector<std::string>> text;
    text.reserve(table.rows.size());
    for (const auto& row : table.rows) {
        std::vector<std::string> line;
        for (const auto& c : row) line.push_back(cell_text(c));
        text.push_back(std::move(line));
    }
    if (format == OutputFormat::csv) {
        print_csv_line(out, table.columns);
        for (const auto& line : text) print_csv_line(out, line);
        return;
    }
    std::vector<std::size_t> width(table.columns.size());
    for (std::size_t i = 0; i < width.size(); ++i) width[i] = table.columns[i].size();
    for (const auto& line : text) {
        for (std::size_t i = 0; i < width.size(); ++i)
            width[i] = std::max(width[i], line[i].size());
    }
    auto emit = [&](const std::vector<std::string>& line) {
        std::string s;
        for (std::size_t i = 0; i < width.size(); ++i) {
            s += line[i];
            if (i + 1 < width.size()) s += std::string(width[i] - line[i].size() + 2, ' ');
        }
        out << s << '\n';
    };
    emit(table.columns);
    for (const auto& line : text) emit(line);
}

void print_fields(std::ostream& out, const std::vector<std::pair<std::string, Cell>>& fields,
                  OutputFormat format) {
    if (format == OutputFormat::json) {
        nlohmann::ordered_json object = nlohmann::ordered_json::object();
        for (const auto& [key, value] : fields) object[key] = cell_json(value);
        out << object.dump(2) << '\n';
        return;
    }
    if (format == OutputFormat::csv) print_csv_line(out, {"key", "value"});
    std::size_t width = 0;
    for (const auto& f : fields) width = std::max(width, f.first.size());
    for (const auto& [key, value] : fields) {
        if (format == OutputFormat::csv) {
            print_csv_line(out, {key, cell_text(value)});
        } else {
            out << key << std::string(width - key.size() + 2, ' ') << cell_text(value) << '\n';
        }
    }
}

}  // namespace tlsmon
