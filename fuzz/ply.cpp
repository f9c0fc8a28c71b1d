// libFuzzer target: the PLY parser on arbitrary bytes. A FormatError is the expected answer
// to bad input; any other exception, a crash, a sanitizer report or a runaway allocation is
// a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "formats/format_error.hpp"
#include "formats/ply_reader.hpp"
#include "fuzz/scan_invariants.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        const auto scans = tlsmon::parse_ply(bytes, "fuzz-input.ply");
        tlsmon::fuzz::check_scan_invariants(scans);
    } catch (const tlsmon::FormatError&) {
    }
    return 0;
}
