/// @file shapes.cpp
/// Section frames and contours, control-surface regions, the aircraft-file error helper and
/// `check_buildable`.

#include "shapes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/meshgen/meshgen.hpp"

namespace manta::meshgen {
namespace detail {

namespace {

/// Line of a key path ("a.b[2].c") in the aircraft file, 0 if it cannot be found.
int key_line(const std::filesystem::path& file, const std::string& key_path) {
    std::error_code ec;
    if (file.empty() || !std::filesystem::is_regular_file(file, ec)) return 0;
    try {
        core::ConfigNode node = core::ConfigNode::parse_file(file);
        const std::regex part(R"(([A-Za-z_0-9]+)((\[[0-9]+\])*))");
        int line = node.line();
        for (auto it = std::sregex_iterator(key_path.begin(), key_path.end(), part);
             it != std::sregex_iterator(); ++it) {
            const std::string key = (*it)[1].str();
            if (!node.is_map() || !node.has(key)) return line;
            line = node.key_line(key);
            node = node.child(key);
            const std::string idx = (*it)[2].str();
            for (std::size_t p = idx.find('['); p != std::string::npos; p = idx.find('[', p + 1)) {
                const std::size_t i = std::stoul(idx.substr(p + 1));
                if (!node.is_sequence() || i >= node.size()) return line;
                node = node.element(i);
                if (node.line() > 0) line = node.line();
            }
        }
        return line;
    } catch (const std::exception&) {
        return 0;
    }
}

}  // namespace

void fail_key(const aircraft::AircraftDefinition& a, const std::string& key_path,
              const std::string& value, std::string_view problem, std::string_view expected) {
    const std::string file = a.file.empty() ? std::string("aircraft") : a.file.string();
    const int line = key_line(a.file, key_path);
    const std::string where = line > 0 ? fmt::format("{}:{}", file, line) : file;
    throw ConfigError(fmt::format("{}: key '{}': value '{}' {}; expected {}", where, key_path,
                                  value, problem, expected));
}

namespace {

SectionFrame make_frame(const geometry::LiftingSurface& w, const Eigen::Vector3d& le, double c,
                        double twist) {
    SectionFrame f;
    f.leading_edge = le;
    f.chord = c;
    const double ct = std::cos(twist), st = std::sin(twist);
    if (w.vertical) {
        // Positive twist turns the leading edge toward +y, so the trailing edge toward -y.
        f.e_chord = Eigen::Vector3d(ct, -st, 0.0);
        f.e_up = Eigen::Vector3d(st, ct, 0.0);
        f.e_span = Eigen::Vector3d::UnitZ();
    } else {
        // Positive twist raises the leading edge: the trailing edge goes down.
        f.e_chord = Eigen::Vector3d(ct, 0.0, -st);
        f.e_up = Eigen::Vector3d(st, 0.0, ct);
        f.e_span = Eigen::Vector3d::UnitY();
    }
    return f;
}

}  // namespace

SectionFrame frame_of(const geometry::LiftingSurface& w, std::size_t i) {
    const auto& s = w.sections.at(i);
    return make_frame(w, s.leading_edge, s.chord, s.twist);
}

SectionFrame frame_at(const geometry::LiftingSurface& w, double eta) {
    const double s = w.spanwise(w.sections.front()) + eta * w.semi_span();
    std::size_t i = 0;
    while (i + 2 < w.sections.size() && w.spanwise(w.sections[i + 1]) < s) ++i;
    const double s0 = w.spanwise(w.sections[i]), s1 = w.spanwise(w.sections[i + 1]);
    const double t = s1 > s0 ? std::clamp((s - s0) / (s1 - s0), 0.0, 1.0) : 0.0;
    const double twist = (1.0 - t) * w.sections[i].twist + t * w.sections[i + 1].twist;
    return make_frame(w, w.leading_edge_at(eta), w.chord_at(eta), twist);
}

std::string section_key(std::size_t i, std::size_t j) {
    return fmt::format("geometry.lifting_surfaces[{}].sections[{}]", i, j);
}

std::pair<std::string, std::string> airfoil_key(const geometry::Airfoil& a, std::size_t i,
                                                std::size_t j) {
    if (a.is_naca()) return {section_key(i, j) + ".airfoil", a.name()};
    return {section_key(i, j) + ".airfoil_file", a.file().string()};
}

Contour section_contour(const geometry::Airfoil& airfoil) {
    Contour c;
    std::vector<Eigen::Vector2d> pts;
    if (airfoil.has_coordinates()) {
        pts = airfoil.coordinates(31);
    } else {
        // A 6-series section: its thickness form is tabulated (Abbott & von Doenhoff, app. I),
        // not analytic. It is meshed with the four-digit thickness form of the same maximum
        // thickness laid perpendicular to its own (analytic) mean line, and the substitution is
        // reported.
        const auto& d = airfoil.designation();
        const int tt = std::clamp(static_cast<int>(std::lround(100.0 * d.thickness)), 1, 40);
        const auto base = geometry::Airfoil::naca(fmt::format("NACA 00{:02d}", tt)).coordinates(31);
        std::vector<Eigen::Vector2d> up, lo;
        for (const auto& p : base) {
            if (p.y() < 0.0) continue;
            const double x = p.x(), yt = p.y();
            const double th = std::atan(airfoil.camber_slope(std::clamp(x, 1e-6, 1.0 - 1e-6)));
            const double yc = airfoil.camber(x);
            up.emplace_back(x - yt * std::sin(th), yc + yt * std::cos(th));
            lo.emplace_back(x + yt * std::sin(th), yc - yt * std::cos(th));
        }
        // `base` runs from the trailing edge over the upper side: up is TE -> LE.
        pts.assign(up.begin(), up.end());
        for (auto it = lo.rbegin() + 1; it != lo.rend(); ++it) pts.push_back(*it);
        c.note = fmt::format(
            "airfoil '{}': 6-series thickness form replaced by the four-digit form NACA 00{:02d} "
            "on the section's own mean line (give a coordinate file for the exact shape)",
            airfoil.name(), tt);
    }
    for (const auto& p : pts)
        if (c.points.empty() || (p - c.points.back()).norm() > 1e-9) c.points.push_back(p);
    c.leading_edge = static_cast<std::size_t>(
        std::min_element(c.points.begin(), c.points.end(),
                         [](const auto& a, const auto& b) { return a.x() < b.x(); }) -
        c.points.begin());
    // A closed contour (sharp trailing edge): the repeated point is dropped; it is lofted as two
    // splines meeting at the leading edge. An open one keeps its trailing-edge base.
    if (c.points.size() > 2 && (c.points.front() - c.points.back()).norm() < 1e-6) {
        c.points.pop_back();
        c.sharp_trailing_edge = true;
    }
    double t = 0.0;
    for (std::size_t i = 0; i <= c.leading_edge; ++i)
        for (std::size_t j = c.leading_edge; j < c.points.size(); ++j)
            if (std::abs(c.points[i].x() - c.points[j].x()) < 0.02)
                t = std::max(t, c.points[i].y() - c.points[j].y());
    c.thickness = t;
    return c;
}

bool ControlRegion::contains(const Eigen::Vector3d& p, double tol) const {
    // Inside the ruled solid between the two end rectangles: parameter along the span from the
    // end planes, then the rectangle of the interpolated frame.
    const Eigen::Vector3d& axis = frame0.e_span;
    const double s0 = frame0.leading_edge.dot(axis), s1 = frame1.leading_edge.dot(axis);
    const double s = p.dot(axis);
    const double lo = std::min(s0, s1), hi = std::max(s0, s1);
    if (s < lo + tol || s > hi - tol) return false;
    const double t = (s - s0) / (s1 - s0);
    const Eigen::Vector3d h = (1.0 - t) * corners[0][0] + t * corners[1][0];   // hinge-low
    const Eigen::Vector3d hh = (1.0 - t) * corners[0][1] + t * corners[1][1];  // hinge-high
    const Eigen::Vector3d al = (1.0 - t) * corners[0][3] + t * corners[1][3];  // aft-low
    const Eigen::Vector3d u = (hh - h), a = (al - h);
    const Eigen::Vector3d d = p - h;
    const double along = d.dot(a.normalized()), up = d.dot(u.normalized());
    return along > tol && along < a.norm() - tol && up > tol && up < u.norm() - tol;
}

ControlRegion control_region(const geometry::AircraftGeometry& g, std::size_t k, bool mirrored,
                             std::string marker) {
    const auto& cs = g.control_surfaces.at(k);
    const auto& w = g.surface(cs.surface);
    ControlRegion r;
    r.marker = std::move(marker);
    r.control_index = k;
    r.mirrored = mirrored;
    r.hinge_fraction = cs.hinge_chord_fraction;
    for (int e = 0; e < 2; ++e) {
        SectionFrame f = frame_at(w, cs.span_fraction[static_cast<std::size_t>(e)]);
        const double c = f.chord, height = 0.5 * c;
        const Eigen::Vector3d hinge = f.at(cs.hinge_chord_fraction, 0.0);
        const Eigen::Vector3d aft = f.at(1.0 + 0.15, 0.0);
        auto& q = r.corners[static_cast<std::size_t>(e)];
        q[0] = hinge - height * f.e_up;
        q[1] = hinge + height * f.e_up;
        q[2] = aft + height * f.e_up;
        q[3] = aft - height * f.e_up;
        if (mirrored) {
            for (auto& p : q) p.y() = -p.y();
            f.leading_edge.y() = -f.leading_edge.y();
            f.e_chord.y() = -f.e_chord.y();
            f.e_up.y() = -f.e_up.y();
            f.e_span.y() = -f.e_span.y();
        }
        (e == 0 ? r.frame0 : r.frame1) = f;
    }
    return r;
}

std::string marker_name(const geometry::ControlSurface& cs, bool symmetric_surface, bool mirrored,
                        bool half_model) {
    if (!symmetric_surface) return cs.name;
    if (half_model && cs.gain == cs.mirror_gain) return cs.name;
    return cs.name + (mirrored ? "_left" : "_right");
}

}  // namespace detail

namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
}

/// True if segments (a, b) and (c, d) cross properly.
bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
    const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a);
    const double d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

/// True if p lies inside the fuselage's elliptic cross-section at its x (linear between
/// stations).
bool inside_fuselage(const geometry::Fuselage& fus, const Eigen::Vector3d& p) {
    const auto& st = fus.stations;
    if (st.size() < 2 || p.x() <= st.front().x || p.x() >= st.back().x) return false;
    std::size_t j = 0;
    while (j + 2 < st.size() && st[j + 1].x < p.x()) ++j;
    const double t = (p.x() - st[j].x) / (st[j + 1].x - st[j].x);
    const double w = (1 - t) * st[j].width + t * st[j + 1].width;
    const double h = (1 - t) * st[j].height + t * st[j + 1].height;
    const double zc = (1 - t) * st[j].z_centre + t * st[j + 1].z_centre;
    if (!(w > 0.0 && h > 0.0)) return false;
    const double u = p.y() / (0.5 * w), v = (p.z() - zc) / (0.5 * h);
    return u * u + v * v < 1.0;
}

}  // namespace

void check_buildable(const aircraft::AircraftDefinition& a) {
    using detail::fail_key;
    const auto& g = a.geometry;
    for (std::size_t i = 0; i < g.surfaces.size(); ++i) {
        const auto& w = g.surfaces[i];
        const std::string surf = fmt::format("geometry.lifting_surfaces[{}]", i);
        if (w.sections.size() < 2)
            fail_key(a, surf + ".sections", fmt::format("{} section(s)", w.sections.size()),
                     "cannot be lofted", "at least two sections, root to tip");
        for (std::size_t j = 0; j < w.sections.size(); ++j) {
            const auto& s = w.sections[j];
            if (j > 0 && !(w.spanwise(s) > w.spanwise(w.sections[j - 1]) + 1e-9)) {
                const auto& p = s.leading_edge;
                fail_key(
                    a, detail::section_key(i, j) + ".leading_edge",
                    fmt::format("[{}, {}, {}]", p.x(), p.y(), p.z()),
                    fmt::format("is out of order: its spanwise coordinate ({}) does not exceed "
                                "that of the section before",
                                w.vertical ? "z" : "y"),
                    "sections root to tip, the spanwise coordinate strictly increasing");
            }
            if (!(s.chord > 0.0) || !std::isfinite(s.chord))
                fail_key(a, detail::section_key(i, j) + ".chord", fmt::format("{}", s.chord),
                         "is not a positive chord", "a chord > 0 m");
            const auto [key, value] = detail::airfoil_key(s.airfoil, i, j);
            const detail::Contour c = detail::section_contour(s.airfoil);
            if (c.points.size() < 7 || !(c.thickness >= 0.005))
                fail_key(a, key, value,
                         fmt::format("is a degenerate section (thickness {:.4g} of the chord)",
                                     c.thickness),
                         "a closed contour at least 0.5 % of the chord thick");
            double area2 = 0.0;
            for (std::size_t p = 0; p < c.points.size(); ++p)
                area2 += cross2(c.points[p], c.points[(p + 1) % c.points.size()]);
            // Selig order runs counter-clockwise (upper surface first, toward the leading edge).
            if (!(0.5 * area2 > 0.002))
                fail_key(a, key, value,
                         fmt::format("is a degenerate section (enclosed area {:.3g} of the chord "
                                     "squared)",
                                     0.5 * area2),
                         "a contour in Selig order enclosing a positive area");
            const std::size_t n = c.points.size();
            for (std::size_t p = 0; p < n; ++p)
                for (std::size_t q = p + 2; q < n; ++q) {
                    if (p == 0 && q == n - 1) continue;  // adjacent through the trailing edge
                    if (segments_cross(c.points[p], c.points[p + 1], c.points[q],
                                       c.points[(q + 1) % n]))
                        fail_key(a, key, value,
                                 fmt::format("self-intersects: its contour crosses itself near "
                                             "x/c = {:.3f}",
                                             c.points[p].x()),
                                 "a contour whose upper and lower surfaces do not cross");
                }
            // Twin copies of a fin (mirrored about y = 0) must not overlap.
            if (w.vertical && w.symmetric && j == 0) {
                const double half = 0.5 * c.thickness * s.chord;
                if (std::abs(s.leading_edge.y()) < half) {
                    const auto& p = s.leading_edge;
                    fail_key(a, detail::section_key(i, j) + ".leading_edge",
                             fmt::format("[{}, {}, {}]", p.x(), p.y(), p.z()),
                             fmt::format("self-intersects: the twin copies mirrored about y = 0 "
                                         "overlap (|y| = {:.4g} m is less than the half "
                                         "thickness {:.4g} m)",
                                         std::abs(p.y()), half),
                             "twin fins apart by more than their thickness, or symmetric: false");
                }
            }
        }
        // A panel must not fold onto itself: the chord's twist change between neighbouring
        // sections moves the trailing edge by less than the spanwise step.
        for (std::size_t j = 0; j + 1 < w.sections.size(); ++j) {
            const auto& s0 = w.sections[j];
            const auto& s1 = w.sections[j + 1];
            const double ds = w.spanwise(s1) - w.spanwise(s0);
            const double dte =
                std::abs(s1.chord * std::sin(s1.twist) - s0.chord * std::sin(s0.twist));
            if (ds > 0.0 && dte > 4.0 * ds)
                fail_key(a, detail::section_key(i, j + 1) + ".twist",
                         fmt::format("{:.4g} deg", s1.twist * 180.0 / M_PI),
                         fmt::format("self-intersects: the trailing edge moves {:.3g} m normal to "
                                     "the chord over a spanwise step of {:.3g} m",
                                     dte, ds),
                         "a twist change that keeps the panel from folding");
        }
    }
    // Fuselage: only the end stations may shrink to a point.
    const auto& st = g.fuselage.stations;
    for (std::size_t j = 0; j < st.size(); ++j) {
        if (j == 0 || j + 1 == st.size()) continue;
        if (!(st[j].width > 0.0) || !(st[j].height > 0.0))
            fail_key(
                a,
                fmt::format("geometry.fuselage.{}[{}]", st[j].width > 0.0 ? "height" : "width", j),
                fmt::format("{}", st[j].width > 0.0 ? st[j].height : st[j].width),
                "is a degenerate cross-section between the ends of the fuselage",
                "a positive width and height (only the first and last stations may be 0)");
    }
    for (std::size_t k = 0; k < g.control_surfaces.size(); ++k) {
        const auto& cs = g.control_surfaces[k];
        const std::string key = fmt::format("geometry.control_surfaces[{}]", k);
        const auto* w = g.find_surface(cs.surface);
        if (!w)
            fail_key(a, key + ".surface", cs.surface, "names no lifting surface", "a surface name");
        const double e0 = cs.span_fraction[0], e1 = cs.span_fraction[1];
        if (!(e0 >= 0.0 && e1 <= 1.0 && e0 < e1))
            fail_key(a, key + ".span_fraction", fmt::format("[{}, {}]", e0, e1),
                     fmt::format("lies outside its surface '{}'", cs.surface),
                     "fractions 0 <= eta0 < eta1 <= 1 of the semi-span");
        // Wholly inside the fuselage: every sampled point of the hinged part (hinge to trailing
        // edge, side to side, upper and lower surface) lies within the elliptic stations.
        if (!g.fuselage.empty()) {
            bool inside = true;
            for (int e = 0; e <= 4 && inside; ++e) {
                const auto f = detail::frame_at(*w, e0 + (e1 - e0) * e / 4.0);
                for (int c = 0; c <= 4 && inside; ++c) {
                    const double x =
                        cs.hinge_chord_fraction + (1.0 - cs.hinge_chord_fraction) * c / 4.0;
                    for (double up : {-0.06, 0.06})
                        inside = inside && inside_fuselage(g.fuselage, f.at(x, up));
                }
            }
            if (inside)
                fail_key(a, key + ".span_fraction", fmt::format("[{}, {}]", e0, e1),
                         fmt::format("puts control surface '{}' inside the fuselage (no wetted "
                                     "face)",
                                     cs.name),
                         "a span range on the exposed part of its surface");
        }
        if (!(cs.hinge_chord_fraction > 0.0 && cs.hinge_chord_fraction < 0.98))
            fail_key(a, key + ".hinge_chord_fraction", fmt::format("{}", cs.hinge_chord_fraction),
                     fmt::format("puts the hinge outside its surface '{}'", cs.surface),
                     "a fraction in (0, 0.98) of the local chord");
    }
}

}  // namespace manta::meshgen
