#pragma once
// What `tlsmon status|query|events` share: where the database is (--db or --config), and
// printing a result as an aligned table, CSV (RFC 4180) or JSON.
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
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
// text.
using Cell = std::variant<std::monostate, std::string, std::int64_t, double, bool, Structured>;

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
    std::string from, to;  // ISO-8601 UTC, empty = open
};

// The database named by --db, or the one of --config's file; opened read-only.
EpochDatabase open_for_reading(const ReadOptions& options);
TimeRange time_range(const ReadOptions& options);  // throws Error for unreadable times

Cell optional_cell(const std::optional<double>& v);
Cell optional_cell(const std::optional<std::int64_t>& v);

// Rows as an aligned table, CSV with a header line, or a JSON array of objects.
void print(std::ostream& out, const Table& table, OutputFormat format);
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
