#pragma once
// Numbers with a fixed count of decimals, for tables and results read by people.
#include <cmath>
#include <cstdio>
#include <string>

namespace tlsmon {

// `value` as printf's "%.*f" writes it; "nan" for NaN whatever its sign bit.
inline std::string fixed_decimals(double value, int decimals) {
    if (std::isnan(value)) return "nan";
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

}  // namespace tlsmon
