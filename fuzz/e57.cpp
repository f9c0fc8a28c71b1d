// libFuzzer target for the E57 reader: any byte string is either scans or a FormatError.
// Each page's CRC-32C is recomputed before parsing, so that mutations reach the XML and
// the compressed vectors instead of stopping at the checksum (the checksum failure itself
// is tested in tests/formats/test_e57_reader.cpp).
#include <boost/crc.hpp>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "formats/e57_reader.hpp"
#include "formats/format_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::filesystem::path source = "fuzz-input.e57";
    std::vector<char> bytes(data, data + size);
    for (std::size_t page = 0; page + 1024 <= size; page += 1024) {
        boost::crc_optimal<32, 0x1EDC6F41, 0xFFFFFFFF, 0xFFFFFFFF, true, true> crc;
        crc.process_bytes(bytes.data() + page, 1020);
        const std::uint32_t c = crc.checksum();
        for (int i = 0; i < 4; ++i) bytes[page + 1020 + i] = static_cast<char>(c >> (24 - 8 * i));
    }
    try {
        const auto scans = tlsmon::parse_e57(bytes.data(), bytes.size(), source);
        for (const tlsmon::Scan& scan : scans) {
            // Per-point arrays agree in length, and grid indices lie inside the grid.
            if (!scan.intensity.empty() && scan.intensity.size() != scan.size()) __builtin_trap();
            if (!scan.rgb.empty() && scan.rgb.size() != scan.size()) __builtin_trap();
            if (scan.grid) {
                if (scan.grid->row.size() != scan.size()) __builtin_trap();
                for (std::size_t i = 0; i < scan.size(); ++i)
                    if (scan.grid->row[i] >= scan.grid->rows ||
                        scan.grid->column[i] >= scan.grid->columns)
                        __builtin_trap();
            }
        }
    } catch (const tlsmon::FormatError&) {
    }
    return 0;
}
