#pragma once
// Errors of the readers: every message names the file and where in it (line or byte).
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/error.hpp"

namespace tlsmon {

// No coordinate on Earth, in any projected frame, lies beyond 1e8 m (UTM northings reach
// 1e7 m, state-plane feet 2e7): the readers refuse what lies further as corrupt.
inline constexpr double kMaxCoordinate = 1e8;

class FormatError : public Error {
  public:
    using Error::Error;
};

[[noreturn]] void throw_format_error(const std::filesystem::path& file, const std::string& what);
[[noreturn]] void throw_at_line(const std::filesystem::path& file, std::uint64_t line,
                                const std::string& what);
[[noreturn]] void throw_at_byte(const std::filesystem::path& file, std::uint64_t offset,
                                const std::string& what);

}  // namespace tlsmon
