#include "formats/pcd_header.hpp"

#include <algorithm>
#include <charconv>
#include <optional>

#include "formats/format_error.hpp"
#include "formats/text_scan_parser.hpp"

namespace tlsmon {

namespace {

// Far above what PCL writes; keeps a binary file given a .pcd name from being scanned to
// its end for line breaks.
constexpr std::size_t max_header_line = 65536;
constexpr std::uint64_t max_header_lines = 1000;

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> w(split_tokens(line, nullptr, 0));
    split_tokens(line, w.data(), w.size());
    return w;
}

// PCD TYPE (I signed, U unsigned, F floating point) and SIZE in bytes.
std::optional<ValueType> value_type(std::string_view type, std::string_view size) {
    if (type.size() != 1 || size.size() != 1) return std::nullopt;
    const char s = size[0];
    switch (type[0]) {
        case 'I':
            if (s == '1') return ValueType::int8;
            if (s == '2') return ValueType::int16;
            if (s == '4') return ValueType::int32;
            if (s == '8') return ValueType::int64;
            break;
        case 'U':
            if (s == '1') return ValueType::uint8;
            if (s == '2') return ValueType::uint16;
            if (s == '4') return ValueType::uint32;
            if (s == '8') return ValueType::uint64;
            break;
        case 'F':
            if (s == '4') return ValueType::float32;
            if (s == '8') return ValueType::float64;
            break;
        default:
            break;
    }
    return std::nullopt;
}

}  // namespace

const PcdField* PcdHeader::find(std::initializer_list<std::string_view> names) const {
    for (std::string_view name : names) {
        for (const auto& f : fields) {
            if (f.name == name) return &f;
        }
    }
    return nullptr;
}

std::size_t PcdHeader::values_per_point() const {
    std::size_t n = 0;
    for (const auto& f : fields) n += f.count;
    return n;
}

PcdHeader parse_pcd_header(std::string_view bytes, const std::filesystem::path& path) {
    PcdHeader h;
    std::vector<std::string_view> names, sizes, types, counts;
    std::optional<std::uint64_t> width, height, points;
    std::size_t pos = 0;
    for (std::uint64_t line_no = 1;; ++line_no) {
        const auto fail = [&](const std::string& what) { throw_at_line(path, line_no, what); };
        if (pos >= bytes.size()) fail("file ends inside the PCD header (no DATA line)");
        if (line_no > max_header_lines) fail("PCD header longer than 1000 lines");
        std::size_t end = bytes.find('\n', pos);
        if (end == std::string_view::npos) end = bytes.size();
        if (end - pos > max_header_line) fail("PCD header line longer than 65536 bytes");
        const std::string_view line = bytes.substr(pos, end - pos);
        pos = end + 1;
        const auto w = words(line);
        if (w.empty() || w[0].starts_with('#')) continue;
        const std::string_view key = w[0];
        const auto number = [&](std::string_view t, const char* what) {
            std::uint64_t v = 0;
            const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
            if (ec != std::errc() || p != t.data() + t.size() || v > 0xffffffffu) {
                fail(std::string(what) + " '" + quote_token(t) +
                     "' is not an unsigned 32-bit integer");
            }
            return v;
        };
        const auto one = [&](const char* what) {
            if (w.size() != 2) fail(std::string("expected '") + what + " <count>'");
            return number(w[1], what);
        };
        const std::vector<std::string_view> rest(w.begin() + 1, w.end());
        if (key == "VERSION") {
            continue;
        } else if (key == "FIELDS") {
            names = rest;
        } else if (key == "SIZE") {
            sizes = rest;
        } else if (key == "TYPE") {
            types = rest;
        } else if (key == "COUNT") {
            counts = rest;
        } else if (key == "WIDTH") {
            width = one("WIDTH");
        } else if (key == "HEIGHT") {
            height = one("HEIGHT");
        } else if (key == "POINTS") {
            points = one("POINTS");
        } else if (key == "VIEWPOINT") {
            // tx ty tz qw qx qy qz: the sensor's position and orientation (PCL's
            // sensor_origin_ and sensor_orientation_).
            if (rest.size() != 7) fail("VIEWPOINT needs 7 numbers: tx ty tz qw qx qy qz");
            const TextCursor at({}, path, line_no);  // names this line in errors
            double v[7];
            for (int k = 0; k < 7; ++k) v[k] = parse_value(rest[k], at);
            h.viewpoint_origin = Eigen::Vector3d(v[0], v[1], v[2]);
            const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
            if (!h.viewpoint_origin.allFinite() || !q.coeffs().allFinite() || q.norm() < 1e-9) {
                fail("VIEWPOINT is not a finite position and a non-zero quaternion");
            }
            h.viewpoint_orientation = q.normalized();
        } else if (key == "DATA") {
            if (w.size() != 2) fail("expected 'DATA ascii|binary|binary_compressed'");
            if (w[1] == "ascii") {
                h.data = PcdData::ascii;
            } else if (w[1] == "binary") {
                h.data = PcdData::binary;
            } else if (w[1] == "binary_compressed") {
                h.data = PcdData::binary_compressed;
            } else {
                fail("unknown DATA '" + quote_token(w[1]) +
                     "' (ascii, binary or binary_compressed)");
            }
            if (names.empty()) fail("the header has no FIELDS before DATA");
            if (sizes.size() != names.size() || types.size() != names.size() ||
                (!counts.empty() && counts.size() != names.size())) {
                fail("FIELDS, SIZE, TYPE and COUNT list different numbers of fields (" +
                     std::to_string(names.size()) + ", " + std::to_string(sizes.size()) + ", " +
                     std::to_string(types.size()) + ", " + std::to_string(counts.size()) + ")");
            }
            if (!width) fail("the header has no WIDTH before DATA");
            for (std::size_t k = 0; k < names.size(); ++k) {
                PcdField f;
                f.name = std::string(names[k]);
                const auto type = value_type(types[k], sizes[k]);
                if (!type) {
                    fail("field " + quote_token(names[k]) + ": TYPE " + quote_token(types[k]) +
                         " with SIZE " + quote_token(sizes[k]) +
                         " is none of I1 I2 I4 I8 U1 U2 U4 U8 F4 F8");
                }
                f.type = *type;
                if (!counts.empty()) f.count = number(counts[k], "COUNT");
                if (f.count == 0) fail("field " + quote_token(names[k]) + " has COUNT 0");
                f.offset = h.record_bytes;
                h.record_bytes += f.bytes();
                h.fields.push_back(std::move(f));
            }
            h.width = *width;
            h.height = height.value_or(1);
            if (points && *points != h.points()) {
                fail("POINTS " + std::to_string(*points) +
                     " is not WIDTH × HEIGHT = " + std::to_string(h.points()));
            }
            h.data_offset = std::min(pos, bytes.size());
            h.header_lines = line_no;
            return h;
        } else {
            fail("unknown PCD header line '" + quote_token(key) + "'");
        }
    }
}

}  // namespace tlsmon
