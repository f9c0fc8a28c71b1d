#pragma once
// Text from outside (file names above all) made safe for a log line or a reason file: it
// can neither start a new line nor send a terminal control sequence.
#include <string>
#include <string_view>

namespace tlsmon {

// `text` with control characters escaped: \n, \r, \t and \\ as such; other C0 controls,
// DEL, C1 controls (U+0080..U+009F) and bytes that are not valid UTF-8 as \xNN per byte;
// line/paragraph separators and bidirectional formatting characters (U+2028, U+2029,
// U+200E, U+200F, U+202A..U+202E, U+2066..U+2069) as \uNNNN. Valid UTF-8 otherwise passes
// unchanged, so an escaped text is only longer than `text` if something was escaped.
std::string escape_control_characters(std::string_view text);

}  // namespace tlsmon
