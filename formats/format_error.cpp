#include "formats/format_error.hpp"

namespace tlsmon {

void throw_format_error(const std::filesystem::path& file, const std::string& what) {
    throw FormatError(file.string() + ": " + what);
}

void throw_at_line(const std::filesystem::path& file, std::uint64_t line, const std::string& what) {
    throw FormatError(file.string() + ":" + std::to_string(line) + ": " + what);
}

void throw_at_byte(const std::filesystem::path& file, std::uint64_t offset,
                   const std::string& what) {
    throw FormatError(file.string() + ": at byte " + std::to_string(offset) + ": " + what);
}

}  // namespace tlsmon
