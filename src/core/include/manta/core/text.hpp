#pragma once
/// @file text.hpp
/// Small text helpers shared by MANTA's line-oriented readers (CSV tables, motion files,
/// trajectories): blank trimming and comma splitting on string views, no copies.

#include <string_view>
#include <vector>

namespace manta::core {

/// `s` without leading and trailing blanks (space, tab, carriage return).
[[nodiscard]] std::string_view trim_blanks(std::string_view s);

/// The comma-separated fields of one line, each trimmed of blanks; an empty line gives one empty
/// field. No quoting: a comma always separates.
[[nodiscard]] std::vector<std::string_view> split_fields(std::string_view line);

}  // namespace manta::core
