/// @file utf8.cpp
/// UTF-8 validation (RFC 3629): the decoder's acceptance rules, written as the table of well-formed
/// byte sequences of the Unicode Standard (chapter 3, table 3-7).

#include "manta/core/utf8.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "manta/core/error.hpp"

namespace manta::core {

std::size_t utf8_invalid_offset(std::string_view text) noexcept {
    const auto* s = reinterpret_cast<const unsigned char*>(text.data());
    const std::size_t n = text.size();
    std::size_t i = 0;
    const auto cont = [&](std::size_t k, unsigned lo = 0x80, unsigned hi = 0xBF) {
        return i + k < n && s[i + k] >= lo && s[i + k] <= hi;
    };
    while (i < n) {
        const unsigned c = s[i];
        if (c < 0x80) {
            ++i;
        } else if (c >= 0xC2 && c <= 0xDF) {
            if (!cont(1)) return i;
            i += 2;
        } else if (c >= 0xE0 && c <= 0xEF) {
            const unsigned lo = c == 0xE0 ? 0xA0 : 0x80;  // no overlong forms
            const unsigned hi = c == 0xED ? 0x9F : 0xBF;  // no surrogates
            if (!cont(1, lo, hi) || !cont(2)) return i;
            i += 3;
        } else if (c >= 0xF0 && c <= 0xF4) {
            const unsigned lo = c == 0xF0 ? 0x90 : 0x80;  // no overlong forms
            const unsigned hi = c == 0xF4 ? 0x8F : 0xBF;  // nothing above U+10FFFF
            if (!cont(1, lo, hi) || !cont(2) || !cont(3)) return i;
            i += 4;
        } else {
            return i;  // a continuation byte without a lead byte, 0xC0, 0xC1 or 0xF5..0xFF
        }
    }
    return std::string_view::npos;
}

std::string describe_utf8_error(std::string_view text, std::size_t offset) {
    if (offset >= text.size()) return fmt::format("a truncated sequence at byte offset {}", offset);
    return fmt::format("byte 0x{:02X} at byte offset {}",
                       static_cast<unsigned>(static_cast<unsigned char>(text[offset])), offset);
}

std::string utf8_escaped(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    while (!text.empty()) {
        const std::size_t bad = utf8_invalid_offset(text);
        if (bad == std::string_view::npos) {
            out.append(text);
            break;
        }
        out.append(text.substr(0, bad));
        out +=
            fmt::format("\\x{:02X}", static_cast<unsigned>(static_cast<unsigned char>(text[bad])));
        text.remove_prefix(bad + 1);
    }
    return out;
}

std::size_t line_of_offset(std::string_view text, std::size_t offset) noexcept {
    const std::size_t end = std::min(offset, text.size());
    return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + end, '\n'));
}

void require_utf8_text(std::string_view text, std::string_view source) {
    const std::size_t bad = utf8_invalid_offset(text);
    if (bad == std::string_view::npos) return;
    throw InputError(fmt::format(
        "{}:{}: text is not valid UTF-8 ({} of the file); expected UTF-8 text (save the file "
        "as UTF-8)",
        source, line_of_offset(text, bad), describe_utf8_error(text, bad)));
}

}  // namespace manta::core
