#include "manta/vlm/lattice.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include "manta/core/error.hpp"

namespace manta::vlm {

namespace {

using Eigen::Vector3d;

/// Distance between two points in the y-z plane (the spanwise measure of a surface).
double yz_distance(const Vector3d& p, const Vector3d& q) {
    return std::hypot(q.y() - p.y(), q.z() - p.z());
}

/// Strip edges of one surface as (panel index j, local fraction u in [0, 1]) pairs, root to tip.
struct Edge {
    int panel = 0;
    double u = 0.0;
    double s = 0.0;  ///< parameter of the spacing law at this edge
    /// Panel-local fraction of the control station of the strip that starts at this edge, when
    /// the distribution fixes it; NaN: the middle of the strip in the spacing parameter.
    double u_mid = std::numeric_limits<double>::quiet_NaN();
};

/// How a surface's strips are distributed: over the whole surface by arc length (global) or per
/// section panel.
struct Distribution {
    bool global = false;
    double parameter = 1.0;          // global law
    std::vector<double> cum, d;      // arc length at each section, length of each panel
    std::vector<double> parameters;  // per-panel laws
    /// Panel-local fraction of the strip's control-point station: the middle of the strip in
    /// the spacing parameter.
    [[nodiscard]] double u_mid(const Edge& a, const Edge& b) const {
        if (std::isfinite(a.u_mid)) return a.u_mid;
        const double sm = 0.5 * (a.s + b.s);
        const auto j = static_cast<std::size_t>(a.panel);
        if (global) {
            const double x = cum.back() * spacing_law(sm, parameter);
            return std::clamp((x - cum[j]) / d[j], a.u, b.u);
        }
        return spacing_law(sm, parameters[j]);
    }
};

std::vector<Edge> strip_edges(const Surface& s, Distribution& dist) {
    const auto n_sec = static_cast<int>(s.sections.size());
    std::vector<double> d(static_cast<std::size_t>(n_sec - 1));
    for (int j = 0; j + 1 < n_sec; ++j) {
        const auto& A = s.sections[static_cast<std::size_t>(j)];
        const auto& B = s.sections[static_cast<std::size_t>(j + 1)];
        d[static_cast<std::size_t>(j)] = yz_distance(A.leading_edge, B.leading_edge);
        if (!(d[static_cast<std::size_t>(j)] > 1e-12 * std::max(1.0, A.chord)))
            throw InputError(fmt::format(
                "vlm: surface '{}': sections {} and {} have the same spanwise position (y {}, z "
                "{}); expected distinct sections",
                s.name, j + 1, j + 2, A.leading_edge.y(), A.leading_edge.z()));
    }
    std::vector<Edge> edges;
    if (s.n_span > 0) {
        // Whole-surface distribution by spanwise arc length, measured on the sections before
        // any scaling (Surface::section_scale).
        auto unscaled = [&](double v, int axis) {
            const double f = s.section_scale[axis];
            return f != 0.0 && std::isfinite(f) ? v / std::abs(f) : v;
        };
        for (int j = 0; j + 1 < n_sec; ++j) {
            const Vector3d e = s.sections[static_cast<std::size_t>(j + 1)].leading_edge -
                               s.sections[static_cast<std::size_t>(j)].leading_edge;
            d[static_cast<std::size_t>(j)] = std::hypot(unscaled(e.y(), 1), unscaled(e.z(), 2));
        }
        std::vector<double> cum(static_cast<std::size_t>(n_sec), 0.0);
        for (int j = 1; j < n_sec; ++j)
            cum[static_cast<std::size_t>(j)] =
                cum[static_cast<std::size_t>(j - 1)] + d[static_cast<std::size_t>(j - 1)];
        const double total = cum.back();
        dist.global = true;
        dist.parameter = s.span_spacing;
        dist.cum = cum;
        dist.d = d;
        std::vector<double> nodes = spacing_fractions(s.n_span, s.span_spacing);
        for (double& x : nodes) x *= total;
        // AVL's convention: the node nearest each interior section is assigned to it, and the
        // nodes between two consecutive sections' nodes are stretched linearly so that those
        // nodes fall exactly on the sections; the control stations (the middle of each strip in
        // the spacing parameter) are carried by the same stretch. Strips then never straddle a
        // section and keep the law's grading.
        {
            const auto nn = nodes.size();
            std::vector<std::size_t> loc(static_cast<std::size_t>(n_sec), 0);
            loc.back() = nn - 1;
            for (int j = 1; j + 1 < n_sec; ++j) {
                const double sj = cum[static_cast<std::size_t>(j)];
                std::size_t k = 0;
                for (std::size_t m = 1; m < nn; ++m)
                    if (std::abs(nodes[m] - sj) < std::abs(nodes[k] - sj)) k = m;
                loc[static_cast<std::size_t>(j)] = k;
            }
            bool distinct = true;
            for (std::size_t j = 1; j < loc.size(); ++j) distinct = distinct && loc[j] > loc[j - 1];
            if (distinct) {
                for (int j = 0; j + 1 < n_sec; ++j) {
                    const auto jj = static_cast<std::size_t>(j);
                    const std::size_t i0 = loc[jj], i1 = loc[jj + 1];
                    const double y0 = nodes[i0], y1 = nodes[i1];
                    const double scale = d[jj] / (y1 - y0);
                    for (std::size_t k = i0; k <= i1; ++k) {
                        Edge e{
                            j,
                            k == i1 ? 1.0 : std::clamp((nodes[k] - y0) * scale / d[jj], 0.0, 1.0),
                            static_cast<double>(k) / s.n_span};
                        if (k < i1) {
                            const double mid =
                                total * spacing_law((static_cast<double>(k) + 0.5) / s.n_span,
                                                    s.span_spacing);
                            e.u_mid = std::clamp((mid - y0) * scale / d[jj], 0.0, 1.0);
                        }
                        edges.push_back(e);
                    }
                }
                return edges;
            }
        }
        // Sections closer together than the nodes (two share a nearest node): the node nearest
        // each interior section is moved onto it, or a node is added there.
        for (int j = 1; j + 1 < n_sec; ++j) {
            const double sj = cum[static_cast<std::size_t>(j)];
            std::size_t k = 0;
            for (std::size_t m = 1; m < nodes.size(); ++m)
                if (std::abs(nodes[m] - sj) < std::abs(nodes[k] - sj)) k = m;
            if (k != 0 && k + 1 != nodes.size()) nodes[k] = sj;
        }
        for (int j = 1; j + 1 < n_sec; ++j) nodes.push_back(cum[static_cast<std::size_t>(j)]);
        std::sort(nodes.begin(), nodes.end());
        std::vector<double> unique;
        for (double x : nodes)
            if (unique.empty() || x - unique.back() > 1e-9 * total) unique.push_back(x);
        // Map to (panel, u).
        for (double x : unique) {
            int j = 0;
            while (j + 2 < n_sec && x > cum[static_cast<std::size_t>(j + 1)] + 1e-9 * total) ++j;
            const double u =
                (x - cum[static_cast<std::size_t>(j)]) / d[static_cast<std::size_t>(j)];
            edges.push_back(
                {j, std::clamp(u, 0.0, 1.0), spacing_parameter_of(x / total, s.span_spacing)});
        }
        // A node exactly on an interior section closes panel j-1 (u = 1) and opens panel j
        // (u = 0): split it into both.
        std::vector<Edge> out;
        for (const Edge& e : edges) {
            if (e.u >= 1.0 - 1e-9 && e.panel + 2 < n_sec) {
                out.push_back({e.panel, 1.0, e.s});
                out.push_back({e.panel + 1, 0.0, e.s});
            } else {
                out.push_back(e);
            }
        }
        return out;
    }
    for (int j = 0; j + 1 < n_sec; ++j) {
        const Section& A = s.sections[static_cast<std::size_t>(j)];
        if (A.n_span < 1)
            throw InputError(fmt::format(
                "vlm: surface '{}' section {}: no spanwise strips to the next section (Nspan {}); "
                "expected Nspan >= 1 on the section or on the surface",
                s.name, j + 1, A.n_span));
        dist.parameters.resize(static_cast<std::size_t>(n_sec - 1), 1.0);
        dist.parameters[static_cast<std::size_t>(j)] = A.span_spacing;
        const auto f = spacing_fractions(A.n_span, A.span_spacing);
        for (std::size_t k = 0; k < f.size(); ++k)
            edges.push_back({j, f[k], static_cast<double>(k) / A.n_span});
    }
    return edges;
}

/// Cubic spline y(s) through strictly increasing s with parabolic run-out ends (the first and
/// last intervals are parabolas: equal second derivatives at their two nodes).
class Spline {
public:
    Spline(std::vector<double> s, std::vector<double> y) : s_(std::move(s)), y_(std::move(y)) {
        const std::size_t n = s_.size();
        m_.assign(n, 0.0);
        if (n < 3) return;
        // Unknowns M_1 .. M_{n-2}; M_0 = M_1 and M_{n-1} = M_{n-2}. Tridiagonal (Thomas).
        const std::size_t k = n - 2;
        std::vector<double> lo(k), di(k), up(k), r(k);
        for (std::size_t i = 1; i + 1 < n; ++i) {
            const double h0 = s_[i] - s_[i - 1], h1 = s_[i + 1] - s_[i];
            const std::size_t j = i - 1;
            lo[j] = h0;
            di[j] = 2.0 * (h0 + h1);
            up[j] = h1;
            r[j] = 6.0 * ((y_[i + 1] - y_[i]) / h1 - (y_[i] - y_[i - 1]) / h0);
        }
        di.front() += lo.front();
        di.back() += up.back();
        for (std::size_t j = 1; j < k; ++j) {
            const double f = lo[j] / di[j - 1];
            di[j] -= f * up[j - 1];
            r[j] -= f * r[j - 1];
        }
        m_[k] = r[k - 1] / di[k - 1];
        for (std::size_t j = k - 1; j-- > 0;) m_[j + 1] = (r[j] - up[j] * m_[j + 2]) / di[j];
        m_.front() = m_[1];
        m_.back() = m_[n - 2];
    }
    [[nodiscard]] double value(double t) const { return eval(t, false); }
    [[nodiscard]] double slope(double t) const { return eval(t, true); }

private:
    [[nodiscard]] double eval(double t, bool derivative) const {
        const std::size_t n = s_.size();
        std::size_t i =
            static_cast<std::size_t>(std::upper_bound(s_.begin(), s_.end(), t) - s_.begin());
        i = std::clamp<std::size_t>(i, 1, n - 1) - 1;
        const double h = s_[i + 1] - s_[i];
        const double a = (s_[i + 1] - t) / h, b = (t - s_[i]) / h;
        if (derivative)
            return (y_[i + 1] - y_[i]) / h +
                   h / 6.0 * ((1.0 - 3.0 * a * a) * m_[i] + (3.0 * b * b - 1.0) * m_[i + 1]);
        return a * y_[i] + b * y_[i + 1] +
               h * h / 6.0 * ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]);
    }
    std::vector<double> s_, y_, m_;
};

/// Akima's local cubic interpolation (Akima 1970): the derivative at each node is a weighted
/// mean of the neighbouring secant slopes, weighted by how much the slopes on the far side
/// change; two secants beyond each end are extrapolated linearly. Little overshoot, and each
/// interval depends on six nodes only.
class Akima {
public:
    Akima(std::vector<double> x, std::vector<double> y) : x_(std::move(x)), y_(std::move(y)) {
        const std::size_t n = x_.size();
        // Secants m[j + 2] for intervals j = -2 .. n (j = -2, -1, n - 1, n extrapolated).
        std::vector<double> m(n + 3, 0.0);
        for (std::size_t j = 0; j + 1 < n; ++j)
            m[j + 2] = (y_[j + 1] - y_[j]) / (x_[j + 1] - x_[j]);
        if (n == 2) m[3] = m[2];
        m[1] = 2.0 * m[2] - m[3];
        m[0] = 2.0 * m[1] - m[2];
        m[n + 1] = 2.0 * m[n] - m[n - 1];
        m[n + 2] = 2.0 * m[n + 1] - m[n];
        t_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            // Node i lies between secants i - 1 (m[i + 1]) and i (m[i + 2]).
            const double w_left = std::abs(m[i + 3] - m[i + 2]);
            const double w_right = std::abs(m[i + 1] - m[i]);
            t_[i] = w_left + w_right > 0.0
                        ? (w_left * m[i + 1] + w_right * m[i + 2]) / (w_left + w_right)
                        : 0.5 * (m[i + 1] + m[i + 2]);
        }
    }
    [[nodiscard]] double value(double x) const { return eval(x, false); }
    [[nodiscard]] double slope(double x) const { return eval(x, true); }

private:
    [[nodiscard]] double eval(double x, bool derivative) const {
        const std::size_t n = x_.size();
        x = std::clamp(x, x_.front(), x_.back());
        std::size_t i =
            static_cast<std::size_t>(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin());
        i = std::clamp<std::size_t>(i, 1, n - 1) - 1;
        const double h = x_[i + 1] - x_[i];
        const double u = (x - x_[i]) / h;
        // Cubic Hermite between the nodes.
        if (derivative) {
            const double d00 = 6.0 * u * u - 6.0 * u, d10 = 3.0 * u * u - 4.0 * u + 1.0;
            const double d11 = 3.0 * u * u - 2.0 * u;
            return (d00 * (y_[i] - y_[i + 1])) / h + d10 * t_[i] + d11 * t_[i + 1];
        }
        const double h00 = (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u), h10 = u * (1.0 - u) * (1.0 - u);
        const double h01 = u * u * (3.0 - 2.0 * u), h11 = u * u * (u - 1.0);
        return h00 * y_[i] + h10 * h * t_[i] + h01 * y_[i + 1] + h11 * h * t_[i + 1];
    }
    std::vector<double> x_, y_, t_;
};

/// Stations at which a section's mean-line slope is tabulated.
constexpr int camber_stations = 50;

/// Mean line of a coordinate airfoil at `camber_stations` cosine-spaced chord fractions, as
/// (x, y) per unit chord. The contour is splined in its arc length; the leading edge is its
/// leftmost point and the trailing edge the mean of the two end points; x is scaled so these
/// are 0 and 1 and y by the same factor (the section is not rotated onto its chord line). The
/// camber at x is the mean of the upper and lower surfaces there.
std::pair<std::vector<double>, std::vector<double>> camber_line(
    const std::vector<Eigen::Vector2d>& pts) {
    std::vector<double> s, x, y;
    for (const auto& p : pts) {
        if (!s.empty()) {
            const double ds = (p - Eigen::Vector2d(x.back(), y.back())).norm();
            if (!(ds > 1e-12)) continue;  // repeated point
            s.push_back(s.back() + ds);
        } else {
            s.push_back(0.0);
        }
        x.push_back(p.x());
        y.push_back(p.y());
    }
    const Spline sx(s, x), sy(s, y);
    // Leading edge: where dx/ds changes sign next to the leftmost input point.
    const auto k = static_cast<std::size_t>(std::min_element(x.begin(), x.end()) - x.begin());
    double lo = s[k == 0 ? 0 : k - 1], hi = s[std::min(k + 1, s.size() - 1)];
    if (sx.slope(lo) < 0.0 && sx.slope(hi) > 0.0) {
        for (int it = 0; it < 80; ++it) {
            const double mid = 0.5 * (lo + hi);
            (sx.slope(mid) < 0.0 ? lo : hi) = mid;
        }
    } else {
        lo = hi = s[k];
    }
    const double s_le = 0.5 * (lo + hi);
    const double x_le = sx.value(s_le), y_le = sy.value(s_le);
    const double x_te = 0.5 * (x.front() + x.back());
    const double scale = 1.0 / (x_te - x_le);
    // Arc-length position on [a, b] where the contour's x equals xt (x monotone there).
    auto locate = [&](double a, double b, double xt) {
        double fa = sx.value(a) - xt;
        for (int it = 0; it < 80; ++it) {
            const double mid = 0.5 * (a + b);
            const double fm = sx.value(mid) - xt;
            if ((fm < 0.0) == (fa < 0.0)) {
                a = mid;
                fa = fm;
            } else {
                b = mid;
            }
        }
        return 0.5 * (a + b);
    };
    std::vector<double> xc(camber_stations), yc(camber_stations);
    xc[0] = 0.0;
    yc[0] = y_le * scale;
    for (int i = 1; i < camber_stations; ++i) {
        const double f = 0.5 * (1.0 - std::cos(std::numbers::pi * i / (camber_stations - 1)));
        const double xt = x_le + f * (x_te - x_le);
        // The search runs a little beyond each end (on the spline's end cubics): the trailing
        // edge x is the mean of the two end points, so one surface stops short of it.
        const double ext = 0.02 * (s.back() - s.front());
        const double yu = sy.value(locate(s.front() - ext, s_le, xt));
        const double yl = sy.value(locate(s_le, s.back() + ext, xt));
        xc[static_cast<std::size_t>(i)] = f;
        yc[static_cast<std::size_t>(i)] = 0.5 * (yu + yl) * scale;
    }
    return {xc, yc};
}

/// Mean-line slope of a section, tabulated at `camber_stations` equally spaced chord fractions
/// and interpolated between them (AVL's convention: the slopes of coordinate and NACA sections
/// alike are smoothed at this resolution, which fixes in particular how much of the steep slope
/// near a cambered leading edge the first control points see). None for a flat plate.
class CamberSlope {
public:
    explicit CamberSlope(const Section& sec) {
        if (!sec.airfoil) return;
        const geometry::Airfoil& af = *sec.airfoil;
        if (af.is_naca() && af.designation().family == geometry::NacaFamily::six_series) {
            // The 6-series mean lines have logarithmic slopes at both ends: a table through
            // x = 0 and 1 would spread those singular values over the end intervals, so the exact
            // slope is taken at each control point instead (control points never lie at the
            // ends).
            exact_ = af;
            return;
        }
        std::vector<double> xu(camber_stations), slope(camber_stations);
        std::optional<Akima> line;
        if (!af.is_naca()) {
            auto [xc, yc] = camber_line(af.coordinates());
            line.emplace(std::move(xc), std::move(yc));
        }
        for (int i = 0; i < camber_stations; ++i) {
            const double x = static_cast<double>(i) / (camber_stations - 1);
            xu[static_cast<std::size_t>(i)] = x;
            slope[static_cast<std::size_t>(i)] = line ? line->slope(x) : af.camber_slope(x);
        }
        table_.emplace(std::move(xu), std::move(slope));
    }
    [[nodiscard]] double operator()(double x) const {
        if (exact_) return exact_->camber_slope(std::clamp(x, 1e-6, 1.0 - 1e-6));
        return table_ ? table_->value(x) : 0.0;
    }

private:
    std::optional<Akima> table_;
    std::optional<geometry::Airfoil> exact_;
};

/// Rotate v about the unit axis k by angle t (Rodrigues).
Vector3d rotate(const Vector3d& v, const Vector3d& k, double t) {
    const double c = std::cos(t), s = std::sin(t);
    return v * c + k.cross(v) * s + k * (k.dot(v)) * (1.0 - c);
}

Vector3d mirror_point(const Vector3d& p, double yd) {
    return {p.x(), 2.0 * yd - p.y(), p.z()};
}

void check_model(const Model& m) {
    if (m.surfaces.empty()) throw InputError("vlm: the model has no lifting surfaces");
    if (!(m.reference.area > 0 && m.reference.span > 0 && m.reference.chord > 0))
        throw InputError(
            fmt::format("vlm: reference area, span and chord must be > 0 (got {}, {}, {})",
                        m.reference.area, m.reference.span, m.reference.chord));
    for (const Surface& s : m.surfaces) {
        if (s.sections.size() < 2)
            throw InputError(fmt::format("vlm: surface '{}' has {} section(s); expected at least 2",
                                         s.name, s.sections.size()));
        if (s.n_chord < 1)
            throw InputError(fmt::format("vlm: surface '{}': {} chordwise vortices; expected >= 1",
                                         s.name, s.n_chord));
        for (std::size_t j = 0; j < s.sections.size(); ++j) {
            const Section& c = s.sections[j];
            if (!(c.chord > 0.0) || !std::isfinite(c.chord))
                throw InputError(fmt::format(
                    "vlm: surface '{}' section {}: chord {}; expected a finite number > 0", s.name,
                    j + 1, c.chord));
            if (!c.leading_edge.allFinite() || !std::isfinite(c.incidence))
                throw InputError(fmt::format(
                    "vlm: surface '{}' section {}: leading edge or incidence is not finite", s.name,
                    j + 1));
            if (!(c.lift_slope_factor > 0.0))
                throw InputError(
                    fmt::format("vlm: surface '{}' section {}: lift-slope factor {}; expected > 0",
                                s.name, j + 1, c.lift_slope_factor));
            for (const SectionControl& k : c.controls) {
                const double h = std::abs(k.hinge_chord_fraction);
                if (!(h >= 0.0 && h < 1.0))
                    throw InputError(fmt::format(
                        "vlm: surface '{}' section {}: control '{}' hinge chord fraction {}; "
                        "expected a value with 0 <= |x/c| < 1 (the control must lie on its "
                        "surface; 0: the whole chord deflects)",
                        s.name, j + 1, k.name, k.hinge_chord_fraction));
            }
        }
    }
}

}  // namespace

Vector3d Lattice::deflected_normal(int i, const Eigen::VectorXd& deflection) const {
    Vector3d n = normal[static_cast<std::size_t>(i)];
    for (const PanelControl& c : controls[static_cast<std::size_t>(i)]) {
        const double d = c.gain * deflection[c.control];
        if (d != 0.0) n = rotate(n, c.axis, d);
    }
    return n;
}

Vector3d Lattice::linearized_normal(int i, const Eigen::VectorXd& deflection) const {
    const Vector3d& n0 = normal[static_cast<std::size_t>(i)];
    Vector3d n = n0;
    for (const PanelControl& c : controls[static_cast<std::size_t>(i)])
        n += c.gain * deflection[c.control] * c.axis.cross(n0);
    return n;
}

Vector3d Lattice::normal_derivative(int i, const Eigen::VectorXd& deflection, int k) const {
    // Rotations about different axes on one panel are composed in list order; the derivative of
    // the composition with respect to control k differentiates each of its factors.
    const auto& list = controls[static_cast<std::size_t>(i)];
    Vector3d total = Vector3d::Zero();
    for (std::size_t m = 0; m < list.size(); ++m) {
        if (list[m].control != k) continue;
        Vector3d n = normal[static_cast<std::size_t>(i)];
        for (std::size_t l = 0; l < list.size(); ++l) {
            const PanelControl& c = list[l];
            const double d = c.gain * deflection[c.control];
            n = rotate(n, c.axis, d);
            if (l == m) n = c.gain * c.axis.cross(n);  // d/dt R(t) v = k x R(t) v
        }
        total += n;
    }
    return total;
}

int Lattice::control_index(std::string_view name) const {
    for (std::size_t k = 0; k < control_names.size(); ++k)
        if (control_names[k] == name) return static_cast<int>(k);
    return -1;
}

Lattice build_lattice(const Model& model) {
    check_model(model);
    Lattice L;
    L.control_names = model.control_names();
    for (std::size_t si = 0; si < model.surfaces.size(); ++si) {
        const Surface& S = model.surfaces[si];
        Distribution dist;
        const std::vector<Edge> edges = strip_edges(S, dist);
        const ChordStations plain = chord_stations(S.n_chord, S.chord_spacing);
        const std::vector<double>& xf = plain.edge;
        const auto first_strip = L.strips.size();
        std::vector<CamberSlope> camber;
        for (const Section& sec : S.sections) camber.emplace_back(sec);
        for (std::size_t e = 0; e + 1 < edges.size(); ++e) {
            const Edge ea = edges[e], eb = edges[e + 1];
            if (ea.panel != eb.panel) continue;  // the split point on a section
            if (!(eb.u > ea.u)) continue;
            const int j = ea.panel;
            const Section& A = S.sections[static_cast<std::size_t>(j)];
            const Section& B = S.sections[static_cast<std::size_t>(j + 1)];
            auto lerp = [](double x, double y, double u) { return x + u * (y - x); };
            const double um = dist.u_mid(ea, eb);
            Strip st;
            st.le_mid = A.leading_edge + um * (B.leading_edge - A.leading_edge);
            st.surface = static_cast<int>(si);
            st.le_a = A.leading_edge + ea.u * (B.leading_edge - A.leading_edge);
            st.le_b = A.leading_edge + eb.u * (B.leading_edge - A.leading_edge);
            st.chord_a = lerp(A.chord, B.chord, ea.u);
            st.chord_b = lerp(A.chord, B.chord, eb.u);
            st.chord = 0.5 * (st.chord_a + st.chord_b);
            st.sheds_wake = S.sheds_wake;
            const Vector3d span_vec = st.le_b - st.le_a;
            st.width = std::hypot(span_vec.y(), span_vec.z());
            st.area = st.chord * st.width;
            st.first_panel = L.size();
            st.n_panels = S.n_chord;
            // The surface between two sections is ruled: chord lines, camber-line heights and
            // hinge lines vary linearly in physical units from one section to the next. Quantities
            // given per unit chord (camber slope, hinge fraction, lift-slope factor) are therefore
            // interpolated as chord-weighted values and divided by the local chord, and the local
            // incidence is the direction of the interpolated chord vector.
            const double c_m = lerp(A.chord, B.chord, um);
            const double wa = (1.0 - um) * A.chord / c_m, wb = um * B.chord / c_m;
            const double incidence =
                std::atan2(wa * std::sin(A.incidence) + wb * std::sin(B.incidence),
                           wa * std::cos(A.incidence) + wb * std::cos(B.incidence));
            const double claf = wa * A.lift_slope_factor + wb * B.lift_slope_factor;
            const ChordStations cs =
                claf == 1.0 ? plain : chord_stations(S.n_chord, S.chord_spacing, claf);
            // Spanwise unit vector perpendicular to x, and the strip normal x-hat x s-hat.
            const Vector3d s_hat = Vector3d(0.0, span_vec.y(), span_vec.z()).normalized();
            const Vector3d n0 = Vector3d::UnitX().cross(s_hat);
            // Controls acting on this strip: present on both bounding sections.
            struct Acting {
                int control;
                double gain, hinge, dup;
                Vector3d axis;
            };
            std::vector<Acting> acting;
            for (const SectionControl& ca : A.controls) {
                const auto it =
                    std::find_if(B.controls.begin(), B.controls.end(),
                                 [&](const SectionControl& c) { return c.name == ca.name; });
                if (it == B.controls.end()) continue;
                // Hinge line straight between the sections (signed: negative for a leading-edge
                // control), gain linear between them.
                const double h = wa * ca.hinge_chord_fraction + wb * it->hinge_chord_fraction;
                const double gain = lerp(ca.gain, it->gain, um);
                Vector3d axis = ca.hinge_axis;
                if (axis.norm() == 0.0) {
                    const Vector3d ha = A.leading_edge + std::abs(ca.hinge_chord_fraction) *
                                                             A.chord * Vector3d::UnitX();
                    const Vector3d hb = B.leading_edge + std::abs(it->hinge_chord_fraction) *
                                                             B.chord * Vector3d::UnitX();
                    axis = hb - ha;
                }
                acting.push_back(
                    {L.control_index(ca.name), gain, h, ca.duplicate_sign, axis.normalized()});
            }
            const Vector3d le_m = A.leading_edge + um * (B.leading_edge - A.leading_edge);
            for (int k = 0; k < S.n_chord; ++k) {
                const double x0 = xf[static_cast<std::size_t>(k)];
                const double x1 = xf[static_cast<std::size_t>(k + 1)];
                const double dx = x1 - x0;
                // Vortex at the quarter point of the panel's interval in the spacing parameter,
                // control point half an interval behind it, scaled by the lift-slope factor (a
                // lumped vortex at 1/4 with tangency at 1/4 + claf/2 gives 2 pi claf per rad).
                const double xv = cs.vortex[static_cast<std::size_t>(k)];
                const double xc = std::min(cs.control[static_cast<std::size_t>(k)], 1.0);
                L.a.push_back(st.le_a + xv * st.chord_a * Vector3d::UnitX());
                L.b.push_back(st.le_b + xv * st.chord_b * Vector3d::UnitX());
                L.bound_point.push_back(le_m + xv * c_m * Vector3d::UnitX());
                L.control_point.push_back(le_m + xc * c_m * Vector3d::UnitX());
                // Normal: perpendicular to the bound vortex and to the local camber-line
                // direction, which is the chord line turned by incidence and camber slope about
                // the strip's spanwise direction (leading edge up positive).
                const double slope = wa * camber[static_cast<std::size_t>(j)](xc) +
                                     wb * camber[static_cast<std::size_t>(j + 1)](xc);
                const double theta = incidence - std::atan(slope);
                const Vector3d e_c = std::cos(theta) * Vector3d::UnitX() - std::sin(theta) * n0;
                const Vector3d e_b = (L.b.back() - L.a.back()).normalized();
                const Vector3d n = e_c.cross(e_b);
                L.normal.push_back(n.norm() > 0.0 ? Vector3d(n.normalized()) : n0);
                L.area.push_back(dx * st.area);
                L.corners.push_back({st.le_a + x0 * st.chord_a * Vector3d::UnitX(),
                                     st.le_b + x0 * st.chord_b * Vector3d::UnitX(),
                                     st.le_b + x1 * st.chord_b * Vector3d::UnitX(),
                                     st.le_a + x1 * st.chord_a * Vector3d::UnitX()});
                L.chord_fraction.push_back(xc);
                L.strip.push_back(static_cast<int>(L.strips.size()));
                L.wake.push_back(S.sheds_wake);
                // A control deflects the panel's normal in proportion to the part of the panel's
                // chord that lies on the control surface: panels cut by the hinge line turn by
                // that fraction of the deflection, so the control derivative varies smoothly
                // with the hinge position instead of jumping as the hinge crosses a panel.
                std::vector<PanelControl> pcs;
                for (const Acting& c : acting) {
                    const double xh = std::abs(c.hinge);
                    const double on =
                        c.hinge >= 0.0 ? x1 - std::clamp(xh, x0, x1) : std::clamp(xh, x0, x1) - x0;
                    const double frac = on / dx;
                    if (frac > 0.0) pcs.push_back({c.control, c.gain * frac, c.axis, c.dup});
                }
                L.controls.push_back(std::move(pcs));
            }
            L.strips.push_back(st);
        }
        if (L.strips.size() == first_strip)
            throw InputError(fmt::format("vlm: surface '{}' produced no strips", S.name));
        if (!S.y_duplicate) continue;
        // Mirror copy: reflected points, a and b swapped so a -> b keeps its sense relative to
        // the flow, reflected normals; control axes mirrored as axial vectors.
        const double yd = *S.y_duplicate;
        const std::size_t last_strip = L.strips.size();
        for (std::size_t t = first_strip; t < last_strip; ++t) {
            Strip st = L.strips[t];
            const int p0 = st.first_panel;
            st.mirrored = true;
            st.first_panel = L.size();
            std::swap(st.le_a, st.le_b);
            st.le_mid = mirror_point(st.le_mid, yd);
            st.le_a = mirror_point(st.le_a, yd);
            st.le_b = mirror_point(st.le_b, yd);
            std::swap(st.chord_a, st.chord_b);
            for (int k = 0; k < st.n_panels; ++k) {
                const auto i = static_cast<std::size_t>(p0 + k);
                L.a.push_back(mirror_point(L.b[i], yd));
                L.b.push_back(mirror_point(L.a[i], yd));
                L.control_point.push_back(mirror_point(L.control_point[i], yd));
                L.bound_point.push_back(mirror_point(L.bound_point[i], yd));
                const Vector3d n = L.normal[i];
                L.normal.push_back(Vector3d(n.x(), -n.y(), n.z()));
                L.area.push_back(L.area[i]);
                const auto& c = L.corners[i];
                L.corners.push_back({mirror_point(c[1], yd), mirror_point(c[0], yd),
                                     mirror_point(c[3], yd), mirror_point(c[2], yd)});
                L.chord_fraction.push_back(L.chord_fraction[i]);
                L.strip.push_back(static_cast<int>(L.strips.size()));
                L.wake.push_back(L.wake[i]);
                std::vector<PanelControl> pcs = L.controls[i];
                for (PanelControl& c : pcs) {
                    c.axis = Vector3d(-c.axis.x(), c.axis.y(), -c.axis.z());
                    c.gain *= c.duplicate_sign;
                }
                L.controls.push_back(std::move(pcs));
            }
            L.strips.push_back(st);
        }
    }
    return L;
}

void check_lattice(const Model& model, const Lattice& L) {
    for (int i = 0; i < L.size(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Strip& st = L.strips[static_cast<std::size_t>(L.strip[k])];
        const std::string& name = model.surfaces[static_cast<std::size_t>(st.surface)].name;
        if (!L.a[k].allFinite() || !L.b[k].allFinite() || !L.control_point[k].allFinite())
            throw InputError(fmt::format("vlm: surface '{}': non-finite lattice point", name));
        if (!(L.area[k] > 0.0) || !((L.b[k] - L.a[k]).norm() > 0.0))
            throw InputError(fmt::format(
                "vlm: surface '{}': degenerate panel {} (area {} m^2); check for zero-width strips",
                name, i, L.area[k]));
    }
    // Crossing lattices: a bound segment of one surface passing through a strip of another
    // (the two surfaces interpenetrate; the influence of one on the other is then singular).
    for (std::size_t t = 0; t < L.strips.size(); ++t) {
        const Strip& st = L.strips[t];
        const Vector3d e = st.le_b - st.le_a;
        const Vector3d n = Vector3d::UnitX().cross(Vector3d(0.0, e.y(), e.z()).normalized());
        const double w2 = e.y() * e.y() + e.z() * e.z();
        for (int i = 0; i < L.size(); ++i) {
            const auto k = static_cast<std::size_t>(i);
            const Strip& other = L.strips[static_cast<std::size_t>(L.strip[k])];
            if (other.surface == st.surface) continue;
            const double da = (L.a[k] - st.le_a).dot(n);
            const double db = (L.b[k] - st.le_a).dot(n);
            const double tol = 1e-9 * st.chord;
            if (!((da > tol && db < -tol) || (da < -tol && db > tol))) continue;
            const Vector3d p = L.a[k] + (da / (da - db)) * (L.b[k] - L.a[k]);
            const Vector3d r = p - st.le_a;
            const double sp = (r.y() * e.y() + r.z() * e.z()) / w2;
            if (sp <= 1e-9 || sp >= 1.0 - 1e-9) continue;
            const double x_le = st.le_a.x() + sp * e.x();
            const double c = st.chord_a + sp * (st.chord_b - st.chord_a);
            if (p.x() > x_le && p.x() < x_le + c)
                throw InputError(fmt::format(
                    "vlm: surfaces '{}' and '{}' cross at ({:.4g}, {:.4g}, {:.4g}); expected "
                    "lifting surfaces that meet only along their edges",
                    model.surfaces[static_cast<std::size_t>(other.surface)].name,
                    model.surfaces[static_cast<std::size_t>(st.surface)].name, p.x(), p.y(),
                    p.z()));
        }
    }
}

}  // namespace manta::vlm
