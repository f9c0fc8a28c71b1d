#include "core/csv.hpp"

#include <charconv>
#include <cmath>

namespace tlsmon {

std::string csv_field(std::string_view text) {
    if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + '"';
}

// std::to_chars without a precision: the shortest text that reads back to the same value,
// in plain decimals (0.0001, not 1e-04) unless that takes more than 24 characters.
std::string csv_number(double value) {
    if (!std::isfinite(value)) return {};
    char text[32];
    const auto fixed = std::to_chars(text, text + 24, value, std::chars_format::fixed);
    if (fixed.ec == std::errc()) return std::string(text, fixed.ptr);
    return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

void append_csv_line(std::string& out, std::span<const std::string> fields) {
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i) out += ',';
        out += csv_field(fields[i]);
    }
    out += '\n';
}

std::string csv_line(std::span<const std::string> fields) {
    std::string out;
    append_csv_line(out, fields);
    return out;
}

}  // namespace tlsmon
