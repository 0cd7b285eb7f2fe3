#include "manta/vlm/lattice.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

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
        // Whole-surface distribution by spanwise arc length, with the node nearest each interior
        // section moved onto it so strips never straddle a section.
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

/// Camber slope of a section's mean line at chord fraction x (0 for a flat plate).
double camber_slope(const Section& s, double x) {
    return s.airfoil ? s.airfoil->camber_slope(std::clamp(x, 1e-6, 1.0 - 1e-6)) : 0.0;
}

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
            const double incidence = lerp(A.incidence, B.incidence, um);
            const double claf = lerp(A.lift_slope_factor, B.lift_slope_factor, um);
            const ChordStations cs =
                claf == 1.0 ? plain : chord_stations(S.n_chord, S.chord_spacing, claf);
            // Spanwise unit vector perpendicular to x, and the undeflected normal x-hat x s-hat.
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
                const double h = lerp(ca.hinge_chord_fraction, it->hinge_chord_fraction, um);
                Vector3d axis = ca.hinge_axis;
                if (axis.norm() == 0.0) {
                    const Vector3d ha = A.leading_edge + std::abs(ca.hinge_chord_fraction) *
                                                             A.chord * Vector3d::UnitX();
                    const Vector3d hb = B.leading_edge + std::abs(it->hinge_chord_fraction) *
                                                             B.chord * Vector3d::UnitX();
                    axis = hb - ha;
                }
                acting.push_back(
                    {L.control_index(ca.name), ca.gain, h, ca.duplicate_sign, axis.normalized()});
            }
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
                const Vector3d le_m = A.leading_edge + um * (B.leading_edge - A.leading_edge);
                const double c_m = lerp(A.chord, B.chord, um);
                L.control_point.push_back(le_m + xc * c_m * Vector3d::UnitX());
                const double slope = lerp(camber_slope(A, xc), camber_slope(B, xc), um);
                const double theta = incidence - std::atan(slope);
                L.normal.push_back(rotate(n0, s_hat, theta));
                L.area.push_back(dx * st.area);
                L.corners.push_back({st.le_a + x0 * st.chord_a * Vector3d::UnitX(),
                                     st.le_b + x0 * st.chord_b * Vector3d::UnitX(),
                                     st.le_b + x1 * st.chord_b * Vector3d::UnitX(),
                                     st.le_a + x1 * st.chord_a * Vector3d::UnitX()});
                L.chord_fraction.push_back(xc);
                L.strip.push_back(static_cast<int>(L.strips.size()));
                L.wake.push_back(S.sheds_wake);
                std::vector<PanelControl> pcs;
                for (const Acting& c : acting) {
                    const bool aft = c.hinge > 0.0;
                    const double xm = 0.5 * (x0 + x1);
                    if ((aft && xm > c.hinge) || (!aft && xm < -c.hinge))
                        pcs.push_back({c.control, c.gain, c.axis, c.dup});
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
