#include "manta/aircraft/aircraft.hpp"

#include "manta/flightdyn/eom.hpp"

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"

namespace manta::aircraft {

namespace {

using core::ConfigMap;
using core::ConfigNode;
using core::NumberSpec;

constexpr int supported_schema_version = 1;
/// Largest relative difference accepted between reference.area/span and the wing planform.
constexpr double reference_tolerance = 0.20;

// ------------------------------------------------------------------------------------ helpers

/// " (found 'ruder_deg' at line 12: a misspelling?)" when the map holds a key close to `key`
/// that is none of `valid`; else empty.
std::string misspelling_hint(const ConfigMap& m, std::string_view key,
                             std::initializer_list<std::string_view> valid) {
    std::vector<std::string> others;
    for (const auto& k : m.node().map_keys())
        if (std::find(valid.begin(), valid.end(), k) == valid.end()) others.push_back(k);
    const std::string guess = core::closest_match(key, others);
    if (guess.empty()) return {};
    return fmt::format(" (found '{}' at line {}: a misspelling?)", guess, m.node().key_line(guess));
}

/// A required choice between two spellings of one quantity (`a` or `b`, exactly one).
/// Returns true if `a` is given.
bool one_of(ConfigMap& m, std::string_view a, std::string_view b, std::string_view what_a,
            std::string_view what_b) {
    const bool has_a = m.has(a);
    const bool has_b = m.has(b);
    if (has_a && has_b) {
        m.fail(b, fmt::format("duplicates '{}'", a),
               fmt::format("either '{}' ({}) or '{}' ({}), not both", a, what_a, b, what_b));
    }
    if (!has_a && !has_b) {
        const std::string path = m.node().key_path();
        std::string hint = misspelling_hint(m, a, {a, b});
        if (hint.empty()) hint = misspelling_hint(m, b, {a, b});
        throw ConfigError(fmt::format("{}: missing required key '{}{}' ({}) or '{}' ({}){}",
                                      m.node().where(), path.empty() ? "" : path + ".", a, what_a,
                                      b, what_b, hint));
    }
    return has_a;
}

/// A list of angles from `key` (radians) or `key_deg` (degrees), strictly increasing, at least
/// `min_size` entries; bounds of `spec` in radians.
std::vector<double> angle_list(ConfigMap& m, std::string_view key, const NumberSpec& spec,
                               std::size_t min_size) {
    const std::string deg_key = std::string(key) + "_deg";
    const bool rad = m.has(key);
    const bool deg = m.has(deg_key);
    if (rad && deg) {
        m.fail(deg_key, fmt::format("duplicates '{}'", key),
               fmt::format("either '{}' (radians) or '{}' (degrees), not both", key, deg_key));
    }
    if (!rad && !deg) {
        const std::string path = m.node().key_path();
        throw ConfigError(fmt::format("{}: missing required key '{}{}' (or '{}' in degrees){}",
                                      m.node().where(), path.empty() ? "" : path + ".", key,
                                      deg_key, misspelling_hint(m, deg_key, {key, deg_key})));
    }
    const std::string used = deg ? deg_key : std::string(key);
    NumberSpec s = spec;
    if (deg) {
        if (s.min) *s.min *= core::rad_to_deg;
        if (s.max) *s.max *= core::rad_to_deg;
        s.unit = "deg";
    } else {
        s.unit = "rad";
    }
    std::vector<double> v;
    if (!deg) {
        // Check for degrees written under the radian key before the range check fires.
        const ConfigNode n = m.node().child(key);
        const auto raw = m.numbers(key, 0, NumberSpec::any("rad"));
        for (std::size_t i = 0; i < raw.size(); ++i) {
            if (std::abs(raw[i]) > 2.0 * core::pi) {
                n.element(i).fail("is in radians but looks like degrees",
                                  fmt::format("{} (write the list as '{}' to give degrees)",
                                              s.describe(), deg_key));
            }
        }
    }
    v = m.numbers(used, 0, s);
    const ConfigNode n = m.node().child(used);
    if (v.size() < min_size) {
        n.fail(fmt::format("has {} entr{}", v.size(), v.size() == 1 ? "y" : "ies"),
               fmt::format("at least {} breakpoints", min_size));
    }
    for (std::size_t i = 1; i < v.size(); ++i) {
        if (!(v[i] > v[i - 1]))
            n.element(i).fail(fmt::format("does not exceed the previous entry {:g}", v[i - 1]),
                              "strictly increasing values");
    }
    if (deg)
        for (double& x : v) x *= core::deg_to_rad;
    return v;
}

/// Strictly increasing list of plain numbers.
std::vector<double> increasing_list(ConfigMap& m, std::string_view key, const NumberSpec& spec,
                                    std::size_t min_size) {
    const auto v = m.numbers(key, 0, spec);
    const ConfigNode n = m.node().child(key);
    if (v.size() < min_size)
        n.fail(fmt::format("has {} entries", v.size()),
               fmt::format("at least {} breakpoints", min_size));
    for (std::size_t i = 1; i < v.size(); ++i) {
        if (!(v[i] > v[i - 1]))
            n.element(i).fail(fmt::format("does not exceed the previous entry {:g}", v[i - 1]),
                              "strictly increasing values");
    }
    return v;
}

/// [lower, upper] angle range with lower < upper, or `fallback` if absent.
std::array<double, 2> strict_angle_range_or(ConfigMap& m, std::string_view key,
                                            std::array<double, 2> fallback,
                                            const NumberSpec& spec) {
    if (!m.has_angle(key)) return fallback;
    const auto r = m.angle_range(key, spec);
    if (!(r[0] < r[1])) {
        const std::string deg_key = std::string(key) + "_deg";
        m.fail(m.node().has(deg_key) ? deg_key : std::string(key),
               "has equal lower and upper bounds", "[lower, upper] with lower < upper");
    }
    return r;
}

/// The wing a reference quantity refers to.
struct WingRef {
    const geometry::LiftingSurface* wing = nullptr;
    std::string name;
    bool explicit_name = false;
};

/// x of the point at fraction f of the reference chord aft of the wing's MAC leading edge; y 0;
/// z of the MAC leading edge.
Eigen::Vector3d mac_point(const WingRef& w, double f, double chord) {
    const Eigen::Vector3d le = w.wing->mac_leading_edge();
    return {le.x() + f * chord, 0.0, le.z()};
}

void require_wing(ConfigMap& m, std::string_view key, const WingRef& w) {
    if (!w.wing) {
        m.fail(
            key,
            fmt::format("needs a lifting surface named '{}' to locate the mean aerodynamic chord",
                        w.name),
            "a geometry.lifting_surfaces entry of that name (see reference.wing), or coordinates "
            "in metres");
    }
}

void check_inside_length(ConfigMap& m, std::string_view key, double x, double length,
                         std::string_view what) {
    if (x < 0.0 || x > length) {
        m.fail(key, fmt::format("puts the {} at x = {:.4g} m, outside the aircraft", what, x),
               fmt::format("a point with 0 <= x <= {:g} m (geometry.length)", length));
    }
}

// Plausible ranges of the dimensions read (issue 16, defect 12): beyond them a value is a unit
// slip or a typing error, refused with the range named. The largest aircraft flown set the
// bounds with a wide margin: Stratolaunch, span 117 m; An-225, wing area 905 m^2, maximum take-off
// mass 640 t, six engines of 229 kN each (Jane's All the World's Aircraft).
namespace plausible {
const NumberSpec length{0.0, 1000.0, true, false, "m"};
const NumberSpec chord{0.0, 100.0, true, false, "m"};
const NumberSpec area{0.0, 1e5, true, false, "m^2"};
const NumberSpec position{-1000.0, 1000.0, false, false, "m"};
const NumberSpec mass{0.0, 1e7, true, false, "kg"};
const NumberSpec inertia{0.0, 1e10, true, false, "kg m^2"};
const NumberSpec product{-1e10, 1e10, false, false, "kg m^2"};
const NumberSpec thrust{0.0, 1e7, true, false, "N"};
}  // namespace plausible

// ------------------------------------------------------------------------------------ sections

flightdyn::ReferenceGeometry parse_reference(ConfigMap& r, const geometry::AircraftGeometry& g,
                                             WingRef& w, Eigen::Vector3d& moment_reference) {
    flightdyn::ReferenceGeometry ref;
    ref.area = r.number("area", plausible::area);
    ref.span = r.number("span", plausible::length);
    ref.chord = r.number("chord", plausible::chord);
    w.explicit_name = r.has("wing");
    w.name = r.string_or("wing", "wing");
    w.wing = g.find_surface(w.name);
    if (w.explicit_name && !w.wing) {
        std::vector<std::string> names;
        for (const auto& s : g.surfaces) names.push_back(s.name);
        std::string expected =
            fmt::format("the name of a lifting surface: {}", fmt::join(names, ", "));
        const std::string guess = core::closest_match(w.name, names);
        if (!guess.empty()) expected += fmt::format(" (did you mean '{}'?)", guess);
        r.fail("wing", "is not a lifting surface", expected);
    }
    if (w.wing) {
        const double s_wing = w.wing->planform_area();
        if (std::abs(ref.area - s_wing) > reference_tolerance * s_wing) {
            r.fail(
                "area",
                fmt::format(
                    "differs by {:.0f} % from the planform area {:.4g} m^2 of lifting surface '{}'",
                    100.0 * (ref.area - s_wing) / s_wing, s_wing, w.name),
                fmt::format("a reference area within {:.0f} % of the wing planform area",
                            100 * reference_tolerance));
        }
        const double b_wing = w.wing->span();
        if (std::abs(ref.span - b_wing) > reference_tolerance * b_wing) {
            r.fail("span",
                   fmt::format("differs by {:.0f} % from the span {:.4g} m of lifting surface '{}'",
                               100.0 * (ref.span - b_wing) / b_wing, b_wing, w.name),
                   fmt::format("a reference span within {:.0f} % of the wing span",
                               100 * reference_tolerance));
        }
    }
    if (one_of(r, "moment_reference", "moment_reference_mac_fraction",
               "[x, y, z] in metres, geometry axes", "fraction of the mean aerodynamic chord")) {
        const auto p = r.vec3("moment_reference", plausible::position);
        moment_reference = Eigen::Vector3d(p[0], p[1], p[2]);
        check_inside_length(r, "moment_reference", p[0], g.length, "moment reference point");
    } else {
        const double f = r.number("moment_reference_mac_fraction",
                                  NumberSpec::range(-0.5, 1.5, "fraction of MAC"));
        require_wing(r, "moment_reference_mac_fraction", w);
        moment_reference = mac_point(w, f, ref.chord);
        check_inside_length(r, "moment_reference_mac_fraction", moment_reference.x(), g.length,
                            "moment reference point");
    }
    r.finish();
    return ref;
}

flightdyn::MassProperties parse_mass_case(ConfigMap& c, const geometry::AircraftGeometry& g,
                                          const WingRef& w, double chord) {
    flightdyn::MassProperties mp;
    mp.name = c.string("name");
    mp.mass = c.number("mass", plausible::mass);
    if (one_of(c, "cg", "cg_mac_fraction", "[x, y, z] in metres, geometry axes",
               "fraction of the mean aerodynamic chord")) {
        const auto p = c.vec3("cg", plausible::position);
        mp.cg_geom = Eigen::Vector3d(p[0], p[1], p[2]);
        check_inside_length(c, "cg", p[0], g.length, "centre of gravity");
    } else {
        const double f =
            c.number("cg_mac_fraction", NumberSpec::range(-0.5, 1.5, "fraction of MAC"));
        require_wing(c, "cg_mac_fraction", w);
        mp.cg_geom = mac_point(w, f, chord);
        check_inside_length(c, "cg_mac_fraction", mp.cg_geom.x(), g.length, "centre of gravity");
    }
    const double ixx = c.number("ixx", plausible::inertia);
    const double iyy = c.number("iyy", plausible::inertia);
    const double izz = c.number("izz", plausible::inertia);
    const double ixz = c.number_or("ixz", 0.0, plausible::product);
    const double ixy = c.number_or("ixy", 0.0, plausible::product);
    const double iyz = c.number_or("iyz", 0.0, plausible::product);
    // Triangle inequalities: each moment is at most the sum of the other two (holds in every
    // frame for a real body, as the diagonal moments are sums of second moments).
    const std::array<std::pair<const char*, double>, 3> m{
        {{"ixx", ixx}, {"iyy", iyy}, {"izz", izz}}};
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& [key, v] = m[k];
        const double others = m[(k + 1) % 3].second + m[(k + 2) % 3].second;
        if (v > others * (1.0 + 1e-12)) {
            c.fail(key,
                   fmt::format("exceeds the sum {:g} of the other two moments of inertia", others),
                   "moments satisfying the triangle inequalities ixx + iyy >= izz, iyy + izz >= "
                   "ixx, izz + ixx >= iyy");
        }
    }
    Eigen::Matrix3d inertia;
    inertia << ixx, -ixy, -ixz, -ixy, iyy, -iyz, -ixz, -iyz, izz;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
    const Eigen::Vector3d p = eig.eigenvalues();
    const std::string_view product_key = ixz != 0.0 ? "ixz" : (ixy != 0.0 ? "ixy" : "iyz");
    if (!(p.minCoeff() > 0.0)) {
        c.fail(product_key,
               fmt::format("makes the inertia tensor not positive definite (principal moments "
                           "{:g}, {:g}, {:g})",
                           p[0], p[1], p[2]),
               "products of inertia small enough that every principal moment is positive");
    }
    if (p[0] + p[1] < p[2] * (1.0 - 1e-12)) {
        c.fail(product_key,
               fmt::format(
                   "makes the principal moments {:g}, {:g}, {:g} violate the triangle inequality",
                   p[0], p[1], p[2]),
               "principal moments each at most the sum of the other two");
    }
    mp.inertia = inertia;
    c.finish();
    return mp;
}

void parse_mass(ConfigMap& m, const geometry::AircraftGeometry& g, const WingRef& w, double chord,
                AircraftDefinition& a) {
    const ConfigNode cases = m.sequence("cases");
    std::vector<std::string> names;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        ConfigMap c(cases.element(i));
        auto mp = parse_mass_case(c, g, w, chord);
        if (std::find(names.begin(), names.end(), mp.name) != names.end())
            cases.element(i).child("name").fail("is used by an earlier mass case",
                                                "a unique mass-case name");
        names.push_back(mp.name);
        a.mass_cases.push_back(std::move(mp));
    }
    const ConfigNode d = m.child("default_case");
    a.default_mass_case = d.to_string();
    if (std::find(names.begin(), names.end(), a.default_mass_case) == names.end()) {
        std::string expected = fmt::format("the name of a mass case: {}", fmt::join(names, ", "));
        const std::string guess = core::closest_match(a.default_mass_case, names);
        if (!guess.empty()) expected += fmt::format(" (did you mean '{}'?)", guess);
        d.fail("is not a mass case", expected);
    }
    m.finish();
}

flightdyn::EngineModel parse_engine(ConfigMap& e, const geometry::AircraftGeometry& g,
                                    Eigen::Vector3d& angular_momentum) {
    flightdyn::EngineModel eng;
    const std::string type = e.choice("type", {"lapse", "table"});
    static constexpr std::array<std::string_view, 4> lapse_keys = {
        "static_thrust", "density_exponent", "mach_a1", "mach_a2"};
    static constexpr std::array<std::string_view, 4> table_keys = {"altitude", "mach", "throttle",
                                                                   "thrust"};
    const auto& foreign = type == "lapse" ? table_keys : lapse_keys;
    for (const auto k : foreign) {
        if (e.has(k)) {
            e.fail(k,
                   fmt::format("belongs to engine type '{}'", type == "lapse" ? "table" : "lapse"),
                   fmt::format("only the keys of type '{}' ({})", type,
                               fmt::join(type == "lapse" ? lapse_keys : table_keys, ", ")));
        }
    }
    if (type == "lapse") {
        eng.type = flightdyn::EngineModel::Type::lapse;
        eng.static_thrust_sl = e.number("static_thrust", plausible::thrust);
        eng.density_exponent =
            e.number_or("density_exponent", 0.7, NumberSpec::range(0.0, 3.0, "-"));
        eng.mach_a1 = e.number_or("mach_a1", -0.3, NumberSpec::range(-5.0, 5.0, "-"));
        eng.mach_a2 = e.number_or("mach_a2", 0.15, NumberSpec::range(-5.0, 5.0, "-"));
        // The Mach factor must stay positive over the subsonic range the model is used in.
        for (int i = 0; i <= 20; ++i) {
            const double mach = 0.05 * i;
            if (1.0 + eng.mach_a1 * mach + eng.mach_a2 * mach * mach <= 0.0) {
                e.fail("mach_a1",
                       fmt::format("with mach_a2 = {:g} gives no thrust at M = {:.2f} (1 + a1 M + "
                                   "a2 M^2 <= 0)",
                                   eng.mach_a2, mach),
                       "coefficients keeping 1 + a1 M + a2 M^2 > 0 for 0 <= M <= 1");
            }
        }
    } else {
        eng.type = flightdyn::EngineModel::Type::table;
        eng.altitude = increasing_list(e, "altitude", NumberSpec::range(-5000.0, 84852.0, "m"), 1);
        eng.mach = increasing_list(e, "mach", NumberSpec::range(0.0, 5.0, "-"), 1);
        eng.throttle = increasing_list(e, "throttle", NumberSpec::range(0.0, 1.0, "-"), 2);
        const ConfigNode rows = e.sequence("thrust");
        const std::size_t n_rows = eng.altitude.size() * eng.mach.size();
        if (rows.size() != n_rows) {
            rows.fail(
                fmt::format("has {} rows", rows.size()),
                fmt::format("{} rows (one per altitude and Mach pair, altitude-major: {} altitudes "
                            "x {} Mach "
                            "numbers), each of {} thrusts [N] for the throttle settings",
                            n_rows, eng.altitude.size(), eng.mach.size(), eng.throttle.size()));
        }
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const auto row = rows.element(i).to_doubles(eng.throttle.size(), NumberSpec::any("N"));
            eng.thrust.insert(eng.thrust.end(), row.begin(), row.end());
        }
    }
    eng.thrust_angle = e.angle_or("thrust_angle", 0.0,
                                  NumberSpec::range(-core::deg(30.0), core::deg(30.0), "rad"));
    if (e.has("position")) {
        eng.position = e.vec3("position", plausible::position);
        eng.has_position = true;
        check_inside_length(e, "position", eng.position[0], g.length,
                            "thrust line's point of action");
    }
    if (e.has("angular_momentum")) {
        const auto h = e.vec3("angular_momentum", NumberSpec::any("kg m^2/s"));
        angular_momentum = Eigen::Vector3d(h[0], h[1], h[2]);
    }
    e.finish();
    return eng;
}

flightdyn::ControlLimits parse_controls(ConfigMap& c) {
    flightdyn::ControlLimits lim;
    const auto spec = NumberSpec::range(-core::deg(90.0), core::deg(90.0), "rad");
    lim.elevator = strict_angle_range_or(c, "elevator", lim.elevator, spec);
    lim.aileron = strict_angle_range_or(c, "aileron", lim.aileron, spec);
    lim.rudder = strict_angle_range_or(c, "rudder", lim.rudder, spec);
    if (c.has("throttle")) {
        const auto t = c.numbers("throttle", 2, NumberSpec::range(0.0, 1.0, "-"));
        if (!(t[0] < t[1]))
            c.fail("throttle", "has its lower bound not below its upper bound",
                   "[lower, upper] with lower < upper");
        lim.throttle = {t[0], t[1]};
    }
    c.finish();
    return lim;
}

Envelope parse_envelope(ConfigMap& e) {
    Envelope env;
    env.max_mach = e.number("max_mach", NumberSpec{0.0, 5.0, true, false, "-"});
    env.dive_mach = e.number("dive_mach", NumberSpec{0.0, 5.0, true, false, "-"});
    if (env.dive_mach < env.max_mach) {
        e.fail("dive_mach", fmt::format("is below max_mach = {:g}", env.max_mach),
               "a dive Mach number M_D >= the maximum operating Mach number M_MO");
    }
    env.ceiling = e.number("ceiling", NumberSpec{0.0, 84852.0, true, false, "m"});
    const auto spec = NumberSpec::range(-core::deg(90.0), core::deg(90.0), "rad");
    env.alpha = strict_angle_range_or(e, "alpha", env.alpha, spec);
    env.beta = strict_angle_range_or(e, "beta", env.beta, spec);
    e.finish();
    return env;
}

/// Every field of aero::LinearDerivatives by its YAML name.
struct DerivativeField {
    const char* name;
    double aero::LinearDerivatives::*member;
    const char* unit;
};
constexpr std::array<DerivativeField, 29> derivative_fields = {{
    {"CL_0", &aero::LinearDerivatives::CL_0, "-"},
    {"CL_alpha", &aero::LinearDerivatives::CL_alpha, "1/rad"},
    {"CL_q", &aero::LinearDerivatives::CL_q, "per q c/(2V)"},
    {"CL_alphadot", &aero::LinearDerivatives::CL_alphadot, "per alphadot c/(2V)"},
    {"CL_de", &aero::LinearDerivatives::CL_de, "1/rad"},
    {"CD_0", &aero::LinearDerivatives::CD_0, "-"},
    {"CD_k", &aero::LinearDerivatives::CD_k, "-"},
    {"CL_min_drag", &aero::LinearDerivatives::CL_min_drag, "-"},
    {"CD_de", &aero::LinearDerivatives::CD_de, "1/rad"},
    {"CY_beta", &aero::LinearDerivatives::CY_beta, "1/rad"},
    {"CY_p", &aero::LinearDerivatives::CY_p, "per p b/(2V)"},
    {"CY_r", &aero::LinearDerivatives::CY_r, "per r b/(2V)"},
    {"CY_da", &aero::LinearDerivatives::CY_da, "1/rad"},
    {"CY_dr", &aero::LinearDerivatives::CY_dr, "1/rad"},
    {"Cl_beta", &aero::LinearDerivatives::Cl_beta, "1/rad"},
    {"Cl_p", &aero::LinearDerivatives::Cl_p, "per p b/(2V)"},
    {"Cl_r", &aero::LinearDerivatives::Cl_r, "per r b/(2V)"},
    {"Cl_da", &aero::LinearDerivatives::Cl_da, "1/rad"},
    {"Cl_dr", &aero::LinearDerivatives::Cl_dr, "1/rad"},
    {"Cm_0", &aero::LinearDerivatives::Cm_0, "-"},
    {"Cm_alpha", &aero::LinearDerivatives::Cm_alpha, "1/rad"},
    {"Cm_q", &aero::LinearDerivatives::Cm_q, "per q c/(2V)"},
    {"Cm_alphadot", &aero::LinearDerivatives::Cm_alphadot, "per alphadot c/(2V)"},
    {"Cm_de", &aero::LinearDerivatives::Cm_de, "1/rad"},
    {"Cn_beta", &aero::LinearDerivatives::Cn_beta, "1/rad"},
    {"Cn_p", &aero::LinearDerivatives::Cn_p, "per p b/(2V)"},
    {"Cn_r", &aero::LinearDerivatives::Cn_r, "per r b/(2V)"},
    {"Cn_da", &aero::LinearDerivatives::Cn_da, "1/rad"},
    {"Cn_dr", &aero::LinearDerivatives::Cn_dr, "1/rad"},
}};

/// Derivatives a flyable model cannot do without; the others default to 0.
bool is_required_derivative(std::string_view name) {
    return name == "CL_alpha" || name == "CD_0" || name == "Cm_alpha";
}

void parse_aero(ConfigMap& a, const std::filesystem::path& base_dir, AircraftDefinition& def) {
    if (one_of(a, "database", "linear_derivatives", "path of an aero database file",
               "a map of stability derivatives")) {
        if (a.has("grids")) {
            a.fail("grids", "applies to 'linear_derivatives' only",
                   "no grids with an aero database file (its tables carry their own)");
        }
        const ConfigNode n = a.child("database");
        std::filesystem::path file = n.to_string();
        if (file.is_relative()) file = base_dir / file;
        try {
            def.aero = std::make_shared<const aero::AeroDatabase>(aero::AeroDatabase::read(file));
        } catch (const Error& e) {
            throw ConfigError(fmt::format("{}: aero database '{}' could not be read: {}", n.where(),
                                          n.value_text(), e.what()));
        }
        def.aero_label = a.string_or("label", def.aero->info().description.empty()
                                                  ? std::string("aero database")
                                                  : def.aero->info().description);
        a.finish();
        return;
    }
    ConfigMap ld = a.map("linear_derivatives");
    // Declare every key before reading any, so a misspelt required derivative is matched against
    // the keys that are really unknown ("CL_alfa"), not against ones read later ("Cm_alpha").
    for (const auto& f : derivative_fields) (void)ld.has(f.name);
    (void)ld.has("mach_ref");
    (void)ld.has("prandtl_glauert");
    aero::LinearDerivatives d;
    for (const auto& f : derivative_fields) {
        const auto spec = NumberSpec::range(-1000.0, 1000.0, f.unit);
        d.*(f.member) = is_required_derivative(f.name) ? ld.number(f.name, spec)
                                                       : ld.number_or(f.name, 0.0, spec);
    }
    if (d.CD_0 < 0.0) ld.fail("CD_0", "is negative", "a zero-lift drag coefficient >= 0");
    if (d.CD_k < 0.0) ld.fail("CD_k", "is negative", "an induced-drag factor >= 0 (1 / (pi e AR))");
    d.mach_ref = ld.number_or("mach_ref", 0.0, NumberSpec{0.0, 1.0, false, true, "-"});
    d.prandtl_glauert = ld.boolean_or("prandtl_glauert", false);
    ld.finish();

    ConfigMap gr = a.map("grids");
    aero::DerivativeGrids grids;
    const auto angle_spec = NumberSpec::range(-core::deg(90.0), core::deg(90.0), "rad");
    grids.alpha = angle_list(gr, "alpha", angle_spec, 2);
    grids.mach = increasing_list(gr, "mach", NumberSpec::range(0.0, 5.0, "-"), 2);
    grids.beta = angle_list(gr, "beta", angle_spec, 2);
    grids.elevator = angle_list(gr, "elevator", angle_spec, 2);
    grids.aileron = angle_list(gr, "aileron", angle_spec, 2);
    grids.rudder = angle_list(gr, "rudder", angle_spec, 2);
    if (d.prandtl_glauert && grids.mach.back() >= 0.95) {
        gr.fail("mach",
                fmt::format("reaches M = {:g} with prandtl_glauert: true", grids.mach.back()),
                "Mach numbers below 0.95 (the Prandtl-Glauert factor 1/sqrt(1 - M^2) is singular "
                "at M = 1)");
    }
    gr.finish();
    def.aero_label = a.string_or("label", "linear stability derivatives");
    a.finish();

    aero::DatabaseInfo info;
    info.name = def.name;
    info.description = def.aero_label;
    info.source = "linear-derivatives";
    try {
        def.aero = std::make_shared<const aero::AeroDatabase>(
            aero::AeroDatabase::from_derivatives(d, grids, info));
    } catch (const Error& e) {
        throw ConfigError(fmt::format("{}: the derivative model could not be tabulated: {}",
                                      a.node().child("linear_derivatives").where(), e.what()));
    }
}

AircraftDefinition parse(const ConfigNode& root_node, const std::filesystem::path& file,
                         const std::filesystem::path& base_dir) {
    ConfigMap root(root_node);
    // Declare the sections first so a misspelt section name is reported as such (with a
    // suggestion) before any "missing section" error.
    for (const char* k : {"schema_version", "name", "description", "reference", "geometry", "mass",
                          "engine", "controls", "environment", "envelope", "aero"})
        (void)root.has(k);
    root.finish();

    AircraftDefinition a;
    a.file = file;
    const ConfigNode v = root.child("schema_version");
    const long version = v.to_integer(NumberSpec::any("-"));
    if (version != supported_schema_version) {
        v.fail("is not a supported schema version",
               fmt::format("{} (this MANTA reads aircraft files of version {})",
                           supported_schema_version, supported_schema_version));
    }
    a.name = root.string("name");
    a.description = root.string_or("description", "");

    ConfigMap gm = root.map("geometry");
    a.geometry = geometry::parse_geometry(gm, base_dir);

    WingRef wing;
    ConfigMap rm = root.map("reference");
    a.reference = parse_reference(rm, a.geometry, wing, a.moment_reference_geom);

    ConfigMap mm = root.map("mass");
    parse_mass(mm, a.geometry, wing, a.reference.chord, a);

    ConfigMap em = root.map("engine");
    a.engine = parse_engine(em, a.geometry, a.engine_angular_momentum);

    if (auto c = root.optional_child("controls")) {
        ConfigMap cm(*c);
        a.limits = parse_controls(cm);
    }
    if (auto e = root.optional_child("environment")) {
        ConfigMap envm(*e);
        a.environment.gravity =
            envm.number_or("gravity", core::standard_gravity, NumberSpec::positive("m/s^2"));
        envm.finish();
    }
    if (auto e = root.optional_child("envelope")) {
        ConfigMap envm(*e);
        a.envelope = parse_envelope(envm);
    }
    ConfigMap am = root.map("aero");
    parse_aero(am, base_dir, a);
    root.finish();
    return a;
}

}  // namespace

AircraftDefinition load_aircraft(const std::filesystem::path& file) {
    const ConfigNode root = ConfigNode::parse_file(file);
    const std::filesystem::path base =
        file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
    return parse(root, file, base);
}

AircraftDefinition parse_aircraft(std::string_view yaml_text, const std::string& source,
                                  const std::filesystem::path& base_dir) {
    const ConfigNode root = ConfigNode::parse_string(yaml_text, source);
    return parse(root, source, base_dir);
}

const flightdyn::MassProperties& AircraftDefinition::mass_case(std::string_view name) const {
    const std::string_view wanted = name.empty() ? std::string_view(default_mass_case) : name;
    for (const auto& m : mass_cases)
        if (m.name == wanted) return m;
    std::vector<std::string> names;
    for (const auto& m : mass_cases) names.push_back(m.name);
    std::string hint;
    const std::string guess = core::closest_match(wanted, names);
    if (!guess.empty()) hint = fmt::format(" (did you mean '{}'?)", guess);
    throw InputError(fmt::format("aircraft '{}': no mass case '{}'{}; mass cases: {}", this->name,
                                 wanted, hint, fmt::join(names, ", ")));
}

flightdyn::FlightModel AircraftDefinition::flight_model(std::string_view mass_case_name) const {
    if (!aero)
        throw InputError(fmt::format(
            "aircraft '{}': has no aerodynamic model; expected an 'aero' section", name));
    flightdyn::FlightModel m;
    m.name = name;
    m.reference = reference;
    m.moment_reference_geom = moment_reference_geom;
    m.mass = mass_case(mass_case_name);
    m.engine = engine;
    m.engine_angular_momentum = engine_angular_momentum;
    m.aero = aero;
    m.limits = limits;
    m.environment = environment;
    flightdyn::finalize(m);  // derived flags (alpha-dot terms) and the model checks
    return m;
}

std::vector<aero::ModeLimit> AircraftDefinition::mode_limits() const {
    return {{"elevator", limits.elevator[0], limits.elevator[1]},
            {"aileron", limits.aileron[0], limits.aileron[1]},
            {"rudder", limits.rudder[0], limits.rudder[1]}};
}

}  // namespace manta::aircraft
