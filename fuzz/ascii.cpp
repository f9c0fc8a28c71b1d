// libFuzzer target: the PTS and XYZ parsers on arbitrary bytes. A FormatError is the
// expected answer to bad input; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "formats/ascii_reader.hpp"
#include "formats/format_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    for (auto* parse : {&tlsmon::parse_pts, &tlsmon::parse_xyz}) {
        try {
            for (const auto& scan : parse(text, "fuzz-input")) {
                if (!scan.intensity.empty() && scan.intensity.size() != scan.size()) {
                    __builtin_trap();
                }
                if (!scan.rgb.empty() && scan.rgb.size() != scan.size()) __builtin_trap();
            }
        } catch (const tlsmon::FormatError&) {
        }
    }
    return 0;
}
