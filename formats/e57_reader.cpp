#include "formats/e57_reader.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>

#include "core/utc_time.hpp"
#include "formats/e57_bitstream.hpp"
#include "formats/e57_pages.hpp"
#include "formats/e57_xml.hpp"
#include "formats/mapped_file.hpp"

namespace tlsmon {

namespace {

// Prototype field names of E2807 §10.5 PointRecord that the reader uses.
enum Column {
    cartesian_x,
    cartesian_y,
    cartesian_z,
    spherical_range,
    spherical_azimuth,
    spherical_elevation,
    intensity,
    color_red,
    color_green,
    color_blue,
    row_index,
    column_index,
    cartesian_invalid,
    spherical_invalid,
    column_count
};
constexpr std::array<std::string_view, column_count> column_names = {"cartesianX",
                                                                     "cartesianY",
                                                                     "cartesianZ",
                                                                     "sphericalRange",
                                                                     "sphericalAzimuth",
                                                                     "sphericalElevation",
                                                                     "intensity",
                                                                     "colorRed",
                                                                     "colorGreen",
                                                                     "colorBlue",
                                                                     "rowIndex",
                                                                     "columnIndex",
                                                                     "cartesianInvalidState",
                                                                     "sphericalInvalidState"};

// colorLimits -> 8 bits by equal buckets, floor((v - min) / (max - min) * 256) capped at
// 255: the identity for 0..255 and v >> 8 for 0..65535 (as the LAS reader scales 16-bit
// colour), so a LAS colour that went through E57 keeps its 8-bit value.
struct ColourScale {
    double minimum = 0.0;
    double factor = 0.0;  // 256 / (max - min), 0 when the limits are empty
    ColourScale() = default;
    explicit ColourScale(const E57Range& r)
        : minimum(r.minimum),
          factor(r.maximum > r.minimum ? 256.0 / (r.maximum - r.minimum) : 0.0) {}
    std::uint8_t operator()(double v) const {
        const double c = (v - minimum) * factor;  // truncation below is the floor for c >= 0
        return c <= 0.0 ? 0 : c >= 255.0 ? 255 : static_cast<std::uint8_t>(c);
    }
};

// Limits from the scan's *Limits element, else the prototype field's declared range
// (E2807 §10.5: the limits default to the field's minimum and maximum).
E57Range limits_of(const std::optional<E57Range>& given, const E57Field& f) {
    if (given) return *given;
    E57Range r{f.declared_minimum(), f.declared_maximum()};
    // Float fields without declared bounds carry ±FLT_MAX: take them as already 0..1.
    if (std::abs(r.minimum) > 1e30 || std::abs(r.maximum) > 1e30) r = {0.0, 1.0};
    return r;
}

Scan read_scan(E57Pages& pages, const E57ScanInfo& info, std::string source) {
    const E57CompressedVector& cv = info.points;
    std::array<int, column_count> field_of;
    field_of.fill(-1);
    for (std::size_t f = 0; f < cv.fields.size(); ++f)
        for (int c = 0; c < column_count; ++c)
            if (cv.fields[f].name == column_names[c]) field_of[c] = static_cast<int>(f);
    const auto has = [&](int c) { return field_of[c] >= 0; };

    const bool cartesian = has(cartesian_x) && has(cartesian_y) && has(cartesian_z);
    const bool spherical =
        has(spherical_range) && has(spherical_azimuth) && has(spherical_elevation);
    if (!cartesian && !spherical)
        pages.fail(cv.xml_byte,
                   "bad prototype: neither cartesianX/Y/Z nor "
                   "sphericalRange/Azimuth/Elevation");
    const bool has_intensity = has(intensity);
    const bool has_colour = has(color_red) && has(color_green) && has(color_blue);
    const bool has_grid = has(row_index) && has(column_index);
    const int invalid = cartesian ? cartesian_invalid : spherical_invalid;

    // Columns handed to the decoder, in this order; -1 where the field is absent.
    std::vector<std::size_t> wanted;
    std::array<int, column_count> slot;
    slot.fill(-1);
    const auto want = [&](int c) {
        if (!has(c)) return;
        slot[c] = static_cast<int>(wanted.size());
        wanted.push_back(static_cast<std::size_t>(field_of[c]));
    };
    for (const int c : cartesian
                           ? std::array{cartesian_x, cartesian_y, cartesian_z}
                           : std::array{spherical_range, spherical_azimuth, spherical_elevation})
        want(c);
    if (has_intensity) want(intensity);
    if (has_colour)
        for (const int c : {color_red, color_green, color_blue}) want(c);
    if (has_grid)
        for (const int c : {row_index, column_index}) want(c);
    want(invalid);

    Scan scan;
    scan.source = std::move(source);
    scan.name = info.name;
    scan.pose = info.pose;
    if (info.acquisition_start_gps)
        // E2807 §8.4.2 DateTime: dateTimeValue is GPS time (seconds since 1980-01-06,
        // no leap seconds); Scan wants UTC.
        scan.acquired_utc = gps_to_utc(*info.acquisition_start_gps);

    E57Range intensity_range{0.0, 1.0};
    if (has_intensity) {
        intensity_range = limits_of(info.intensity_limits, cv.fields[field_of[intensity]]);
        scan.intensity_raw_min = intensity_range.minimum;
        scan.intensity_raw_max = intensity_range.maximum;
    }
    std::array<ColourScale, 3> colour_scale{};
    if (has_colour)
        for (int k = 0; k < 3; ++k)
            colour_scale[k] =
                ColourScale(limits_of(info.color_limits[k], cv.fields[field_of[color_red + k]]));

    // Grid size from indexBounds (E2807 §10.3), else from the largest indices seen.
    std::int64_t row_min = 0, column_min = 0, row_limit = -1, column_limit = -1;
    constexpr std::int64_t max_index = 0xFFFFFFFF;  // rows = index + 1 must fit in 32 bits
    if (has_grid && info.index_bounds) {
        const E57IndexBounds& b = *info.index_bounds;
        constexpr std::int64_t big = std::int64_t{1} << 40;  // keeps the differences exact
        for (const std::int64_t v :
             {b.row_minimum, b.row_maximum, b.column_minimum, b.column_maximum})
            if (v <= -big || v >= big) pages.fail(info.xml_byte, "indexBounds out of range");
        row_min = b.row_minimum;
        column_min = b.column_minimum;
        row_limit = b.row_maximum - b.row_minimum;
        column_limit = b.column_maximum - b.column_minimum;
        if (row_limit < 0 || column_limit < 0 || row_limit >= max_index ||
            column_limit >= max_index)
            pages.fail(info.xml_byte, "indexBounds do not describe a grid");
    }
    ScanGrid grid;
    // Reserve the declared record count, capped by the file size so a lying count costs
    // at most a few bytes of memory per byte of file (the decoder checks it again).
    const std::size_t expected =
        static_cast<std::size_t>(std::min<std::uint64_t>(cv.record_count, pages.physical_size()));
    scan.xyz.reserve(expected);
    if (has_intensity) scan.intensity.reserve(expected);
    if (has_colour) scan.rgb.reserve(expected);
    if (has_grid) {
        grid.row.reserve(expected);
        grid.column.reserve(expected);
    }
    std::int64_t row_max_seen = -1, column_max_seen = -1;
    std::int64_t row_min_seen = max_index, column_min_seen = max_index;

    const Eigen::Matrix3d rotation = scan.pose.linear();
    const Eigen::Vector3d translation = scan.pose.translation();
    const float intensity_span =
        static_cast<float>(intensity_range.maximum - intensity_range.minimum);

    decode_e57_records(
        pages, cv, wanted, [&](const std::vector<std::vector<double>>& col, std::size_t n) {
            const auto value = [&](int c, std::size_t i) {
                return col[static_cast<std::size_t>(slot[c])][i];
            };
            for (std::size_t i = 0; i < n; ++i) {
                // Invalid state 0 = valid; 1 = direction only (no range), 2 = no point: skip both.
                if (slot[invalid] >= 0 && value(invalid, i) != 0.0) continue;
                Eigen::Vector3d p;
                if (cartesian) {
                    p = {value(cartesian_x, i), value(cartesian_y, i), value(cartesian_z, i)};
                } else {
                    // E2807 §10.5: azimuth from +x towards +y, elevation from the xy plane.
                    const double r = value(spherical_range, i);
                    const double az = value(spherical_azimuth, i);
                    const double el = value(spherical_elevation, i);
                    p = {r * std::cos(el) * std::cos(az), r * std::cos(el) * std::sin(az),
                         r * std::sin(el)};
                }
                scan.xyz.push_back(rotation * p + translation);
                if (has_intensity) {
                    const float v =
                        static_cast<float>(value(intensity, i) - intensity_range.minimum);
                    scan.intensity.push_back(intensity_span > 0 ? v / intensity_span : 0.0f);
                }
                if (has_colour)
                    scan.rgb.push_back({colour_scale[0](value(color_red, i)),
                                        colour_scale[1](value(color_green, i)),
                                        colour_scale[2](value(color_blue, i))});
                if (has_grid) {
                    const double row_value = value(row_index, i);
                    const double column_value = value(column_index, i);
                    constexpr double huge = 1e12;  // |index| below this converts to int64 exactly
                    if (!(std::abs(row_value) < huge && std::abs(column_value) < huge))
                        pages.fail(cv.xml_byte, "point " + std::to_string(scan.xyz.size() - 1) +
                                                    " has rowIndex/columnIndex out of range");
                    const auto r = static_cast<std::int64_t>(row_value) - row_min;
                    const auto c = static_cast<std::int64_t>(column_value) - column_min;
                    const bool bounded = row_limit >= 0;
                    if (r < 0 || c < 0 || (bounded && (r > row_limit || c > column_limit)) ||
                        r >= max_index || c >= max_index)
                        pages.fail(cv.xml_byte,
                                   "point " + std::to_string(scan.xyz.size() - 1) +
                                       " has rowIndex/columnIndex outside indexBounds");
                    row_max_seen = std::max(row_max_seen, r);
                    column_max_seen = std::max(column_max_seen, c);
                    row_min_seen = std::min(row_min_seen, r);
                    column_min_seen = std::min(column_min_seen, c);
                    grid.row.push_back(static_cast<std::uint32_t>(r));
                    grid.column.push_back(static_cast<std::uint32_t>(c));
                }
            }
        });

    if (has_grid) {
        grid.rows = static_cast<std::uint32_t>((row_limit >= 0 ? row_limit : row_max_seen) + 1);
        grid.columns =
            static_cast<std::uint32_t>((column_limit >= 0 ? column_limit : column_max_seen) + 1);
        // The indices are not tied to the record count: a region cut out of a scan keeps its
        // place in the whole scan's grid, and a damaged file may claim any bounds. What works
        // on the grid holds a few bytes a cell (algorithms/depth_discontinuity.cpp,
        // registration/plane_detection.cpp), so a grid far larger than its points is cut to
        // the cells they occupy, and one that is still that sparse is no scanner's grid.
        const std::uint64_t points = grid.row.size();
        if (points == 0 && grid.too_sparse()) {
            grid.rows = grid.columns = 0;
        } else if (grid.too_sparse()) {
            for (auto& r : grid.row) r -= static_cast<std::uint32_t>(row_min_seen);
            for (auto& c : grid.column) c -= static_cast<std::uint32_t>(column_min_seen);
            grid.rows = static_cast<std::uint32_t>(row_max_seen - row_min_seen + 1);
            grid.columns = static_cast<std::uint32_t>(column_max_seen - column_min_seen + 1);
            if (grid.too_sparse())
                pages.fail(cv.xml_byte, "rowIndex/columnIndex spread " + std::to_string(points) +
                                            " points over " + std::to_string(grid.rows) +
                                            " rows and " + std::to_string(grid.columns) +
                                            " columns, more than " +
                                            std::to_string(ScanGrid::kMaxCellsPerPoint) +
                                            " cells a point: not a scanner's grid");
        }
        scan.grid = std::move(grid);
    }
    return scan;
}

}  // namespace

std::vector<Scan> parse_e57(const char* data, std::size_t size, const std::filesystem::path& path) {
    E57Pages pages(data, size, path);
    const std::string xml = pages.read_xml();
    const std::vector<E57ScanInfo> infos = parse_e57_xml(pages, xml);
    std::vector<Scan> scans;
    scans.reserve(infos.size());
    for (std::size_t k = 0; k < infos.size(); ++k) {
        std::string source = path.string();
        if (infos.size() > 1) source.append("#").append(std::to_string(k + 1));  // 1-based, as PTX
        scans.push_back(read_scan(pages, infos[k], std::move(source)));
    }
    return scans;
}

std::optional<double> read_e57_acquired_utc(const std::filesystem::path& path) {
    const MappedFile file(path);
    E57Pages pages(file.data(), file.size(), path);
    for (const E57ScanInfo& info : parse_e57_xml(pages, pages.read_xml()))
        if (info.acquisition_start_gps) return gps_to_utc(*info.acquisition_start_gps);
    return std::nullopt;
}

std::vector<Scan> read_e57(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_e57(file.data(), file.size(), path);
}

}  // namespace tlsmon
