#include "manta/vlm/avl_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <optional>
#include <utility>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/vlm/detail/avl_text.hpp"

namespace manta::vlm {

namespace {

namespace fs = std::filesystem;
using geometry::Airfoil;

constexpr double deg = std::numbers::pi / 180.0;

using detail::avl::is_non_finite;
using detail::avl::leading_numbers;
using detail::avl::Line;
using detail::avl::lower;
using detail::avl::non_finite_message;
using detail::avl::significant_lines;
using detail::avl::to_number;
using detail::avl::upper;
using detail::avl::words;

/// Plausible magnitudes of the file's values (lengths in the file's own unit). They leave room
/// for any aircraft in millimetres and reject what no geometry means (ANGLE -1e308).
constexpr double max_length = 1e6;        ///< coordinates, chords, offsets, reference lengths
constexpr double max_area = 1e12;         ///< Sref
constexpr double max_angle_deg = 180.0;   ///< ANGLE, Ainc
constexpr double max_factor = 1e3;        ///< CONTROL gain and SgnDup, DESIGN weight
constexpr double max_scale = 1e6;         ///< SCALE factors
constexpr double max_coefficient = 10.0;  ///< CDp, CLAF, CDCL values
constexpr int max_chordwise = 1000;       ///< Nchord
constexpr int max_spanwise = 10000;       ///< Nspan (surface or section), Nbody

/// Every word of a coordinate file that spells a non-finite number: InputError naming the file and
/// its line (AFILE and BFILE files are checked before they are read as coordinates).
void check_coordinates_finite(std::string_view text, const std::string& path) {
    for (const Line& l : significant_lines(text))
        for (const std::string& w : words(l.text))
            if (is_non_finite(w))
                throw InputError(fmt::format("{}:{}: {}", path, l.number,
                                             non_finite_message(w, "coordinate pairs 'x y'")));
}

// ------------------------------------------------------------------------------ coordinates

/// Signed area of a closed polygon (positive counter-clockwise).
double signed_area(const std::vector<Eigen::Vector2d>& p) {
    double a = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const auto& u = p[i];
        const auto& w = p[(i + 1) % p.size()];
        a += u.x() * w.y() - w.x() * u.y();
    }
    return 0.5 * a;
}

/// Scale a section contour to unit chord with the leading edge (smallest x) at the origin, and
/// put it in Selig order (trailing edge, upper surface, leading edge, lower surface): AVL accepts
/// any chord length and either direction around the contour.
std::vector<Eigen::Vector2d> normalise_contour(std::vector<Eigen::Vector2d> p) {
    if (p.size() < 3) return p;
    std::size_t le = 0;
    double xmax = p[0].x();
    for (std::size_t i = 1; i < p.size(); ++i) {
        if (p[i].x() < p[le].x()) le = i;
        xmax = std::max(xmax, p[i].x());
    }
    const Eigen::Vector2d origin = p[le];
    const double chord = xmax - origin.x();
    if (!(chord > 0.0)) return p;
    for (auto& q : p) q = (q - origin) / chord;
    // Selig order runs counter-clockwise (x right, y up).
    if (signed_area(p) < 0.0) std::reverse(p.begin(), p.end());
    return p;
}

/// y on a polyline with x non-decreasing, at x (clamped to its ends).
double interpolate(const std::vector<Eigen::Vector2d>& p, double x) {
    if (x <= p.front().x()) return p.front().y();
    if (x >= p.back().x()) return p.back().y();
    for (std::size_t i = 1; i < p.size(); ++i) {
        if (x <= p[i].x()) {
            const double dx = p[i].x() - p[i - 1].x();
            if (dx <= 0.0) return p[i].y();
            const double t = (x - p[i - 1].x()) / dx;
            return (1.0 - t) * p[i - 1].y() + t * p[i].y();
        }
    }
    return p.back().y();
}

/// Upper and lower halves of a contour in Selig order, each from the leading edge aft.
std::pair<std::vector<Eigen::Vector2d>, std::vector<Eigen::Vector2d>> split_contour(
    const std::vector<Eigen::Vector2d>& p) {
    std::size_t le = 0;
    for (std::size_t i = 1; i < p.size(); ++i)
        if (p[i].x() < p[le].x()) le = i;
    std::vector<Eigen::Vector2d> up(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(le) + 1);
    std::reverse(up.begin(), up.end());
    std::vector<Eigen::Vector2d> lo(p.begin() + static_cast<std::ptrdiff_t>(le), p.end());
    return {std::move(up), std::move(lo)};
}

/// The part x/c in [x1, x2] of a section, stretched to a unit chord (AVL's optional x/c range
/// of NACA, AIRFOIL and AFILE): the section's own mean line plus the half thickness of its
/// contour, sampled at cosine-spaced stations. The whole range returns the section unchanged.
Airfoil restrict_to_range(const Airfoil& a, double x1, double x2, const std::string& where) {
    if (x1 == 0.0 && x2 == 1.0) return a;
    const auto [up, lo] = split_contour(a.coordinates());
    constexpr int n = 81;
    const double c = x2 - x1;
    std::vector<Eigen::Vector2d> u, l;
    for (int i = 0; i < n; ++i) {
        const double t = 0.5 * (1.0 - std::cos(std::numbers::pi * i / (n - 1)));
        const double x = x1 + c * t;
        const double half = 0.5 * std::max(0.0, interpolate(up, x) - interpolate(lo, x));
        const double mean = a.camber(x);
        u.emplace_back(t, (mean + half) / c);
        l.emplace_back(t, (mean - half) / c);
    }
    std::vector<Eigen::Vector2d> pts(u.rbegin(), u.rend());
    pts.insert(pts.end(), l.begin() + 1, l.end());
    return Airfoil::from_points(fmt::format("{} (x/c {:g} to {:g})", a.name(), x1, x2),
                                std::move(pts), where);
}

// ----------------------------------------------------------------------------------- reader

/// What a keyword of the file means (its first four letters are significant).
enum class Key {
    surface,
    component,
    yduplicate,
    scale,
    translate,
    angle,
    nowake,
    noalbe,
    noload,
    section,
    naca,
    airfoil,
    afile,
    claf,
    cdcl,
    control,
    design,
    body,
    bfile,
};

struct KeyName {
    std::string_view prefix;  // first four letters, upper case
    Key key;
    std::string_view name;  // spelling used in messages
};

constexpr KeyName key_names[] = {
    {"SURF", Key::surface, "SURFACE"}, {"COMP", Key::component, "COMPONENT"},
    {"INDE", Key::component, "INDEX"}, {"YDUP", Key::yduplicate, "YDUPLICATE"},
    {"SCAL", Key::scale, "SCALE"},     {"TRAN", Key::translate, "TRANSLATE"},
    {"ANGL", Key::angle, "ANGLE"},     {"NOWA", Key::nowake, "NOWAKE"},
    {"NOAL", Key::noalbe, "NOALBE"},   {"NOLO", Key::noload, "NOLOAD"},
    {"SECT", Key::section, "SECTION"}, {"NACA", Key::naca, "NACA"},
    {"AIRF", Key::airfoil, "AIRFOIL"}, {"AFIL", Key::afile, "AFILE"},
    {"CLAF", Key::claf, "CLAF"},       {"CDCL", Key::cdcl, "CDCL"},
    {"CONT", Key::control, "CONTROL"}, {"DESI", Key::design, "DESIGN"},
    {"BODY", Key::body, "BODY"},       {"BFIL", Key::bfile, "BFILE"},
};

constexpr std::string_view known_keywords =
    "SURFACE, COMPONENT (INDEX), YDUPLICATE, SCALE, TRANSLATE, ANGLE, NOWAKE, NOALBE, NOLOAD, "
    "SECTION, NACA, AIRFOIL, AFILE, CLAF, CDCL, CONTROL, DESIGN, BODY or BFILE";

class Reader {
public:
    Reader(std::string_view text, const std::string& source, fs::path base_dir,
           std::vector<std::string>& warnings)
        : lines_(significant_lines(text)),
          source_(source),
          base_dir_(std::move(base_dir)),
          warnings_(warnings) {
        // Number of the last line, for errors at the end of the file.
        end_line_ = 1 + static_cast<int>(std::count(text.begin(), text.end(), '\n'));
        if (!text.empty() && text.back() == '\n') --end_line_;
    }

    Model read() {
        read_header();
        while (pos_ < lines_.size()) keyword(lines_[pos_++]);
        finish_block();
        if (model_.surfaces.empty())
            fail(end_line_, "end of file",
                 "no SURFACE in the file; expected at least one SURFACE block");
        flush_warnings();
        return std::move(model_);
    }

private:
    struct PendingSection {
        Section section;
        int line = 0;  // line of the SECTION keyword
    };
    struct PendingSurface {
        Surface surface;
        int line = 0;
        std::vector<PendingSection> sections;
        Eigen::Vector3d scale = Eigen::Vector3d::Ones();
        Eigen::Vector3d translate = Eigen::Vector3d::Zero();
        double angle = 0.0;  // [rad]
    };
    struct PendingBody {
        Body body;
        int line = 0;
        Eigen::Vector3d scale = Eigen::Vector3d::Ones();
        Eigen::Vector3d translate = Eigen::Vector3d::Zero();
        std::vector<Eigen::Vector2d> outline;  // BFILE points as read
        std::string outline_source;
    };
    struct Ignored {
        int first_line = 0;
        int count = 0;
        std::string reason;
    };

    std::vector<Line> lines_;
    std::size_t pos_ = 0;
    const std::string& source_;
    fs::path base_dir_;
    std::vector<std::string>& warnings_;
    int end_line_ = 1;
    Model model_;
    std::optional<PendingSurface> surface_;
    std::optional<PendingBody> body_;
    std::map<std::string, Airfoil> airfoils_;  // coordinate files already read
    std::vector<std::pair<std::string, Ignored>> ignored_;

    // -------------------------------------------------------------------------- messages

    [[noreturn]] void fail(int line, std::string_view keyword, std::string_view message) const {
        throw InputError(fmt::format("{}:{}: {}: {}", source_, line, keyword, message));
    }

    void warn(int line, std::string_view keyword, std::string_view message) {
        warnings_.push_back(fmt::format("{}:{}: {}: {}", source_, line, keyword, message));
    }

    /// Note a keyword that is read but has no effect on the model (one warning per keyword).
    void ignore(int line, std::string_view keyword, std::string_view reason) {
        for (auto& [k, v] : ignored_) {
            if (k == keyword) {
                ++v.count;
                return;
            }
        }
        ignored_.emplace_back(std::string(keyword), Ignored{line, 1, std::string(reason)});
    }

    void flush_warnings() {
        for (const auto& [k, v] : ignored_) {
            const std::string times =
                v.count > 1 ? fmt::format(" ({} times, first here)", v.count) : std::string();
            warn(v.first_line, k, fmt::format("ignored{}: {}", times, v.reason));
        }
    }

    // ------------------------------------------------------------------------ data lines

    /// The data line after keyword line `kw`; error at the end of the file.
    const Line& data_line(const Line& kw, std::string_view keyword, std::string_view expected) {
        if (pos_ >= lines_.size())
            fail(kw.number, keyword, fmt::format("expected {}, got the end of the file", expected));
        return lines_[pos_++];
    }

    /// Between `min` and `max` leading numbers of `line` (from word `first`); an error naming the
    /// fields (`fields`) if fewer.
    std::vector<double> numbers(const Line& line, std::string_view keyword, std::size_t min,
                                std::size_t max, std::string_view fields,
                                std::size_t first = 0) const {
        const auto ws = words(line.text);
        std::string stop;
        auto v = leading(line, keyword, ws, first, max, fields, &stop);
        if (v.size() < min) {
            const std::string what = min == 1 ? "1 number" : fmt::format("{} numbers", min);
            if (!stop.empty())
                fail(line.number, keyword,
                     fmt::format("expected {} ({}), got '{}'", what, fields, stop));
            fail(
                line.number, keyword,
                fmt::format("expected {} ({}), got {} in '{}'", what, fields, v.size(), line.text));
        }
        return v;
    }

    /// leading_numbers of the words `ws` of `line`, an error if one of them spells a non-finite
    /// number (`fields`: what the line holds, for the message).
    std::vector<double> leading(const Line& line, std::string_view keyword,
                                const std::vector<std::string>& ws, std::size_t first,
                                std::size_t max, std::string_view fields,
                                std::string* stop = nullptr) const {
        std::string bad;
        auto v = leading_numbers(ws, first, max, stop, &bad);
        if (!bad.empty()) fail(line.number, keyword, non_finite_message(bad, fields));
        return v;
    }

    /// `v` (a field of `line`) within [lo, hi]; `unit` for the message ("" for none).
    double within(double v, double lo, double hi, const Line& line, std::string_view keyword,
                  std::string_view field, std::string_view what, std::string_view unit = "") const {
        if (!(v >= lo && v <= hi)) {
            const std::string u = unit.empty() ? std::string() : fmt::format(" {}", unit);
            fail(line.number, keyword,
                 fmt::format("{} = {:g}{}; expected {} in [{:g}, {:g}]{}", field, v, u, what, lo,
                             hi, u));
        }
        return v;
    }
    /// A length of the file within +-max_length.
    double length(double v, const Line& line, std::string_view keyword,
                  std::string_view field) const {
        return within(v, -max_length, max_length, line, keyword, field, "a length");
    }
    /// An angle [deg] within +-max_angle_deg.
    double angle_deg(double v, const Line& line, std::string_view keyword,
                     std::string_view field) const {
        return within(v, -max_angle_deg, max_angle_deg, line, keyword, field, "an angle", "deg");
    }
    /// A vortex count in [lo, hi].
    int count(double v, int lo, int hi, const Line& line, std::string_view keyword,
              std::string_view field, std::string_view what) const {
        const int n = integer(v, line, keyword, field);
        if (n < lo || n > hi)
            fail(line.number, keyword,
                 fmt::format("{} = {}; expected {} in [{}, {}]", field, n, what, lo, hi));
        return n;
    }

    int integer(double v, const Line& line, std::string_view keyword,
                std::string_view field) const {
        if (!(std::abs(v - std::round(v)) <= 1e-9 && std::abs(v) <= 1e6))  // NaN fails too
            fail(line.number, keyword,
                 fmt::format("{} = {:g} in '{}'; expected an integer", field, v, line.text));
        return static_cast<int>(std::lround(v));
    }

    void check_spacing(double p, const Line& line, std::string_view keyword,
                       std::string_view field) const {
        if (!(std::abs(p) <= 3.0))
            fail(line.number, keyword,
                 fmt::format("{} = {:g}; expected a spacing parameter in [-3, 3]", field, p));
    }

    /// Optional "X1 X2" x/c range in words `ws` from index `first` of `line`.
    std::optional<std::pair<double, double>> x_range(const Line& line, std::string_view keyword,
                                                     const std::vector<std::string>& ws,
                                                     std::size_t first) const {
        const auto v = leading(line, keyword, ws, first, 2, "an x/c range 'X1 X2'");
        if (v.empty()) return std::nullopt;
        if (v.size() < 2)
            fail(line.number, keyword,
                 fmt::format("expected an x/c range 'X1 X2' (two numbers), got '{}'", line.text));
        if (!(v[0] >= 0.0 && v[1] <= 1.0 && v[0] < v[1]))
            fail(line.number, keyword,
                 fmt::format("x/c range {:g} to {:g}; expected 0 <= X1 < X2 <= 1", v[0], v[1]));
        return std::make_pair(v[0], v[1]);
    }
    std::optional<std::pair<double, double>> x_range(const Line& line, std::string_view keyword,
                                                     std::size_t first) const {
        return x_range(line, keyword, words(line.text), first);
    }

    /// File name of an AFILE/BFILE data line (double quotes allow blanks) and the words after it.
    std::pair<std::string, std::vector<std::string>> file_name(const Line& line,
                                                               std::string_view keyword) const {
        const std::string& t = line.text;
        if (t.front() == '"') {
            const std::size_t close = t.find('"', 1);
            if (close == std::string::npos || close == 1)
                fail(line.number, keyword,
                     fmt::format("unmatched or empty quotes in '{}'; expected \"file name\"", t));
            return {t.substr(1, close - 1), words(std::string_view(t).substr(close + 1))};
        }
        auto ws = words(t);
        std::string name = ws.front();
        ws.erase(ws.begin());
        return {name, ws};
    }

    fs::path resolve(const std::string& name) const {
        const fs::path p(name);
        return p.is_absolute() ? p : base_dir_ / p;
    }

    // ---------------------------------------------------------------------------- header

    void read_header() {
        if (lines_.empty())
            fail(end_line_, "header", "the file is empty; expected a title line, then Mach");
        const Line& title = lines_[pos_++];
        model_.name = title.text;

        const Line& mach = data_line(title, "header", "a line with Mach");
        model_.mach = numbers(mach, "header", 1, 1, "Mach")[0];
        if (!(model_.mach >= 0.0 && model_.mach < 1.0))
            fail(
                mach.number, "header",
                fmt::format("Mach = {:g}; expected a subsonic Mach number in [0, 1)", model_.mach));

        const Line& sym = data_line(mach, "header", "a line with IYsym IZsym Zsym");
        const auto s = numbers(sym, "header", 3, 3, "IYsym IZsym Zsym");
        const auto sign = [](int i) { return i > 0 ? 1 : (i < 0 ? -1 : 0); };
        model_.y_symmetry = sign(integer(s[0], sym, "header", "IYsym"));
        model_.z_symmetry = sign(integer(s[1], sym, "header", "IZsym"));
        model_.z_symmetry_plane = length(s[2], sym, "header", "Zsym");

        const Line& ref = data_line(sym, "header", "a line with Sref Cref Bref");
        const auto r = numbers(ref, "header", 3, 3, "Sref Cref Bref");
        within(r[0], -max_area, max_area, ref, "header", "Sref", "an area");
        length(r[1], ref, "header", "Cref");
        length(r[2], ref, "header", "Bref");
        const auto positive = [&](double v, std::string_view field) {
            if (v > 0.0) return v;
            warn(ref.number, "header",
                 fmt::format("{} = {:g} is not positive; 1 is used (as AVL does)", field, v));
            return 1.0;
        };
        model_.reference.area = positive(r[0], "Sref");
        model_.reference.chord = positive(r[1], "Cref");
        model_.reference.span = positive(r[2], "Bref");

        const Line& point = data_line(ref, "header", "a line with Xref Yref Zref");
        const auto p = numbers(point, "header", 3, 3, "Xref Yref Zref");
        model_.reference.point = Eigen::Vector3d(length(p[0], point, "header", "Xref"),
                                                 length(p[1], point, "header", "Yref"),
                                                 length(p[2], point, "header", "Zref"));

        // Optional CDp: a line that starts with a number (a keyword line does not; nor does
        // "nan", which is an error here rather than an unknown keyword).
        if (pos_ < lines_.size()) {
            const auto ws = words(lines_[pos_].text);
            if (to_number(ws.front()) || is_non_finite(ws.front())) {
                const Line& cdp = lines_[pos_++];
                model_.profile_drag =
                    within(numbers(cdp, "header", 1, 1, "CDp")[0], -max_coefficient,
                           max_coefficient, cdp, "header", "CDp", "a drag coefficient");
            }
        }
    }

    // -------------------------------------------------------------------------- keywords

    void keyword(const Line& line) {
        const auto ws = words(line.text);
        const std::string head = upper(ws.front());
        const KeyName* k = nullptr;
        if (head.size() >= 4)
            for (const auto& kn : key_names)
                if (std::string_view(head).substr(0, 4) == kn.prefix) k = &kn;
        if (!k)
            fail(line.number, "keyword",
                 fmt::format("unknown keyword '{}'; expected one of {}", ws.front(),
                             known_keywords));
        const std::string_view name = k->name;
        switch (k->key) {
            case Key::surface:
                return start_surface(line);
            case Key::body:
                return start_body(line);
            case Key::component: {
                auto& s = in_surface(line, name);
                const Line& d = data_line(line, name, "a line with Lcomp");
                s.surface.component = integer(numbers(d, name, 1, 1, "Lcomp")[0], d, name, "Lcomp");
                return;
            }
            case Key::yduplicate: {
                in_surface_or_body(line, name);
                const Line& d = data_line(line, name, "a line with Ydupl");
                const double y = length(numbers(d, name, 1, 1, "Ydupl")[0], d, name, "Ydupl");
                if (model_.y_symmetry != 0)
                    warn(line.number, name,
                         "given although the header sets IYsym != 0: the mirror copy coincides "
                         "with the symmetry image (AVL warns of the same)");
                if (surface_)
                    surface_->surface.y_duplicate = y;
                else
                    body_->body.y_duplicate = y;
                return;
            }
            case Key::scale: {
                in_surface_or_body(line, name);
                const Line& d = data_line(line, name, "a line with Xscale Yscale Zscale");
                const auto v = numbers(d, name, 3, 3, "Xscale Yscale Zscale");
                for (int i = 0; i < 3; ++i)
                    within(v[static_cast<std::size_t>(i)], -max_scale, max_scale, d, name,
                           std::array{"Xscale", "Yscale", "Zscale"}[static_cast<std::size_t>(i)],
                           "a scale factor");
                if (!(v[0] > 0.0))
                    fail(d.number, name,
                         fmt::format("Xscale = {:g}; expected a positive factor (it scales the "
                                     "chords)",
                                     v[0]));
                (surface_ ? surface_->scale : body_->scale) = Eigen::Vector3d(v[0], v[1], v[2]);
                return;
            }
            case Key::translate: {
                in_surface_or_body(line, name);
                const Line& d = data_line(line, name, "a line with dX dY dZ");
                const auto v = numbers(d, name, 3, 3, "dX dY dZ");
                length(v[0], d, name, "dX");
                length(v[1], d, name, "dY");
                length(v[2], d, name, "dZ");
                (surface_ ? surface_->translate : body_->translate) =
                    Eigen::Vector3d(v[0], v[1], v[2]);
                return;
            }
            case Key::angle: {
                in_surface_or_body(line, name);
                const Line& d = data_line(line, name, "a line with dAinc");
                const double a =
                    angle_deg(numbers(d, name, 1, 1, "dAinc [deg]")[0], d, name, "dAinc");
                if (surface_)
                    surface_->angle = a * deg;
                else
                    ignore(line.number, name, "a body has no incidence");
                return;
            }
            case Key::nowake:
                in_surface(line, name).surface.sheds_wake = false;
                return;
            case Key::noalbe:
                (void)in_surface(line, name);
                ignore(line.number, name,
                       "every surface sees the free stream and the rotation rates");
                return;
            case Key::noload:
                (void)in_surface(line, name);
                ignore(line.number, name, "the loads of every surface are included in the totals");
                return;
            case Key::section:
                return read_section(line);
            case Key::naca:
                return read_naca(line);
            case Key::airfoil:
                return read_airfoil(line);
            case Key::afile:
                return read_afile(line);
            case Key::claf: {
                auto& sec = in_section(line, name);
                const Line& d = data_line(line, name, "a line with CLaf");
                const double f = within(numbers(d, name, 1, 1, "CLaf")[0], -max_coefficient,
                                        max_coefficient, d, name, "CLaf", "a lift-slope factor");
                if (f > 0.0 && f < 2.0) {
                    sec.lift_slope_factor = f;
                } else {
                    warn(d.number, name,
                         fmt::format("CLaf = {:g} is outside (0, 2); 1 is used (as AVL does)", f));
                    sec.lift_slope_factor = 1.0;
                }
                return;
            }
            case Key::cdcl: {
                (void)in_section(line, name);
                const Line& d = data_line(line, name, "a line with CL1 CD1 CL2 CD2 CL3 CD3");
                const auto v = numbers(d, name, 6, 6, "CL1 CD1 CL2 CD2 CL3 CD3");
                for (std::size_t i = 0; i < 6; ++i)
                    within(v[i], -max_coefficient, max_coefficient, d, name,
                           fmt::format("{}{}", i % 2 == 0 ? "CL" : "CD", i / 2 + 1),
                           "a polar coefficient");
                ignore(line.number, name,
                       "section profile drag polars are not modelled (the header CDp is)");
                return;
            }
            case Key::control:
                return read_control(line);
            case Key::design: {
                (void)in_section(line, name);
                const Line& d = data_line(line, name, "a line with DName Wdes");
                const auto v = numbers(d, name, 0, 1, "DName Wdes", 1);
                if (!v.empty())
                    within(v[0], -max_factor, max_factor, d, name, "Wdes", "a design weight");
                ignore(line.number, name, "design variables are not modelled");
                return;
            }
            case Key::bfile:
                return read_bfile(line);
        }
    }

    PendingSurface& in_surface(const Line& line, std::string_view keyword) {
        if (!surface_ && body_)
            fail(line.number, keyword,
                 fmt::format("inside BODY '{}'; expected it in a SURFACE block", body_->body.name));
        if (!surface_)
            fail(line.number, keyword, "outside a SURFACE block; expected it after SURFACE");
        return *surface_;
    }

    void in_surface_or_body(const Line& line, std::string_view keyword) const {
        if (!surface_ && !body_)
            fail(line.number, keyword,
                 "outside a SURFACE or BODY block; expected it after SURFACE or BODY");
    }

    Section& in_section(const Line& line, std::string_view keyword) {
        auto& s = in_surface(line, keyword);
        if (s.sections.empty())
            fail(line.number, keyword,
                 fmt::format("before the first SECTION of SURFACE '{}'; expected it after a "
                             "SECTION",
                             s.surface.name));
        return s.sections.back().section;
    }

    // --------------------------------------------------------------------------- surfaces

    void start_surface(const Line& line) {
        finish_block();
        PendingSurface s;
        s.line = line.number;
        const Line& name = data_line(line, "SURFACE", "a line with the surface name");
        s.surface.name = name.text;
        const Line& d = data_line(name, "SURFACE", "a line with Nchord Cspace [Nspan Sspace]");
        const auto v = numbers(d, "SURFACE", 2, 4, "Nchord Cspace, then optionally Nspan Sspace");
        s.surface.n_chord = integer(v[0], d, "SURFACE", "Nchord");
        if (s.surface.n_chord < 1)
            fail(d.number, "SURFACE",
                 fmt::format("Nchord = {}; expected at least 1 chordwise vortex",
                             s.surface.n_chord));
        (void)count(v[0], 1, max_chordwise, d, "SURFACE", "Nchord", "a chordwise vortex count");
        s.surface.chord_spacing = v[1];
        check_spacing(v[1], d, "SURFACE", "Cspace");
        if (v.size() == 3)
            warn(d.number, "SURFACE",
                 "Nspan given without Sspace: ignored (as AVL does); the SECTION counts apply");
        if (v.size() >= 4) {
            s.surface.n_span = integer(v[2], d, "SURFACE", "Nspan");
            if (s.surface.n_span < 0)
                fail(d.number, "SURFACE",
                     fmt::format("Nspan = {}; expected a count >= 0", s.surface.n_span));
            (void)count(v[2], 0, max_spanwise, d, "SURFACE", "Nspan", "a spanwise vortex count");
            s.surface.span_spacing = v[3];
            check_spacing(v[3], d, "SURFACE", "Sspace");
        } else {
            s.surface.n_span = 0;
            s.surface.span_spacing = 0.0;
        }
        // AVL's default component is the surface's number, mirror copies counted.
        s.surface.component = 1 +
                              static_cast<int>(std::count_if(
                                  model_.surfaces.begin(), model_.surfaces.end(),
                                  [](const Surface& o) { return o.y_duplicate.has_value(); })) +
                              static_cast<int>(model_.surfaces.size());
        surface_ = std::move(s);
    }

    void read_section(const Line& line) {
        auto& s = in_surface(line, "SECTION");
        const Line& d = data_line(line, "SECTION", "a line with Xle Yle Zle Chord Ainc");
        const auto v =
            numbers(d, "SECTION", 5, 7, "Xle Yle Zle Chord Ainc, then optionally Nspan Sspace");
        PendingSection p;
        p.line = line.number;
        p.section.leading_edge =
            Eigen::Vector3d(length(v[0], d, "SECTION", "Xle"), length(v[1], d, "SECTION", "Yle"),
                            length(v[2], d, "SECTION", "Zle"));
        p.section.chord = v[3];
        if (!(v[3] > 0.0))
            fail(d.number, "SECTION", fmt::format("Chord = {:g}; expected a chord > 0", v[3]));
        (void)length(v[3], d, "SECTION", "Chord");
        p.section.incidence = angle_deg(v[4], d, "SECTION", "Ainc") * deg;
        if (v.size() == 6)
            warn(d.number, "SECTION", "Nspan given without Sspace: ignored (as AVL does)");
        if (v.size() == 7) {
            p.section.n_span = integer(v[5], d, "SECTION", "Nspan");
            if (p.section.n_span < 0)
                fail(d.number, "SECTION",
                     fmt::format("Nspan = {}; expected a count >= 0", p.section.n_span));
            (void)count(v[5], 0, max_spanwise, d, "SECTION", "Nspan", "a spanwise vortex count");
            p.section.span_spacing = v[6];
        } else {
            p.section.n_span = 0;
            p.section.span_spacing = 0.0;
        }
        s.sections.push_back(std::move(p));
    }

    void read_naca(const Line& line) {
        auto& sec = in_section(line, "NACA");
        auto range = x_range(line, "NACA", 1);
        const Line& d = data_line(line, "NACA", "a line with a 4-digit NACA designation");
        const auto ws = words(d.text);
        std::string digits = ws.front();
        if (digits.size() > 4 && upper(digits.substr(0, 4)) == "NACA") digits = digits.substr(4);
        const bool all_digits =
            !digits.empty() && std::all_of(digits.begin(), digits.end(), [](char c) {
                return std::isdigit(static_cast<unsigned char>(c)) != 0;
            });
        if (!all_digits || digits.size() > 4)
            fail(d.number, "NACA",
                 fmt::format("'{}' is not a NACA 4-digit designation; expected up to 4 digits "
                             "such as 2412 or 4300",
                             ws.front()));
        digits.insert(0, 4 - digits.size(), '0');
        // Only the mean line matters to the lattice; AVL takes a thickness of 00 (its own
        // example is 4300), which the designation parser rejects: read it as 1 %.
        if (digits.substr(2) == "00") digits.replace(2, 2, "01");
        if (const auto r = x_range(d, "NACA", 1)) range = r;
        try {
            Airfoil a = Airfoil::naca("NACA " + digits);
            sec.airfoil = range ? restrict_to_range(a, range->first, range->second,
                                                    fmt::format("{}:{}", source_, d.number))
                                : a;
        } catch (const InputError& e) {
            fail(d.number, "NACA", e.what());
        }
    }

    void read_airfoil(const Line& line) {
        auto& sec = in_section(line, "AIRFOIL");
        const auto range = x_range(line, "AIRFOIL", 1);
        std::vector<Eigen::Vector2d> pts;
        while (pos_ < lines_.size()) {
            const auto v =
                leading(lines_[pos_], "AIRFOIL", words(lines_[pos_].text), 0, 2, "'x y' pairs");
            if (v.size() < 2) break;
            pts.emplace_back(v[0], v[1]);
            ++pos_;
        }
        const std::string where = "inline coordinates";
        try {
            Airfoil a = Airfoil::from_points(fmt::format("AIRFOIL at line {}", line.number),
                                             normalise_contour(std::move(pts)), where);
            sec.airfoil = range ? restrict_to_range(a, range->first, range->second, where) : a;
        } catch (const InputError& e) {
            fail(line.number, "AIRFOIL", e.what());
        }
    }

    void read_afile(const Line& line) {
        auto& sec = in_section(line, "AFILE");
        auto range = x_range(line, "AFILE", 1);
        const Line& d = data_line(line, "AFILE", "a line with the airfoil file name");
        const auto [name, rest] = file_name(d, "AFILE");
        if (const auto r = x_range(d, "AFILE", rest, 0)) range = r;
        const Airfoil& a = airfoil_file(resolve(name), d);
        try {
            sec.airfoil = range ? restrict_to_range(a, range->first, range->second,
                                                    fmt::format("{}:{}", source_, d.number))
                                : a;
        } catch (const InputError& e) {
            fail(d.number, "AFILE", e.what());
        }
    }

    /// Read an airfoil coordinate file (cached). AVL normalises the coordinates itself, so a
    /// file that `Airfoil::from_file` rejects as not chord-normalised or not in Selig order is
    /// normalised here and built with `from_points`.
    const Airfoil& airfoil_file(const fs::path& path, const Line& d) {
        const std::string key = path.lexically_normal().string();
        if (const auto it = airfoils_.find(key); it != airfoils_.end()) return it->second;
        const std::string text = read_referenced(path, d, "AFILE");
        try {
            check_coordinates_finite(text, path.string());
        } catch (const InputError& e) {
            fail(d.number, "AFILE", e.what());
        }
        try {
            return airfoils_.emplace(key, Airfoil::from_file(path)).first->second;
        } catch (const InputError& original) {
            try {
                auto [name, pts] = coordinate_pairs(text, path);
                if (name.empty()) name = path.stem().string();
                return airfoils_
                    .emplace(key, Airfoil::from_points(name, normalise_contour(std::move(pts)),
                                                       path.string()))
                    .first->second;
            } catch (const InputError&) {
                fail(d.number, "AFILE", original.what());
            }
        } catch (const IoError& e) {
            throw IoError(fmt::format("{}:{}: AFILE: {}", source_, d.number, e.what()));
        }
    }

    /// Text of a file named on line `d`; IoError naming the file and the .avl line.
    std::string read_referenced(const fs::path& path, const Line& d,
                                std::string_view keyword) const {
        std::error_code ec;
        if (!fs::is_regular_file(path, ec))
            throw IoError(
                fmt::format("{}:{}: {}: cannot read '{}': no such file; expected a "
                            "file name relative to the folder of {}",
                            source_, d.number, keyword, path.string(), source_));
        try {
            return core::read_file(path);
        } catch (const IoError& e) {
            throw IoError(fmt::format("{}:{}: {}: {}", source_, d.number, keyword, e.what()));
        }
    }

    /// An optional name line, then "x y" pairs up to the first line that is not one (as AVL
    /// reads airfoil and body files). InputError if there are no pairs.
    static std::pair<std::string, std::vector<Eigen::Vector2d>> coordinate_pairs(
        std::string_view text, const fs::path& path) {
        const auto lines = significant_lines(text);
        std::string name;
        std::vector<Eigen::Vector2d> pts;
        for (std::size_t i = 0; i < lines.size(); ++i) {
            const auto v = leading_numbers(words(lines[i].text), 0, 2);
            if (v.size() < 2) {
                if (i == 0) {
                    name = lines[i].text;
                    continue;
                }
                break;
            }
            pts.emplace_back(v[0], v[1]);
        }
        if (pts.empty())
            throw InputError(fmt::format(
                "{}: has no coordinates; expected an optional name line, then lines 'x y'",
                path.string()));
        return {name, std::move(pts)};
    }

    void read_control(const Line& line) {
        auto& sec = in_section(line, "CONTROL");
        const Line& d = data_line(line, "CONTROL", "a line with name gain Xhinge XYZhvec SgnDup");
        const auto ws = words(d.text);
        constexpr std::string_view fields = "name gain Xhinge Xhvec Yhvec Zhvec SgnDup";
        if (to_number(ws.front()))
            fail(d.number, "CONTROL",
                 fmt::format("control name '{}' is a number; expected {}", ws.front(), fields));
        const auto v = numbers(d, "CONTROL", 0, 6, fields, 1);
        if (v.size() == 3 || v.size() == 4)
            fail(d.number, "CONTROL",
                 fmt::format("the hinge vector has {} of 3 components in '{}'; expected {}",
                             v.size() - 2, d.text, fields));
        SectionControl c;
        c.name = lower(ws.front());
        c.gain = v.size() > 0 ? within(v[0], -max_factor, max_factor, d, "CONTROL", "gain",
                                       "a deflection gain")
                              : 1.0;
        c.hinge_chord_fraction = v.size() > 1 ? v[1] : 0.0;
        if (!(std::abs(c.hinge_chord_fraction) <= 1.0))
            fail(d.number, "CONTROL",
                 fmt::format("Xhinge = {:g}; expected a chord fraction in [-1, 1] (negative: "
                             "leading-edge surface)",
                             c.hinge_chord_fraction));
        if (v.size() >= 5)
            c.hinge_axis = Eigen::Vector3d(length(v[2], d, "CONTROL", "Xhvec"),
                                           length(v[3], d, "CONTROL", "Yhvec"),
                                           length(v[4], d, "CONTROL", "Zhvec"));
        c.duplicate_sign = v.size() >= 6 ? within(v[5], -max_factor, max_factor, d, "CONTROL",
                                                  "SgnDup", "a deflection factor")
                                         : 1.0;
        sec.controls.push_back(std::move(c));
    }

    void finish_surface() {
        PendingSurface& s = *surface_;
        const std::size_t n = s.sections.size();
        if (n < 2)
            fail(s.line, "SURFACE",
                 fmt::format("'{}' has {} SECTION{}; expected at least 2", s.surface.name, n,
                             n == 1 ? "" : "s"));
        for (std::size_t i = 0; i + 1 < n; ++i) {
            const Section& sec = s.sections[i].section;
            if (s.surface.n_span == 0 && sec.n_span < 1)
                fail(s.sections[i].line, "SECTION",
                     fmt::format("no spanwise vortex count up to the next section of SURFACE "
                                 "'{}'; expected Nspan >= 1 on this SECTION or Nspan Sspace on "
                                 "the SURFACE line",
                                 s.surface.name));
            if (s.surface.n_span == 0 && !(std::abs(sec.span_spacing) <= 3.0))
                fail(s.sections[i].line, "SECTION",
                     fmt::format("Sspace = {:g}; expected a spacing parameter in [-3, 3]",
                                 sec.span_spacing));
        }
        s.surface.section_scale = s.scale;
        for (auto& p : s.sections) {
            Section sec = std::move(p.section);
            sec.leading_edge = s.scale.cwiseProduct(sec.leading_edge) + s.translate;
            sec.chord *= s.scale.x();
            sec.incidence += s.angle;
            // An explicit hinge vector is given in the section coordinates: scaled with them.
            for (SectionControl& c : sec.controls)
                c.hinge_axis = s.scale.cwiseProduct(c.hinge_axis);
            s.surface.sections.push_back(std::move(sec));
        }
        model_.surfaces.push_back(std::move(s.surface));
        surface_.reset();
    }

    // ----------------------------------------------------------------------------- bodies

    void start_body(const Line& line) {
        finish_block();
        PendingBody b;
        b.line = line.number;
        const Line& name = data_line(line, "BODY", "a line with the body name");
        b.body.name = name.text;
        const Line& d = data_line(name, "BODY", "a line with Nbody Bspace");
        const auto v = numbers(d, "BODY", 2, 2, "Nbody Bspace");
        if (integer(v[0], d, "BODY", "Nbody") < 2)
            fail(d.number, "BODY", fmt::format("Nbody = {:g}; expected at least 2 nodes", v[0]));
        (void)count(v[0], 2, max_spanwise, d, "BODY", "Nbody", "a node count");
        check_spacing(v[1], d, "BODY", "Bspace");
        body_ = std::move(b);
    }

    void read_bfile(const Line& line) {
        if (!body_) fail(line.number, "BFILE", "outside a BODY block; expected it after BODY");
        const Line& d = data_line(line, "BFILE", "a line with the body file name");
        const auto [name, rest] = file_name(d, "BFILE");
        const auto range = x_range(d, "BFILE", rest, 0);
        if (range && (range->first != 0.0 || range->second != 1.0))
            warn(d.number, "BFILE", "the x/c range is ignored; the whole outline is used");
        const fs::path path = resolve(name);
        const std::string text = read_referenced(path, d, "BFILE");
        try {
            check_coordinates_finite(text, path.string());
            body_->outline = coordinate_pairs(text, path).second;
        } catch (const InputError& e) {
            fail(d.number, "BFILE", e.what());
        }
        body_->outline_source =
            fmt::format("{} (BFILE at {}:{})", path.string(), source_, d.number);
        if (body_->outline.size() < 3)
            fail(d.number, "BFILE",
                 fmt::format("{} has {} points; expected a closed side-view outline of at least "
                             "3 points",
                             path.string(), body_->outline.size()));
    }

    /// Axis and equivalent radius from a side-view outline: at every x of the outline, the
    /// centre and half the height between its upper and lower branches.
    void finish_body() {
        PendingBody& b = *body_;
        if (b.outline.empty())
            fail(b.line, "BODY",
                 fmt::format("'{}' has no BFILE; expected a BFILE line naming its outline",
                             b.body.name));
        const auto [up, lo] = split_contour(b.outline);
        const auto monotone = [](const std::vector<Eigen::Vector2d>& p) {
            for (std::size_t i = 1; i < p.size(); ++i)
                if (p[i].x() < p[i - 1].x() - 1e-9 * (1.0 + std::abs(p[i].x()))) return false;
            return true;
        };
        if (up.size() < 2 || lo.size() < 2 || !monotone(up) || !monotone(lo))
            fail(b.line, "BODY",
                 fmt::format("the outline in {} is not a closed contour running from the tail "
                             "over the top to the nose and back below (or the reverse); "
                             "expected x to change monotonically on each side",
                             b.outline_source));
        const double x0 = up.front().x();
        const double x1 = std::min(up.back().x(), lo.back().x());
        std::vector<double> xs;
        for (const auto* side : {&up, &lo})
            for (const auto& p : *side)
                if (p.x() <= x1) xs.push_back(p.x());
        std::sort(xs.begin(), xs.end());
        const double tol = 1e-9 * std::max(1.0, x1 - x0);
        xs.erase(std::unique(xs.begin(), xs.end(),
                             [tol](double a, double c) { return std::abs(a - c) <= tol; }),
                 xs.end());
        if (xs.size() < 2 || !(x1 > x0))
            fail(b.line, "BODY",
                 fmt::format("the outline in {} has no length; expected points spread along x",
                             b.outline_source));
        const double radius_scale = std::sqrt(std::abs(b.scale.y() * b.scale.z()));
        for (double x : xs) {
            const double yu = interpolate(up, x), yl = interpolate(lo, x);
            b.body.axis.emplace_back(b.translate.x() + b.scale.x() * x, b.translate.y(),
                                     b.translate.z() + b.scale.z() * 0.5 * (yu + yl));
            b.body.radius.push_back(radius_scale * 0.5 * std::abs(yu - yl));
        }
        model_.bodies.push_back(std::move(b.body));
        body_.reset();
    }

    void finish_block() {
        if (surface_) finish_surface();
        if (body_) finish_body();
    }
};

}  // namespace

Model parse_avl(std::string_view text, const std::string& source,
                const std::filesystem::path& base_dir, std::vector<std::string>& warnings) {
    return Reader(text, source, base_dir, warnings).read();
}

Model parse_avl(std::string_view text, const std::string& source,
                const std::filesystem::path& base_dir) {
    std::vector<std::string> warnings;
    Model m = parse_avl(text, source, base_dir, warnings);
    for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    return m;
}

Model read_avl(const std::filesystem::path& file, std::vector<std::string>& warnings) {
    const std::string text = core::read_file(file);
    return parse_avl(text, file.string(), file.parent_path(), warnings);
}

Model read_avl(const std::filesystem::path& file) {
    std::vector<std::string> warnings;
    Model m = read_avl(file, warnings);
    for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    return m;
}

}  // namespace manta::vlm
