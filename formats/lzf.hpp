#pragma once
// LZF decompression (Marc Lehmann's liblzf format), as used by PCD's DATA binary_compressed.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace tlsmon {

// Every input byte is either a literal-run control (ctrl < 32: ctrl + 1 literal bytes
// follow) or starts a back reference (length ctrl >> 5, 7 meaning "7 + next byte"; the
// distance's high 5 bits in ctrl and its low byte next; copies length + 2 bytes from
// distance + 1 bytes back). A back reference outputs at most 264 bytes for 3 input bytes.
constexpr std::size_t lzf_max_expansion = 88;

// Decompresses `in` into `out` of exactly `out_size` bytes. Returns an explanation when
// the input is damaged (a run or reference beyond either buffer, or a different size).
std::optional<std::string> lzf_decompress(std::string_view in, char* out, std::size_t out_size);

}  // namespace tlsmon
