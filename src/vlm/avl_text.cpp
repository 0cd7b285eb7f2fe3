/// Text helpers of the AVL file readers (detail/avl_text.hpp).

#include "manta/vlm/detail/avl_text.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>

namespace manta::vlm::detail::avl {

bool is_space(char c) {
    // NUL counts as whitespace: AVL's sample vanilla.run is padded with NUL bytes.
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f' || c == '\0';
}

std::string trim(std::string_view s) {
    std::size_t b = 0, e = s.size();
    while (b < e && is_space(s[b])) ++b;
    while (e > b && is_space(s[e - 1])) --e;
    return std::string(s.substr(b, e - b));
}

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

/// Lines that carry data: blank lines (commas count as blanks) and lines whose first non-blank
/// character is '#' or '!' are dropped, and everything from a '!' on is a remark.
std::vector<Line> significant_lines(std::string_view text) {
    std::vector<Line> out;
    int number = 0;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        ++number;
        std::string t = trim(text.substr(start, end - start));
        const std::size_t bang = t.find('!');
        if (bang != std::string::npos) t = trim(std::string_view(t).substr(0, bang));
        for (char& c : t)
            if (is_space(c)) c = ' ';
        const bool blank = t.find_first_not_of(" ,") == std::string::npos;
        if (!blank && t.front() != '#') out.push_back({std::move(t), number});
        if (end == text.size()) break;
        start = end + 1;
    }
    return out;
}

/// Whitespace- (or comma-) separated words of a line.
std::vector<std::string> words(std::string_view s) {
    std::vector<std::string> out;
    std::string w;
    for (char c : s) {
        if (is_space(c) || c == ',') {
            if (!w.empty()) out.push_back(std::move(w));
            w.clear();
        } else {
            w += c;
        }
    }
    if (!w.empty()) out.push_back(std::move(w));
    return out;
}

/// Read a word in Fortran-friendly notation ("+1", "1.", ".5", "1.0E-3", "1.0D-3").
Word read_word(std::string s, double& v) {
    if (!s.empty() && s.front() == '+') s.erase(0, 1);
    for (char& c : s)
        if (c == 'd' || c == 'D') c = 'e';
    v = 0.0;
    if (s.empty()) return Word::text;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ptr != s.data() + s.size()) return Word::text;
    if (r.ec == std::errc::result_out_of_range) return Word::non_finite;
    if (r.ec != std::errc()) return Word::text;
    return std::isfinite(v) ? Word::number : Word::non_finite;
}

/// A finite number, or nothing for any other word.
std::optional<double> to_number(const std::string& s) {
    double v = 0.0;
    if (read_word(s, v) != Word::number) return std::nullopt;
    return v;
}

bool is_non_finite(const std::string& s) {
    double v = 0.0;
    return read_word(s, v) == Word::non_finite;
}

/// The leading numbers of `ws` from index `first` (at most `max`); `stop` receives the first word
/// that is not a number (empty if none). A word that spells a non-finite number (NaN, infinity,
/// overflow) also stops the list; `non_finite` (if given) receives it, and stays empty otherwise.
std::vector<double> leading_numbers(const std::vector<std::string>& ws, std::size_t first,
                                    std::size_t max, std::string* stop, std::string* non_finite) {
    std::vector<double> v;
    if (non_finite) non_finite->clear();
    for (std::size_t i = first; i < ws.size() && v.size() < max; ++i) {
        double x = 0.0;
        const Word k = read_word(ws[i], x);
        if (k != Word::number) {
            if (stop) *stop = ws[i];
            if (non_finite && k == Word::non_finite) *non_finite = ws[i];
            return v;
        }
        v.push_back(x);
    }
    if (stop) stop->clear();
    return v;
}

/// The message of a non-finite word.
std::string non_finite_message(const std::string& word, std::string_view expected) {
    return fmt::format(
        "'{}' is not a finite number (NaN, infinity or beyond the range of a double); expected {}",
        word, expected);
}

}  // namespace manta::vlm::detail::avl
