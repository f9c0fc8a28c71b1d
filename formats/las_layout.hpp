#pragma once
// Record sizes of ASPRS LAS 1.4 (R15) that the reader and the writer share.
#include <cstddef>

namespace tlsmon::las {

constexpr std::size_t kHeaderSize14 = 375;  // the 1.4 public header (Table 3)
constexpr std::size_t kVlrHeaderSize = 54;  // reserved, user id, record id, length, text (Table 13)
constexpr std::size_t kExtraBytesDescriptorSize = 192;  // one Extra Bytes descriptor (Table 24)

}  // namespace tlsmon::las
