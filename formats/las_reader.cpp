#include "formats/las_reader.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "core/utc_time.hpp"
#include "formats/format_error.hpp"
#include "formats/las_layout.hpp"
#include "formats/las_points.hpp"
#include "formats/mapped_file.hpp"

namespace tlsmon {

namespace {

static_assert(std::endian::native == std::endian::little, "LAS is little-endian");

// Byte offsets of the public header (LAS 1.4 R15, Table 3; 1.0–1.3 share the first 227).
constexpr std::size_t kVersionMajorAt = 24;
constexpr std::size_t kHeaderSizeAt = 94;
constexpr std::size_t kPointDataOffsetAt = 96;
constexpr std::size_t kVlrCountAt = 100;
constexpr std::size_t kPointFormatAt = 104;
constexpr std::size_t kRecordLengthAt = 105;
constexpr std::size_t kLegacyPointCountAt = 107;
constexpr std::size_t kScaleAt = 131;      // X, Y, Z scale factors, then X, Y, Z offsets
constexpr std::size_t kEvlrStartAt = 235;  // 1.4
constexpr std::size_t kEvlrCountAt = 243;
constexpr std::size_t kPointCountAt = 247;

constexpr std::size_t kEvlrHeaderSize = 60;  // the same with a 64-bit length

// Per point data record format 0–10 (LAS 1.4 R15 §2.6): the base record length and where
// GPS time and RGB sit in it (0: the format has none).
constexpr std::array<std::uint16_t, 11> kBaseRecordLength{20, 28, 26, 34, 57, 63,
                                                          30, 36, 38, 59, 67};
constexpr std::array<std::uint8_t, 11> kGpsTimeAt{0, 20, 0, 20, 20, 20, 22, 22, 22, 22, 22};
constexpr std::array<std::uint8_t, 11> kRgbAt{0, 0, 20, 28, 0, 28, 0, 30, 30, 0, 30};

// Global encoding bit 0: GPS time is Adjusted Standard GPS time (GPS seconds − 1e9).
constexpr std::uint16_t kAdjustedStandardGpsTime = 0x0001;

template <class T>
T load(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

std::size_t required_header_size(unsigned minor) {
    if (minor >= 4) return las::kHeaderSize14;
    if (minor == 3) return 235;
    return 227;
}

bool is_laszip_vlr(const char* user_id) {
    constexpr std::string_view kLaszip = "laszip encoded";
    return std::memcmp(user_id, kLaszip.data(), kLaszip.size()) == 0;
}

class LasParser {
  public:
    LasParser(const char* data, std::size_t size, const std::filesystem::path& source)
        : data_(data), size_(size), source_(source) {}

    Scan parse() {
        read_header();
        skip_vlrs();
        check_point_records();
        skip_evlrs();
        return read_points();
    }

    LasPoints parse_with_attributes() {
        Scan scan = parse();
        LasPoints out;
        out.xyz = std::move(scan.xyz);
        out.acquired_utc = scan.acquired_utc;
        read_extra_bytes(out);
        if (const Vlr* w = find_vlr("LASF_Projection", 2112)) {
            out.wkt.assign(data_ + w->at, w->length);
            out.wkt.erase(out.wkt.find_last_not_of('\0') + 1);
        }
        return out;
    }

  private:
    [[noreturn]] void fail(std::uint64_t at, const std::string& what) const {
        throw_at_byte(source_, at, what);
    }

    [[noreturn]] void fail_compressed(std::uint64_t at) const {
        fail(at,
             "compressed LAS (LAZ/COPC) is not supported; decompress it first, e.g. "
             "`laszip -i in.laz -o out.las` or `pdal translate in.laz out.las`");
    }

    void read_header() {
        if (size_ < 4 || std::memcmp(data_, "LASF", 4) != 0) {
            fail(0, "not a LAS file: the file signature \"LASF\" is missing");
        }
        // The compression bits first: a LAZ file is rejected for what it is, even truncated.
        if (size_ > kPointFormatAt && (load<std::uint8_t>(data_ + kPointFormatAt) & 0xC0) != 0) {
            fail_compressed(kPointFormatAt);
        }
        if (size_ < 227) {
            fail(size_, "file ends inside the LAS public header (227 bytes needed, " +
                            std::to_string(size_) + " present)");
        }
        const unsigned major = load<std::uint8_t>(data_ + kVersionMajorAt);
        minor_ = load<std::uint8_t>(data_ + kVersionMajorAt + 1);
        if (major != 1 || minor_ > 4) {
            fail(kVersionMajorAt, "unsupported LAS version " + std::to_string(major) + "." +
                                      std::to_string(minor_) + " (1.0–1.4 are read)");
        }
        header_size_ = load<std::uint16_t>(data_ + kHeaderSizeAt);
        const std::size_t needed = required_header_size(minor_);
        if (header_size_ < needed) {
            fail(kHeaderSizeAt, "header size " + std::to_string(header_size_) +
                                    " is smaller than LAS 1." + std::to_string(minor_) +
                                    " needs (" + std::to_string(needed) + ")");
        }
        if (header_size_ > size_) {
            fail(kHeaderSizeAt, "header size " + std::to_string(header_size_) +
                                    " runs past the end of the file (" + std::to_string(size_) +
                                    " bytes)");
        }
        point_offset_ = load<std::uint32_t>(data_ + kPointDataOffsetAt);
        if (point_offset_ < header_size_ || point_offset_ > size_) {
            fail(kPointDataOffsetAt, "offset to point data " + std::to_string(point_offset_) +
                                         " is outside the file's data area (" +
                                         std::to_string(header_size_) + ".." +
                                         std::to_string(size_) + ")");
        }
        vlr_count_ = load<std::uint32_t>(data_ + kVlrCountAt);
        format_ = load<std::uint8_t>(data_ + kPointFormatAt);
        if (format_ >= kBaseRecordLength.size()) {
            fail(kPointFormatAt,
                 "unknown point data record format " + std::to_string(format_) + " (0–10)");
        }
        record_length_ = load<std::uint16_t>(data_ + kRecordLengthAt);
        if (record_length_ < kBaseRecordLength[format_]) {
            fail(kRecordLengthAt, "point record length " + std::to_string(record_length_) +
                                      " is smaller than point format " + std::to_string(format_) +
                                      " needs (" + std::to_string(kBaseRecordLength[format_]) +
                                      ")");
        }
        point_count_ = load<std::uint32_t>(data_ + kLegacyPointCountAt);
        if (minor_ >= 4) {
            // LAS 1.4 §2.4: the 64-bit count is authoritative; the legacy one is 0 for
            // formats 6–10. Writers that filled only the legacy count are still read.
            const auto count64 = load<std::uint64_t>(data_ + kPointCountAt);
            if (count64 != 0 || point_count_ == 0) point_count_ = count64;
            evlr_start_ = load<std::uint64_t>(data_ + kEvlrStartAt);
            evlr_count_ = load<std::uint32_t>(data_ + kEvlrCountAt);
        }
        global_encoding_ = load<std::uint16_t>(data_ + 6);
        for (int k = 0; k < 6; ++k) {
            const std::size_t at = kScaleAt + 8 * std::size_t(k);
            const double v = load<double>(data_ + at);
            if (!std::isfinite(v) || (k < 3 && v == 0.0)) {
                fail(at, std::string(k < 3 ? "scale factor" : "offset") + " of " + "XYZ"[k % 3] +
                             " is " + std::to_string(v));
            }
            // A coordinate step above a metre cannot hold a laser scan (its points would lie
            // on a grid of metres), nor an offset lie beyond any coordinate on Earth: the
            // header is corrupt. (Its bounding box is not checked: writers fill it loosely,
            // one of the shared samples in raw units.)
            if (k < 3 && std::abs(v) > 1.0) {
                fail(at, std::string("scale factor of ") + "XYZ"[k] + " is " + std::to_string(v) +
                             " m per unit (at most 1): the header is corrupt");
            }
            if (k >= 3 && std::abs(v) > kMaxCoordinate) {
                char text[32];
                std::snprintf(text, sizeof text, "%g", v);
                fail(at, std::string("offset of ") + "XYZ"[k % 3] + " is " + text +
                             ", beyond any coordinate on Earth (1e8): the header is corrupt");
            }
            (k < 3 ? scale_ : offset_)[k % 3] = v;
        }
    }

    // Variable length records between the header and the point data (LAS 1.4 §2.5).
    void skip_vlrs() {
        std::uint64_t at = header_size_;
        for (std::uint32_t i = 0; i < vlr_count_; ++i) {
            if (at + las::kVlrHeaderSize > point_offset_) {
                fail(at, "VLR " + std::to_string(i + 1) + " of " + std::to_string(vlr_count_) +
                             " does not fit before the point data at byte " +
                             std::to_string(point_offset_));
            }
            if (is_laszip_vlr(data_ + at + 2)) fail_compressed(at + 2);
            const std::uint64_t length = load<std::uint16_t>(data_ + at + 20);
            if (at + las::kVlrHeaderSize + length > point_offset_) {
                fail(at + 20, "VLR " + std::to_string(i + 1) + " record length " +
                                  std::to_string(length) + " runs past the point data at byte " +
                                  std::to_string(point_offset_));
            }
            vlrs_.push_back({std::string(data_ + at + 2, ::strnlen(data_ + at + 2, 16)),
                             load<std::uint16_t>(data_ + at + 18), at + las::kVlrHeaderSize,
                             length});
            at += las::kVlrHeaderSize + length;
        }
    }

    struct Vlr {
        std::string user;
        std::uint16_t record = 0;
        std::uint64_t at = 0, length = 0;  // the content
    };

    const Vlr* find_vlr(std::string_view user, std::uint16_t record) const {
        for (const auto& v : vlrs_)
            if (v.user == user && v.record == record) return &v;
        return nullptr;
    }

    // The Extra Bytes VLR's fields (R15 §2.5.3): each descriptor's type and options; values
    // with its scale and offset applied. Undocumented bytes (type 0) are stepped over; the
    // deprecated arrays of two or three values (types 11–30, LAS 1.4 R13) give one attribute
    // per element, "name[k]", with the element's scale and offset.
    void read_extra_bytes(LasPoints& out) const {
        const Vlr* v = find_vlr("LASF_Spec", 4);
        if (v == nullptr) return;
        if (v->length % las::kExtraBytesDescriptorSize != 0) {
            fail(v->at, "Extra Bytes VLR of " + std::to_string(v->length) +
                            " bytes is not a whole number of 192-byte descriptors");
        }
        constexpr std::array<std::uint8_t, 11> kSize{0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
        std::size_t offset = kBaseRecordLength[format_];
        for (std::uint64_t d = v->at; d < v->at + v->length; d += las::kExtraBytesDescriptorSize) {
            const char* e = data_ + d;
            const unsigned type = load<std::uint8_t>(e + 2), options = load<std::uint8_t>(e + 3);
            if (type > 30)
                fail(d + 2, "extra bytes data type " + std::to_string(type) + " is not defined");
            const unsigned scalar = type == 0 ? 0 : (type - 1) % 10 + 1;
            const unsigned elements = type == 0 ? 1 : (type - 1) / 10 + 1;
            const std::size_t size = type == 0 ? options : kSize[scalar];
            if (offset + size * elements > record_length_) {
                fail(d, "extra bytes field runs past the point record length " +
                            std::to_string(record_length_));
            }
            const std::string name(e + 4, ::strnlen(e + 4, 32));
            for (unsigned k = 0; type != 0 && k < elements; ++k) {
                LasAttribute a;
                a.name = elements == 1 ? name : name + "[" + std::to_string(k) + "]";
                a.description.assign(e + 160, ::strnlen(e + 160, 32));
                a.type = scalar == 1   ? LasAttribute::Type::u8
                         : scalar == 5 ? LasAttribute::Type::u32
                         : scalar == 6 ? LasAttribute::Type::i32
                         : scalar == 9 ? LasAttribute::Type::f32
                                       : LasAttribute::Type::f64;
                const double scale = (options & 0x08) ? load<double>(e + 112 + 8 * k) : 1.0;
                const double shift = (options & 0x10) ? load<double>(e + 136 + 8 * k) : 0.0;
                a.values.resize(point_count_);
                const char* r = data_ + point_offset_ + offset + k * size;
                for (std::size_t i = 0; i < point_count_; ++i, r += record_length_) {
                    a.values[i] = field_value(r, scalar) * scale + shift;
                }
                out.attributes.push_back(std::move(a));
            }
            offset += size * elements;
        }
    }

    static double field_value(const char* p, unsigned type) {
        switch (type) {
            case 1:
                return load<std::uint8_t>(p);
            case 2:
                return load<std::int8_t>(p);
            case 3:
                return load<std::uint16_t>(p);
            case 4:
                return load<std::int16_t>(p);
            case 5:
                return load<std::uint32_t>(p);
            case 6:
                return load<std::int32_t>(p);
            case 7:
                return static_cast<double>(load<std::uint64_t>(p));
            case 8:
                return static_cast<double>(load<std::int64_t>(p));
            case 9:
                return load<float>(p);
            default:
                return load<double>(p);
        }
    }

    void check_point_records() {
        const std::uint64_t available = size_ - point_offset_;
        if (point_count_ > available / record_length_) {
            fail(point_offset_,
                 std::to_string(point_count_) + " point records of " +
                     std::to_string(record_length_) + " bytes need " +
                     (point_count_ > std::numeric_limits<std::uint64_t>::max() / record_length_
                          ? std::string("more")
                          : std::to_string(point_count_ * record_length_)) +
                     " bytes, the file has " + std::to_string(available) +
                     " after the point data offset");
        }
        points_end_ = point_offset_ + point_count_ * record_length_;
    }

    // Extended VLRs after the point records (LAS 1.4 §2.7).
    void skip_evlrs() {
        if (evlr_count_ == 0) return;
        if (evlr_start_ < points_end_ || evlr_start_ > size_) {
            fail(kEvlrStartAt, "start of the first EVLR " + std::to_string(evlr_start_) +
                                   " is outside " + std::to_string(points_end_) + ".." +
                                   std::to_string(size_) + " (after the point records)");
        }
        std::uint64_t at = evlr_start_;
        for (std::uint32_t i = 0; i < evlr_count_; ++i) {
            if (kEvlrHeaderSize > size_ - at) {
                fail(at, "EVLR " + std::to_string(i + 1) + " of " + std::to_string(evlr_count_) +
                             " does not fit in the file");
            }
            const auto length = load<std::uint64_t>(data_ + at + 20);
            if (length > size_ - at - kEvlrHeaderSize) {
                fail(at + 20, "EVLR " + std::to_string(i + 1) + " record length " +
                                  std::to_string(length) + " runs past the end of the file");
            }
            at += kEvlrHeaderSize + length;
        }
    }

    Scan read_points() const {
        Scan scan;
        scan.source = source_.string();
        const std::size_t n = point_count_;
        scan.xyz.resize(n);
        scan.intensity.resize(n);
        const std::size_t rgb_at = kRgbAt[format_];
        std::vector<std::array<std::uint16_t, 3>> rgb16(rgb_at != 0 ? n : 0);
        const std::size_t gps_at = kGpsTimeAt[format_];
        const bool dated = gps_at != 0 && (global_encoding_ & kAdjustedStandardGpsTime) != 0;
        std::uint16_t colour_max = 0;
        double earliest_gps = std::numeric_limits<double>::infinity();

        const char* record = data_ + point_offset_;
        for (std::size_t i = 0; i < n; ++i, record += record_length_) {
            for (int k = 0; k < 3; ++k) {
                const auto raw = load<std::int32_t>(record + 4 * k);
                scan.xyz[i][k] = raw * scale_[k] + offset_[k];
            }
            const auto intensity = load<std::uint16_t>(record + 12);
            scan.intensity[i] = intensity;
            if (rgb_at != 0) {
                for (int c = 0; c < 3; ++c) {
                    rgb16[i][c] = load<std::uint16_t>(record + rgb_at + 2 * c);
                    colour_max = std::max(colour_max, rgb16[i][c]);
                }
            }
            if (dated) {
                const auto t = load<double>(record + gps_at);
                if (std::isfinite(t)) earliest_gps = std::min(earliest_gps, t);
            }
        }

        // LAS 1.4 R15, sec. 2.6: intensity "shall always be normalized to a 16 bit,
        // unsigned value". The scale is fixed, not guessed per file, so that intensities of
        // successive epochs stay comparable even where an exporter wrote 8-bit values.
        scan.intensity_raw_min = 0.0;
        scan.intensity_raw_max = 65535.0;
        const float inverse = 1.0f / static_cast<float>(scan.intensity_raw_max);
        for (float& v : scan.intensity) v *= inverse;

        if (rgb_at != 0) {
            const int shift = colour_max <= 255 ? 0 : 8;
            scan.rgb.resize(n);
            for (std::size_t i = 0; i < n; ++i) {
                for (int c = 0; c < 3; ++c) {
                    scan.rgb[i][c] = static_cast<std::uint8_t>(rgb16[i][c] >> shift);
                }
            }
        }
        if (dated && std::isfinite(earliest_gps)) {
            scan.acquired_utc = gps_to_utc(earliest_gps + 1e9);
        }
        return scan;
    }

    const char* data_;
    std::size_t size_;
    const std::filesystem::path& source_;

    unsigned minor_ = 0;
    std::uint64_t header_size_ = 0;
    std::uint64_t point_offset_ = 0;
    std::uint32_t vlr_count_ = 0;
    unsigned format_ = 0;
    std::uint64_t record_length_ = 0;
    std::uint64_t point_count_ = 0;
    std::uint64_t points_end_ = 0;
    std::uint64_t evlr_start_ = 0;
    std::uint32_t evlr_count_ = 0;
    std::uint16_t global_encoding_ = 0;
    std::array<double, 3> scale_{};
    std::array<double, 3> offset_{};
    std::vector<Vlr> vlrs_;
};

}  // namespace

Scan parse_las(const char* data, std::size_t size, const std::filesystem::path& source) {
    return LasParser(data, size, source).parse();
}

LasPoints parse_las_points(const char* data, std::size_t size,
                           const std::filesystem::path& source) {
    return LasParser(data, size, source).parse_with_attributes();
}

LasPoints read_las_points(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_las_points(file.data(), file.size(), path);
}

std::vector<Scan> read_las(const std::filesystem::path& path) {
    const MappedFile file(path);
    std::vector<Scan> scans;
    scans.push_back(parse_las(file.data(), file.size(), path));
    return scans;
}

}  // namespace tlsmon
