#include "formats/ptx_reader.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include "formats/format_error.hpp"
#include "formats/mapped_file.hpp"
#include "formats/text_scan_parser.hpp"

namespace tlsmon {

namespace {

// Shortest possible point line: "0 0 0 0" and its end of line.
constexpr std::uint64_t min_point_line_bytes = 8;

// Integer intensity scale of exporters that do not write 0..1.
constexpr double integer_raw_min = -2047.0;
constexpr double integer_raw_max = 2048.0;

void read_header_line(TextCursor& cur, std::string_view& line, double* out, int count,
                      const char* what) {
    if (!cur.next_line(line))
        cur.fail(std::string("file ends inside the header: expected ") + what);
    const int n = parse_numbers(line, out, count, cur);
    if (n != count) {
        cur.fail(std::string("expected ") + std::to_string(count) + " numbers (" + what +
                 "), found " + std::to_string(n));
    }
}

// Header lines 3..10 after columns and rows; returns the scanner -> project transform.
Eigen::Affine3d read_pose(TextCursor& cur) {
    std::string_view line;
    double v[4];
    read_header_line(cur, line, v, 3, "scanner position");
    for (const char* axis : {"scanner X axis", "scanner Y axis", "scanner Z axis"}) {
        read_header_line(cur, line, v, 3, axis);
    }
    // Row-vector form: p' = [x y z 1]·M, so the column-vector transform is M transposed.
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
        read_header_line(cur, line, v, 4, "a row of the 4x4 transformation matrix");
        for (int c = 0; c < 4; ++c) m(r, c) = v[c];
        const double expected_last = r == 3 ? 1.0 : 0.0;
        if (std::abs(v[3] - expected_last) > 1e-9) {
            cur.fail(
                "the 4x4 matrix is not affine: the last column must be 0 0 0 1 (row-vector "
                "form, translation on the last line)");
        }
    }
    // A rotation, possibly scaled (PDAL's test file scales z by 2): its singular values lie
    // near 1, never at 0 (every point on a plane or a line) nor at 1e300.
    const Eigen::Vector3d sv =
        Eigen::JacobiSVD<Eigen::Matrix3d>(m.topLeftCorner<3, 3>()).singularValues();
    if (!(sv.minCoeff() >= 1e-3 && sv.maxCoeff() <= 1e3)) {
        char text[64];
        std::snprintf(text, sizeof text, "%g to %g", sv.minCoeff(), sv.maxCoeff());
        cur.fail(std::string("the 4x4 matrix's rotation part scales by ") + text +
                 " (a rotation scales by 1): the transformation is corrupt");
    }
    Eigen::Affine3d pose = Eigen::Affine3d::Identity();
    pose.linear() = m.topLeftCorner<3, 3>().transpose();
    pose.translation() = m.block<1, 3>(3, 0).transpose();
    return pose;
}

// How many of the next `cells` point lines are returns: lines not written "0 0 0 ..." (the
// cell without a return). One pass of memchr over the lines, a few percent of the parse;
// a return written with zeros another way ("0.0 0.0 0.0") is counted as a point, so the
// count never falls short for the usual files and is only a reservation anyway.
std::uint64_t count_returns(std::string_view text, std::uint64_t cells) {
    std::uint64_t lines = 0, empty = 0;
    const char* p = text.data();
    const char* const end = p + text.size();
    while (p < end && lines < cells) {
        const char* nl =
            static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
        const char* line_end = nl ? nl : end;
        const char* q = p;
        while (q < line_end && (*q == ' ' || *q == '\t')) ++q;
        if (q < line_end && *q != '\r') {  // not blank: one cell
            ++lines;
            const std::string_view line(q, static_cast<std::size_t>(line_end - q));
            if (line.starts_with("0 0 0 ") || line.starts_with("0 0 0\t")) ++empty;
        }
        p = nl ? nl + 1 : end;
    }
    return cells - empty;
}

Scan read_scan(TextCursor& cur, std::string_view first_line, std::size_t index) {
    if (!is_single_count(first_line)) {
        // Only a later scan has a previous header whose cells may have been miscounted; a
        // file whose first line is no count is most likely not PTX at all.
        const std::string hint = index == 0
                                     ? " (a PTX file starts with the column count of its first "
                                       "scan: is this a PTX export?)"
                                     : " (more point lines than the previous header's "
                                       "columns × rows?)";
        cur.fail("expected the column count that starts scan " + std::to_string(index + 1) +
                 ", found '" + quote_token(first_line) + "'" + hint);
    }
    const std::uint64_t columns = parse_count(first_line, "column count", cur);
    std::string_view line;
    if (!cur.next_line(line)) cur.fail("file ends inside the header: expected the row count");
    const std::uint64_t rows = parse_count(line, "row count", cur);
    constexpr std::uint64_t max_side = std::numeric_limits<std::uint32_t>::max();
    if (columns == 0 || rows == 0) {
        cur.fail("scan declares " + std::to_string(columns) + " columns × " + std::to_string(rows) +
                 " rows: no cells");
    }
    if (columns > max_side || rows > max_side) cur.fail("absurd grid size in the header");
    const std::uint64_t cells = columns * rows;
    const std::uint64_t header_line = cur.line_number();

    Scan scan;
    scan.pose = read_pose(cur);

    // Bound every allocation by the file: each cell needs a line of at least 8 bytes.
    const std::uint64_t room = (cur.remaining_bytes() + 1) / min_point_line_bytes;
    if (cells > room) {
        throw_at_line(cur.file(), header_line,
                      "header declares " + std::to_string(columns) + " × " + std::to_string(rows) +
                          " = " + std::to_string(cells) + " cells but only " +
                          std::to_string(cur.remaining_bytes()) + " bytes follow");
    }
    // Reserve for the points, not the cells: a scan of a bridge often has a third of its
    // cells empty (sky), and each point costs 39 bytes across the arrays.
    const std::uint64_t points = count_returns(cur.rest(), cells);
    scan.xyz.reserve(points);
    scan.intensity.reserve(points);
    ScanGrid grid;
    grid.rows = static_cast<std::uint32_t>(rows);
    grid.columns = static_cast<std::uint32_t>(columns);
    grid.row.reserve(points);
    grid.column.reserve(points);

    int fields = 0;  // values per point line, fixed by the first non-empty cell
    double v[10];
    float raw_min = std::numeric_limits<float>::max();
    float raw_max = std::numeric_limits<float>::lowest();
    std::uint32_t row = 0;
    std::uint32_t column = 0;
    for (std::uint64_t cell = 0; cell < cells; ++cell) {
        if (!cur.next_line(line)) {
            cur.fail("file ends after " + std::to_string(cell) + " of the " +
                     std::to_string(cells) + " point lines the header on line " +
                     std::to_string(header_line) + " declares");
        }
        const int n = parse_numbers(line, v, 10, cur);
        if (n < 3) cur.fail("a point line needs x y z, found " + std::to_string(n) + " values");
        const std::uint32_t r = row;
        const std::uint32_t c = column;
        if (++row == rows) {
            row = 0;
            ++column;
        }
        if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0) continue;  // no return in this cell

        if (fields == 0) {
            if (n != 4 && n != 7 && n != 10) {
                cur.fail(
                    "a PTX point line has 4, 7 or 10 values (x y z i [r g b [nx ny nz]]), "
                    "found " +
                    std::to_string(n));
            }
            fields = n;
            if (fields >= 7) scan.rgb.reserve(points);
        } else if (n != fields) {
            cur.fail("point line has " + std::to_string(n) +
                     " values, earlier lines of this "
                     "scan have " +
                     std::to_string(fields));
        }
        const double i = v[3];
        if (i < -2048.0 || i > 2048.0) {
            cur.fail("intensity " + std::to_string(i) + " is outside 0..1 and -2047..2048");
        }
        if (fields >= 7) {
            Rgb8 rgb;
            for (int k = 0; k < 3; ++k) {
                const double x = v[4 + k];
                if (x < 0.0 || x > 255.0) {
                    cur.fail("colour value " + std::to_string(x) + " is outside 0..255");
                }
                rgb[k] = static_cast<std::uint8_t>(std::lround(x));
            }
            scan.rgb.push_back(rgb);
        }
        scan.xyz.push_back(scan.pose * Eigen::Vector3d(v[0], v[1], v[2]));
        const auto fi = static_cast<float>(i);
        raw_min = std::min(raw_min, fi);
        raw_max = std::max(raw_max, fi);
        scan.intensity.push_back(fi);
        grid.row.push_back(r);
        grid.column.push_back(c);
    }

    if (!scan.intensity.empty() && (raw_min < 0.0f || raw_max > 1.0f)) {
        scan.intensity_raw_min = integer_raw_min;
        scan.intensity_raw_max = integer_raw_max;
        constexpr double span = integer_raw_max - integer_raw_min;
        for (float& x : scan.intensity) {
            x = static_cast<float>(std::clamp((x - integer_raw_min) / span, 0.0, 1.0));
        }
    }
    scan.grid = std::move(grid);
    return scan;
}

}  // namespace

std::vector<Scan> parse_ptx(std::string_view text, const std::filesystem::path& file) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark
    TextCursor cur(text, file);
    std::vector<Scan> scans;
    std::string_view line;
    while (cur.next_line(line)) scans.push_back(read_scan(cur, line, scans.size()));
    if (scans.empty()) throw_format_error(file, "no PTX scan: the file is empty");
    for (std::size_t k = 0; k < scans.size(); ++k) {
        scans[k].source = file.string();
        if (scans.size() > 1) scans[k].source.append("#").append(std::to_string(k + 1));
    }
    return scans;
}

std::vector<Scan> read_ptx(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_ptx(file.text(), path);
}

}  // namespace tlsmon
