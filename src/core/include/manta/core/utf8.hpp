#pragma once
/// @file utf8.hpp
/// UTF-8 validation of text read from input files (YAML, CSV, AVL). Every name MANTA reads ends up
/// in a JSON file, and JSON text is UTF-8 (RFC 8259, section 8.1), so text that is not UTF-8 is
/// refused where it is read, not after a computation when a writer fails on it.

#include <cstddef>
#include <string>
#include <string_view>

namespace manta::core {

/// Byte offset in `text` of the first byte that does not belong to a well-formed UTF-8 sequence
/// (RFC 3629, section 4: no overlong forms, no surrogates U+D800..U+DFFF, nothing above
/// U+10FFFF), or std::string_view::npos if `text` is valid UTF-8.
[[nodiscard]] std::size_t utf8_invalid_offset(std::string_view text) noexcept;

/// True if `text` is valid UTF-8.
[[nodiscard]] inline bool is_utf8(std::string_view text) noexcept {
    return utf8_invalid_offset(text) == std::string_view::npos;
}

/// "byte 0xE9 at byte offset 12" for the first invalid byte of `text` at `offset` (as returned
/// by utf8_invalid_offset); used in messages.
[[nodiscard]] std::string describe_utf8_error(std::string_view text, std::size_t offset);

/// `text` with each byte that is not part of valid UTF-8 written as \xNN (for messages that quote
/// a value which failed the check).
[[nodiscard]] std::string utf8_escaped(std::string_view text);

/// 1-based line of byte `offset` in `text` (lines end at '\n').
[[nodiscard]] std::size_t line_of_offset(std::string_view text, std::size_t offset) noexcept;

/// InputError "<source>:<line>: text is not valid UTF-8 (byte 0xE9 at byte offset 12 of the
/// file); expected UTF-8 text" if `text`, the whole content of `source`, is not UTF-8.
void require_utf8_text(std::string_view text, std::string_view source);

}  // namespace manta::core
