// Escaping control characters of text that goes into a log line or a reason file.
#include <gtest/gtest.h>

#include "core/text_escape.hpp"

namespace tlsmon {
namespace {

TEST(TextEscape, PlainTextAndUtf8PassUnchanged) {
    EXPECT_EQ(escape_control_characters("pier_20260601T061500Z.ptx"), "pier_20260601T061500Z.ptx");
    EXPECT_EQ(escape_control_characters("Brücke ł 橋 😀"), "Brücke ł 橋 😀");  // ł = C5 82
    EXPECT_EQ(escape_control_characters(""), "");
}

TEST(TextEscape, ControlCharactersAreEscaped) {
    EXPECT_EQ(escape_control_characters("a\nb\rc\td"), "a\\nb\\rc\\td");
    EXPECT_EQ(escape_control_characters(std::string("\0\x01\x1b[31m\x7f", 8)),
              "\\x00\\x01\\x1b[31m\\x7f");
    EXPECT_EQ(escape_control_characters("back\\slash"), "back\\\\slash");
    // C1 controls (U+0080..U+009F, e.g. CSI U+009B) and bytes that are not UTF-8.
    EXPECT_EQ(escape_control_characters("a\xc2\x9b"
                                        "b\xc2\x85"),
              "a\\xc2\\x9bb\\xc2\\x85");
    EXPECT_EQ(escape_control_characters("\xff\xfe"), "\\xff\\xfe");
    EXPECT_EQ(escape_control_characters("\xc3"), "\\xc3");                    // cut short
    EXPECT_EQ(escape_control_characters("\xc0\xaf"), "\\xc0\\xaf");           // overlong '/'
    EXPECT_EQ(escape_control_characters("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // surrogate
    // Line separators and bidirectional overrides reorder or break what a reader sees.
    EXPECT_EQ(escape_control_characters("a\xe2\x80\xa8"
                                        "b\xe2\x80\xae"
                                        "c"),
              "a\\u2028b\\u202ec");
}

}  // namespace
}  // namespace tlsmon
