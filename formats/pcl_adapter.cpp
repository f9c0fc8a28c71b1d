// The one translation unit that includes PCL: PLY and PCD through pcl::PLYReader and
// pcl::PCDReader into a pcl::PCLPointCloud2, then the fields a Scan needs.
#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "formats/format_error.hpp"
#include "formats/mapped_file.hpp"
#include "formats/pcl_formats.hpp"

namespace tlsmon {

namespace {

using pcl::PCLPointField;

std::size_t field_size(std::uint8_t datatype) {
    switch (datatype) {
        case PCLPointField::INT8:
        case PCLPointField::UINT8:
            return 1;
        case PCLPointField::INT16:
        case PCLPointField::UINT16:
            return 2;
        case PCLPointField::INT32:
        case PCLPointField::UINT32:
        case PCLPointField::FLOAT32:
            return 4;
        case PCLPointField::INT64:
        case PCLPointField::UINT64:
        case PCLPointField::FLOAT64:
            return 8;
        default:
            return 0;
    }
}

template <class T>
double load_as_double(const std::uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
}

double load_number(const std::uint8_t* p, std::uint8_t datatype) {
    switch (datatype) {
        case PCLPointField::INT8:
            return load_as_double<std::int8_t>(p);
        case PCLPointField::UINT8:
            return load_as_double<std::uint8_t>(p);
        case PCLPointField::INT16:
            return load_as_double<std::int16_t>(p);
        case PCLPointField::UINT16:
            return load_as_double<std::uint16_t>(p);
        case PCLPointField::INT32:
            return load_as_double<std::int32_t>(p);
        case PCLPointField::UINT32:
            return load_as_double<std::uint32_t>(p);
        case PCLPointField::INT64:
            return load_as_double<std::int64_t>(p);
        case PCLPointField::UINT64:
            return load_as_double<std::uint64_t>(p);
        case PCLPointField::FLOAT32:
            return load_as_double<float>(p);
        default:
            return load_as_double<double>(p);
    }
}

class CloudFields {
  public:
    CloudFields(const pcl::PCLPointCloud2& cloud, const std::filesystem::path& path)
        : cloud_(cloud), path_(path) {
        const std::uint64_t points = std::uint64_t{cloud.width} * cloud.height;
        if (cloud.point_step == 0 && points != 0) fail("point step is 0");
        if (cloud.data.size() / std::max<std::uint32_t>(cloud.point_step, 1) < points) {
            fail("declares " + std::to_string(points) + " points of " +
                 std::to_string(cloud.point_step) + " bytes but holds " +
                 std::to_string(cloud.data.size()) + " bytes");
        }
    }

    // The field named one of `names`, checked to lie inside the point record.
    const PCLPointField* find(std::initializer_list<const char*> names) const {
        for (const char* name : names) {
            for (const auto& f : cloud_.fields) {
                if (f.name != name) continue;
                const std::size_t size = field_size(f.datatype);
                if (size == 0) fail("field " + f.name + " has an unknown data type");
                if (f.offset + size > cloud_.point_step) {
                    fail("field " + f.name + " lies outside the point record");
                }
                return &f;
            }
        }
        return nullptr;
    }

    double number(std::size_t point, const PCLPointField& f) const {
        return load_number(record(point) + f.offset, f.datatype);
    }

    std::uint32_t packed_colour(std::size_t point, const PCLPointField& f) const {
        std::uint32_t v = 0;
        std::memcpy(&v, record(point) + f.offset, std::min<std::size_t>(4, field_size(f.datatype)));
        return v;
    }

    [[noreturn]] void fail(const std::string& what) const { throw_format_error(path_, what); }

  private:
    const std::uint8_t* record(std::size_t point) const {
        return cloud_.data.data() + point * cloud_.point_step;
    }

    const pcl::PCLPointCloud2& cloud_;
    const std::filesystem::path& path_;
};

Scan to_scan(const pcl::PCLPointCloud2& cloud, const Eigen::Vector4f& origin,
             const Eigen::Quaternionf& orientation, const std::filesystem::path& path) {
    const CloudFields fields(cloud, path);
    const PCLPointField* x = fields.find({"x"});
    const PCLPointField* y = fields.find({"y"});
    const PCLPointField* z = fields.find({"z"});
    if (!x || !y || !z) fields.fail("has no x, y and z fields");
    const PCLPointField* intensity =
        fields.find({"intensity", "Intensity", "scalar_Intensity", "scalar_intensity"});
    const PCLPointField* rgb = fields.find({"rgb", "rgba"});

    Scan scan;
    scan.source = path.string();
    // The viewpoint is where the sensor stood in the frame of the points (PCD VIEWPOINT).
    scan.pose = Eigen::Translation3d(origin.head<3>().cast<double>()) *
                orientation.cast<double>().normalized();
    const bool organised = cloud.height > 1;
    if (organised) {
        scan.grid.emplace();
        scan.grid->rows = cloud.height;
        scan.grid->columns = cloud.width;
    }

    const std::size_t n = std::size_t{cloud.width} * cloud.height;
    scan.xyz.reserve(n);
    std::vector<double> raw_intensity;
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d p(fields.number(i, *x), fields.number(i, *y), fields.number(i, *z));
        if (!p.allFinite()) continue;  // PCL writes NaN for a cell without a return
        scan.xyz.push_back(p);
        if (organised) {
            scan.grid->row.push_back(static_cast<std::uint32_t>(i / cloud.width));
            scan.grid->column.push_back(static_cast<std::uint32_t>(i % cloud.width));
        }
        if (intensity) {
            const double v = fields.number(i, *intensity);
            if (!std::isfinite(v))
                fields.fail("intensity of point " + std::to_string(i) + " is " + std::to_string(v));
            raw_intensity.push_back(v);
        }
        if (rgb) {
            // PCL packs colour as 0x00RRGGBB (pcl::PointXYZRGB::rgb).
            const std::uint32_t c = fields.packed_colour(i, *rgb);
            scan.rgb.push_back({static_cast<std::uint8_t>(c >> 16),
                                static_cast<std::uint8_t>(c >> 8), static_cast<std::uint8_t>(c)});
        }
    }

    if (intensity && !raw_intensity.empty()) {
        const auto [lo, hi] = std::minmax_element(raw_intensity.begin(), raw_intensity.end());
        if (intensity->datatype == PCLPointField::UINT8) {
            scan.intensity_raw_min = 0.0, scan.intensity_raw_max = 255.0;
        } else if (intensity->datatype == PCLPointField::UINT16) {
            scan.intensity_raw_min = 0.0, scan.intensity_raw_max = 65535.0;
        } else if (*lo >= 0.0 && *hi <= 1.0) {
            scan.intensity_raw_min = 0.0, scan.intensity_raw_max = 1.0;
        } else {
            scan.intensity_raw_min = *lo;
            scan.intensity_raw_max = *hi > *lo ? *hi : *lo + 1.0;
        }
        const double span = scan.intensity_raw_max - scan.intensity_raw_min;
        scan.intensity.reserve(raw_intensity.size());
        for (double v : raw_intensity) {
            scan.intensity.push_back(static_cast<float>((v - scan.intensity_raw_min) / span));
        }
    }
    return scan;
}

void check_readable(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        throw_format_error(path, "cannot open: not a readable regular file");
    }
}

// PCL skips an ASCII PCD line with the wrong number of values (leaving a zero point behind)
// and reads a word that is no number with only a console warning, so every data line is
// checked here first: count of values, each a number (PCL's "nan" included), count of lines.
void check_ascii_pcd_body(const std::filesystem::path& path, std::size_t body_at,
                          std::size_t values_per_point, std::uint64_t points) {
    const MappedFile file(path);
    const std::string_view text = file.text();
    if (body_at > text.size()) throw_at_byte(path, body_at, "PCD data start is past the end");
    std::uint64_t line = 1 + std::count(text.begin(), text.begin() + body_at, '\n');
    std::uint64_t seen = 0;
    for (std::size_t pos = body_at; pos < text.size(); ++line) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::size_t values = 0;
        for (std::size_t t = pos; t < end;) {
            if (text[t] == ' ' || text[t] == '\t' || text[t] == '\r') {
                ++t;
                continue;
            }
            std::size_t u = t;
            while (u < end && text[u] != ' ' && text[u] != '\t' && text[u] != '\r') ++u;
            double v = 0;
            const auto [ptr, ec] = std::from_chars(text.data() + t, text.data() + u, v);
            if (ec != std::errc() || ptr != text.data() + u) {
                throw_at_line(path, line,
                              "\"" + std::string(text.substr(t, std::min<std::size_t>(u - t, 40))) +
                                  "\" is not a number");
            }
            ++values;
            t = u;
        }
        if (values != 0) {
            if (values != values_per_point) {
                throw_at_line(path, line,
                              std::to_string(values) + " values, the header declares " +
                                  std::to_string(values_per_point) + " per point");
            }
            ++seen;
        }
        pos = end + 1;
    }
    if (seen != points) {
        throw_at_line(path, line,
                      "file ends after " + std::to_string(seen) + " points, the header declares " +
                          std::to_string(points));
    }
}

}  // namespace

std::vector<Scan> read_ply(const std::filesystem::path& path) {
    check_readable(path);
    pcl::PCLPointCloud2 cloud;
    Eigen::Vector4f origin = Eigen::Vector4f::Zero();
    Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
    int version = 0;
    pcl::PLYReader reader;
    if (reader.read(path.string(), cloud, origin, orientation, version) < 0) {
        throw_format_error(path,
                           "PCL's PLY reader rejected the file (malformed header, or "
                           "data truncated or not matching the header)");
    }
    std::vector<Scan> scans;
    scans.push_back(to_scan(cloud, origin, orientation, path));
    return scans;
}

std::vector<Scan> read_pcd(const std::filesystem::path& path) {
    check_readable(path);
    pcl::PCLPointCloud2 cloud;
    Eigen::Vector4f origin = Eigen::Vector4f::Zero();
    Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
    int version = 0;
    pcl::PCDReader reader;
    int data_type = 0;
    unsigned int body_at = 0;
    if (reader.readHeader(path.string(), cloud, origin, orientation, version, data_type, body_at) <
            0 ||
        body_at == 0 || cloud.fields.empty()) {
        throw_format_error(path, "PCD header is malformed or incomplete (FIELDS ... DATA)");
    }
    if (data_type == 0) {
        std::size_t values_per_point = 0;
        for (const auto& f : cloud.fields) values_per_point += f.count;
        check_ascii_pcd_body(path, body_at, values_per_point,
                             std::uint64_t{cloud.width} * cloud.height);
    }
    if (reader.read(path.string(), cloud, origin, orientation, version) < 0) {
        throw_format_error(path,
                           "PCL's PCD reader rejected the file (malformed header, or "
                           "data truncated or not matching the header)");
    }
    std::vector<Scan> scans;
    scans.push_back(to_scan(cloud, origin, orientation, path));
    return scans;
}

}  // namespace tlsmon
