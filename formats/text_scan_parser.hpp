#pragma once
// Line-by-line number parsing shared by the ASCII scan readers (PTX, PTS, XYZ): a cursor
// over a text buffer that knows its line number, and a field splitter built on
// std::from_chars. Every error names the file and the line.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace tlsmon {

class TextCursor {
  public:
    // `lines_before`: lines of the file before `text` (a header read elsewhere), so that
    // line numbers count from the start of the file.
    TextCursor(std::string_view text, const std::filesystem::path& file,
               std::uint64_t lines_before = 0)
        : text_(text), file_(file), line_(lines_before) {}

    // The next line that is not blank (whitespace only), without its end of line; false at
    // the end of the text. The line number then names that line (1-based).
    bool next_line(std::string_view& line);

    bool at_end() const { return pos_ >= text_.size(); }
    std::uint64_t line_number() const { return line_; }
    std::size_t remaining_bytes() const { return text_.size() - pos_; }
    std::string_view rest() const { return text_.substr(pos_); }
    const std::filesystem::path& file() const { return file_; }

    // FormatError "<file>:<line>: what" at the current line.
    [[noreturn]] void fail(const std::string& what) const;

  private:
    std::string_view text_;
    const std::filesystem::path& file_;
    std::size_t pos_ = 0;
    std::uint64_t line_;
};

// Splits `line` into numbers separated by spaces, tabs or commas and stores at most `max`
// of them in `out`. Returns how many the line holds. A token that is not a number, a
// number followed by other characters, a non-finite value (nan, inf), or more than `max`
// numbers is a FormatError at the cursor's line.
int parse_numbers(std::string_view line, double* out, int max, const TextCursor& at);

// Splits `line` at spaces, tabs and carriage returns, storing at most `max` tokens in `out`.
// Returns how many tokens the line holds (more than `max` when it holds more).
std::size_t split_tokens(std::string_view line, std::string_view* out, std::size_t max);

// One token as a number. Unlike parse_numbers, NaN and infinities are accepted ("nan",
// "inf"): PCL writes them for points without a return. Anything else that is not a whole
// number is a FormatError at the cursor's line.
double parse_value(std::string_view token, const TextCursor& at);

// The line's single unsigned integer (a header count), or a FormatError naming `what`.
std::uint64_t parse_count(std::string_view line, const char* what, const TextCursor& at);

// True when the line holds exactly one token and it is an unsigned integer.
bool is_single_count(std::string_view line);

// A token as it may be quoted in an error: at most 24 characters, bytes that are not
// printable ASCII written as \xNN.
std::string quote_token(std::string_view token);

}  // namespace tlsmon
