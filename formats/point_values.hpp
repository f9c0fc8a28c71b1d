#pragma once
// Typed values in the point records of PLY and PCD files, and the rules both readers share
// for turning them into a Scan's intensity and colour.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>

#include "core/scan.hpp"

namespace tlsmon {

enum class ValueType : std::uint8_t {
    int8,
    uint8,
    int16,
    uint16,
    int32,
    uint32,
    int64,
    uint64,
    float32,
    float64
};

constexpr std::size_t value_size(ValueType t) {
    switch (t) {
        case ValueType::int8:
        case ValueType::uint8:
            return 1;
        case ValueType::int16:
        case ValueType::uint16:
            return 2;
        case ValueType::int32:
        case ValueType::uint32:
        case ValueType::float32:
            return 4;
        default:
            return 8;
    }
}

std::string_view to_string(ValueType t);

namespace detail {

template <class T>
inline T load_raw(const char* p, bool swap) {
    using Bits = std::conditional_t<
        sizeof(T) == 1, std::uint8_t,
        std::conditional_t<sizeof(T) == 2, std::uint16_t,
                           std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
    Bits b;
    std::memcpy(&b, p, sizeof b);
    if constexpr (sizeof(T) > 1) {
        if (swap) {  // std::byteswap is C++23
            if constexpr (sizeof(T) == 2) b = __builtin_bswap16(b);
            if constexpr (sizeof(T) == 4) b = __builtin_bswap32(b);
            if constexpr (sizeof(T) == 8) b = __builtin_bswap64(b);
        }
    }
    return std::bit_cast<T>(b);
}

}  // namespace detail

// The value of type `t` at `p`; `swap` when the file's byte order is not the machine's.
inline double load_value(const char* p, ValueType t, bool swap) {
    using detail::load_raw;
    switch (t) {
        case ValueType::int8:
            return load_raw<std::int8_t>(p, swap);
        case ValueType::uint8:
            return load_raw<std::uint8_t>(p, swap);
        case ValueType::int16:
            return load_raw<std::int16_t>(p, swap);
        case ValueType::uint16:
            return load_raw<std::uint16_t>(p, swap);
        case ValueType::int32:
            return load_raw<std::int32_t>(p, swap);
        case ValueType::uint32:
            return load_raw<std::uint32_t>(p, swap);
        case ValueType::int64:
            return static_cast<double>(load_raw<std::int64_t>(p, swap));
        case ValueType::uint64:
            return static_cast<double>(load_raw<std::uint64_t>(p, swap));
        case ValueType::float32:
            return load_raw<float>(p, swap);
        case ValueType::float64:
            break;
    }
    return load_raw<double>(p, swap);
}

// PCL's packed colour 0x00RRGGBB (pcl::PointXYZRGB::rgb; the alpha byte of rgba is dropped).
inline Rgb8 unpack_rgb(std::uint32_t packed) {
    return {static_cast<std::uint8_t>(packed >> 16), static_cast<std::uint8_t>(packed >> 8),
            static_cast<std::uint8_t>(packed)};
}

// An 8-bit colour channel from a PLY red/green/blue value: 16-bit channels by their high
// byte (like the LAS reader), other types clamped to 0..255.
std::uint8_t colour_channel(double v, ValueType t);

// Tracks the raw intensities a reader stores in Scan::intensity, then normalises them in
// place by the raw scale of the field's type: 0..255 for uint8, 0..65535 for uint16; for
// other types 0..1 when every value lies in it, else the data's own min..max.
class IntensityScale {
  public:
    explicit IntensityScale(ValueType type) : type_(type) {}

    void add(Scan& scan, float raw) {
        lo_ = raw < lo_ ? raw : lo_;
        hi_ = raw > hi_ ? raw : hi_;
        scan.intensity.push_back(raw);
    }

    void normalise(Scan& scan) const;

  private:
    ValueType type_;
    float lo_ = 3.4e38f;
    float hi_ = -3.4e38f;
};

}  // namespace tlsmon
