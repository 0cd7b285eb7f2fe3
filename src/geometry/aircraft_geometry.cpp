#include "manta/geometry/aircraft_geometry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"

namespace manta::geometry {

namespace {

constexpr double pi = std::numbers::pi;

std::string trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return std::string(s);
}

bool all_digits(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
    });
}

int digit(char c) {
    return c - '0';
}

// Five-digit mean-line constants of NACA Report 537 (Jacobs & Pinkerton 1935) for a design lift
// coefficient of 0.3, indexed by the position digit P (max camber at P/20 of the chord):
// r = x/c where the cubic joins the straight line, k1, and for the reflexed lines k2/k1.
struct FiveDigitLine {
    double r, k1, k2_over_k1;
};
constexpr std::array<FiveDigitLine, 5> five_digit_standard = {{
    {0.0580, 361.400, 0.0},  // 210
    {0.1260, 51.640, 0.0},   // 220
    {0.2025, 15.957, 0.0},   // 230
    {0.2900, 6.643, 0.0},    // 240
    {0.3910, 3.230, 0.0},    // 250
}};
constexpr std::array<FiveDigitLine, 4> five_digit_reflexed = {{
    {0.1300, 51.990, 0.000764},  // 221
    {0.2170, 15.793, 0.00677},   // 231
    {0.3180, 6.520, 0.0303},     // 241
    {0.4410, 3.191, 0.1355},     // 251
}};

constexpr std::string_view naca_expected =
    "a NACA designation such as 'NACA 2412' (4-digit), 'NACA 23012' (5-digit) or 'NACA 64-215', "
    "'NACA 64(2)-215', 'NACA 65-410 a=0.5', 'NACA 64A010' (6-series)";

// What is wrong with a designation; turned into InputError or ConfigError by the callers.
struct NacaProblem {
    std::string problem;
};

[[noreturn]] void naca_error(std::string_view /*text*/, std::string problem) {
    throw NacaProblem{std::move(problem)};
}

// The NACA a-series mean line (Abbott & von Doenhoff 1959, eq. 4.26) for design lift c_li and
// uniform loading up to x = a; y and dy/dx. Log singularities at x = 0 and x = a are integrable;
// the slope there is evaluated a hair away.
double xlogx(double x) {
    return x <= 0.0 ? 0.0 : x * std::log(x);
}
double sqlog(double d) {  // d^2 ln|d|, 0 at d = 0
    const double ad = std::abs(d);
    return ad <= 0.0 ? 0.0 : d * d * std::log(ad);
}

double a_series_g(double a) {
    if (a >= 1.0) return -0.25;  // limit used only through h below; a = 1 handled separately
    const double a2ln = a <= 0.0 ? 0.0 : a * a * (0.5 * std::log(a) - 0.25);
    return -1.0 / (1.0 - a) * (a2ln + 0.25);
}
double a_series_h(double a) {
    const double b = 1.0 - a;
    return 1.0 / b * (0.5 * sqlog(b) - 0.25 * b * b) + a_series_g(a);
}

double a_series_camber(double cli, double a, double x) {
    if (a >= 1.0 - 1e-12) return -cli / (4.0 * pi) * (xlogx(1.0 - x) + xlogx(x));
    const double g = a_series_g(a), h = a_series_h(a);
    const double bracket = 1.0 / (1.0 - a) *
                               (0.5 * sqlog(a - x) - 0.5 * sqlog(1.0 - x) +
                                0.25 * (1.0 - x) * (1.0 - x) - 0.25 * (a - x) * (a - x)) -
                           xlogx(x) + g - h * x;
    return cli / (2.0 * pi * (a + 1.0)) * bracket;
}

double a_series_slope(double cli, double a, double x) {
    x = std::clamp(x, 1e-9, 1.0 - 1e-9);
    if (a >= 1.0 - 1e-12) return -cli / (4.0 * pi) * (std::log(x) - std::log(1.0 - x));
    if (std::abs(x - a) < 1e-9) x = a - 1e-9;
    const double h = a_series_h(a);
    const double d = a - x;
    const double bracket =
        1.0 / (1.0 - a) * ((1.0 - x) * std::log(1.0 - x) - d * std::log(std::abs(d))) -
        std::log(x) - 1.0 - h;
    return cli / (2.0 * pi * (a + 1.0)) * bracket;
}

double naca_camber(const NacaDesignation& d, double x) {
    switch (d.family) {
        case NacaFamily::four_digit: {
            const double m = d.max_camber, p = d.camber_position;
            if (m == 0.0) return 0.0;
            return x < p ? m / (p * p) * (2.0 * p * x - x * x)
                         : m / ((1.0 - p) * (1.0 - p)) * (1.0 - 2.0 * p + 2.0 * p * x - x * x);
        }
        case NacaFamily::five_digit: {
            const double r = d.r, k1 = d.k1, q = d.k2_over_k1;
            if (!d.reflexed) {
                return x < r ? k1 / 6.0 * (x * x * x - 3.0 * r * x * x + r * r * (3.0 - r) * x)
                             : k1 * r * r * r / 6.0 * (1.0 - x);
            }
            const double c = std::pow(1.0 - r, 3);
            return x < r ? k1 / 6.0 * (std::pow(x - r, 3) - q * c * x - r * r * r * x + r * r * r)
                         : k1 / 6.0 *
                               (q * std::pow(x - r, 3) - q * c * x - r * r * r * x + r * r * r);
        }
        case NacaFamily::six_series:
            return a_series_camber(d.design_lift, d.mean_line_a, x);
    }
    return 0.0;
}

double naca_camber_slope(const NacaDesignation& d, double x) {
    switch (d.family) {
        case NacaFamily::four_digit: {
            const double m = d.max_camber, p = d.camber_position;
            if (m == 0.0) return 0.0;
            return x < p ? 2.0 * m / (p * p) * (p - x)
                         : 2.0 * m / ((1.0 - p) * (1.0 - p)) * (p - x);
        }
        case NacaFamily::five_digit: {
            const double r = d.r, k1 = d.k1, q = d.k2_over_k1;
            if (!d.reflexed) {
                return x < r ? k1 / 6.0 * (3.0 * x * x - 6.0 * r * x + r * r * (3.0 - r))
                             : -k1 * r * r * r / 6.0;
            }
            const double c = std::pow(1.0 - r, 3);
            return x < r ? k1 / 6.0 * (3.0 * (x - r) * (x - r) - q * c - r * r * r)
                         : k1 / 6.0 * (3.0 * q * (x - r) * (x - r) - q * c - r * r * r);
        }
        case NacaFamily::six_series:
            return a_series_slope(d.design_lift, d.mean_line_a, x);
    }
    return 0.0;
}

// NACA four-digit thickness distribution (half thickness), open trailing edge (NACA Report 460).
double naca_half_thickness(double t, double x) {
    x = std::max(x, 0.0);
    return 5.0 * t *
           (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x -
            0.1015 * x * x * x * x);
}

// Linear interpolation of y on a polyline sorted by increasing x (ties allowed).
double interp_y(const std::vector<Eigen::Vector2d>& pts, double x) {
    if (x <= pts.front().x()) return pts.front().y();
    if (x >= pts.back().x()) return pts.back().y();
    const auto it = std::lower_bound(pts.begin(), pts.end(), x,
                                     [](const Eigen::Vector2d& p, double v) { return p.x() < v; });
    const auto& b = *it;
    const auto& a = *(it - 1);
    const double dx = b.x() - a.x();
    if (dx <= 0.0) return b.y();
    return a.y() + (b.y() - a.y()) * (x - a.x()) / dx;
}

double cosine_station(std::size_t i, std::size_t n) {
    return 0.5 * (1.0 - std::cos(pi * static_cast<double>(i) / static_cast<double>(n - 1)));
}

}  // namespace

// ---------------------------------------------------------------------------------- NACA parsing

namespace {
NacaDesignation parse_naca_impl(std::string_view designation) {
    const std::string original = trim(designation);
    std::string s;
    for (char c : original) s += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (s.empty()) naca_error(original, "is empty");
    if (s.rfind("NACA", 0) == 0) s = trim(s.substr(4));
    if (!s.empty() && (s.front() == '-' || s.front() == '_')) s = s.substr(1);

    // Optional mean-line suffix "a=0.6" (6-series only).
    std::optional<double> a_value;
    if (const auto pos = s.find("A="); pos != std::string::npos) {
        std::string num = trim(s.substr(pos + 2));
        double a = 0.0;
        const auto r = std::from_chars(num.data(), num.data() + num.size(), a);
        if (num.empty() || r.ec != std::errc() || r.ptr != num.data() + num.size())
            naca_error(original, fmt::format("mean-line parameter 'a={}' is not a number", num));
        if (!(a >= 0.0 && a <= 1.0))
            naca_error(original, fmt::format("mean-line parameter a = {} is outside [0, 1]", num));
        a_value = a;
        s = trim(s.substr(0, pos));
        while (!s.empty() && (s.back() == ',' || s.back() == ' ')) s.pop_back();
    }
    std::string body;
    for (char c : s)
        if (c != ' ') body += c;

    NacaDesignation d;
    const auto thickness_of = [&](std::string_view tt) {
        const int t = digit(tt[0]) * 10 + digit(tt[1]);
        if (t < 1 || t > 40)
            naca_error(original, fmt::format("thickness {} % is outside 1 % to 40 %", t));
        return t / 100.0;
    };

    if (all_digits(body) && body.size() == 4) {
        if (a_value)
            naca_error(original, "a mean-line parameter 'a=' applies to 6-series sections only");
        d.family = NacaFamily::four_digit;
        const int m = digit(body[0]), p = digit(body[1]);
        if (m > 0 && p == 0)
            naca_error(original,
                       "maximum camber position (second digit) is 0 for a cambered section");
        if (m == 0 && p != 0)
            naca_error(original, "a symmetric section (first digit 0) takes 0 as its second digit");
        d.max_camber = m / 100.0;
        d.camber_position = p / 10.0;
        d.thickness = thickness_of(body.substr(2));
        d.text = "NACA " + body;
        return d;
    }
    if (all_digits(body) && body.size() == 5) {
        if (a_value)
            naca_error(original, "a mean-line parameter 'a=' applies to 6-series sections only");
        d.family = NacaFamily::five_digit;
        const int l = digit(body[0]), p = digit(body[1]), q = digit(body[2]);
        if (l == 0)
            naca_error(original,
                       "design-lift digit (first) is 0; a symmetric section is a four-digit 00TT");
        if (q > 1)
            naca_error(original,
                       fmt::format("third digit {} is neither 0 (normal) nor 1 (reflexed)", q));
        d.reflexed = q == 1;
        const int p_min = d.reflexed ? 2 : 1;
        if (p < p_min || p > 5)
            naca_error(original,
                       fmt::format("camber-position digit {} is outside {} to 5 for {} mean lines",
                                   p, p_min, d.reflexed ? "reflexed" : "standard"));
        const FiveDigitLine line = d.reflexed
                                       ? five_digit_reflexed[static_cast<std::size_t>(p - 2)]
                                       : five_digit_standard[static_cast<std::size_t>(p - 1)];
        d.design_lift = 0.15 * l;
        d.camber_position = p / 20.0;
        d.r = line.r;
        d.k1 = line.k1 * d.design_lift / 0.3;  // the tabulated lines are for c_li = 0.3
        d.k2_over_k1 = line.k2_over_k1;
        d.thickness = thickness_of(body.substr(3));
        d.text = "NACA " + body;
        return d;
    }

    // 6-series: 6 S [ (R) | _R | R ] ( - | A | A- ) L TT
    std::size_t i = 0;
    if (body.size() < 5 || body[0] != '6')
        naca_error(original, "is not a 4-digit, 5-digit or 6-series designation");
    i = 1;
    if (!std::isdigit(static_cast<unsigned char>(body[i])))
        naca_error(original, "the digit after '6' is missing");
    const int series = digit(body[i++]);
    if (series < 1 || series > 7)
        naca_error(original, fmt::format("minimum-pressure digit {} is outside 1 to 7", series));
    int range = 0;
    bool range_given = false;
    if (i < body.size() && body[i] == '(') {
        if (i + 2 >= body.size() || !std::isdigit(static_cast<unsigned char>(body[i + 1])) ||
            body[i + 2] != ')')
            naca_error(
                original,
                "the low-drag-range subscript must be one digit in parentheses, e.g. 64(2)-215");
        range = digit(body[i + 1]);
        range_given = true;
        i += 3;
    } else if (i < body.size() && body[i] == '_') {
        if (i + 1 >= body.size() || !std::isdigit(static_cast<unsigned char>(body[i + 1])))
            naca_error(original,
                       "the low-drag-range subscript after '_' must be one digit, e.g. 64_2-215");
        range = digit(body[i + 1]);
        range_given = true;
        i += 2;
    } else if (i < body.size() && std::isdigit(static_cast<unsigned char>(body[i]))) {
        range = digit(body[i]);
        range_given = true;
        i += 1;
    }
    if (range_given && range == 0)
        naca_error(original, "the low-drag-range subscript is 0; expected 1 to 9");
    bool a_mod = false;
    if (i < body.size() && body[i] == 'A') {
        a_mod = true;
        ++i;
        if (i < body.size() && body[i] == '-') ++i;
    } else if (i < body.size() && body[i] == '-') {
        ++i;
    } else {
        naca_error(original,
                   "the '-' (or 'A') between the series and the design-lift digit is missing");
    }
    const std::string rest = body.substr(std::min(i, body.size()));
    if (rest.size() != 3 || !all_digits(rest))
        naca_error(
            original,
            fmt::format("'{}' after the dash is not three digits (design lift, thickness)", rest));
    d.family = NacaFamily::six_series;
    d.min_pressure_tenths = series;
    d.low_drag_range_tenths = range;
    d.a_modified = a_mod;
    d.design_lift = digit(rest[0]) / 10.0;
    d.thickness = thickness_of(rest.substr(1));
    // 6A sections use a (modified) a = 0.8 mean line; the plain a = 0.8 line is used here.
    d.mean_line_a = a_value ? *a_value : (a_mod ? 0.8 : 1.0);
    d.text = fmt::format("NACA 6{}{}{}{}", series,
                         range > 0 ? fmt::format("({})", range) : std::string(), a_mod ? "A" : "-",
                         rest);
    if (a_value) d.text += fmt::format(" a={}", *a_value);
    return d;
}
}  // namespace

NacaDesignation parse_naca(std::string_view designation) {
    try {
        return parse_naca_impl(designation);
    } catch (const NacaProblem& p) {
        throw InputError(fmt::format("airfoil '{}': {}; expected {}", trim(designation), p.problem,
                                     naca_expected));
    }
}

// ---------------------------------------------------------------------------------------- Airfoil

namespace {

// Validate a contour in Selig order and split it into upper and lower surfaces (leading edge to
// trailing edge). `lines` (same size as points, or empty) gives file lines for messages.
void split_selig(const std::vector<Eigen::Vector2d>& pts, const std::vector<int>& lines,
                 const std::string& source, std::vector<Eigen::Vector2d>& upper,
                 std::vector<Eigen::Vector2d>& lower) {
    const auto at = [&](std::size_t i) {
        return lines.empty() ? fmt::format("{}: point {}", source, i + 1)
                             : fmt::format("{}:{}", source, lines[i]);
    };
    if (pts.size() < 7) {
        throw InputError(fmt::format(
            "{}: has {} coordinate points; expected at least 7 (a closed section contour)", source,
            pts.size()));
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
        if (!pts[i].allFinite())
            throw InputError(
                fmt::format("{}: coordinate is not finite; expected finite numbers 'x y'", at(i)));
    }
    std::size_t le = 0;
    double xmax = pts[0].x();
    for (std::size_t i = 1; i < pts.size(); ++i) {
        if (pts[i].x() < pts[le].x()) le = i;
        xmax = std::max(xmax, pts[i].x());
    }
    const double xmin = pts[le].x();
    if (std::abs(xmin) > 0.01 || std::abs(xmax - 1.0) > 0.01) {
        throw InputError(
            fmt::format("{}: x runs from {:g} to {:g}; expected chord-normalised coordinates, x "
                        "from 0 at the leading edge "
                        "to 1 at the trailing edge",
                        source, xmin, xmax));
    }
    if (le == 0 || le + 1 == pts.size()) {
        throw InputError(
            fmt::format("{}: the leading edge (smallest x) is the {} point; expected Selig order: "
                        "trailing edge, upper "
                        "surface, leading edge, lower surface, trailing edge",
                        source, le == 0 ? "first" : "last"));
    }
    constexpr double tol = 1e-6;
    for (std::size_t i = 1; i <= le; ++i) {
        if (pts[i].x() > pts[i - 1].x() + tol) {
            throw InputError(fmt::format(
                "{}: x = {:g} increases on the upper surface (after x = {:g}); expected Selig "
                "order with x "
                "decreasing from the trailing edge to the leading edge on the upper surface",
                at(i), pts[i].x(), pts[i - 1].x()));
        }
    }
    for (std::size_t i = le + 1; i < pts.size(); ++i) {
        if (pts[i].x() < pts[i - 1].x() - tol) {
            throw InputError(fmt::format(
                "{}: x = {:g} decreases on the lower surface (after x = {:g}); expected Selig "
                "order with x "
                "increasing from the leading edge to the trailing edge on the lower surface",
                at(i), pts[i].x(), pts[i - 1].x()));
        }
    }
    upper.assign(pts.rbegin() + static_cast<std::ptrdiff_t>(pts.size() - 1 - le), pts.rend());
    lower.assign(pts.begin() + static_cast<std::ptrdiff_t>(le), pts.end());
    for (int k = 1; k < 50; ++k) {
        const double x = 0.02 + 0.96 * k / 50.0;
        if (interp_y(upper, x) < interp_y(lower, x) - tol) {
            throw InputError(
                fmt::format("{}: the upper surface lies below the lower surface at x = {:.3f}; "
                            "expected Selig order "
                            "(trailing edge, upper surface, leading edge, lower surface, trailing "
                            "edge) of a closed contour",
                            source, x));
        }
    }
}

// "x y" (whitespace or comma separated) -> two numbers.
bool parse_pair(const std::string& line, double& a, double& b) {
    std::string t = line;
    std::replace(t.begin(), t.end(), ',', ' ');
    std::istringstream in(t);
    std::string s1, s2, extra;
    if (!(in >> s1 >> s2) || (in >> extra)) return false;
    const auto num = [](const std::string& s, double& v) {
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        return r.ec == std::errc() && r.ptr == s.data() + s.size();
    };
    return num(s1, a) && num(s2, b);
}

}  // namespace

Airfoil::Airfoil() : naca_(parse_naca("NACA 0012")), name_(naca_->text) {}

Airfoil Airfoil::naca(std::string_view designation) {
    Airfoil a;
    a.naca_ = parse_naca(designation);
    a.name_ = a.naca_->text;
    return a;
}

Airfoil Airfoil::from_points(std::string name, std::vector<Eigen::Vector2d> points,
                             const std::string& source) {
    Airfoil a;
    a.naca_.reset();
    a.name_ = std::move(name);
    split_selig(points, {}, source, a.upper_, a.lower_);
    a.points_ = std::move(points);
    return a;
}

Airfoil Airfoil::from_file(const std::filesystem::path& file) {
    const std::string text = core::read_file(file);
    const std::string source = file.string();
    std::vector<std::pair<std::string, int>> lines;  // non-blank lines with their numbers
    {
        std::istringstream in(text);
        std::string line;
        int n = 0;
        while (std::getline(in, line)) {
            ++n;
            const std::string t = trim(line);
            if (!t.empty()) lines.emplace_back(t, n);
        }
    }
    if (lines.empty())
        throw InputError(fmt::format(
            "{}: is empty; expected an airfoil coordinate file (Selig or Lednicer)", source));
    Airfoil a;
    a.naca_.reset();
    a.file_ = file;
    std::size_t first = 0;
    double x = 0.0, y = 0.0;
    if (parse_pair(lines[0].first, x, y) && x >= -0.1 && x <= 1.1) {
        a.name_ = file.stem().string();  // no name line
    } else {
        a.name_ = lines[0].first;
        first = 1;
    }
    std::vector<Eigen::Vector2d> pts;
    std::vector<int> pts_lines;
    for (std::size_t i = first; i < lines.size(); ++i) {
        if (!parse_pair(lines[i].first, x, y)) {
            throw InputError(
                fmt::format("{}:{}: '{}' is not a coordinate pair; expected two numbers 'x y'",
                            source, lines[i].second, lines[i].first));
        }
        pts.emplace_back(x, y);
        pts_lines.push_back(lines[i].second);
    }
    if (pts.empty())
        throw InputError(fmt::format("{}: has no coordinates; expected lines of 'x y'", source));
    // Lednicer: a first line of two integer point counts, then the upper surface and the lower
    // surface, each from the leading edge to the trailing edge.
    const double n_up = pts[0].x(), n_lo = pts[0].y();
    if (n_up > 1.5 && n_lo > 1.5 && std::floor(n_up) == n_up && std::floor(n_lo) == n_lo) {
        const auto nu = static_cast<std::size_t>(n_up), nl = static_cast<std::size_t>(n_lo);
        if (pts.size() - 1 != nu + nl) {
            throw InputError(
                fmt::format("{}:{}: Lednicer header announces {} upper and {} lower points but {} "
                            "follow; expected the counts "
                            "to match the coordinate lines",
                            source, pts_lines[0], nu, nl, pts.size() - 1));
        }
        std::vector<Eigen::Vector2d> selig;
        std::vector<int> selig_lines;
        for (std::size_t i = nu; i >= 1; --i) {
            selig.push_back(pts[i]);
            selig_lines.push_back(pts_lines[i]);
        }
        // The lower surface starts at the leading edge too; skip that point if it repeats.
        std::size_t start = 1 + nu;
        if ((pts[start] - pts[1]).norm() < 1e-12) ++start;
        for (std::size_t i = start; i < pts.size(); ++i) {
            selig.push_back(pts[i]);
            selig_lines.push_back(pts_lines[i]);
        }
        split_selig(selig, selig_lines, source, a.upper_, a.lower_);
        a.points_ = std::move(selig);
        return a;
    }
    split_selig(pts, pts_lines, source, a.upper_, a.lower_);
    a.points_ = std::move(pts);
    return a;
}

const NacaDesignation& Airfoil::designation() const {
    MANTA_REQUIRE(naca_.has_value(), fmt::format("airfoil '{}' is not a NACA section", name_));
    return *naca_;
}

double Airfoil::thickness_ratio() const {
    if (naca_) return naca_->thickness;
    double t = 0.0;
    for (std::size_t i = 0; i < 201; ++i) {
        const double x = cosine_station(i, 201);
        t = std::max(t, interp_y(upper_, x) - interp_y(lower_, x));
    }
    return t;
}

double Airfoil::camber(double x) const {
    x = std::clamp(x, 0.0, 1.0);
    if (naca_) return naca_camber(*naca_, x);
    return 0.5 * (interp_y(upper_, x) + interp_y(lower_, x));
}

double Airfoil::camber_slope(double x) const {
    if (naca_) return naca_camber_slope(*naca_, std::clamp(x, 0.0, 1.0));
    const double h = 1e-3;
    const double a = std::clamp(x - h, 0.0, 1.0), b = std::clamp(x + h, 0.0, 1.0);
    return (camber(b) - camber(a)) / (b - a);
}

std::vector<Eigen::Vector2d> Airfoil::coordinates(std::size_t n_per_side) const {
    if (!naca_) return points_;
    if (naca_->family == NacaFamily::six_series) {
        throw InputError(fmt::format(
            "airfoil '{}': coordinates of NACA 6-series sections are not generated (their "
            "thickness forms are "
            "tabulated, not analytic); expected the section as a coordinate file ('airfoil_file')",
            name_));
    }
    MANTA_REQUIRE(n_per_side >= 3, "coordinates: n_per_side must be at least 3");
    std::vector<Eigen::Vector2d> up, lo;
    for (std::size_t i = 0; i < n_per_side; ++i) {
        const double x = cosine_station(i, n_per_side);
        const double yc = naca_camber(*naca_, x);
        const double th = std::atan(naca_camber_slope(*naca_, x));
        const double yt = naca_half_thickness(naca_->thickness, x);
        up.emplace_back(x - yt * std::sin(th), yc + yt * std::cos(th));
        lo.emplace_back(x + yt * std::sin(th), yc - yt * std::cos(th));
    }
    std::vector<Eigen::Vector2d> out(up.rbegin(), up.rend());
    out.insert(out.end(), lo.begin() + 1, lo.end());
    return out;
}

// ---------------------------------------------------------------------------------- LiftingSurface

namespace {

// Integrals over one panel with chord and a coordinate q varying linearly over ds.
double int_c(double ds, double c0, double c1) {
    return ds * (c0 + c1) / 2.0;
}
double int_c2(double ds, double c0, double c1) {
    return ds * (c0 * c0 + c0 * c1 + c1 * c1) / 3.0;
}
double int_cq(double ds, double c0, double c1, double q0, double q1) {
    return ds / 6.0 * (2.0 * c0 * q0 + c0 * q1 + c1 * q0 + 2.0 * c1 * q1);
}

}  // namespace

double LiftingSurface::semi_span() const {
    return spanwise(sections.back()) - spanwise(sections.front());
}

double LiftingSurface::span() const {
    if (symmetric && !vertical) return 2.0 * std::abs(sections.back().leading_edge.y());
    return semi_span();
}

double LiftingSurface::planform_area() const {
    double a = 0.0;
    for (std::size_t i = 0; i + 1 < sections.size(); ++i)
        a += int_c(spanwise(sections[i + 1]) - spanwise(sections[i]), sections[i].chord,
                   sections[i + 1].chord);
    return a * n_copies();
}

double LiftingSurface::mean_aerodynamic_chord() const {
    double a = 0.0, b = 0.0;
    for (std::size_t i = 0; i + 1 < sections.size(); ++i) {
        const double ds = spanwise(sections[i + 1]) - spanwise(sections[i]);
        a += int_c(ds, sections[i].chord, sections[i + 1].chord);
        b += int_c2(ds, sections[i].chord, sections[i + 1].chord);
    }
    return b / a;
}

Eigen::Vector3d LiftingSurface::mac_leading_edge() const {
    double a = 0.0;
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i + 1 < sections.size(); ++i) {
        const auto& s0 = sections[i];
        const auto& s1 = sections[i + 1];
        const double ds = spanwise(s1) - spanwise(s0);
        a += int_c(ds, s0.chord, s1.chord);
        for (int k = 0; k < 3; ++k)
            m[k] += int_cq(ds, s0.chord, s1.chord, s0.leading_edge[k], s1.leading_edge[k]);
    }
    return m / a;
}

double LiftingSurface::aspect_ratio() const {
    const double b = span();
    const double area = planform_area();
    if (symmetric && !vertical) return b * b / area;
    return b * b / (area / n_copies());
}

double LiftingSurface::eta_of(double s) const {
    return (s - spanwise(sections.front())) / semi_span();
}

namespace {
// Panel index and local weight for fraction eta of the semi-span.
std::pair<std::size_t, double> locate(const LiftingSurface& w, double eta) {
    const double s = w.spanwise(w.sections.front()) + std::clamp(eta, 0.0, 1.0) * w.semi_span();
    std::size_t i = 0;
    while (i + 2 < w.sections.size() && s > w.spanwise(w.sections[i + 1])) ++i;
    const double s0 = w.spanwise(w.sections[i]), s1 = w.spanwise(w.sections[i + 1]);
    return {i, (s - s0) / (s1 - s0)};
}
}  // namespace

Eigen::Vector3d LiftingSurface::leading_edge_at(double eta) const {
    const auto [i, t] = locate(*this, eta);
    return (1.0 - t) * sections[i].leading_edge + t * sections[i + 1].leading_edge;
}

double LiftingSurface::chord_at(double eta) const {
    const auto [i, t] = locate(*this, eta);
    return (1.0 - t) * sections[i].chord + t * sections[i + 1].chord;
}

double LiftingSurface::leading_edge_sweep(std::size_t panel) const {
    MANTA_REQUIRE(panel + 1 < sections.size(),
                  fmt::format("surface '{}': no panel {}", name, panel));
    const Eigen::Vector3d d = sections[panel + 1].leading_edge - sections[panel].leading_edge;
    return std::atan2(d.x(), vertical ? d.z() : d.y());
}

double LiftingSurface::dihedral(std::size_t panel) const {
    MANTA_REQUIRE(panel + 1 < sections.size(),
                  fmt::format("surface '{}': no panel {}", name, panel));
    if (vertical) return 0.0;
    const Eigen::Vector3d d = sections[panel + 1].leading_edge - sections[panel].leading_edge;
    return std::atan2(d.z(), d.y());
}

// ---------------------------------------------------------------------------------------- Fuselage

double Fuselage::length() const {
    return stations.empty() ? 0.0 : stations.back().x - stations.front().x;
}

double Fuselage::max_width() const {
    double w = 0.0;
    for (const auto& s : stations) w = std::max(w, s.width);
    return w;
}

double Fuselage::max_height() const {
    double h = 0.0;
    for (const auto& s : stations) h = std::max(h, s.height);
    return h;
}

double Fuselage::volume() const {
    double v = 0.0;
    for (std::size_t i = 0; i + 1 < stations.size(); ++i) {
        const double a0 = pi / 4.0 * stations[i].width * stations[i].height;
        const double a1 = pi / 4.0 * stations[i + 1].width * stations[i + 1].height;
        v += 0.5 * (a0 + a1) * (stations[i + 1].x - stations[i].x);
    }
    return v;
}

// ---------------------------------------------------------------------------------- control
// surfaces

std::string_view to_string(Control c) {
    switch (c) {
        case Control::none:
            return "none";
        case Control::elevator:
            return "elevator";
        case Control::aileron:
            return "aileron";
        case Control::rudder:
            return "rudder";
    }
    return "none";
}

const LiftingSurface* AircraftGeometry::find_surface(std::string_view name) const {
    for (const auto& s : surfaces)
        if (s.name == name) return &s;
    return nullptr;
}

const LiftingSurface& AircraftGeometry::surface(std::string_view name) const {
    if (const auto* s = find_surface(name)) return *s;
    std::vector<std::string> names;
    for (const auto& s : surfaces) names.push_back(s.name);
    throw InputError(fmt::format("no lifting surface named '{}'; surfaces present: {}", name,
                                 fmt::join(names, ", ")));
}

const ControlSurface* AircraftGeometry::find_control_surface(std::string_view name) const {
    for (const auto& c : control_surfaces)
        if (c.name == name) return &c;
    return nullptr;
}

double AircraftGeometry::control_surface_area(const ControlSurface& cs) const {
    const LiftingSurface& w = surface(cs.surface);
    // Chord is piecewise linear in the spanwise coordinate; integrate exactly between the
    // section stations that fall inside [eta0, eta1].
    std::vector<double> etas{cs.span_fraction[0], cs.span_fraction[1]};
    for (const auto& s : w.sections) {
        const double e = w.eta_of(w.spanwise(s));
        if (e > cs.span_fraction[0] && e < cs.span_fraction[1]) etas.push_back(e);
    }
    std::sort(etas.begin(), etas.end());
    double a = 0.0;
    for (std::size_t i = 0; i + 1 < etas.size(); ++i)
        a += int_c((etas[i + 1] - etas[i]) * w.semi_span(), w.chord_at(etas[i]),
                   w.chord_at(etas[i + 1]));
    return a * (1.0 - cs.hinge_chord_fraction) * w.n_copies();
}

std::array<Eigen::Vector3d, 2> AircraftGeometry::hinge_line(const ControlSurface& cs) const {
    const LiftingSurface& w = surface(cs.surface);
    std::array<Eigen::Vector3d, 2> out;
    for (int k = 0; k < 2; ++k) {
        const double eta = cs.span_fraction[static_cast<std::size_t>(k)];
        const auto [i, t] = locate(w, eta);
        const double twist = (1.0 - t) * w.sections[i].twist + t * w.sections[i + 1].twist;
        const double d = cs.hinge_chord_fraction * w.chord_at(eta);
        Eigen::Vector3d p = w.leading_edge_at(eta);
        p.x() += d * std::cos(twist);
        // Positive twist raises the leading edge (horizontal) or turns it toward +y (fins).
        if (w.vertical)
            p.y() -= d * std::sin(twist);
        else
            p.z() -= d * std::sin(twist);
        out[static_cast<std::size_t>(k)] = p;
    }
    return out;
}

// ---------------------------------------------------------------------------------- parse_geometry

namespace {

std::string join_names(const std::vector<std::string>& names) {
    return fmt::format("{}", fmt::join(names, ", "));
}

Airfoil parse_airfoil(core::ConfigMap& m, const std::filesystem::path& base_dir) {
    const bool by_name = m.has("airfoil");
    const bool by_file = m.has("airfoil_file");
    if (by_name && by_file) {
        m.fail("airfoil_file", "duplicates 'airfoil'",
               "either 'airfoil' (a NACA designation) or 'airfoil_file' (a coordinate file), not "
               "both");
    }
    if (!by_name && !by_file) {
        throw ConfigError(
            fmt::format("{}: missing required key '{}' (a NACA designation such as 'NACA 64-215') "
                        "or '{}' (a Selig/Lednicer "
                        "coordinate file)",
                        m.node().where(),
                        m.node().key_path().empty() ? "airfoil" : m.node().key_path() + ".airfoil",
                        "airfoil_file"));
    }
    if (by_name) {
        const core::ConfigNode n = m.child("airfoil");
        const std::string text = n.to_string();
        try {
            (void)parse_naca_impl(text);
        } catch (const NacaProblem& p) {
            n.fail(fmt::format("is not a valid NACA designation: {}", p.problem), naca_expected);
        }
        return Airfoil::naca(text);
    }
    const core::ConfigNode n = m.child("airfoil_file");
    std::filesystem::path file = n.to_string();
    if (file.is_relative()) file = base_dir / file;
    try {
        return Airfoil::from_file(file);
    } catch (const Error& e) {
        throw ConfigError(fmt::format("{}: airfoil file '{}' is invalid: {}", n.where(),
                                      n.value_text(), e.what()));
    }
}

LiftingSurface parse_surface(const core::ConfigNode& node, const std::filesystem::path& base_dir,
                             double length) {
    core::ConfigMap m(node);
    LiftingSurface s;
    s.name = m.string("name");
    s.vertical = m.boolean_or("vertical", false);
    s.symmetric = m.boolean_or("symmetric", !s.vertical);
    const core::ConfigNode seq = m.sequence("sections");
    if (seq.size() < 2)
        seq.fail(fmt::format("has {} entry", seq.size()), "at least 2 sections (root and tip)");
    for (std::size_t i = 0; i < seq.size(); ++i) {
        core::ConfigMap sm(seq.element(i));
        SurfaceSection sec;
        const auto le = sm.vec3("leading_edge", core::NumberSpec::range(-1000.0, 1000.0, "m"));
        sec.leading_edge = Eigen::Vector3d(le[0], le[1], le[2]);
        sec.chord = sm.number("chord", core::NumberSpec{0.0, 100.0, true, false, "m"});
        sec.twist = sm.angle_or("twist", 0.0,
                                core::NumberSpec::range(-core::deg(30.0), core::deg(30.0), "rad"));
        sec.airfoil = parse_airfoil(sm, base_dir);
        const double sp = s.spanwise(sec);
        const char* axis = s.vertical ? "z" : "y";
        if (i == 0 && s.symmetric && !s.vertical && sp < 0.0) {
            sm.fail("leading_edge",
                    fmt::format("puts the root of a symmetric surface at y = {:g} < 0", sp),
                    "y >= 0 (the surface is given on the right side and mirrored about y = 0)");
        }
        if (!s.sections.empty() && !(sp > s.spanwise(s.sections.back()))) {
            sm.fail("leading_edge",
                    fmt::format("has {} = {:g}, not beyond the previous section's {} = {:g}", axis,
                                sp, axis, s.spanwise(s.sections.back())),
                    fmt::format("sections ordered root to tip with {} strictly increasing", axis));
        }
        const double slack = 0.01 * length;
        if (le[0] < -slack || le[0] + sec.chord > length + slack) {
            sm.fail(
                "leading_edge",
                fmt::format("puts the section from x = {:g} to {:g}, outside the aircraft length",
                            le[0], le[0] + sec.chord),
                fmt::format("x and x + chord within [0, {:g}] m (geometry.length)", length));
        }
        sm.finish();
        s.sections.push_back(std::move(sec));
    }
    m.finish();
    return s;
}

Fuselage parse_fuselage(core::ConfigMap& f, double length) {
    Fuselage fus;
    const auto x = f.numbers("x", 0, core::NumberSpec::range(-1000.0, 1000.0, "m"));
    const auto n = x.size();
    const auto w = f.numbers("width", n, core::NumberSpec::range(0.0, 100.0, "m"));
    const auto h = f.numbers("height", n, core::NumberSpec::range(0.0, 100.0, "m"));
    const auto z = f.numbers("z_centre", n, core::NumberSpec::range(-1000.0, 1000.0, "m"));
    if (n < 2) f.fail("x", "has 1 station", "at least 2 stations (nose and tail)");
    const core::ConfigNode xn = f.node().child("x");
    for (std::size_t i = 0; i < n; ++i) {
        if (i > 0 && !(x[i] > x[i - 1])) {
            xn.element(i).fail(fmt::format("is not beyond the previous station x = {:g}", x[i - 1]),
                               "stations with x strictly increasing");
        }
        if (x[i] < -0.01 * length || x[i] > 1.01 * length) {
            xn.element(i).fail("lies outside the aircraft length",
                               fmt::format("x within [0, {:g}] m (geometry.length)", length));
        }
        fus.stations.push_back({x[i], w[i], h[i], z[i]});
    }
    f.finish();
    return fus;
}

ControlSurface parse_control_surface(const core::ConfigNode& node,
                                     const std::vector<LiftingSurface>& surfaces) {
    core::ConfigMap m(node);
    ControlSurface cs;
    cs.name = m.string("name");
    const core::ConfigNode sn = m.child("surface");
    cs.surface = sn.to_string();
    const LiftingSurface* w = nullptr;
    std::vector<std::string> names;
    for (const auto& s : surfaces) {
        names.push_back(s.name);
        if (s.name == cs.surface) w = &s;
    }
    if (!w) {
        std::string expected = fmt::format("the name of a lifting surface: {}", join_names(names));
        const std::string guess = core::closest_match(cs.surface, names);
        if (!guess.empty()) expected += fmt::format(" (did you mean '{}'?)", guess);
        sn.fail("is not a lifting surface", expected);
    }
    std::string default_control = "none";
    if (cs.name == "elevator" || cs.name == "aileron" || cs.name == "rudder")
        default_control = cs.name;
    const std::string control =
        m.choice_or("control", default_control, {"none", "elevator", "aileron", "rudder"});
    cs.control = control == "elevator"  ? Control::elevator
                 : control == "aileron" ? Control::aileron
                 : control == "rudder"  ? Control::rudder
                                        : Control::none;

    const bool by_fraction = m.has("span_fraction");
    const bool by_position = m.has("span_position");
    if (by_fraction && by_position) {
        m.fail("span_position", "duplicates 'span_fraction'",
               "either 'span_fraction' (fractions of the semi-span) or 'span_position' (metres), "
               "not both");
    }
    if (!by_fraction && !by_position) {
        throw ConfigError(
            fmt::format("{}: missing required key '{}.span_fraction' (fractions of the semi-span, "
                        "e.g. [0.55, 0.95]) or "
                        "'span_position' ([{}0, {}1] in metres)",
                        m.node().where(), m.node().key_path(), w->vertical ? "z" : "y",
                        w->vertical ? "z" : "y"));
    }
    if (by_fraction) {
        const auto v = m.numbers("span_fraction", 2, core::NumberSpec::range(0.0, 1.0, "-"));
        cs.span_fraction = {v[0], v[1]};
    } else {
        const double s0 = w->spanwise(w->sections.front()), s1 = w->spanwise(w->sections.back());
        const auto v = m.numbers("span_position", 2, core::NumberSpec::range(s0, s1, "m"));
        cs.span_fraction = {w->eta_of(v[0]), w->eta_of(v[1])};
    }
    if (!(cs.span_fraction[0] < cs.span_fraction[1])) {
        m.fail(by_fraction ? "span_fraction" : "span_position",
               "has its inboard end not inboard of its outboard end",
               "[inboard, outboard] with inboard < outboard");
    }
    cs.hinge_chord_fraction =
        m.number("hinge_chord_fraction",
                 core::NumberSpec{0.0, 1.0, true, true, "fraction of the local chord"});
    // The gain keys say which copies exist; the wrong kind for the surface is named as such.
    for (const char* k : {"gain", "gain_right", "gain_left"}) {
        const bool side_key = std::string_view(k) != "gain";
        if (side_key != w->symmetric && m.has(k)) {
            m.fail(k,
                   fmt::format("applies to {} surfaces only",
                               side_key ? "symmetric" : "non-symmetric"),
                   side_key ? fmt::format("'gain' for the one copy of surface '{}'", w->name)
                            : fmt::format(
                                  "'gain_right' and 'gain_left' for the two copies of surface '{}'",
                                  w->name));
        }
    }
    if (w->symmetric) {
        cs.gain = m.number_or("gain_right", 1.0, core::NumberSpec::range(-10.0, 10.0, "-"));
        cs.mirror_gain = m.number_or("gain_left", 1.0, core::NumberSpec::range(-10.0, 10.0, "-"));
    } else {
        cs.gain = m.number_or("gain", 1.0, core::NumberSpec::range(-10.0, 10.0, "-"));
        cs.mirror_gain = 0.0;
    }
    if (m.has_angle("limits")) {
        const auto lim = m.angle_range(
            "limits", core::NumberSpec::range(-core::deg(90.0), core::deg(90.0), "rad"));
        if (!(lim[0] < lim[1])) {
            m.fail(m.node().has("limits_deg") ? "limits_deg" : "limits", "has equal bounds",
                   "[lower, upper] with lower < upper");
        }
        cs.limits = lim;
    }
    m.finish();
    return cs;
}

}  // namespace

AircraftGeometry parse_geometry(core::ConfigMap& map, const std::filesystem::path& base_dir) {
    AircraftGeometry g;
    // Plausible sizes (issue 16): the largest aircraft flown is 117 m in span and 84 m long.
    const core::NumberSpec size{0.0, 1000.0, true, false, "m"};
    g.length = map.number("length", size);
    g.height = map.number("height", size);
    const core::ConfigNode seq = map.sequence("lifting_surfaces");
    for (std::size_t i = 0; i < seq.size(); ++i) {
        const core::ConfigNode el = seq.element(i);
        LiftingSurface s = parse_surface(el, base_dir, g.length);
        if (g.find_surface(s.name)) {
            el.child("name").fail("is used by an earlier lifting surface", "a unique surface name");
        }
        g.surfaces.push_back(std::move(s));
    }
    if (auto f = map.optional_child("fuselage")) {
        core::ConfigMap fm(*f);
        g.fuselage = parse_fuselage(fm, g.length);
    }
    if (map.has("control_surfaces")) {
        const core::ConfigNode cseq = map.sequence("control_surfaces", true);
        for (std::size_t i = 0; i < cseq.size(); ++i) {
            const core::ConfigNode el = cseq.element(i);
            ControlSurface cs = parse_control_surface(el, g.surfaces);
            if (g.find_control_surface(cs.name)) {
                el.child("name").fail("is used by an earlier control surface",
                                      "a unique control-surface name");
            }
            g.control_surfaces.push_back(std::move(cs));
        }
    }
    map.finish();
    return g;
}

}  // namespace manta::geometry
