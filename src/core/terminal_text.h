#pragma once
// Text from files (WRF Times, .nph time strings and provenance, attribute values) printed on a
// terminal (issue #18): control characters are shown as \xNN escapes instead of being sent, so
// a crafted file cannot move the cursor, retitle the window or hide output with ESC sequences.
#include <string>
#include <string_view>

namespace nph {

/// `text` with every C0 control character (0x00-0x1F, except '\n' when keep_newlines), DEL
/// (0x7F) and C1 control (U+0080-U+009F, UTF-8 C2 80-9F, which some terminals obey like ESC [)
/// replaced by a visible escape: "\x1b", "\x9b". Everything else is kept byte for byte.
std::string terminalSafe(std::string_view text, bool keep_newlines = true);

}  // namespace nph
