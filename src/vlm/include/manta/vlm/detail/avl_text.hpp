#pragma once
/// @file avl_text.hpp
/// Text helpers shared by the readers of AVL's geometry (.avl), mass (.mass) and run-case (.run)
/// files: significant lines, words, numbers in Fortran notation and the non-finite check.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace manta::vlm::detail::avl {

/// One significant line of a file: comments and inline '!' remarks removed, trimmed.
struct Line {
    std::string text;
    int number = 0;  ///< 1-based line number in the file
};

/// Blank, tab, line ends, form feed and NUL (AVL's sample vanilla.run is padded with NUL bytes).
[[nodiscard]] bool is_space(char c);
[[nodiscard]] std::string trim(std::string_view s);
[[nodiscard]] std::string upper(std::string s);
[[nodiscard]] std::string lower(std::string s);

/// Lines that carry data: blank lines (commas count as blanks) and lines whose first non-blank
/// character is '#' or '!' are dropped, and everything from a '!' on is a remark.
[[nodiscard]] std::vector<Line> significant_lines(std::string_view text);

/// Whitespace- (or comma-) separated words of a line.
[[nodiscard]] std::vector<std::string> words(std::string_view s);

/// How a word reads as a number.
enum class Word {
    number,      ///< a finite number
    text,        ///< not a number at all (a name, a remark)
    non_finite,  ///< NaN, infinity or beyond the range of a double ("nan", "-inf", "1e999")
};

/// Read a word in Fortran-friendly notation ("+1", "1.", ".5", "1.0E-3", "1.0D-3") into `v`.
[[nodiscard]] Word read_word(std::string s, double& v);
/// A finite number, or nothing for any other word.
[[nodiscard]] std::optional<double> to_number(const std::string& s);
/// True for a word that spells a non-finite number.
[[nodiscard]] bool is_non_finite(const std::string& s);

/// The leading numbers of `ws` from index `first` (at most `max`); `stop` receives the first word
/// that is not a number (empty if none). A word that spells a non-finite number (NaN, infinity,
/// overflow) also stops the list; `non_finite` (if given) receives it, and stays empty otherwise.
[[nodiscard]] std::vector<double> leading_numbers(const std::vector<std::string>& ws,
                                                  std::size_t first, std::size_t max,
                                                  std::string* stop = nullptr,
                                                  std::string* non_finite = nullptr);

/// "'WORD' is not a finite number (NaN, infinity or beyond the range of a double); expected
/// EXPECTED".
[[nodiscard]] std::string non_finite_message(const std::string& word, std::string_view expected);

}  // namespace manta::vlm::detail::avl
