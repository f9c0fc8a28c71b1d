#include "formats/ascii_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "formats/format_error.hpp"
#include "formats/mapped_file.hpp"
#include "formats/text_scan_parser.hpp"

namespace tlsmon {

namespace {

enum class Dialect { pts, xyz };

// Shortest possible point line: "0 0 0" and its end of line.
constexpr std::uint64_t min_point_line_bytes = 6;

// Leica PTS intensity scale.
constexpr double pts_raw_min = -2048.0;
constexpr double pts_raw_max = 2047.0;

// "1,5 2,3 4,1": numbers written with a decimal comma, which the comma separator would read
// as six values. A comma between two digits inside a field of a line whose fields are
// separated by blanks ("1.5,2.3,4.1" is one comma-separated field list, not this).
bool has_decimal_comma(std::string_view line, std::string_view& field) {
    std::size_t begin = 0;
    int fields = 0;
    std::string_view with_comma;
    while (begin < line.size()) {
        begin = line.find_first_not_of(" \t\r", begin);
        if (begin == std::string_view::npos) break;
        std::size_t end = line.find_first_of(" \t\r", begin);
        if (end == std::string_view::npos) end = line.size();
        const std::string_view f = line.substr(begin, end - begin);
        ++fields;
        const std::size_t comma = f.find(',');
        if (with_comma.empty() && comma != std::string_view::npos && comma > 0 &&
            comma + 1 < f.size() && std::isdigit(static_cast<unsigned char>(f[comma - 1])) &&
            std::isdigit(static_cast<unsigned char>(f[comma + 1]))) {
            with_comma = f;
        }
        begin = end;
    }
    field = with_comma;
    return fields >= 2 && !with_comma.empty();
}

bool is_comment(std::string_view line) {
    const std::size_t k = line.find_first_not_of(" \t");
    if (k == std::string_view::npos) return false;
    return line[k] == '#' || line.substr(k).starts_with("//");
}

struct Block {
    Scan scan;
    int fields = 0;                         // values per line: 3, 4, 6 or 7
    std::optional<std::uint64_t> declared;  // PTS count line
    std::uint64_t declared_on = 0;          // its line number
    double raw_min = std::numeric_limits<double>::max();
    double raw_max = std::numeric_limits<double>::lowest();
};

void check_count(const Block& b, const TextCursor& cur) {
    if (b.declared && b.scan.size() != *b.declared) {
        cur.fail("the count on line " + std::to_string(b.declared_on) + " declares " +
                 std::to_string(*b.declared) + " points, " + std::to_string(b.scan.size()) +
                 " point lines follow it");
    }
}

// Raw intensity scale of an XYZ file: see ascii_reader.hpp.
std::pair<double, double> xyz_raw_scale(double lo, double hi) {
    if (lo >= 0.0 && hi <= 1.0) return {0.0, 1.0};
    if (lo >= 0.0 && hi <= 255.0) return {0.0, 255.0};
    if (lo >= 0.0 && hi <= 65535.0) return {0.0, 65535.0};
    if (hi > lo) return {lo, hi};
    return {lo, lo + 1.0};
}

void finish(Block& b, Dialect dialect, std::vector<Scan>& scans) {
    Scan& s = b.scan;
    if (!s.intensity.empty()) {
        const auto [lo, hi] = dialect == Dialect::pts ? std::pair{pts_raw_min, pts_raw_max}
                                                      : xyz_raw_scale(b.raw_min, b.raw_max);
        s.intensity_raw_min = lo;
        s.intensity_raw_max = hi;
        if (lo != 0.0 || hi != 1.0) {
            const double span = hi - lo;
            for (float& x : s.intensity) {
                x = static_cast<float>(std::clamp((x - lo) / span, 0.0, 1.0));
            }
        }
    }
    scans.push_back(std::move(s));
}

std::vector<Scan> parse_points(std::string_view text, const std::filesystem::path& file,
                               Dialect dialect) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark
    TextCursor cur(text, file);
    std::vector<Scan> scans;
    std::optional<Block> block;
    std::string_view line;
    double v[7];
    while (cur.next_line(line)) {
        if (is_comment(line)) continue;
        if (dialect == Dialect::pts && is_single_count(line)) {
            if (block) {
                check_count(*block, cur);
                finish(*block, dialect, scans);
            }
            block.emplace();
            block->declared = parse_count(line, "point count", cur);
            block->declared_on = cur.line_number();
            // Bound the allocation by the file: each point needs a line of 6 bytes or more.
            const std::uint64_t room = (cur.remaining_bytes() + 1) / min_point_line_bytes;
            if (*block->declared > room) {
                cur.fail("count declares " + std::to_string(*block->declared) +
                         " points but only " + std::to_string(cur.remaining_bytes()) +
                         " bytes follow");
            }
            block->scan.xyz.reserve(*block->declared);
            continue;
        }
        if (!block) block.emplace();
        Block& b = *block;
        if (b.fields == 0) {
            std::string_view field;
            if (has_decimal_comma(line, field)) {
                cur.fail("'" + quote_token(field) +
                         "' is written with a decimal comma: write numbers with a decimal point "
                         "(fields may be separated by blanks or commas)");
            }
        }
        const int n = parse_numbers(line, v, 7, cur);
        if (b.fields == 0) {
            if (n != 3 && n != 4 && n != 6 && n != 7) {
                cur.fail("a point line has 3, 4, 6 or 7 values (x y z [i] [r g b]), found " +
                         std::to_string(n));
            }
            b.fields = n;
            if (b.declared) {
                if (n == 4 || n == 7) b.scan.intensity.reserve(*b.declared);
                if (n >= 6) b.scan.rgb.reserve(*b.declared);
            }
        } else if (n != b.fields) {
            cur.fail("point line has " + std::to_string(n) + " values, earlier lines have " +
                     std::to_string(b.fields));
        }
        if (b.declared && b.scan.size() == *b.declared) {
            cur.fail("more point lines than the count " + std::to_string(*b.declared) +
                     " on line " + std::to_string(b.declared_on));
        }
        b.scan.xyz.emplace_back(v[0], v[1], v[2]);
        const bool has_intensity = n == 4 || n == 7;
        if (has_intensity) {
            const double i = v[3];
            if (dialect == Dialect::pts && (i < pts_raw_min || i > pts_raw_max)) {
                cur.fail("PTS intensity " + std::to_string(i) + " is outside -2048..2047");
            }
            b.raw_min = std::min(b.raw_min, i);
            b.raw_max = std::max(b.raw_max, i);
            b.scan.intensity.push_back(static_cast<float>(i));
        }
        if (n >= 6) {
            const int first = has_intensity ? 4 : 3;
            Rgb8 rgb;
            for (int k = 0; k < 3; ++k) {
                const double x = v[first + k];
                if (x < 0.0 || x > 255.0) {
                    cur.fail("colour value " + std::to_string(x) + " is outside 0..255");
                }
                rgb[k] = static_cast<std::uint8_t>(std::lround(x));
            }
            b.scan.rgb.push_back(rgb);
        }
    }
    // A file cut short (a copy or a write interrupted) usually ends inside a line, which
    // may still hold as many values, the last one cut ("12.3 4.5 6" of "12.3 4.5 6.789").
    // A point file ends its last line; one of a single line is taken as written.
    const std::size_t last_end = text.rfind('\n');
    if (last_end != std::string_view::npos) {
        const std::string_view tail = text.substr(last_end + 1);
        const std::size_t value = tail.find_last_of(" \t,");
        if (tail.find_first_not_of(" \t\r") != std::string_view::npos && !is_comment(tail)) {
            cur.fail("the file ends inside its last line (no end of line after '" +
                     quote_token(value == std::string_view::npos ? tail : tail.substr(value + 1)) +
                     "'): it was cut short while it was written or copied");
        }
    }
    if (block) {
        check_count(*block, cur);
        finish(*block, dialect, scans);
    }
    std::uint64_t points = 0;
    for (const Scan& s : scans) points += s.size();
    if (points == 0) throw_format_error(file, "no points in the file");
    for (std::size_t k = 0; k < scans.size(); ++k) {
        scans[k].source = file.string();
        if (scans.size() > 1) scans[k].source.append("#").append(std::to_string(k + 1));
    }
    return scans;
}

}  // namespace

std::vector<Scan> parse_pts(std::string_view text, const std::filesystem::path& file) {
    return parse_points(text, file, Dialect::pts);
}

std::vector<Scan> parse_xyz(std::string_view text, const std::filesystem::path& file) {
    return parse_points(text, file, Dialect::xyz);
}

std::vector<Scan> read_pts(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_pts(file.text(), path);
}

std::vector<Scan> read_xyz(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_xyz(file.text(), path);
}

}  // namespace tlsmon
