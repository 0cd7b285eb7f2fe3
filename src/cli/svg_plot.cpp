#include "svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "manta/core/frames.hpp"

namespace manta::cli {

namespace {

// "Nice" tick step of about n intervals over [lo, hi].
double nice_step(double lo, double hi, int n) {
    const double raw = (hi - lo) / n;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double f = raw / mag;
    const double nice = f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0;
    return nice * mag;
}

std::string num(double v) {
    if (std::abs(v) < 1e-12) return "0";
    return fmt::format("{:g}", v);
}

// Widen a flat y range and add a 6 % margin above and below.
void pad_range(double& lo, double& hi) {
    if (hi - lo < 1e-9 * std::max(1.0, std::abs(hi))) {
        lo -= std::max(1e-3, 0.05 * std::abs(lo));
        hi += std::max(1e-3, 0.05 * std::abs(hi));
    }
    const double pad = 0.06 * (hi - lo);
    lo -= pad;
    hi += pad;
}

// A panel's frame and its horizontal grid lines with y tick labels; Y maps a value to pixels.
template <class YMap>
std::string frame_and_y_grid(int x0, int x1, int y0, int y1, double lo, double hi, const YMap& Y) {
    std::string s = fmt::format(
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444\"/>\n", x0,
        y0, x1 - x0, y1 - y0);
    const double ys = nice_step(lo, hi, 4);
    for (double v = std::ceil(lo / ys) * ys; v <= hi; v += ys) {
        s += fmt::format(
            "<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>"
            "<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n",
            x0, x1, Y(v), Y(v), x0 - 4, Y(v) + 4, num(v));
    }
    return s;
}

}  // namespace

std::string svg_time_histories(const std::string& title, const std::string& x_label,
                               const std::vector<double>& t, const std::vector<Panel>& panels,
                               int columns) {
    const int pw = 420, ph = 190, ml = 62, mr = 14, mt = 26, mb = 40;
    const int rows = static_cast<int>((panels.size() + columns - 1) / columns);
    const int W = columns * pw, H = rows * ph + 34;
    std::string s = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} "
        "{}\" "
        "font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" "
        "fill=\"white\"/>\n"
        "<text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"14\" "
        "font-weight=\"bold\">{}</text>\n",
        W, H, W, H, W / 2, title);
    if (t.empty()) return s + "</svg>\n";
    const double t0 = t.front(), t1 = std::max(t.back(), t.front() + 1e-9);
    for (std::size_t k = 0; k < panels.size(); ++k) {
        const auto& p = panels[k];
        const int ox = static_cast<int>(k % columns) * pw,
                  oy = 34 + static_cast<int>(k / columns) * ph;
        const int x0 = ox + ml, x1 = ox + pw - mr, y0 = oy + mt, y1 = oy + ph - mb;
        double lo = *std::min_element(p.y.begin(), p.y.end()),
               hi = *std::max_element(p.y.begin(), p.y.end());
        pad_range(lo, hi);
        auto X = [&](double v) { return x0 + (v - t0) / (t1 - t0) * (x1 - x0); };
        auto Y = [&](double v) { return y1 - (v - lo) / (hi - lo) * (y1 - y0); };
        s += frame_and_y_grid(x0, x1, y0, y1, lo, hi, Y);
        const double xs = nice_step(t0, t1, 6);
        for (double v = std::ceil(t0 / xs) * xs; v <= t1 + 1e-9; v += xs) {
            s += fmt::format(
                "<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{}\" y2=\"{}\" stroke=\"#eee\"/>"
                "<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
                X(v), X(v), y0, y1, X(v), y1 + 14, num(v));
        }
        s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
                         (x0 + x1) / 2, y1 + 30, x_label);
        s += fmt::format(
            "<text transform=\"translate({},{}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
            ox + 14, (y0 + y1) / 2, p.label);
        s += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" points=\"",
                         p.colour);
        const std::size_t n = std::min(t.size(), p.y.size());
        const std::size_t stride = std::max<std::size_t>(1, n / 800);
        for (std::size_t i = 0; i < n; i += stride)
            s += fmt::format("{:.1f},{:.1f} ", X(t[i]), Y(p.y[i]));
        s += "\"/>\n";
    }
    return s + "</svg>\n";
}

std::string svg_xy_panels(const std::string& title, const std::string& x_label,
                          const std::vector<XyPanel>& panels, int columns) {
    const int pw = 380, ph = 230, ml = 66, mr = 14, mt = 20, mb = 40, head = 52;
    columns = std::max(1, columns);
    const int rows = static_cast<int>((panels.size() + columns - 1) / columns);
    const int W = columns * pw, H = rows * ph + head;
    std::string s = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} "
        "{}\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" "
        "height=\"100%\" fill=\"white\"/>\n<text x=\"{}\" y=\"18\" text-anchor=\"middle\" "
        "font-size=\"14\" font-weight=\"bold\">{}</text>\n",
        W, H, W, H, W / 2, title);
    // Legend from the first panel.
    if (!panels.empty()) {
        int lx = 20;
        for (const auto& c : panels.front().curves) {
            s += fmt::format(
                "<line x1=\"{}\" x2=\"{}\" y1=\"36\" y2=\"36\" stroke=\"{}\" stroke-width=\"2\"/>"
                "<text x=\"{}\" y=\"40\">{}</text>\n",
                lx, lx + 20, c.colour, lx + 24, c.label);
            lx += 34 + 6 * static_cast<int>(c.label.size());
        }
        for (const auto& p : panels.front().points) {
            s += fmt::format(
                "<circle cx=\"{}\" cy=\"36\" r=\"3.5\" fill=\"{}\"/><text x=\"{}\" "
                "y=\"40\">{}</text>\n",
                lx + 6, p.colour, lx + 14, p.label);
            lx += 24 + 6 * static_cast<int>(p.label.size());
        }
    }
    for (std::size_t k = 0; k < panels.size(); ++k) {
        const XyPanel& p = panels[k];
        const int ox = static_cast<int>(k % static_cast<std::size_t>(columns)) * pw,
                  oy = head + static_cast<int>(k / static_cast<std::size_t>(columns)) * ph;
        const int x0 = ox + ml, x1 = ox + pw - mr, y0 = oy + mt, y1 = oy + ph - mb;
        double xlo = 1e300, xhi = -1e300, lo = 1e300, hi = -1e300;
        auto take = [&](const std::vector<double>& xs, const std::vector<double>& ys) {
            for (std::size_t i = 0; i < std::min(xs.size(), ys.size()); ++i) {
                if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) continue;
                xlo = std::min(xlo, xs[i]);
                xhi = std::max(xhi, xs[i]);
                lo = std::min(lo, ys[i]);
                hi = std::max(hi, ys[i]);
            }
        };
        for (const auto& c : p.curves) {
            take(c.x, c.y);
            take(c.x, c.band_lo);
            take(c.x, c.band_hi);
        }
        for (const auto& q : p.points) take(q.x, q.y);
        if (xlo > xhi) continue;
        if (xhi - xlo < 1e-12) xhi = xlo + 1.0;
        pad_range(lo, hi);
        auto X = [&](double v) { return x0 + (v - xlo) / (xhi - xlo) * (x1 - x0); };
        auto Y = [&](double v) { return y1 - (v - lo) / (hi - lo) * (y1 - y0); };
        s += frame_and_y_grid(x0, x1, y0, y1, lo, hi, Y);
        const double xs = nice_step(xlo, xhi, 6);
        for (double v = std::ceil(xlo / xs) * xs; v <= xhi + 1e-9; v += xs)
            s += fmt::format(
                "<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{}\" y2=\"{}\" stroke=\"#eee\"/>"
                "<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
                X(v), X(v), y0, y1, X(v), y1 + 14, num(v));
        s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
                         (x0 + x1) / 2, y1 + 30, x_label);
        s += fmt::format(
            "<text transform=\"translate({},{}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
            ox + 14, (y0 + y1) / 2, p.y_label);
        for (const auto& c : p.curves) {
            if (!c.band_lo.empty() && c.band_lo.size() == c.x.size() &&
                c.band_hi.size() == c.x.size()) {
                s += fmt::format(
                    "<polygon fill=\"{}\" fill-opacity=\"0.2\" stroke=\"none\" points=\"",
                    c.colour);
                for (std::size_t i = 0; i < c.x.size(); ++i)
                    s += fmt::format("{:.1f},{:.1f} ", X(c.x[i]), Y(c.band_hi[i]));
                for (std::size_t i = c.x.size(); i-- > 0;)
                    s += fmt::format("{:.1f},{:.1f} ", X(c.x[i]), Y(c.band_lo[i]));
                s += "\"/>\n";
            }
            s += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" points=\"",
                             c.colour);
            for (std::size_t i = 0; i < std::min(c.x.size(), c.y.size()); ++i)
                s += fmt::format("{:.1f},{:.1f} ", X(c.x[i]), Y(c.y[i]));
            s += "\"/>\n";
        }
        for (const auto& q : p.points)
            for (std::size_t i = 0; i < std::min(q.x.size(), q.y.size()); ++i)
                s += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"{}\"/>\n",
                                 X(q.x[i]), Y(q.y[i]), q.colour);
    }
    return s + "</svg>\n";
}

namespace {

/// A point in the plot's world axes: e east, n north, h up [m].
struct World {
    double e = 0.0, n = 0.0, h = 0.0;
};

/// Oblique view: azimuth `az` about the vertical (from the east axis), elevation `el` above
/// the horizon; returns screen coordinates before scaling (right, up).
struct View {
    double ca, sa, ce, se;
    View(double az, double el)
        : ca(std::cos(az)), sa(std::sin(az)), ce(std::cos(el)), se(std::sin(el)) {}
    [[nodiscard]] std::pair<double, double> operator()(const World& w) const {
        const double right = w.e * ca - w.n * sa;
        const double depth = w.e * sa + w.n * ca;
        return {right, w.h * ce + depth * se};
    }
};

}  // namespace

std::string svg_flight_path_3d(const std::string& title, const FlightPath3d& fp) {
    const int W = 820, H = 640;
    std::string s = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} "
        "{}\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" "
        "height=\"100%\" fill=\"white\"/>\n<text x=\"{}\" y=\"20\" text-anchor=\"middle\" "
        "font-size=\"14\" font-weight=\"bold\">{}</text>\n",
        W, H, W, H, W / 2, title);
    const std::size_t n = fp.north.size();
    if (n < 2 || fp.east.size() != n || fp.altitude.size() != n) return s + "</svg>\n";
    auto range = [](const std::vector<double>& v, double& lo, double& hi) {
        lo = *std::min_element(v.begin(), v.end());
        hi = *std::max_element(v.begin(), v.end());
        pad_range(lo, hi);
    };
    double n0, n1, e0, e1, h0, h1;
    range(fp.north, n0, n1);
    range(fp.east, e0, e1);
    range(fp.altitude, h0, h1);
    // equal scale on every axis: widen the smaller extents of the horizontal axes to at least a
    // quarter of the largest, so that a flat manoeuvre still shows as a volume
    const double big = std::max({n1 - n0, e1 - e0, h1 - h0});
    auto widen = [&](double& lo, double& hi) {
        const double want = 0.25 * big;
        if (hi - lo < want) {
            const double c = 0.5 * (lo + hi);
            lo = c - 0.5 * want;
            hi = c + 0.5 * want;
        }
    };
    widen(n0, n1);
    widen(e0, e1);
    widen(h0, h1);
    const View view(-0.55, 0.45);
    // the box corners fix the screen scale
    double sx0 = 1e300, sx1 = -1e300, sy0 = 1e300, sy1 = -1e300;
    for (const double e : {e0, e1}) {
        for (const double nn : {n0, n1}) {
            for (const double h : {h0, h1}) {
                const auto [x, y] = view({e, nn, h});
                sx0 = std::min(sx0, x);
                sx1 = std::max(sx1, x);
                sy0 = std::min(sy0, y);
                sy1 = std::max(sy1, y);
            }
        }
    }
    const double ml = 90, mr = 90, mt = 50, mb = 70;
    const double scale = std::min((W - ml - mr) / (sx1 - sx0), (H - mt - mb) / (sy1 - sy0));
    const double ox = ml + 0.5 * ((W - ml - mr) - scale * (sx1 - sx0));
    const double oy = mt + 0.5 * ((H - mt - mb) - scale * (sy1 - sy0));
    auto P = [&](const World& w) {
        const auto [x, y] = view(w);
        return std::pair<double, double>{ox + (x - sx0) * scale, oy + (sy1 - y) * scale};
    };
    auto line = [&](const World& a, const World& b, const char* style) {
        const auto [x1, y1] = P(a);
        const auto [x2, y2] = P(b);
        return fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" {}/>\n",
                           x1, y1, x2, y2, style);
    };
    // floor grid and the three back walls' edges
    const char* grid = "stroke=\"#e2e2e2\"";
    const char* edge = "stroke=\"#666\"";
    const double es = nice_step(e0, e1, 4), ns = nice_step(n0, n1, 4), hs = nice_step(h0, h1, 4);
    for (double v = std::ceil(e0 / es) * es; v <= e1; v += es)
        s += line({v, n0, h0}, {v, n1, h0}, grid);
    for (double v = std::ceil(n0 / ns) * ns; v <= n1; v += ns)
        s += line({e0, v, h0}, {e1, v, h0}, grid);
    for (double v = std::ceil(h0 / hs) * hs; v <= h1; v += hs) {
        s += line({e0, n1, v}, {e1, n1, v}, grid);
        s += line({e0, n0, v}, {e0, n1, v}, grid);
    }
    s += line({e0, n0, h0}, {e1, n0, h0}, edge);
    s += line({e0, n0, h0}, {e0, n1, h0}, edge);
    s += line({e0, n0, h0}, {e0, n0, h1}, edge);
    s += line({e1, n0, h0}, {e1, n1, h0}, edge);
    s += line({e0, n1, h0}, {e1, n1, h0}, edge);
    s += line({e0, n1, h0}, {e0, n1, h1}, edge);
    // tick labels: east along the front floor edge, north along the right floor edge,
    // altitude up the left front edge
    for (double v = std::ceil(e0 / es) * es; v <= e1; v += es) {
        const auto [x, y] = P({v, n0, h0});
        s += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>\n", x,
                         y + 16, num(v));
    }
    for (double v = std::ceil(n0 / ns) * ns; v <= n1; v += ns) {
        const auto [x, y] = P({e1, v, h0});
        s += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"start\">{}</text>\n", x + 6,
                         y + 4, num(v));
    }
    for (double v = std::ceil(h0 / hs) * hs; v <= h1; v += hs) {
        const auto [x, y] = P({e0, n0, v});
        s += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n", x - 6,
                         y + 4, num(v));
    }
    {
        const auto [xa, ya] = P({0.5 * (e0 + e1), n0, h0});
        s += fmt::format(
            "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">east y [m]</text>\n", xa,
            ya + 34);
        const auto [xb, yb] = P({e1, 0.5 * (n0 + n1), h0});
        s += fmt::format(
            "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"start\">north x [m]</text>\n", xb + 46,
            yb + 4);
        const auto [xc, yc] = P({e0, n0, h1});
        s += fmt::format(
            "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">altitude [m]</text>\n", xc,
            yc - 10);
    }
    // ground track and the path
    auto polyline = [&](bool ground, const char* style) {
        std::string pts;
        for (std::size_t i = 0; i < n; ++i) {
            const auto [x, y] = P({fp.east[i], fp.north[i], ground ? h0 : fp.altitude[i]});
            pts += fmt::format("{:.1f},{:.1f} ", x, y);
        }
        return fmt::format("<polyline points=\"{}\" fill=\"none\" {}/>\n", pts, style);
    };
    s += polyline(true, "stroke=\"#bbb\" stroke-dasharray=\"4 3\"");
    s += polyline(false, "stroke=\"#1f77b4\" stroke-width=\"1.8\"");
    // attitude glyphs: body axes from the Euler angles, drawn as wings, fuselage and fin
    const bool attitude = fp.phi.size() == n && fp.theta.size() == n && fp.psi.size() == n;
    const int g = attitude ? std::max(fp.glyphs, 2) : 0;
    const double size = 0.028 * big;
    for (int k = 0; k < g; ++k) {
        const std::size_t i = static_cast<std::size_t>(
            std::lround(static_cast<double>(k) * static_cast<double>(n - 1) / (g - 1)));
        // columns of the body-to-earth rotation (north, east, down components) as (east, north,
        // up): body x (nose), body y (right wing) and -z (fin up)
        const Eigen::Matrix3d C = core::dcm_earth_from_body(fp.phi[i], fp.theta[i], fp.psi[i]);
        const World nose{C(1, 0), C(0, 0), -C(2, 0)};
        const World wing{C(1, 1), C(0, 1), -C(2, 1)};
        const World top{-C(1, 2), -C(0, 2), C(2, 2)};
        const World c{fp.east[i], fp.north[i], fp.altitude[i]};
        auto at = [&](double fx, double fy, double fz) {
            return World{c.e + size * (fx * nose.e + fy * wing.e + fz * top.e),
                         c.n + size * (fx * nose.n + fy * wing.n + fz * top.n),
                         c.h + size * (fx * nose.h + fy * wing.h + fz * top.h)};
        };
        std::string poly;
        for (const World& w :
             {at(1.0, 0.0, 0.0), at(-0.2, 1.0, 0.0), at(-0.6, 0.0, 0.0), at(-0.2, -1.0, 0.0)}) {
            const auto [x, y] = P(w);
            poly += fmt::format("{:.1f},{:.1f} ", x, y);
        }
        s += fmt::format(
            "<polygon points=\"{}\" fill=\"#d62728\" fill-opacity=\"0.55\" stroke=\"#8b1a1a\"/>\n",
            poly);
        s += line(at(-0.6, 0.0, 0.0), at(-0.7, 0.0, 0.45),
                  "stroke=\"#8b1a1a\" stroke-width=\"1.5\"");
        if (!fp.time.empty()) {
            const auto [x, y] = P(c);
            s += fmt::format(
                "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"9\" fill=\"#555\">{:.1f} s</text>\n",
                x + 8, y - 8, fp.time[i]);
        }
    }
    // start and end markers and a legend line
    const auto [xs, ys] = P({fp.east.front(), fp.north.front(), fp.altitude.front()});
    const auto [xe, ye] = P({fp.east.back(), fp.north.back(), fp.altitude.back()});
    s += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"4\" fill=\"#2ca02c\"/>\n", xs, ys);
    s += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"7\" height=\"7\" fill=\"#000\"/>\n",
                     xe - 3.5, ye - 3.5);
    s += fmt::format(
        "<text x=\"{}\" y=\"{}\" fill=\"#444\">flight path (blue), ground track (dashed), "
        "aircraft attitude (red glyphs, fin up), start (green dot), end (black square); equal "
        "scale on all axes</text>\n",
        20, H - 12);
    return s + "</svg>\n";
}

}  // namespace manta::cli
