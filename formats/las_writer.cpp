#include "formats/las_writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <utility>

#include "core/error.hpp"
#include "core/utc_time.hpp"
#include "formats/las_layout.hpp"

namespace tlsmon {

static_assert(std::endian::native == std::endian::little, "LAS is little-endian");

namespace {

constexpr std::size_t kFormat6RecordLength = 30;    // point data record format 6 (Table 12)
constexpr std::uint16_t kGpsTimeAdjusted = 0x0001;  // global encoding bit 0
constexpr std::uint16_t kWktCrs = 0x0010;           // bit 4: required for formats 6–10

// A byte buffer written field by field at fixed offsets (the tables' layout).
class Bytes {
  public:
    explicit Bytes(std::size_t size) : b_(size, '\0') {}
    template <class T>
    void put(std::size_t at, T v) {
        std::memcpy(b_.data() + at, &v, sizeof v);
    }
    void text(std::size_t at, std::string_view s, std::size_t room) {
        std::memcpy(b_.data() + at, s.data(), std::min(s.size(), room));
    }
    const std::string& str() const { return b_; }

  private:
    std::string b_;
};

std::size_t field_size(LasAttribute::Type t) {
    switch (t) {
        case LasAttribute::Type::u8:
            return 1;
        case LasAttribute::Type::u32:
        case LasAttribute::Type::i32:
        case LasAttribute::Type::f32:
            return 4;
        case LasAttribute::Type::f64:
            return 8;
    }
    return 0;
}

std::pair<double, double> integer_range(LasAttribute::Type t) {
    switch (t) {
        case LasAttribute::Type::u8:
            return {0.0, 255.0};
        case LasAttribute::Type::u32:
            return {0.0, 4294967295.0};
        default:
            return {-2147483648.0, 2147483647.0};
    }
}

bool is_float(LasAttribute::Type t) {
    return t == LasAttribute::Type::f32 || t == LasAttribute::Type::f64;
}

// Table 24: data_type, options (bit 1 min, bit 2 max given), name, min, max, description.
// "anytype" fields hold a double for floats and a 64-bit integer of the type's sign
// otherwise.
std::string descriptor(const LasAttribute& a) {
    Bytes d(las::kExtraBytesDescriptorSize);
    d.put<std::uint8_t>(2, static_cast<std::uint8_t>(a.type));
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : a.values)
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (lo <= hi) {
        d.put<std::uint8_t>(3, 0x06);
        if (is_float(a.type)) {
            d.put<double>(64, lo);
            d.put<double>(88, hi);
        } else {
            d.put<std::int64_t>(64, static_cast<std::int64_t>(lo));
            d.put<std::int64_t>(88, static_cast<std::int64_t>(hi));
        }
    }
    d.text(4, a.name, 32);
    d.text(160, a.description, 32);
    return d.str();
}

std::string vlr(std::string_view user, std::uint16_t record, std::string_view description,
                const std::string& content) {
    Bytes h(las::kVlrHeaderSize);
    h.text(2, user, 16);
    h.put<std::uint16_t>(18, record);
    h.put<std::uint16_t>(20, static_cast<std::uint16_t>(content.size()));
    h.text(22, description, 32);
    return h.str() + content;
}

void check(const std::filesystem::path& path, const LasPoints& p) {
    for (const auto& a : p.attributes) {
        const auto fail = [&](const std::string& what) {
            throw Error(path.string() + ": attribute " + a.name + " " + what);
        };
        if (a.values.size() != p.xyz.size()) {
            fail("has " + std::to_string(a.values.size()) + " values for " +
                 std::to_string(p.xyz.size()) + " points");
        }
        if (a.name.empty() || a.name.size() > 32) fail("needs a name of 1 to 32 bytes");
        if (a.description.size() > 32) fail("has a description longer than 32 bytes");
        if (!is_float(a.type)) {
            const auto [bottom, top] = integer_range(a.type);
            for (double v : a.values)
                if (!(v >= bottom && v <= top && v == std::floor(v)))
                    fail("holds " + std::to_string(v) + ", not an integer of its type");
        }
    }
    if (p.wkt.size() + 1 > std::numeric_limits<std::uint16_t>::max())
        throw Error(path.string() + ": the coordinate system's WKT is too long for a VLR");
    if ((p.attributes.size() * las::kExtraBytesDescriptorSize) >
        std::numeric_limits<std::uint16_t>::max())
        throw Error(path.string() + ": too many attributes for one Extra Bytes VLR");
}

}  // namespace

LasQuantisation las_quantisation(const std::vector<Eigen::Vector3d>& xyz) {
    LasQuantisation q{Eigen::Vector3d::Constant(1e-6), Eigen::Vector3d::Zero()};
    if (xyz.empty()) return q;
    Eigen::Vector3d lo = xyz.front(), hi = xyz.front();
    for (const auto& p : xyz) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    constexpr double kLimit = 2147483647.0 * 0.999;  // a margin for the rounding below
    for (int k = 0; k < 3; ++k) {
        q.offset[k] = std::round(0.5 * (lo[k] + hi[k]));
        const double reach = std::max(hi[k] - q.offset[k], q.offset[k] - lo[k]);
        while (reach / q.scale[k] > kLimit) q.scale[k] *= 10.0;
    }
    return q;
}

void write_las(const std::filesystem::path& path, const LasPoints& p) {
    check(path, p);
    const std::size_t n = p.xyz.size();
    std::size_t record_length = kFormat6RecordLength;
    for (const auto& a : p.attributes) record_length += field_size(a.type);

    std::string vlrs;
    std::uint32_t vlr_count = 0;
    if (!p.attributes.empty()) {
        std::string descriptors;
        for (const auto& a : p.attributes) descriptors += descriptor(a);
        vlrs += vlr("LASF_Spec", 4, "Extra bytes: the attributes", descriptors);
        ++vlr_count;
    }
    if (!p.wkt.empty()) {
        vlrs += vlr("LASF_Projection", 2112, "OGC WKT coordinate system", p.wkt + '\0');
        ++vlr_count;
    }

    const LasQuantisation q = las_quantisation(p.xyz);
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    if (n > 0) lo = hi = p.xyz.front();
    for (const auto& x : p.xyz) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);

    Bytes h(las::kHeaderSize14);
    h.text(0, "LASF", 4);
    h.put<std::uint16_t>(6, kWktCrs | (p.acquired_utc ? kGpsTimeAdjusted : 0));
    h.put<std::uint8_t>(24, 1);
    h.put<std::uint8_t>(25, 4);
    h.text(26, "tlsmon", 32);
    h.text(58, "tlsmon export", 32);
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    h.put<std::uint16_t>(90, static_cast<std::uint16_t>(utc.tm_yday + 1));
    h.put<std::uint16_t>(92, static_cast<std::uint16_t>(utc.tm_year + 1900));
    h.put<std::uint16_t>(94, las::kHeaderSize14);
    h.put<std::uint32_t>(96, static_cast<std::uint32_t>(las::kHeaderSize14 + vlrs.size()));
    h.put<std::uint32_t>(100, vlr_count);
    h.put<std::uint8_t>(104, 6);
    h.put<std::uint16_t>(105, static_cast<std::uint16_t>(record_length));
    // 107, 111: the legacy counts stay 0 for formats 6–10 (R15 §2.4).
    for (int k = 0; k < 3; ++k) {
        h.put<double>(131 + 8 * k, q.scale[k]);
        h.put<double>(155 + 8 * k, q.offset[k]);
        h.put<double>(179 + 16 * k, hi[k]);
        h.put<double>(187 + 16 * k, lo[k]);
    }
    h.put<std::uint64_t>(247, n);
    h.put<std::uint64_t>(255, n);  // every point is a first (and only) return

    const double gps =
        p.acquired_utc ? utc_to_gps(*p.acquired_utc) - 1e9 : 0.0;  // Adjusted Standard
    std::string records(n * record_length, '\0');
    for (std::size_t i = 0; i < n; ++i) {
        char* r = records.data() + i * record_length;
        const auto put = [&](std::size_t at, auto v) { std::memcpy(r + at, &v, sizeof v); };
        for (int k = 0; k < 3; ++k) {
            put(4 * std::size_t(k),
                static_cast<std::int32_t>(std::llround((p.xyz[i][k] - q.offset[k]) / q.scale[k])));
        }
        put(14, std::uint8_t{0x11});  // return 1 of 1
        put(22, gps);
        std::size_t at = kFormat6RecordLength;
        for (const auto& a : p.attributes) {
            const double v = a.values[i];
            switch (a.type) {
                case LasAttribute::Type::u8:
                    put(at, static_cast<std::uint8_t>(v));
                    break;
                case LasAttribute::Type::u32:
                    put(at, static_cast<std::uint32_t>(v));
                    break;
                case LasAttribute::Type::i32:
                    put(at, static_cast<std::int32_t>(v));
                    break;
                case LasAttribute::Type::f32:
                    put(at, static_cast<float>(v));
                    break;
                case LasAttribute::Type::f64:
                    put(at, v);
                    break;
            }
            at += field_size(a.type);
        }
    }

    const std::filesystem::path part = path.string() + ".part";
    {
        std::ofstream out(part, std::ios::binary | std::ios::trunc);
        if (!out) throw Error("cannot write " + part.string() + ": " + std::strerror(errno));
        out << h.str() << vlrs << records;
        out.close();
        if (!out) throw Error("cannot write " + part.string() + ": " + std::strerror(errno));
    }
    std::error_code ec;
    std::filesystem::rename(part, path, ec);
    if (ec)
        throw Error("cannot rename " + part.string() + " to " + path.string() + ": " +
                    ec.message());
}

}  // namespace tlsmon
