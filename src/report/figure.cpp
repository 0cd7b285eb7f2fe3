/// @file figure.cpp
/// Figure model: colours, JSON, standalone SVG and CSV. The page's JavaScript renderer
/// (assets.cpp) uses the same layout constants, so a figure looks the same in both.

#include "manta/report/figure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "manta/core/frames.hpp"
#include "manta/report/html.hpp"

namespace manta::report {

namespace {

// Layout shared with the JavaScript renderer (assets.cpp): panel size and margins [px].
constexpr double panel_w = 340, panel_h = 220;
constexpr double margin_l = 64, margin_r = 14, margin_t = 26, margin_b = 42;
constexpr double title_h = 30, legend_row_h = 20;
constexpr double pi = 3.14159265358979323846;

double round7(double v) {
    if (!std::isfinite(v) || v == 0.0) return v;
    return std::stod(fmt::format("{:.7g}", v));
}

nlohmann::json rounded(const std::vector<double>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (const double x : v) a.push_back(round7(x));
    return a;
}

const char* style_name(SeriesStyle s) {
    switch (s) {
        case SeriesStyle::line:
            return "line";
        case SeriesStyle::dashed:
            return "dashed";
        case SeriesStyle::markers:
            return "markers";
        case SeriesStyle::squares:
            return "squares";
        case SeriesStyle::band:
            return "band";
    }
    return "line";
}

/// Tick label text: enough decimals for the step, exponent form for very large or small values.
std::string tick_text(double v, double step) {
    if (std::abs(v) < step * 1e-9) v = 0.0;
    const double mag = std::max(std::abs(v), step);
    if (mag >= 1e6 || step < 1e-4) return v == 0.0 ? std::string("0") : fmt::format("{:.3g}", v);
    const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
    return fmt::format("{:.{}f}", v, decimals);
}

struct Range {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    void add(double v) {
        if (!std::isfinite(v)) return;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    void finish(double pad) {
        if (!(lo <= hi)) {
            lo = 0.0;
            hi = 1.0;
        }
        if (hi - lo <= 1e-12 * std::max(1.0, std::abs(hi))) {
            const double d = std::max(std::abs(hi) * 0.1, 1e-6);
            lo -= d;
            hi += d;
        }
        const double d = (hi - lo) * pad;
        lo -= d;
        hi += d;
    }
};

std::string svg_panel(const Panel& p, double ox, double oy) {
    std::string s;
    const double x0 = ox + margin_l, x1 = ox + panel_w - margin_r;
    const double y0 = oy + margin_t, y1 = oy + panel_h - margin_b;
    Range rx, ry;
    for (const auto& se : p.series) {
        for (const double v : se.x) rx.add(v);
        for (const double v : se.y) ry.add(v);
        for (const double v : se.y_upper) ry.add(v);
    }
    rx.finish(0.0);
    ry.finish(0.06);
    auto X = [&](double v) { return x0 + (v - rx.lo) / (rx.hi - rx.lo) * (x1 - x0); };
    auto Y = [&](double v) { return y1 - (v - ry.lo) / (ry.hi - ry.lo) * (y1 - y0); };
    s += fmt::format(
        R"(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="#fff" stroke="#999"/>)",
        x0, y0, x1 - x0, y1 - y0);
    s += '\n';
    for (const auto& sh : p.shades) {
        const double a = X(std::clamp(sh.x0, rx.lo, rx.hi)), b = X(std::clamp(sh.x1, rx.lo, rx.hi));
        s += fmt::format(
            R"(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="{}" fill-opacity="0.28"><title>{}</title></rect>)",
            a, y0, std::max(b - a, 1.0), y1 - y0, colour_of("flag"), escape_html(sh.label));
        s += '\n';
    }
    const auto xt = nice_ticks(rx.lo, rx.hi), yt = nice_ticks(ry.lo, ry.hi);
    const double xs = xt.size() > 1 ? xt[1] - xt[0] : 1.0, ys = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
    for (const double v : xt) {
        s += fmt::format(
            R"(<line x1="{0:.1f}" y1="{1:.1f}" x2="{0:.1f}" y2="{2:.1f}" stroke="#e4e4e4"/><text x="{0:.1f}" y="{3:.1f}" text-anchor="middle" class="tick">{4}</text>)",
            X(v), y0, y1, y1 + 14, tick_text(v, xs));
        s += '\n';
    }
    for (const double v : yt) {
        s += fmt::format(
            R"(<line x1="{0:.1f}" y1="{1:.1f}" x2="{2:.1f}" y2="{1:.1f}" stroke="#e4e4e4"/><text x="{3:.1f}" y="{4:.1f}" text-anchor="end" class="tick">{5}</text>)",
            x0, Y(v), x1, x0 - 4, Y(v) + 4, tick_text(v, ys));
        s += '\n';
    }
    s += fmt::format(
        R"~(<clipPath id="c{0}_{1}"><rect x="{2:.1f}" y="{3:.1f}" width="{4:.1f}" height="{5:.1f}"/></clipPath><g clip-path="url(#c{0}_{1})">)~",
        static_cast<int>(ox), static_cast<int>(oy), x0, y0, x1 - x0, y1 - y0);
    s += '\n';
    for (const auto& se : p.series) {
        if (se.style == SeriesStyle::band) {
            std::string pts;
            for (std::size_t i = 0; i < se.x.size(); ++i)
                pts += fmt::format("{:.2f},{:.2f} ", X(se.x[i]), Y(se.y_upper[i]));
            for (std::size_t i = se.x.size(); i-- > 0;)
                pts += fmt::format("{:.2f},{:.2f} ", X(se.x[i]), Y(se.y[i]));
            s += fmt::format(R"(<polygon points="{}" fill="{}" fill-opacity="{}" stroke="none"/>)",
                             pts, se.colour, se.opacity);
        } else if (se.style == SeriesStyle::markers) {
            for (std::size_t i = 0; i < se.x.size(); ++i)
                s += fmt::format(
                    R"(<circle cx="{:.2f}" cy="{:.2f}" r="3" fill="none" stroke="{}" stroke-width="1.2"/>)",
                    X(se.x[i]), Y(se.y[i]), se.colour);
        } else if (se.style == SeriesStyle::squares) {
            for (std::size_t i = 0; i < se.x.size(); ++i)
                s += fmt::format(
                    R"(<rect x="{:.2f}" y="{:.2f}" width="6" height="6" fill="none" stroke="{}" stroke-width="1.2"/>)",
                    X(se.x[i]) - 3, Y(se.y[i]) - 3, se.colour);
        } else {
            std::string pts;
            for (std::size_t i = 0; i < se.x.size(); ++i)
                pts += fmt::format("{:.2f},{:.2f} ", X(se.x[i]), Y(se.y[i]));
            s += fmt::format(
                R"(<polyline points="{}" fill="none" stroke="{}" stroke-width="1.6"{}/>)", pts,
                se.colour, se.style == SeriesStyle::dashed ? R"( stroke-dasharray="5,4")" : "");
        }
        s += '\n';
    }
    s += "</g>\n";
    s += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" text-anchor="middle" class="label">{}</text>)",
                     (x0 + x1) / 2, y1 + 32, escape_html(p.x_label));
    s += fmt::format(
        R"~(<text transform="translate({:.1f},{:.1f}) rotate(-90)" text-anchor="middle" class="label">{}</text>)~",
        ox + 14, (y0 + y1) / 2, escape_html(p.y_label));
    s += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" text-anchor="middle" class="ptitle">{}</text>)",
                     (x0 + x1) / 2, oy + 17, escape_html(p.title));
    s += '\n';
    return s;
}

/// Legend entries of a figure: each (name, colour, style) once, in order of appearance.
std::vector<const Series*> legend_entries(const Figure& f) {
    std::vector<const Series*> out;
    for (const auto& p : f.panels)
        for (const auto& s : p.series)
            if (s.legend && std::none_of(out.begin(), out.end(), [&](const Series* o) {
                    return o->name == s.name && o->colour == s.colour && o->style == s.style;
                }))
                out.push_back(&s);
    return out;
}

const char* svg_style =
    "<style>text{font-family:Helvetica,Arial,sans-serif;fill:#222}.tick{font-size:11px}"
    ".label{font-size:12px}.ptitle{font-size:12px;font-weight:bold}.title{font-size:15px;"
    "font-weight:bold}.legend{font-size:12px}</style>\n";

std::string csv_text(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

}  // namespace

std::string colour_of(const std::string& key) {
    static const std::map<std::string, std::string> colours{
        {"table", "#1f77b4"},
        {"replay", "#d62728"},
        {"samples", "#111111"},
        {"difference", "#9467bd"},
        {"tolerance", "#7f7f7f"},
        {"flag", "#ffb000"},
        {"nodes", "#111111"},
        {"V", "#1f77b4"},
        {"altitude", "#8c564b"},
        {"alpha", "#d62728"},
        {"beta", "#ff7f0e"},
        {"phi", "#2ca02c"},
        {"theta", "#17becf"},
        {"psi", "#bcbd22"},
        {"p", "#2ca02c"},
        {"q", "#17becf"},
        {"r", "#bcbd22"},
        {"nz", "#e377c2"},
        {"elevator", "#9467bd"},
        {"aileron", "#8c564b"},
        {"rudder", "#e377c2"},
        {"throttle", "#7f7f7f"},
        {"mach", "#1f77b4"},
        {"path", "#1f77b4"},
        {"delta_min", "#2ca02c"},
        {"delta_max", "#ff7f0e"},
        {"compare", "#c2185b"},
        {"compare_min", "#6a3d9a"},
        {"compare_max", "#c2185b"},
        {"replay_other", "#2ca02c"},
        {"replay_other2", "#ff7f0e"},
    };
    const auto it = colours.find(key);
    return it == colours.end() ? std::string("#7f7f7f") : it->second;
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
    std::vector<double> t;
    if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return t;
    const double raw = (hi - lo) / std::max(target, 1);
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double r = raw / mag;
    const double step = (r < 1.5 ? 1.0 : r < 3.5 ? 2.0 : r < 7.5 ? 5.0 : 10.0) * mag;
    for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step)
        t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
    return t;
}

nlohmann::json to_json(const Figure& f) {
    nlohmann::json j{{"id", f.id}, {"title", f.title}, {"columns", f.columns}, {"kind", "xy"}};
    j["panels"] = nlohmann::json::array();
    for (const auto& p : f.panels) {
        nlohmann::json jp{{"title", p.title}, {"x", p.x_label}, {"y", p.y_label}};
        jp["series"] = nlohmann::json::array();
        for (const auto& s : p.series) {
            nlohmann::json js{{"name", s.name},
                              {"colour", s.colour},
                              {"style", style_name(s.style)},
                              {"x", rounded(s.x)},
                              {"y", rounded(s.y)}};
            if (s.style == SeriesStyle::band) {
                js["y_upper"] = rounded(s.y_upper);
                js["opacity"] = s.opacity;
            }
            if (!s.legend) js["legend"] = false;
            jp["series"].push_back(std::move(js));
        }
        jp["shades"] = nlohmann::json::array();
        for (const auto& sh : p.shades)
            jp["shades"].push_back(
                {{"x0", round7(sh.x0)}, {"x1", round7(sh.x1)}, {"label", sh.label}});
        j["panels"].push_back(std::move(jp));
    }
    return j;
}

nlohmann::json to_json(const FlightPath& p) {
    nlohmann::json j{{"id", p.id},
                     {"title", p.title},
                     {"kind", "path3d"},
                     {"t", rounded(p.t)},
                     {"north", rounded(p.north)},
                     {"east", rounded(p.east)},
                     {"altitude", rounded(p.altitude)},
                     {"phi", rounded(p.phi)},
                     {"theta", rounded(p.theta)},
                     {"psi", rounded(p.psi)},
                     {"glyphs", p.glyphs},
                     {"glyph_scale", round7(p.glyph_scale)},
                     {"colour", colour_of("path")}};
    j["segments"] = nlohmann::json::array();
    for (const auto& s : p.body_segments) {
        nlohmann::json a = nlohmann::json::array();
        for (const double v : s) a.push_back(round7(v));
        j["segments"].push_back(std::move(a));
    }
    return j;
}

std::string to_svg(const Figure& f) {
    const int cols = std::max(1, std::min<int>(f.columns, static_cast<int>(f.panels.size())));
    const int rows = static_cast<int>((f.panels.size() + cols - 1) / cols);
    const double width = cols * panel_w;
    // Legend: entries laid out left to right, wrapped.
    std::string legend;
    double lx = 10, ly = title_h + 14;
    for (const Series* s : legend_entries(f)) {
        const double w = 34 + 7.0 * static_cast<double>(s->name.size());
        if (lx + w > width && lx > 10) {
            lx = 10;
            ly += legend_row_h;
        }
        if (s->style == SeriesStyle::band)
            legend += fmt::format(
                R"(<rect x="{:.1f}" y="{:.1f}" width="22" height="10" fill="{}" fill-opacity="{}"/>)",
                lx, ly - 9, s->colour, std::min(1.0, s->opacity + 0.05));
        else if (s->style == SeriesStyle::markers)
            legend += fmt::format(
                R"(<circle cx="{:.1f}" cy="{:.1f}" r="3" fill="none" stroke="{}" stroke-width="1.2"/>)",
                lx + 11, ly - 4, s->colour);
        else if (s->style == SeriesStyle::squares)
            legend += fmt::format(
                R"(<rect x="{:.1f}" y="{:.1f}" width="6" height="6" fill="none" stroke="{}" stroke-width="1.2"/>)",
                lx + 8, ly - 7, s->colour);
        else
            legend += fmt::format(
                R"(<line x1="{:.1f}" y1="{:.1f}" x2="{:.1f}" y2="{:.1f}" stroke="{}" stroke-width="2"{}/>)",
                lx, ly - 4, lx + 22, ly - 4, s->colour,
                s->style == SeriesStyle::dashed ? R"( stroke-dasharray="5,4")" : "");
        legend += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" class="legend">{}</text>)", lx + 27,
                              ly, escape_html(s->name));
        legend += '\n';
        lx += w;
    }
    const double top = legend.empty() ? title_h : ly + 10;  // no legend row without entries
    const double height = top + rows * panel_h;
    std::string s = fmt::format(
        R"(<svg xmlns="http://www.w3.org/2000/svg" width="{0:.0f}" height="{1:.0f}" viewBox="0 0 {0:.0f} {1:.0f}">)",
        width, height);
    s += '\n';
    s += svg_style;
    s += fmt::format(
        R"(<rect width="100%" height="100%" fill="#fff"/><text x="10" y="20" class="title">{}</text>)",
        escape_html(f.title));
    s += '\n' + legend;
    for (std::size_t i = 0; i < f.panels.size(); ++i)
        s += svg_panel(f.panels[i], static_cast<double>(i % cols) * panel_w,
                       top + static_cast<double>(i / cols) * panel_h);
    s += "</svg>\n";
    return s;
}

std::string to_svg(const FlightPath& p) {
    const double w = 760, h = 560;
    const double az = -60.0 * pi / 180.0, el = 25.0 * pi / 180.0;
    Range re, rn, rh;
    for (std::size_t i = 0; i < p.t.size(); ++i) {
        re.add(p.east[i]);
        rn.add(p.north[i]);
        rh.add(p.altitude[i]);
    }
    re.finish(0.05);
    rn.finish(0.05);
    rh.finish(0.05);
    // A box of comparable sides (each at least 40 % of the largest), so a flat manoeuvre still
    // reads as 3-D and the ticks of a short axis do not pile up.
    const double largest = std::max({re.hi - re.lo, rn.hi - rn.lo, rh.hi - rh.lo});
    for (Range* r : {&re, &rn, &rh}) {
        const double grow = std::max(0.0, 0.4 * largest - (r->hi - r->lo)) / 2;
        r->lo -= grow;
        r->hi += grow;
    }
    const double ce = (re.lo + re.hi) / 2, cn = (rn.lo + rn.hi) / 2, ch = (rh.lo + rh.hi) / 2;
    const double extent = std::max({re.hi - re.lo, rn.hi - rn.lo, rh.hi - rh.lo});
    const double scale = 0.75 * std::min(w, h) / extent;
    auto proj = [&](double e, double n, double a) {
        const double x1 = std::cos(az) * (e - ce) + std::sin(az) * (n - cn);
        const double y1 = -std::sin(az) * (e - ce) + std::cos(az) * (n - cn);
        const double sy = std::sin(el) * y1 + std::cos(el) * (a - ch);
        return std::array<double, 2>{w / 2 + scale * x1, h / 2 + 20 - scale * sy};
    };
    std::string s = fmt::format(
        R"(<svg xmlns="http://www.w3.org/2000/svg" width="{0:.0f}" height="{1:.0f}" viewBox="0 0 {0:.0f} {1:.0f}">)",
        w, h);
    s += '\n';
    s += svg_style;
    s += fmt::format(
        R"(<rect width="100%" height="100%" fill="#fff"/><text x="10" y="20" class="title">{}</text>)",
        escape_html(p.title));
    s += '\n';
    // Axes along the box edges from the corner (east min, north min, altitude min).
    // Tick labels: east to the right of its axis, north and altitude to the left, so the three
    // sets do not overlap at the common corner.
    constexpr double label_dx[3] = {6, -4, -6}, label_dy[3] = {12, 14, 4};
    auto axis = [&](int k, const Range& r, const std::string& label) {
        for (const double v : nice_ticks(r.lo, r.hi, 4)) {
            const double e = k == 0 ? v : re.lo, n = k == 1 ? v : rn.lo, a = k == 2 ? v : rh.lo;
            const auto q = proj(e, n, a);
            s += fmt::format(
                R"(<circle cx="{:.1f}" cy="{:.1f}" r="1.5" fill="#555"/><text x="{:.1f}" y="{:.1f}" class="tick" text-anchor="{}">{:.0f}</text>)",
                q[0], q[1], q[0] + label_dx[k], q[1] + label_dy[k], k == 0 ? "start" : "end", v);
        }
        const auto a0 = proj(re.lo, rn.lo, rh.lo);
        const auto a1 =
            proj(k == 0 ? re.hi : re.lo, k == 1 ? rn.hi : rn.lo, k == 2 ? rh.hi : rh.lo);
        s += fmt::format(
            R"(<line x1="{:.1f}" y1="{:.1f}" x2="{:.1f}" y2="{:.1f}" stroke="#555"/><text x="{:.1f}" y="{:.1f}" class="label">{}</text>)",
            a0[0], a0[1], a1[0], a1[1], a1[0] + 6, a1[1] - 4, label);
        s += '\n';
    };
    axis(0, re, "east [m]");
    axis(1, rn, "north [m]");
    axis(2, rh, "altitude [m]");
    std::string track, path;
    for (std::size_t i = 0; i < p.t.size(); ++i) {
        const auto g = proj(p.east[i], p.north[i], rh.lo);
        const auto q = proj(p.east[i], p.north[i], p.altitude[i]);
        track += fmt::format("{:.1f},{:.1f} ", g[0], g[1]);
        path += fmt::format("{:.1f},{:.1f} ", q[0], q[1]);
    }
    s += fmt::format(
        R"(<polyline points="{}" fill="none" stroke="#bbb" stroke-width="1" stroke-dasharray="3,3"/>)",
        track);
    s += fmt::format(R"(<polyline points="{}" fill="none" stroke="{}" stroke-width="2"/>)", path,
                     colour_of("path"));
    s += '\n';
    for (const std::size_t i : p.glyphs) {
        // Body to earth (NED).
        const Eigen::Matrix3d R = core::dcm_earth_from_body(p.phi[i], p.theta[i], p.psi[i]);
        auto earth = [&](double bx, double by, double bz) {
            const double n = R(0, 0) * bx + R(0, 1) * by + R(0, 2) * bz;
            const double e = R(1, 0) * bx + R(1, 1) * by + R(1, 2) * bz;
            const double d = R(2, 0) * bx + R(2, 1) * by + R(2, 2) * bz;
            return proj(p.east[i] + p.glyph_scale * e, p.north[i] + p.glyph_scale * n,
                        p.altitude[i] - p.glyph_scale * d);
        };
        for (const auto& seg : p.body_segments) {
            const auto a = earth(seg[0], seg[1], seg[2]);
            const auto b = earth(seg[3], seg[4], seg[5]);
            s += fmt::format(
                R"(<line x1="{:.1f}" y1="{:.1f}" x2="{:.1f}" y2="{:.1f}" stroke="#333" stroke-width="0.8"/>)",
                a[0], a[1], b[0], b[1]);
        }
        s += '\n';
    }
    s += fmt::format(
        R"(<text x="10" y="{:.0f}" class="legend">aircraft drawn {:.0f}:1 at {} instants; view azimuth -60 deg, elevation 25 deg; dashed: ground track</text>)",
        h - 10, p.glyph_scale, p.glyphs.size());
    s += "\n</svg>\n";
    return s;
}

std::string to_csv(const Figure& f) {
    std::string s = fmt::format("# figure: {}\n", f.title);
    for (std::size_t i = 0; i < f.panels.size(); ++i)
        s += fmt::format("# panel {}: {}; x: {}; y: {}\n", i, f.panels[i].title,
                         f.panels[i].x_label, f.panels[i].y_label);
    s += "panel,series,x,y,y_upper\n";
    for (std::size_t i = 0; i < f.panels.size(); ++i)
        for (const auto& se : f.panels[i].series)
            for (std::size_t k = 0; k < se.x.size(); ++k)
                s += fmt::format("{},{},{},{},{}\n", i, csv_text(se.name), se.x[k], se.y[k],
                                 se.style == SeriesStyle::band ? fmt::format("{}", se.y_upper[k])
                                                               : std::string());
    return s;
}

std::string to_csv(const FlightPath& p) {
    std::string s = fmt::format("# flight path: {} (earth axes; altitude = -z)\n", p.title);
    s += "t,north,east,altitude,phi,theta,psi\n";
    for (std::size_t i = 0; i < p.t.size(); ++i)
        s += fmt::format("{},{},{},{},{},{},{}\n", p.t[i], p.north[i], p.east[i], p.altitude[i],
                         p.phi[i], p.theta[i], p.psi[i]);
    return s;
}

}  // namespace manta::report
