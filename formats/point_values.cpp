#include "formats/point_values.hpp"

#include <algorithm>
#include <cmath>

namespace tlsmon {

std::string_view to_string(ValueType t) {
    switch (t) {
        case ValueType::int8:
            return "int8";
        case ValueType::uint8:
            return "uint8";
        case ValueType::int16:
            return "int16";
        case ValueType::uint16:
            return "uint16";
        case ValueType::int32:
            return "int32";
        case ValueType::uint32:
            return "uint32";
        case ValueType::int64:
            return "int64";
        case ValueType::uint64:
            return "uint64";
        case ValueType::float32:
            return "float32";
        case ValueType::float64:
            break;
    }
    return "float64";
}

std::uint8_t colour_channel(double v, ValueType t) {
    if (t == ValueType::uint16) v = std::floor(v / 256.0);
    if (!(v > 0.0)) return 0;  // NaN too
    return static_cast<std::uint8_t>(std::lround(std::min(v, 255.0)));
}

void IntensityScale::normalise(Scan& scan) const {
    if (scan.intensity.empty()) return;
    if (type_ == ValueType::uint8) {
        scan.intensity_raw_min = 0.0, scan.intensity_raw_max = 255.0;
    } else if (type_ == ValueType::uint16) {
        scan.intensity_raw_min = 0.0, scan.intensity_raw_max = 65535.0;
    } else if (lo_ >= 0.0f && hi_ <= 1.0f) {
        scan.intensity_raw_min = 0.0, scan.intensity_raw_max = 1.0;
    } else {
        scan.intensity_raw_min = lo_;
        scan.intensity_raw_max = hi_ > lo_ ? hi_ : lo_ + 1.0;
    }
    if (scan.intensity_raw_min == 0.0 && scan.intensity_raw_max == 1.0) return;
    const double span = scan.intensity_raw_max - scan.intensity_raw_min;
    for (float& v : scan.intensity) {
        v = static_cast<float>((v - scan.intensity_raw_min) / span);
    }
}

}  // namespace tlsmon
