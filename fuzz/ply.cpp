// libFuzzer target: the PLY parser on arbitrary bytes. A FormatError is the expected answer
// to bad input; any other exception, a crash, a sanitizer report or a runaway allocation is
// a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "formats/format_error.hpp"
#include "formats/ply_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        const auto scans = tlsmon::parse_ply(bytes, "fuzz-input.ply");
        for (const auto& scan : scans) {
            // Every per-point array is empty or as long as xyz; grid cells lie in the grid.
            if (!scan.intensity.empty() && scan.intensity.size() != scan.size()) __builtin_trap();
            if (!scan.rgb.empty() && scan.rgb.size() != scan.size()) __builtin_trap();
            if (!scan.grid) continue;
            if (scan.grid->row.size() != scan.size()) __builtin_trap();
            for (std::size_t k = 0; k < scan.size(); ++k) {
                if (scan.grid->row[k] >= scan.grid->rows) __builtin_trap();
                if (scan.grid->column[k] >= scan.grid->columns) __builtin_trap();
            }
        }
    } catch (const tlsmon::FormatError&) {
    }
    return 0;
}
