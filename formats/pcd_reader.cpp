#include "formats/pcd_reader.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "formats/format_error.hpp"
#include "formats/lzf.hpp"
#include "formats/mapped_file.hpp"
#include "formats/pcd_header.hpp"
#include "formats/point_values.hpp"
#include "formats/text_scan_parser.hpp"

namespace tlsmon {

namespace {

// The fields a Scan uses, checked against the header.
struct ScanFields {
    const PcdField *x, *y, *z, *intensity, *rgb;

    ScanFields(const PcdHeader& h, const std::filesystem::path& path)
        : x(h.find({"x"})),
          y(h.find({"y"})),
          z(h.find({"z"})),
          intensity(h.find({"intensity", "Intensity", "scalar_Intensity", "scalar_intensity"})),
          rgb(h.find({"rgb", "rgba"})) {
        if (!x || !y || !z) throw_format_error(path, "has no x, y and z fields");
        if (rgb && value_size(rgb->type) != 4) {
            throw_format_error(path, "field " + rgb->name + " is not a packed 4-byte colour");
        }
    }
};

// Appends the points of the cloud to a Scan: skips points without a return, keeps the
// grid cell of each point of an organised cloud, collects intensity and colour.
class ScanBuilder {
  public:
    // `room`: at most this many points are reserved (what the bytes can hold).
    ScanBuilder(const PcdHeader& h, const ScanFields& f, const std::filesystem::path& path,
                std::uint64_t room)
        : width_(h.width), scale_(f.intensity ? f.intensity->type : ValueType::float32) {
        scan_.source = path.string();
        scan_.pose = Eigen::Translation3d(h.viewpoint_origin) * h.viewpoint_orientation;
        const auto n = static_cast<std::size_t>(std::min(h.points(), room));
        scan_.xyz.reserve(n);
        if (f.intensity) scan_.intensity.reserve(n);
        if (f.rgb) scan_.rgb.reserve(n);
        if (h.height > 1) {
            scan_.grid.emplace();
            scan_.grid->rows = static_cast<std::uint32_t>(h.height);
            scan_.grid->columns = static_cast<std::uint32_t>(h.width);
            scan_.grid->row.reserve(n);
            scan_.grid->column.reserve(n);
        }
    }

    // False when the point has no return (and nothing was added).
    bool add(std::uint64_t i, double x, double y, double z) {
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return false;
        scan_.xyz.emplace_back(x, y, z);
        if (scan_.grid) {
            scan_.grid->row.push_back(static_cast<std::uint32_t>(i / width_));
            scan_.grid->column.push_back(static_cast<std::uint32_t>(i % width_));
        }
        return true;
    }
    // Returns false for a non-finite intensity.
    bool add_intensity(double v) {
        if (!std::isfinite(v)) return false;
        scale_.add(scan_, static_cast<float>(v));
        return true;
    }
    void add_rgb(std::uint32_t packed) { scan_.rgb.push_back(unpack_rgb(packed)); }

    Scan finish() {
        scale_.normalise(scan_);
        return std::move(scan_);
    }

  private:
    std::uint64_t width_;
    IntensityScale scale_;
    Scan scan_;
};

// Binary layouts: the value of field f for point i lies at base(f) + i * stride(f). For
// DATA binary records are stored one after the other; binary_compressed stores each
// field's values for all points together.
struct Layout {
    const char* data;
    std::size_t points;
    bool by_field;
    std::size_t record_bytes;

    const char* at(const PcdField& f, std::size_t i) const {
        if (by_field) return data + f.offset * points + i * f.bytes();
        return data + i * record_bytes + f.offset;
    }
};

void read_binary(const Layout& l, const ScanFields& f, ScanBuilder& b, std::size_t data_offset,
                 const std::filesystem::path& path) {
    for (std::size_t i = 0; i < l.points; ++i) {
        if (!b.add(i, load_value(l.at(*f.x, i), f.x->type, false),
                   load_value(l.at(*f.y, i), f.y->type, false),
                   load_value(l.at(*f.z, i), f.z->type, false))) {
            continue;
        }
        if (f.intensity &&
            !b.add_intensity(load_value(l.at(*f.intensity, i), f.intensity->type, false))) {
            throw_at_byte(path, data_offset,
                          "intensity of point " + std::to_string(i) + " is not finite");
        }
        if (f.rgb) {
            std::uint32_t packed;
            std::memcpy(&packed, l.at(*f.rgb, i), 4);
            b.add_rgb(packed);
        }
    }
}

// ASCII colour: PCL writes a packed rgb as its unsigned integer, older writers as the float
// whose bits it is; a token with a decimal point, exponent or "nan" is taken as the latter.
std::uint32_t packed_rgb(std::string_view token, const PcdField& f, const TextCursor& at) {
    const double v = parse_value(token, at);
    const bool float_bits =
        f.type == ValueType::float32 && token.find_first_of(".eEnN") != std::string_view::npos;
    if (float_bits) return std::bit_cast<std::uint32_t>(static_cast<float>(v));
    if (v < -2147483648.0 || v > 4294967295.0 || v != std::floor(v)) {
        at.fail("\"" + quote_token(token) + "\" is not a packed colour");
    }
    return v < 0 ? static_cast<std::uint32_t>(static_cast<std::int32_t>(v))
                 : static_cast<std::uint32_t>(v);
}

void read_ascii(std::string_view text, const PcdHeader& h, const ScanFields& f, ScanBuilder& b,
                const std::filesystem::path& path) {
    TextCursor cur(text, path, h.header_lines);
    const std::size_t values = h.values_per_point();
    // Token index of each field's first value.
    std::vector<std::size_t> first(h.fields.size());
    for (std::size_t k = 0, t = 0; k < h.fields.size(); ++k) {
        first[k] = t;
        t += h.fields[k].count;
    }
    const auto token_of = [&](const PcdField* field) {
        return first[static_cast<std::size_t>(field - h.fields.data())];
    };
    const std::size_t tx = token_of(f.x), ty = token_of(f.y), tz = token_of(f.z);
    const std::size_t ti = f.intensity ? token_of(f.intensity) : 0;
    const std::size_t tc = f.rgb ? token_of(f.rgb) : 0;
    std::vector<std::string_view> tokens(h.points() > 0 ? values : 0);  // bounded by the caller
    std::string_view line;
    const std::uint64_t points = h.points();
    for (std::uint64_t i = 0; i < points; ++i) {
        if (!cur.next_line(line)) {
            throw_at_line(path, cur.line_number() + 1,
                          "file ends after " + std::to_string(i) + " points, the header declares " +
                              std::to_string(points));
        }
        const std::size_t n = split_tokens(line, tokens.data(), values);
        if (n != values) {
            cur.fail(std::to_string(n) + " values, the header declares " + std::to_string(values) +
                     " per point");
        }
        if (!b.add(i, parse_value(tokens[tx], cur), parse_value(tokens[ty], cur),
                   parse_value(tokens[tz], cur))) {
            continue;
        }
        if (f.intensity && !b.add_intensity(parse_value(tokens[ti], cur))) {
            cur.fail("intensity \"" + quote_token(tokens[ti]) + "\" is not finite");
        }
        if (f.rgb) b.add_rgb(packed_rgb(tokens[tc], *f.rgb, cur));
    }
    if (cur.next_line(line)) {
        cur.fail("more point lines than the " + std::to_string(points) +
                 " points the header declares");
    }
}

}  // namespace

std::vector<Scan> parse_pcd(std::string_view bytes, const std::filesystem::path& path) {
    const PcdHeader h = parse_pcd_header(bytes, path);
    const ScanFields fields(h, path);
    const std::uint64_t points = h.points();
    const std::size_t left = bytes.size() - h.data_offset;
    const std::string_view data = bytes.substr(h.data_offset);

    if (h.data == PcdData::ascii) {
        // The line loop finds a short file; the reservation is only capped by what the bytes
        // can hold (a value takes a character and a separator or line break). COUNTs that a
        // single line could not hold are refused before the line's tokens are allocated.
        if (points > 0 && 2 * h.values_per_point() > left + 1) {
            throw_at_byte(path, h.data_offset,
                          "a point line of " + std::to_string(h.values_per_point()) +
                              " values needs more than the " + std::to_string(left) +
                              " bytes that follow");
        }
        ScanBuilder b(h, fields, path, (left + 1) / (2 * h.values_per_point()));
        read_ascii(data, h, fields, b, path);
        return {b.finish()};
    }
    if (h.data == PcdData::binary) {
        if (points > left / h.record_bytes) {
            throw_at_byte(path, h.data_offset,
                          "header declares " + std::to_string(points) + " points of " +
                              std::to_string(h.record_bytes) + " bytes, but only " +
                              std::to_string(left) + " bytes follow");
        }
        ScanBuilder b(h, fields, path, points);
        read_binary({data.data(), static_cast<std::size_t>(points), false, h.record_bytes}, fields,
                    b, h.data_offset, path);
        return {b.finish()};
    }

    // binary_compressed: uint32 compressed size, uint32 uncompressed size, LZF data.
    if (left < 8) throw_at_byte(path, h.data_offset, "file ends inside the compressed sizes");
    std::uint32_t compressed = 0, uncompressed = 0;
    std::memcpy(&compressed, data.data(), 4);
    std::memcpy(&uncompressed, data.data() + 4, 4);
    if (compressed > left - 8) {
        throw_at_byte(path, h.data_offset,
                      "compressed size " + std::to_string(compressed) + " but only " +
                          std::to_string(left - 8) + " bytes follow");
    }
    if (points > std::numeric_limits<std::uint32_t>::max() / h.record_bytes ||
        uncompressed != points * h.record_bytes) {
        throw_at_byte(path, h.data_offset + 4,
                      "uncompressed size " + std::to_string(uncompressed) + " is not " +
                          std::to_string(points) + " points × " + std::to_string(h.record_bytes) +
                          " bytes");
    }
    if (uncompressed / lzf_max_expansion > compressed) {
        throw_at_byte(path, h.data_offset,
                      "compressed size " + std::to_string(compressed) +
                          " cannot expand to the uncompressed size " +
                          std::to_string(uncompressed));
    }
    std::string plain(uncompressed, '\0');
    if (auto damage = lzf_decompress(data.substr(8, compressed), plain.data(), plain.size())) {
        throw_at_byte(path, h.data_offset + 8, "LZF data damaged: " + *damage);
    }
    ScanBuilder b(h, fields, path, points);
    read_binary({plain.data(), static_cast<std::size_t>(points), true, h.record_bytes}, fields, b,
                h.data_offset, path);
    return {b.finish()};
}

std::vector<Scan> read_pcd(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_pcd(file.text(), path);
}

}  // namespace tlsmon
