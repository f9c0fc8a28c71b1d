#include "formats/ply_header.hpp"

#include <algorithm>
#include <charconv>
#include <optional>

#include "formats/format_error.hpp"
#include "formats/text_scan_parser.hpp"

namespace tlsmon {

namespace {

// A header line is at most this long; the whole header at most this many lines. Both far
// above what any writer produces, and they keep a binary file given a .ply name from being
// scanned to its end for line breaks.
constexpr std::size_t max_header_line = 4096;
constexpr std::uint64_t max_header_lines = 10000;

// PLY's type names and the sized aliases (int8 ... float64) that rply and CloudCompare write.
std::optional<ValueType> type_named(std::string_view n) {
    if (n == "char" || n == "int8") return ValueType::int8;
    if (n == "uchar" || n == "uint8") return ValueType::uint8;
    if (n == "short" || n == "int16") return ValueType::int16;
    if (n == "ushort" || n == "uint16") return ValueType::uint16;
    if (n == "int" || n == "int32") return ValueType::int32;
    if (n == "uint" || n == "uint32") return ValueType::uint32;
    if (n == "float" || n == "float32") return ValueType::float32;
    if (n == "double" || n == "float64") return ValueType::float64;
    return std::nullopt;
}

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> w;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) w.push_back(line.substr(start, i - start));
    }
    return w;
}

}  // namespace

bool PlyElement::has_lists() const {
    for (const auto& p : properties) {
        if (p.is_list) return true;
    }
    return false;
}

std::size_t PlyElement::min_record_bytes() const {
    std::size_t n = 0;
    for (const auto& p : properties) n += value_size(p.is_list ? p.count_type : p.type);
    return n;
}

int PlyElement::find(std::initializer_list<std::string_view> names) const {
    for (std::string_view name : names) {
        for (std::size_t k = 0; k < properties.size(); ++k) {
            if (!properties[k].is_list && properties[k].name == name) return static_cast<int>(k);
        }
    }
    return -1;
}

PlyHeader parse_ply_header(std::string_view bytes, const std::filesystem::path& path) {
    PlyHeader h;
    std::size_t pos = 0;
    bool have_format = false;
    for (std::uint64_t line_no = 1;; ++line_no) {
        const auto fail = [&](const std::string& what) { throw_at_line(path, line_no, what); };
        if (pos >= bytes.size()) fail("file ends inside the PLY header (no end_header line)");
        if (line_no > max_header_lines) fail("PLY header longer than 10000 lines");
        std::size_t end = bytes.find('\n', pos);
        if (end == std::string_view::npos) end = bytes.size();
        if (end - pos > max_header_line) fail("PLY header line longer than 4096 bytes");
        std::string_view line = bytes.substr(pos, end - pos);
        pos = end + 1;
        if (line.ends_with('\r')) line.remove_suffix(1);
        const auto w = words(line);

        if (line_no == 1) {
            if (w.size() != 1 || w[0] != "ply") {
                fail("not a PLY file: the first line must be 'ply', found '" + quote_token(line) +
                     "'");
            }
            continue;
        }
        if (w.empty()) continue;
        const std::string_view key = w[0];
        if (key == "comment" || key == "obj_info") continue;
        if (key == "format") {
            if (w.size() != 3) fail("expected 'format <encoding> 1.0'");
            if (w[1] == "ascii") {
                h.encoding = PlyEncoding::ascii;
            } else if (w[1] == "binary_little_endian") {
                h.encoding = PlyEncoding::binary_little_endian;
            } else if (w[1] == "binary_big_endian") {
                h.encoding = PlyEncoding::binary_big_endian;
            } else {
                fail("unknown PLY encoding '" + quote_token(w[1]) +
                     "' (ascii, binary_little_endian or binary_big_endian)");
            }
            if (w[2] != "1.0" && w[2] != "1") {
                fail("PLY version " + quote_token(w[2]) + " is not 1.0");
            }
            have_format = true;
        } else if (key == "element") {
            if (w.size() != 3) fail("expected 'element <name> <count>'");
            PlyElement e;
            e.name = std::string(w[1]);
            const auto [p, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
            if (ec != std::errc() || p != w[2].data() + w[2].size()) {
                fail("element " + quote_token(w[1]) + ": count '" + quote_token(w[2]) +
                     "' is not an unsigned integer");
            }
            e.header_line = line_no;
            h.elements.push_back(std::move(e));
        } else if (key == "property") {
            if (h.elements.empty()) fail("property before the first element");
            PlyProperty prop;
            std::optional<ValueType> type;
            if (w.size() == 5 && w[1] == "list") {
                const auto count_type = type_named(w[2]);
                type = type_named(w[3]);
                if (!count_type || !type) fail("unknown type in list property");
                if (*count_type == ValueType::float32 || *count_type == ValueType::float64) {
                    fail("a list's count type must be an integer type");
                }
                prop.is_list = true;
                prop.count_type = *count_type;
                prop.name = std::string(w[4]);
            } else if (w.size() == 3) {
                type = type_named(w[1]);
                if (!type) fail("unknown property type '" + quote_token(w[1]) + "'");
                prop.name = std::string(w[2]);
            } else {
                fail(
                    "expected 'property <type> <name>' or 'property list <count type> "
                    "<type> <name>'");
            }
            prop.type = *type;
            h.elements.back().properties.push_back(std::move(prop));
        } else if (key == "end_header") {
            if (!have_format) fail("end_header before the format line");
            h.data_offset = std::min(pos, bytes.size());
            h.header_lines = line_no;
            return h;
        } else {
            fail("unknown PLY header keyword '" + quote_token(key) + "'");
        }
    }
}

}  // namespace tlsmon
