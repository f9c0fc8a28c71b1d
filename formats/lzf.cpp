#include "formats/lzf.hpp"

#include <cstdint>
#include <cstring>

namespace tlsmon {

std::optional<std::string> lzf_decompress(std::string_view in, char* out, std::size_t out_size) {
    const auto* ip = reinterpret_cast<const std::uint8_t*>(in.data());
    const auto* const in_end = ip + in.size();
    std::size_t op = 0;
    const auto at = [&] {
        return " at compressed byte " +
               std::to_string(ip - reinterpret_cast<const std::uint8_t*>(in.data()));
    };
    while (ip < in_end) {
        const unsigned ctrl = *ip++;
        if (ctrl < 32) {  // literal run of ctrl + 1 bytes
            const std::size_t n = ctrl + 1;
            if (static_cast<std::size_t>(in_end - ip) < n) return "literal run past the end" + at();
            if (out_size - op < n) return "literal run past the declared size" + at();
            std::memcpy(out + op, ip, n);
            ip += n;
            op += n;
            continue;
        }
        std::size_t len = ctrl >> 5;
        std::size_t back = (ctrl & 0x1f) << 8;
        if (len == 7) {
            if (ip >= in_end) return "back reference cut off" + at();
            len += *ip++;
        }
        if (ip >= in_end) return "back reference cut off" + at();
        back += *ip++;
        len += 2;
        if (back + 1 > op) return "back reference before the start" + at();
        if (out_size - op < len) return "back reference past the declared size" + at();
        // Byte by byte: source and destination overlap when the distance is below the length.
        const char* ref = out + op - back - 1;
        for (std::size_t k = 0; k < len; ++k) out[op + k] = ref[k];
        op += len;
    }
    if (op != out_size) {
        return "decompressed to " + std::to_string(op) + " bytes, the header declares " +
               std::to_string(out_size);
    }
    return std::nullopt;
}

}  // namespace tlsmon
