#include "formats/text_scan_parser.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <system_error>

#include "formats/format_error.hpp"

namespace tlsmon {

namespace {

bool is_separator(char c) {
    return c == ' ' || c == '\t' || c == ',' || c == '\r';
}

bool is_blank(std::string_view line) {
    for (char c : line) {
        if (c != ' ' && c != '\t' && c != '\r') return false;
    }
    return true;
}

std::string_view token_at(const char* p, const char* end) {
    const char* q = p;
    while (q < end && !is_separator(*q)) ++q;
    return {p, static_cast<std::size_t>(q - p)};
}

}  // namespace

bool TextCursor::next_line(std::string_view& line) {
    while (pos_ < text_.size()) {
        const char* begin = text_.data() + pos_;
        const std::size_t left = text_.size() - pos_;
        const void* nl = std::memchr(begin, '\n', left);
        const std::size_t len =
            nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - begin) : left;
        pos_ += nl ? len + 1 : len;
        ++line_;
        line = {begin, len};
        if (!is_blank(line)) return true;
    }
    return false;
}

void TextCursor::fail(const std::string& what) const {
    throw_at_line(file_, line_, what);
}

int parse_numbers(std::string_view line, double* out, int max, const TextCursor& at) {
    const char* p = line.data();
    const char* const end = p + line.size();
    int n = 0;
    for (;;) {
        while (p < end && is_separator(*p)) ++p;
        if (p == end) return n;
        if (n == max) at.fail("more than " + std::to_string(max) + " values on the line");
        const char* start = p;
        if (*p == '+') ++p;  // from_chars rejects an explicit plus sign
        double v = 0.0;
        const auto [q, ec] = std::from_chars(p, end, v);
        if (ec == std::errc::result_out_of_range) {
            at.fail("value out of range: '" + quote_token(token_at(start, end)) + "'");
        }
        if (ec != std::errc() || (q < end && !is_separator(*q))) {
            at.fail("not a number: '" + quote_token(token_at(start, end)) + "'");
        }
        if (!std::isfinite(v)) {
            at.fail("non-finite value: '" + quote_token(token_at(start, end)) + "'");
        }
        out[n++] = v;
        p = q;
    }
}

std::size_t split_tokens(std::string_view line, std::string_view* out, std::size_t max) {
    const char* p = line.data();
    const char* const end = p + line.size();
    std::size_t n = 0;
    for (;;) {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
        if (p == end) return n;
        const char* start = p;
        while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
        if (n < max) out[n] = {start, static_cast<std::size_t>(p - start)};
        ++n;
    }
}

double parse_value(std::string_view token, const TextCursor& at) {
    const char* p = token.data();
    const char* const end = p + token.size();
    if (p < end && *p == '+') ++p;  // from_chars rejects an explicit plus sign
    double v = 0.0;
    const auto [q, ec] = std::from_chars(p, end, v);
    if (ec == std::errc::result_out_of_range) {
        at.fail("value out of range: '" + quote_token(token) + "'");
    }
    if (ec != std::errc() || q != end) at.fail("\"" + quote_token(token) + "\" is not a number");
    return v;
}

bool is_single_count(std::string_view line) {
    const char* p = line.data();
    const char* const end = p + line.size();
    while (p < end && is_separator(*p)) ++p;
    const char* digits = p;
    while (p < end && *p >= '0' && *p <= '9') ++p;
    if (p == digits) return false;
    while (p < end && is_separator(*p)) ++p;
    return p == end;
}

std::uint64_t parse_count(std::string_view line, const char* what, const TextCursor& at) {
    const char* p = line.data();
    const char* const end = p + line.size();
    while (p < end && is_separator(*p)) ++p;
    const char* start = p;
    std::uint64_t v = 0;
    const auto [q, ec] = std::from_chars(p, end, v);
    const char* r = q;
    while (r < end && is_separator(*r)) ++r;
    if (ec != std::errc() || r != end) {
        at.fail(std::string("expected the ") + what + " (one unsigned integer), found '" +
                quote_token(std::string_view(start, static_cast<std::size_t>(end - start))) + "'");
    }
    return v;
}

std::string quote_token(std::string_view token) {
    constexpr std::size_t limit = 24;
    std::string out;
    for (std::size_t i = 0; i < token.size() && i < limit; ++i) {
        const auto c = static_cast<unsigned char>(token[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            static const char hex[] = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 0xf];
        }
    }
    if (token.size() > limit) out += "...";
    return out;
}

}  // namespace tlsmon
