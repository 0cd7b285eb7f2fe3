#include "manta/vlm/viscous.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"

namespace manta::vlm {

namespace {

constexpr double pi = std::numbers::pi;

// Below this Reynolds number on a component's length the flat-plate fits (made for about 1e5 to
// 1e9) mean nothing; such a component is reported instead of extrapolated.
constexpr double min_component_reynolds = 1e4;

// Lifting-surface wetted-area rule Swet = S_exposed (1.977 + 0.52 t/c) (Raymer eq. 7.12), which
// Raymer replaces by 2.003 S_exposed below t/c = 0.05 (eq. 7.11): the same value at 0.05.
constexpr double wetted_area_min_thickness = 0.05;

// 8-point Gauss-Legendre rule on [-1, 1] (Abramowitz & Stegun, table 25.4).
constexpr std::array<double, 4> gauss_nodes{0.1834346424956498, 0.5255324099163290,
                                            0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> gauss_weights{0.3626837833783620, 0.3137066458778873,
                                              0.2223810344533745, 0.1012285362903763};

// InputError "<what> <value>; expected <expected>" unless `ok`.
void require(bool ok, std::string_view what, double value, std::string_view expected) {
    if (!ok) throw InputError(fmt::format("{} {:g}; expected {}", what, value, expected));
}

void require_positive(double value, std::string_view what, std::string_view expected) {
    require(std::isfinite(value) && value > 0.0, what, value, expected);
}

void require_mach(double mach, std::string_view context) {
    require(std::isfinite(mach) && mach >= 0.0 && mach < 1.0, fmt::format("{}Mach number", context),
            mach,
            "a subsonic value in [0, 1) (the skin-friction correction, the form factors and the "
            "build-up are subsonic)");
}

double lerp(double a, double b, double t) {
    return a + t * (b - a);
}

// y on a polyline sorted by increasing x (ties allowed), clamped at the ends.
double polyline_y(const std::vector<Eigen::Vector2d>& p, double x) {
    if (x <= p.front().x()) return p.front().y();
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
        const double x0 = p[i].x(), x1 = p[i + 1].x();
        if (x >= x0 && x <= x1) {
            return x1 > x0 ? lerp(p[i].y(), p[i + 1].y(), (x - x0) / (x1 - x0)) : p[i + 1].y();
        }
    }
    return p.back().y();
}

// d/da of Ramanujan's perimeter pi [3(a + b) - sqrt((3a + b)(a + 3b))]; the derivative in b is
// the same with a and b exchanged. Requires a + b > 0.
double perimeter_da(double a, double b) {
    const double s = std::sqrt((3.0 * a + b) * (a + 3.0 * b));
    return pi * (3.0 - (3.0 * a + 5.0 * b) / s);
}

}  // namespace

// ------------------------------------------------------------------------------------ ingredients

double reynolds_per_metre(double density, double speed, double viscosity) {
    require_positive(density, "Reynolds number per metre: density", "a positive density [kg/m^3]");
    require_positive(speed, "Reynolds number per metre: speed", "a positive airspeed [m/s]");
    require_positive(viscosity, "Reynolds number per metre: viscosity",
                     "a positive dynamic viscosity [Pa s]");
    return density * speed / viscosity;
}

double laminar_skin_friction(double reynolds) {
    require_positive(reynolds, "laminar skin friction: Reynolds number", "a positive number");
    return 1.328 / std::sqrt(reynolds);
}

double turbulent_skin_friction(double reynolds, double mach) {
    require(std::isfinite(reynolds) && reynolds > 10.0, "turbulent skin friction: Reynolds number",
            reynolds, "a number above 10 (the fit needs log10 Re > 1)");
    require_mach(mach, "turbulent skin friction: ");
    return 0.455 /
           (std::pow(std::log10(reynolds), 2.58) * std::pow(1.0 + 0.144 * mach * mach, 0.65));
}

double cutoff_reynolds(double length, double roughness_height) {
    require_positive(length, "cut-off Reynolds number: length", "a positive length [m]");
    require_positive(roughness_height, "cut-off Reynolds number: roughness height",
                     "a positive height [m]");
    return 38.21 * std::pow(length / roughness_height, 1.053);
}

double roughness_height(SkinRoughness roughness) {
    switch (roughness) {
        case SkinRoughness::camouflage_paint:
            return 1.015e-5;
        case SkinRoughness::smooth_paint:
            return 0.634e-5;
        case SkinRoughness::production_sheet_metal:
            return 0.405e-5;
        case SkinRoughness::polished_sheet_metal:
            return 0.152e-5;
        case SkinRoughness::smooth_molded_composite:
            return 0.052e-5;
    }
    return 0.634e-5;
}

std::string_view to_string(SkinRoughness roughness) {
    switch (roughness) {
        case SkinRoughness::camouflage_paint:
            return "camouflage_paint";
        case SkinRoughness::smooth_paint:
            return "smooth_paint";
        case SkinRoughness::production_sheet_metal:
            return "production_sheet_metal";
        case SkinRoughness::polished_sheet_metal:
            return "polished_sheet_metal";
        case SkinRoughness::smooth_molded_composite:
            return "smooth_molded_composite";
    }
    return "?";
}

double skin_friction(double reynolds, double mach, double length, double roughness_height,
                     double laminar_fraction) {
    require(std::isfinite(laminar_fraction) && laminar_fraction >= 0.0 && laminar_fraction <= 1.0,
            "skin friction: laminar fraction", laminar_fraction, "a fraction in [0, 1]");
    // The laminar part sees the actual Reynolds number (roughness does not act on a laminar layer
    // that stays laminar); the turbulent part the smaller of it and the roughness cut-off.
    const double re_turbulent = std::min(reynolds, cutoff_reynolds(length, roughness_height));
    const double turbulent = turbulent_skin_friction(re_turbulent, mach);
    if (laminar_fraction == 0.0) return turbulent;
    return laminar_fraction * laminar_skin_friction(reynolds) +
           (1.0 - laminar_fraction) * turbulent;
}

double form_factor_mach_term(double mach, bool floor_at_one) {
    require_mach(mach, "form factor: ");
    const double t = 1.34 * std::pow(mach, 0.18);
    return floor_at_one ? std::max(t, 1.0) : t;
}

double surface_form_factor(double thickness_ratio, double max_thickness_position,
                           double max_thickness_sweep, double mach, bool floor_mach_term) {
    require(std::isfinite(thickness_ratio) && thickness_ratio >= 0.0 && thickness_ratio < 0.5,
            "form factor: thickness ratio", thickness_ratio, "t/c in [0, 0.5)");
    require(std::isfinite(max_thickness_position) && max_thickness_position > 0.0 &&
                max_thickness_position < 1.0,
            "form factor: position of maximum thickness", max_thickness_position,
            "a chord fraction in (0, 1)");
    require(std::isfinite(max_thickness_sweep) && std::abs(max_thickness_sweep) < pi / 2.0,
            "form factor: sweep of the maximum-thickness line [rad]", max_thickness_sweep,
            "an angle within (-pi/2, pi/2)");
    const double tc = thickness_ratio;
    const double thickness_term = 1.0 + 0.6 / max_thickness_position * tc + 100.0 * std::pow(tc, 4);
    return thickness_term * form_factor_mach_term(mach, floor_mach_term) *
           std::pow(std::cos(max_thickness_sweep), 0.28);
}

std::string_view to_string(BodyFormFactor law) {
    return law == BodyFormFactor::classic ? "classic" : "raymer_2018";
}

double body_form_factor(double fineness_ratio, BodyFormFactor law) {
    require_positive(fineness_ratio, "body form factor: fineness ratio",
                     "a positive length over equivalent diameter");
    const double f = fineness_ratio;
    if (law == BodyFormFactor::raymer_2018) return 0.9 + 5.0 / std::pow(f, 1.5) + f / 400.0;
    return 1.0 + 60.0 / (f * f * f) + f / 400.0;
}

double max_thickness_position(const geometry::Airfoil& airfoil) {
    if (airfoil.is_naca()) {
        const auto& d = airfoil.designation();
        if (d.family == geometry::NacaFamily::six_series && d.min_pressure_tenths > 0)
            return d.min_pressure_tenths / 10.0;
        return 0.3;
    }
    // Coordinate airfoil (Selig order): split at the leading edge (smallest x) into the upper
    // and lower surfaces, both ordered by increasing x, and look for the largest distance.
    const auto pts = airfoil.coordinates();
    const auto le = static_cast<std::size_t>(
        std::min_element(pts.begin(), pts.end(),
                         [](const auto& a, const auto& b) { return a.x() < b.x(); }) -
        pts.begin());
    std::vector<Eigen::Vector2d> upper(pts.begin(), pts.begin() + static_cast<long>(le) + 1);
    std::reverse(upper.begin(), upper.end());
    const std::vector<Eigen::Vector2d> lower(pts.begin() + static_cast<long>(le), pts.end());
    if (upper.size() < 2 || lower.size() < 2) return 0.3;
    double best = -1.0, x_best = 0.3;
    const int n = 400;
    for (int i = 1; i < n; ++i) {
        const double x = 0.5 * (1.0 - std::cos(pi * i / n));
        const double t = polyline_y(upper, x) - polyline_y(lower, x);
        if (t > best) best = t, x_best = x;
    }
    return x_best;
}

double ellipse_perimeter(double width, double height) {
    require(std::isfinite(width) && width >= 0.0, "ellipse perimeter: width", width,
            "a non-negative width [m]");
    require(std::isfinite(height) && height >= 0.0, "ellipse perimeter: height", height,
            "a non-negative height [m]");
    const double a = 0.5 * width, b = 0.5 * height;
    return pi * (3.0 * (a + b) - std::sqrt((3.0 * a + b) * (a + 3.0 * b)));
}

double fuselage_wetted_area(const geometry::Fuselage& fuselage) {
    const auto& st = fuselage.stations;
    double area = 0.0;
    for (std::size_t i = 0; i + 1 < st.size(); ++i) {
        const auto& s0 = st[i];
        const auto& s1 = st[i + 1];
        const double dx = s1.x - s0.x;
        require(std::isfinite(dx) && dx > 0.0, "fuselage wetted area: station interval", dx,
                "stations with x strictly increasing");
        // Semi-axes and centre are linear in x over the interval.
        const double a0 = 0.5 * s0.width, a1 = 0.5 * s1.width;
        const double b0 = 0.5 * s0.height, b1 = 0.5 * s1.height;
        const double da = (a1 - a0) / dx, db = (b1 - b0) / dx;
        const double dz = (s1.z_centre - s0.z_centre) / dx;
        double sum = 0.0;
        for (std::size_t k = 0; k < gauss_nodes.size(); ++k) {
            for (const double sign : {-1.0, 1.0}) {
                const double t = 0.5 * (1.0 + sign * gauss_nodes[k]);
                const double a = lerp(a0, a1, t), b = lerp(b0, b1, t);
                if (a + b <= 0.0) continue;
                const double p = ellipse_perimeter(2.0 * a, 2.0 * b);
                // Slope of the equivalent radius P / (2 pi) along x.
                const double r_slope =
                    (perimeter_da(a, b) * da + perimeter_da(b, a) * db) / (2.0 * pi);
                sum += gauss_weights[k] * p * std::sqrt(1.0 + r_slope * r_slope + 0.5 * dz * dz);
            }
        }
        area += 0.5 * dx * sum;
    }
    return area;
}

std::optional<geometry::FuselageStation> fuselage_section_at(const geometry::Fuselage& fuselage,
                                                             double x) {
    const auto& st = fuselage.stations;
    if (st.empty() || !(x >= st.front().x) || !(x <= st.back().x)) return std::nullopt;
    std::size_t i = 0;
    while (i + 2 < st.size() && x > st[i + 1].x) ++i;
    if (st.size() == 1) return st.front();
    const auto& s0 = st[i];
    const auto& s1 = st[i + 1];
    const double t = s1.x > s0.x ? (x - s0.x) / (s1.x - s0.x) : 0.0;
    geometry::FuselageStation s;
    s.x = x;
    s.width = lerp(s0.width, s1.width, t);
    s.height = lerp(s0.height, s1.height, t);
    s.z_centre = lerp(s0.z_centre, s1.z_centre, t);
    return s;
}

namespace {

// Area-weighted section data of the part of `w` beyond spanwise coordinate `start` (one copy).
// Thickness and the chordwise distance to the maximum-thickness point vary linearly between
// sections (the surface is ruled), so their integrals over the span are exact trapezoids.
ExposedPlanform integrate_beyond(const geometry::LiftingSurface& w, double start) {
    ExposedPlanform e;
    e.start = start;
    double area = 0.0, thickness = 0.0, distance = 0.0, sweep = 0.0;
    for (std::size_t i = 0; i + 1 < w.sections.size(); ++i) {
        const auto& p0 = w.sections[i];
        const auto& p1 = w.sections[i + 1];
        const double s0 = w.spanwise(p0), s1 = w.spanwise(p1);
        const double lo = std::max(s0, start);
        if (!(lo < s1)) continue;
        const double u = (lo - s0) / (s1 - s0);
        const double t0 = p0.chord * p0.airfoil.thickness_ratio();
        const double t1 = p1.chord * p1.airfoil.thickness_ratio();
        const double d0 = p0.chord * max_thickness_position(p0.airfoil);
        const double d1 = p1.chord * max_thickness_position(p1.airfoil);
        const double ds = s1 - lo;
        const double panel = 0.5 * ds * (lerp(p0.chord, p1.chord, u) + p1.chord);
        area += panel;
        thickness += 0.5 * ds * (lerp(t0, t1, u) + t1);
        distance += 0.5 * ds * (lerp(d0, d1, u) + d1);
        // The maximum-thickness line is straight over the panel.
        const double xm0 = p0.leading_edge.x() + d0, xm1 = p1.leading_edge.x() + d1;
        sweep += panel * std::atan2(xm1 - xm0, s1 - s0);
    }
    e.area = area;
    if (area > 0.0) {
        e.thickness_ratio = thickness / area;
        e.max_thickness_position = distance / area;
        e.max_thickness_sweep = sweep / area;
    }
    return e;
}

}  // namespace

ExposedPlanform exposed_planform(const geometry::LiftingSurface& surface,
                                 const geometry::Fuselage& fuselage) {
    const auto& secs = surface.sections;
    if (secs.size() < 2) {
        throw InputError(fmt::format(
            "viscous drag: surface '{}' has {} section(s); expected at least 2 (root and tip)",
            surface.name, secs.size()));
    }
    for (std::size_t i = 0; i < secs.size(); ++i) {
        require_positive(
            secs[i].chord,
            fmt::format("viscous drag: surface '{}' section {} chord", surface.name, i),
            "a positive chord [m]");
        if (i + 1 < secs.size()) {
            const double ds = surface.spanwise(secs[i + 1]) - surface.spanwise(secs[i]);
            require(ds > 0.0,
                    fmt::format("viscous drag: surface '{}' sections {}-{} spanwise step",
                                surface.name, i, i + 1),
                    ds,
                    fmt::format("sections ordered root to tip with {} strictly increasing",
                                surface.vertical ? "z" : "y"));
        }
    }
    const auto& root = secs.front();
    double start = surface.spanwise(root);
    const auto body = fuselage_section_at(fuselage, root.leading_edge.x() + 0.5 * root.chord);
    if (body && body->width > 0.0 && body->height > 0.0) {
        const double a = 0.5 * body->width, b = 0.5 * body->height;
        const double ry = root.leading_edge.y() / a;
        const double rz = (root.leading_edge.z() - body->z_centre) / b;
        if (ry * ry + rz * rz < 1.0) {
            // Root inside the body: cut where the body surface is, at the root's height (side of
            // the body) for horizontal surfaces, at the root's y (top of the body) for fins.
            const double cut = surface.vertical ? body->z_centre + b * std::sqrt(1.0 - ry * ry)
                                                : a * std::sqrt(1.0 - rz * rz);
            start = std::max(start, cut);
        }
    }
    ExposedPlanform e = integrate_beyond(surface, start);
    if (!(e.area > 0.0)) {
        // Wholly inside the body: no exposed area; report the section data of the whole surface.
        e = integrate_beyond(surface, surface.spanwise(root));
        e.start = start;
        e.area = 0.0;
    }
    e.area *= surface.n_copies();
    return e;
}

// ------------------------------------------------------------------------------------- build-up

std::string_view to_string(ComponentKind kind) {
    switch (kind) {
        case ComponentKind::wing:
            return "wing";
        case ComponentKind::tail:
            return "tail";
        case ComponentKind::fuselage:
            return "fuselage";
    }
    return "?";
}

const ComponentDrag* ViscousDrag::find(std::string_view name) const {
    for (const auto& c : components)
        if (c.name == name) return &c;
    return nullptr;
}

namespace {

void check_options(const ViscousDragOptions& o, const geometry::AircraftGeometry& g) {
    if (o.roughness_height_override) {
        require_positive(*o.roughness_height_override, "viscous drag: roughness height override",
                         "a positive height [m]");
    }
    for (const auto& [value, what] :
         {std::pair{o.laminar_fraction_surfaces, "laminar_fraction_surfaces"},
          std::pair{o.laminar_fraction_fuselage, "laminar_fraction_fuselage"}}) {
        require(std::isfinite(value) && value >= 0.0 && value <= 1.0,
                fmt::format("viscous drag: {}", what), value, "a fraction in [0, 1]");
    }
    for (const auto& [value, what] :
         {std::pair{o.interference_wing, "interference_wing"},
          std::pair{o.interference_tail, "interference_tail"},
          std::pair{o.interference_fuselage, "interference_fuselage"}}) {
        require_positive(value, fmt::format("viscous drag: {}", what),
                         "a positive interference factor (Raymer: 1.0 to about 1.5)");
    }
    require(std::isfinite(o.leakage_protuberance_fraction) &&
                o.leakage_protuberance_fraction >= 0.0 && o.leakage_protuberance_fraction <= 0.5,
            "viscous drag: leakage_protuberance_fraction", o.leakage_protuberance_fraction,
            "a fraction of the total in [0, 0.5] (Raymer Table 12.8: 0.02 to 0.15)");

    std::vector<std::string> names;
    for (const auto& s : g.surfaces) names.push_back(s.name);
    if (!g.fuselage.empty()) names.emplace_back("fuselage");
    const std::string listed = names.empty() ? "(none)" : fmt::format("{}", fmt::join(names, ", "));
    for (const auto& [name, q] : o.interference_by_name) {
        if (std::find(names.begin(), names.end(), name) == names.end()) {
            throw InputError(fmt::format(
                "viscous drag: interference factor for '{}', which is not a component; expected "
                "one of: {}",
                name, listed));
        }
        require_positive(q, fmt::format("viscous drag: interference factor of '{}'", name),
                         "a positive interference factor");
    }
    if (!o.main_wing.empty() && !g.find_surface(o.main_wing)) {
        std::vector<std::string> surfaces;
        for (const auto& s : g.surfaces) surfaces.push_back(s.name);
        throw InputError(fmt::format(
            "viscous drag: main wing '{}' is not a lifting surface; expected one of: {}",
            o.main_wing,
            surfaces.empty() ? "(none)" : fmt::format("{}", fmt::join(surfaces, ", "))));
    }
}

// Name of the main wing: the option, else the horizontal surface of largest planform area.
std::string main_wing_name(const geometry::AircraftGeometry& g, const ViscousDragOptions& o) {
    if (!o.main_wing.empty()) return o.main_wing;
    std::string best;
    double best_area = -1.0;
    for (const auto& s : g.surfaces) {
        if (s.vertical || s.sections.size() < 2) continue;
        const double a = s.planform_area();
        if (a > best_area) best_area = a, best = s.name;
    }
    return best;
}

void check_component_reynolds(const std::string& name, double re, double length,
                              std::string_view length_name) {
    if (!(re >= min_component_reynolds)) {
        throw InputError(fmt::format(
            "viscous drag: component '{}': Reynolds number {:g} on its {:g} m {}; expected at "
            "least {:g} (the flat-plate correlations are fits for about 1e5 to 1e9)",
            name, re, length, length_name, min_component_reynolds));
    }
}

}  // namespace

ViscousDrag viscous_drag(const geometry::AircraftGeometry& geometry, double reference_area,
                         double mach, double reynolds_per_metre,
                         const ViscousDragOptions& options) {
    require_positive(reference_area, "viscous drag: reference area", "a positive area [m^2]");
    require_mach(mach, "viscous drag: ");
    require_positive(reynolds_per_metre, "viscous drag: Reynolds number per metre",
                     "a positive number rho V / mu [1/m]");
    check_options(options, geometry);

    const double k =
        options.roughness_height_override.value_or(roughness_height(options.roughness));
    const std::string wing = main_wing_name(geometry, options);
    auto interference = [&](const std::string& name, double fallback) {
        const auto it = options.interference_by_name.find(name);
        return it == options.interference_by_name.end() ? fallback : it->second;
    };

    ViscousDrag out;
    out.reference_area = reference_area;
    out.mach = mach;
    out.reynolds_per_metre = reynolds_per_metre;

    for (const auto& s : geometry.surfaces) {
        ComponentDrag c;
        c.name = s.name;
        c.kind = s.name == wing ? ComponentKind::wing : ComponentKind::tail;
        const ExposedPlanform e = exposed_planform(s, geometry.fuselage);
        c.length = s.mean_aerodynamic_chord();
        c.reynolds = reynolds_per_metre * c.length;
        check_component_reynolds(c.name, c.reynolds, c.length, "mean aerodynamic chord");
        c.cutoff_reynolds = cutoff_reynolds(c.length, k);
        c.laminar_fraction = options.laminar_fraction_surfaces;
        c.skin_friction = skin_friction(c.reynolds, mach, c.length, k, c.laminar_fraction);
        c.exposed_area = e.area;
        c.thickness_ratio = e.thickness_ratio;
        c.max_thickness_position = e.max_thickness_position;
        c.max_thickness_sweep = e.max_thickness_sweep;
        c.form_factor =
            surface_form_factor(e.thickness_ratio, e.max_thickness_position, e.max_thickness_sweep,
                                mach, options.floor_form_factor_mach_term);
        c.interference =
            interference(c.name, c.kind == ComponentKind::wing ? options.interference_wing
                                                               : options.interference_tail);
        c.wetted_area =
            e.area * (1.977 + 0.52 * std::max(e.thickness_ratio, wetted_area_min_thickness));
        c.cd0 = c.skin_friction * c.form_factor * c.interference * c.wetted_area / reference_area;
        out.components.push_back(c);
    }

    if (!geometry.fuselage.empty()) {
        const auto& f = geometry.fuselage;
        ComponentDrag c;
        c.name = "fuselage";
        c.kind = ComponentKind::fuselage;
        c.length = f.length();
        double max_section = 0.0;  // width * height, proportional to the elliptic section area
        for (const auto& st : f.stations) max_section = std::max(max_section, st.width * st.height);
        require_positive(c.length, "viscous drag: fuselage length",
                         "a positive length (at least two stations)");
        require_positive(max_section, "viscous drag: fuselage largest width * height",
                         "a body with a section of positive area");
        // f = l / sqrt((4/pi) A_max) with A_max = (pi/4) w h (Raymer eq. 12.33).
        c.fineness_ratio = c.length / std::sqrt(max_section);
        c.reynolds = reynolds_per_metre * c.length;
        check_component_reynolds(c.name, c.reynolds, c.length, "length");
        c.cutoff_reynolds = cutoff_reynolds(c.length, k);
        c.laminar_fraction = options.laminar_fraction_fuselage;
        c.skin_friction = skin_friction(c.reynolds, mach, c.length, k, c.laminar_fraction);
        c.form_factor = body_form_factor(c.fineness_ratio, options.body_form_factor);
        c.interference = interference(c.name, options.interference_fuselage);
        c.wetted_area = fuselage_wetted_area(f);
        c.cd0 = c.skin_friction * c.form_factor * c.interference * c.wetted_area / reference_area;
        out.components.push_back(c);
    }

    for (const auto& c : out.components) out.components_cd0 += c.cd0;
    const double lp = options.leakage_protuberance_fraction;
    out.leakage_protuberance_cd0 = lp / (1.0 - lp) * out.components_cd0;
    out.cd0 = out.components_cd0 + out.leakage_protuberance_cd0;
    return out;
}

}  // namespace manta::vlm
