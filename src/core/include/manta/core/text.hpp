#pragma once
/// @file text.hpp
/// Small text helpers shared by MANTA's line-oriented readers (CSV tables, motion files,
/// trajectories): blank trimming and comma splitting on string views, no copies; and the one
/// escaping of text quoted in messages.

#include <string>
#include <string_view>
#include <vector>

namespace manta::core {

/// `s` without leading and trailing blanks (space, tab, carriage return).
[[nodiscard]] std::string_view trim_blanks(std::string_view s);

/// The comma-separated fields of one line, each trimmed of blanks; an empty line gives one empty
/// field. No quoting: a comma always separates.
[[nodiscard]] std::vector<std::string_view> split_fields(std::string_view line);

/// `s` safe to print in a one-line message: control bytes (C0: NUL, tab, line feed, carriage
/// return, ESC, ...; DEL; the C1 controls U+0080-U+009F) and bytes that are not part of valid
/// UTF-8 are written as \xNN (lower-case hex, one per byte); valid UTF-8 and everything else,
/// backslashes included, stay as they are (so escaping twice changes nothing). Every
/// manta::Error message goes through it (error.cpp), and so does the CLI's output of errors.
[[nodiscard]] std::string printable(std::string_view s);

}  // namespace manta::core
