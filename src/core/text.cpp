/// @file text.cpp
/// Blank trimming and comma splitting (text.hpp).

#include "manta/core/text.hpp"

namespace manta::core {

namespace {
constexpr bool blank(char c) {
    return c == ' ' || c == '\t' || c == '\r';
}
}  // namespace

std::string_view trim_blanks(std::string_view s) {
    while (!s.empty() && blank(s.front())) s.remove_prefix(1);
    while (!s.empty() && blank(s.back())) s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> split_fields(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (;;) {
        const std::size_t p = line.find(',', start);
        out.push_back(trim_blanks(
            line.substr(start, p == std::string_view::npos ? std::string_view::npos : p - start)));
        if (p == std::string_view::npos) break;
        start = p + 1;
    }
    return out;
}

}  // namespace manta::core
