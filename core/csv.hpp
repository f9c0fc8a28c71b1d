#pragma once
// CSV as RFC 4180 writes it, the one writer of every CSV file and CSV output of tlsmon
// (query output, the report's tables, the one-shot commands' results, the Modbus map).
// Numbers at full precision: a table for people rounds, a CSV for programs does not.
#include <span>
#include <string>
#include <string_view>

namespace tlsmon {

// A field as it is written: quoted when it holds a comma, a quote or a line break, inner
// quotes doubled.
std::string csv_field(std::string_view text);

// A number as the shortest text that reads back to the same double, in plain decimals when
// that takes at most 24 characters; "" (a missing value) for NaN and infinities.
std::string csv_number(double value);

// One record: the fields through csv_field, separated by commas, ended by "\n".
void append_csv_line(std::string& out, std::span<const std::string> fields);
std::string csv_line(std::span<const std::string> fields);

}  // namespace tlsmon
