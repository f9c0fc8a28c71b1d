// libFuzzer target for the LAS reader: any byte string is either one scan or a FormatError;
// so it is for the reader of points with their extra bytes.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "formats/format_error.hpp"
#include "formats/las_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::filesystem::path source = "fuzz-input.las";
    try {
        const tlsmon::Scan scan =
            tlsmon::parse_las(reinterpret_cast<const char*>(data), size, source);
        // Every point came from a record inside the input (records are at least 20 bytes).
        if (scan.size() > size / 20 || scan.intensity.size() != scan.size()) __builtin_trap();
    } catch (const tlsmon::FormatError&) {
    }
    try {
        const tlsmon::LasPoints points =
            tlsmon::parse_las_points(reinterpret_cast<const char*>(data), size, source);
        for (const auto& a : points.attributes)
            if (a.values.size() != points.xyz.size()) __builtin_trap();
    } catch (const tlsmon::FormatError&) {
    }
    return 0;
}
