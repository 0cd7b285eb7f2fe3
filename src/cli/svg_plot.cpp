#include "svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

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

}  // namespace manta::cli
