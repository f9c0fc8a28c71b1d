#include "core/config_key.hpp"

#include <cmath>
#include <sstream>
#include <utility>

namespace tlsmon {

std::string toml_string(const std::string& s) {
    std::string out = "\"";
    for (char ch : s) {
        if (ch == '"' || ch == '\\') out += '\\';
        out += ch;
    }
    return out + '"';
}

std::string toml_number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string duration_text(double seconds) {
    for (const auto& [unit, size] : {std::pair{"d", 86400.0}, {"h", 3600.0}, {"min", 60.0}}) {
        if (seconds >= size && std::fmod(seconds, size) == 0.0) {
            return toml_number(seconds / size) + " " + unit;
        }
    }
    return toml_number(seconds) + " s";
}

std::string joined_rules(std::initializer_list<std::string> parts) {
    std::string out;
    for (const auto& p : parts) {
        if (!p.empty()) out += (out.empty() ? "" : ", ") + p;
    }
    return out;
}

}  // namespace tlsmon
