/// @file checks.cpp
/// Command-line value checks (checks.hpp).

#include "checks.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <string_view>
#include <system_error>

#include "manta/core/text.hpp"

namespace manta::cli {

namespace {

/// What the text of a value is.
enum class Text { number, too_large, not_a_number };

/// Read the whole text as one number into `v`: an optional sign (a leading '+' too), decimal or
/// exponent form; "nan" and "inf" read as themselves. A number beyond the doubles is too_large.
Text read_number(std::string_view text, double& v) {
    std::string_view t = text;
    if (t.size() > 1 && t.front() == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ptr != t.data() + t.size()) return Text::not_a_number;
    if (r.ec == std::errc::result_out_of_range) return Text::too_large;
    return r.ec == std::errc() ? Text::number : Text::not_a_number;
}

std::string with_unit(const std::string& unit) {
    return unit.empty() ? std::string() : " " + unit;
}

/// "'TEXT'", escaped for the terminal.
std::string in_quotes(std::string_view text) {
    return "'" + core::printable(text) + "'";
}

}  // namespace

CLI::Validator real_in(double lo, double hi, const std::string& unit, bool lo_open,
                       const std::string& range_name) {
    const std::string outside = range_name.empty() ? std::string("the range") : range_name;
    const std::string range =
        fmt::format("{}{:g}, {:g}]{}", lo_open ? "(" : "[", lo, hi, with_unit(unit));
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            if (text.find_first_not_of(" \t") == std::string::npos)
                return fmt::format("the value is empty; expected a number in {}", range);
            double v = 0.0;
            const Text kind = read_number(text, v);
            if (kind == Text::not_a_number)
                return fmt::format("value {} is not a number; expected a number in {}",
                                   in_quotes(text), range);
            if (kind == Text::too_large)
                return fmt::format("value {} is outside {}; expected a number in {}",
                                   in_quotes(text), outside, range);
            if (!std::isfinite(v))
                return fmt::format("value {} is not a finite number; expected a number in {}",
                                   in_quotes(text), range);
            if (v > hi || v < lo || (lo_open && v == lo))
                return fmt::format("value {} is outside {}; expected a number in {}",
                                   in_quotes(text), outside, range);
            return {};
        },
        fmt::format("NUMBER in {}", range), "real_in");
}

CLI::Validator altitude() {
    return real_in(range::min_altitude, range::max_altitude, "m", false,
                   "the US Standard Atmosphere 1976 range");
}

CLI::Validator real_positive(double hi, const std::string& unit) {
    return real_in(0.0, hi, unit, true);
}

CLI::Validator integer_in(long long lo, long long hi) {
    const std::string range = fmt::format("[{}, {}]", lo, hi);
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            if (text.find_first_not_of(" \t") == std::string::npos)
                return fmt::format("the value is empty; expected an integer in {}", range);
            std::string_view t = text;
            if (t.size() > 1 && t.front() == '+' && t[1] != '-') t.remove_prefix(1);
            long long v = 0;
            const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
            if (r.ec == std::errc::result_out_of_range)
                return fmt::format("value {} is outside the range; expected an integer in {}",
                                   in_quotes(text), range);
            if (r.ec != std::errc() || r.ptr != t.data() + t.size())
                return fmt::format("value {} is not an integer; expected an integer in {}",
                                   in_quotes(text), range);
            if (v < lo || v > hi)
                return fmt::format("value {} is outside the range; expected an integer in {}",
                                   in_quotes(text), range);
            return {};
        },
        fmt::format("INTEGER in {}", range), "integer_in");
}

CLI::Validator output_path() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            if (text.find_first_not_of(" \t") == std::string::npos)
                return "the path is empty; expected a file or folder path";
            return {};
        },
        "PATH", "output_path");
}

}  // namespace manta::cli
