#include "formats/ptx_writer.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

#include "core/error.hpp"

namespace tlsmon {

namespace {

void append_fixed(std::string& out, double v, int decimals) {
    char buf[64];
    // Write values that round to zero as 0, never "-0.000000".
    const double half_unit = 0.5 * std::pow(10.0, -decimals);
    if (v > -half_unit && v < half_unit) v = 0.0;
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
    out.append(buf, r.ptr);
}

void append_row(std::string& out, double a, double b, double c, int decimals) {
    append_fixed(out, a, decimals);
    out += ' ';
    append_fixed(out, b, decimals);
    out += ' ';
    append_fixed(out, c, decimals);
}

// Header numbers are written exactly (shortest text that reads back to the same double):
// with 6 decimals a rotation of 30° would be off by 2e-7 rad, 10 µm at 50 m.
void append_exact(std::string& out, double v) {
    char buf[64];
    if (v == 0.0) v = 0.0;  // no "-0"
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

void append_header_row(std::string& out, double a, double b, double c) {
    append_exact(out, a);
    out += ' ';
    append_exact(out, b);
    out += ' ';
    append_exact(out, c);
}

}  // namespace

std::string ptx_text(const Scan& scan, const PtxWriteOptions& options) {
    if (!scan.grid) throw Error("PTX writer: scan '" + scan.source + "' has no grid");
    const ScanGrid& g = *scan.grid;
    const std::size_t n = scan.xyz.size();
    if (g.row.size() != n || g.column.size() != n ||
        (!scan.intensity.empty() && scan.intensity.size() != n)) {
        throw Error("PTX writer: grid indices, intensities and points differ in number");
    }
    // Cell -> point index (column-major, as the file is written).
    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    if (g.cells() >= none) throw Error("PTX writer: grid too large");
    std::vector<std::uint32_t> cell(g.cells(), none);
    for (std::size_t i = 0; i < n; ++i) {
        if (g.row[i] >= g.rows || g.column[i] >= g.columns) {
            throw Error("PTX writer: point " + std::to_string(i) + " lies outside the grid");
        }
        std::uint32_t& slot = cell[std::uint64_t{g.column[i]} * g.rows + g.row[i]];
        if (slot != none) {
            throw Error("PTX writer: two points in grid cell row " + std::to_string(g.row[i]) +
                        " column " + std::to_string(g.column[i]));
        }
        slot = static_cast<std::uint32_t>(i);
    }

    const int cd = options.coordinate_decimals;
    std::string out;
    out.reserve(200 + g.cells() *
                          static_cast<std::size_t>(3 * (cd + 5) + options.intensity_decimals + 4));
    out += std::to_string(g.columns) + '\n' + std::to_string(g.rows) + '\n';
    const Eigen::Matrix3d r = scan.pose.linear();
    const Eigen::Vector3d t = scan.pose.translation();
    append_header_row(out, t.x(), t.y(), t.z());
    out += '\n';
    // Scanner axes in the project frame: the columns of R.
    for (int a = 0; a < 3; ++a) {
        append_header_row(out, r(0, a), r(1, a), r(2, a));
        out += '\n';
    }
    // Row-vector form: M = [Rᵀ 0; tᵀ 1].
    for (int a = 0; a < 3; ++a) {
        append_header_row(out, r(0, a), r(1, a), r(2, a));
        out += " 0\n";
    }
    append_header_row(out, t.x(), t.y(), t.z());
    out += " 1\n";

    const Eigen::Affine3d to_scanner = scan.pose.inverse();
    for (const std::uint32_t i : cell) {
        if (i == none) {
            out += "0 0 0 0.5\n";
            continue;
        }
        const Eigen::Vector3d p = to_scanner * scan.xyz[i];
        append_row(out, p.x(), p.y(), p.z(), cd);
        out += ' ';
        append_fixed(out, scan.intensity.empty() ? 0.5 : scan.intensity[i],
                     options.intensity_decimals);
        out += '\n';
    }
    return out;
}

void write_ptx(const Scan& scan, const std::filesystem::path& path,
               const PtxWriteOptions& options) {
    const std::string text = ptx_text(scan, options);
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    f.close();
    if (!f) throw Error("PTX writer: cannot write " + path.string());
}

}  // namespace tlsmon
