#pragma once
// 32-bit values in two 16-bit Modbus registers, by tlsmon's own code: Debian 12's libmodbus
// 3.1.6 float helpers (modbus_set_float_abcd & co.) swap the bytes inside each word on
// little-endian hosts, so they are not used. A register is sent big-endian (Modbus
// Application Protocol V1.1b3, 4.2); only the order of the two words is configurable.
#include <array>
#include <cstdint>

#include "config/modbus_config.hpp"

namespace tlsmon {

// IEEE 754 binary32 bits of `value`, high half first (ABCD) or low half first (CDAB):
// 123456.0f = 0x47F12000 -> ABCD {0x47F1, 0x2000}, CDAB {0x2000, 0x47F1}.
std::array<std::uint16_t, 2> float_words(float value, WordOrder order);
std::array<std::uint16_t, 2> u32_words(std::uint32_t value, WordOrder order);
// The inverse of float_words (for tests and the bench client).
float float_from_words(std::array<std::uint16_t, 2> words, WordOrder order);

}  // namespace tlsmon
