#include "daemon/modbus/register_words.hpp"

#include <bit>

namespace tlsmon {

std::array<std::uint16_t, 2> u32_words(std::uint32_t value, WordOrder order) {
    const auto high = static_cast<std::uint16_t>(value >> 16);
    const auto low = static_cast<std::uint16_t>(value & 0xFFFFu);
    if (order == WordOrder::abcd) return {high, low};
    return {low, high};
}

std::array<std::uint16_t, 2> float_words(float value, WordOrder order) {
    return u32_words(std::bit_cast<std::uint32_t>(value), order);
}

float float_from_words(std::array<std::uint16_t, 2> words, WordOrder order) {
    const std::uint16_t high = order == WordOrder::abcd ? words[0] : words[1];
    const std::uint16_t low = order == WordOrder::abcd ? words[1] : words[0];
    return std::bit_cast<float>((std::uint32_t{high} << 16) | low);
}

}  // namespace tlsmon
