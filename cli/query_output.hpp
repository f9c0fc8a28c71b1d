#pragma once
// What `tlsmon status|query|events` share: where the database is (--db or --config), and
// printing a result as an aligned table, CSV (RFC 4180) or JSON.
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "storage/epoch_database.hpp"

namespace tlsmon {

enum class OutputFormat { table, csv, json };

// A value with parts (each target of a registration, each zone's σ): one line of text in a
// table or CSV, a nested JSON value in JSON, so a program never parses free text.
struct Structured {
    std::string text;
    std::string json;  // one JSON value
};

// A printed value: null, text, integer, real, flag or structured. Times are ISO-8601 UTC
// text. A structured value is held by pointer, so a cell is no larger than a string (a year
// of one series is 280,000 cells).
using StructuredCell = std::shared_ptr<const Structured>;
using Cell = std::variant<std::monostate, std::string, std::int64_t, double, bool, StructuredCell>;
Cell structured_cell(Structured value);

struct Table {
    std::vector<std::string> columns;
    std::vector<std::vector<Cell>> rows;
    // Per column, the name whose unit suffix sets the table's rounding when the column's own
    // name has none (a series' value is in its quantity's unit: "m3c2_median_m"); empty: the
    // columns' own names.
    std::vector<std::string> rounded_as = {};
};

// The options every reading command takes (cli/main.cpp declares them).
struct ReadOptions {
    std::string db;
    std::string config;
    OutputFormat format = OutputFormat::table;
    std::string from, to;  // ISO-8601 UTC, "now" or a duration before now ("-7d"); empty = open
};

// The database named by --db, or the one of --config's file.
std::filesystem::path database_path(const ReadOptions& options);
// That database, opened read-only.
EpochDatabase open_for_reading(const ReadOptions& options);
// The database of --db, or of --config's file, opened to write (an operator's action); an
// Error when it does not exist (never created by an action).
EpochDatabase open_for_writing(const std::string& db, const std::string& config);
// Who acts, for the audit in system events: `by` when given, else "cli:$USER".
std::string cli_actor(const std::string& by);
TimeRange time_range(const ReadOptions& options);  // throws Error for unreadable times
// One bound: ISO-8601 UTC, "now", or a duration before `now` ("-7d", "-12h", "-30min").
UtcSeconds time_bound(const std::string& text, UtcSeconds now);

Cell optional_cell(const std::optional<double>& v);
Cell optional_cell(const std::optional<std::int64_t>& v);
// A time as ISO-8601 UTC text, null when absent.
Cell optional_time_cell(const std::optional<UtcSeconds>& t);

// Rows as an aligned table, CSV with a header line, or a JSON array of objects.
void print(std::ostream& out, const Table& table, OutputFormat format);

// The same, row by row, for a command with many rows (a year of one series is 35,040): CSV
// and JSON go out in blocks of 64 KiB as the rows come, an aligned table keeps only its
// text until finish() knows every column's width. No row is kept as cells.
class RowPrinter {
  public:
    RowPrinter(std::ostream& out, std::vector<std::string> columns,
               std::vector<std::string> rounded_as, OutputFormat format);
    RowPrinter(const RowPrinter&) = delete;
    RowPrinter& operator=(const RowPrinter&) = delete;
    void row(std::span<const Cell> cells);  // one cell per column
    void finish();                          // the table, or the end of the JSON array

  private:
    static constexpr std::size_t kBlock = 64 * 1024;
    void add_cell_text(std::string_view text);
    void end_line();
    void flush();

    std::ostream& out_;
    std::vector<std::string> columns_;
    std::vector<std::string> rounding_;  // the name whose unit rounds each column
    OutputFormat format_;
    std::vector<std::string> keys_;  // JSON: "column": per column
    std::string buf_;                // the block being written
    static constexpr std::size_t kTextBlock = 1024 * 1024;
    std::vector<std::string> text_;   // table: the cells' text, row-major from the header
    std::size_t cells_ = 0;           // table: cells in text_
    std::vector<std::size_t> width_;  // table: widest text per column
    std::size_t rows_ = 0;
};
// Key/value pairs as "key  value" lines, CSV "key,value" lines, or one JSON object.
void print_fields(std::ostream& out, const std::vector<std::pair<std::string, Cell>>& fields,
                  OutputFormat format);

// Runs `body` and returns the exit status: 0, or 1 after an Error was printed on stderr
// as "tlsmon <command>: message".
template <class F>
int run_reporting_errors(const std::string& command, F&& body) {
    try {
        body();
        return 0;
    } catch (const Error& e) {
        std::cerr << "tlsmon " << command << ": " << e.what() << '\n';
        return 1;
    }
}

}  // namespace tlsmon
