#pragma once
#include <numbers>

namespace tlsmon {

inline constexpr double kDeg = std::numbers::pi / 180.0;  // one degree in radians

}  // namespace tlsmon
