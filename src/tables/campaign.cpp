/// @file campaign.cpp
/// Reading and validation of campaign files (format: docs/formats.md#campaign-file).

#include "manta/tables/campaign.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"

namespace manta::tables {

namespace {

using core::ConfigMap;
using core::ConfigNode;
using core::NumberSpec;

constexpr int supported_schema_version = 1;

/// Ranger 2000 defaults of the issue: alpha -4..12 deg, M 0.1..0.6, beta -8..8 deg (486 entries).
const std::vector<double> default_alpha = linspace(core::deg(-4.0), core::deg(12.0), 9);
const std::vector<double> default_mach = linspace(0.1, 0.6, 6);
const std::vector<double> default_beta = linspace(core::deg(-8.0), core::deg(8.0), 9);

/// Strictly increasing check of a parsed axis.
void check_increasing(const ConfigNode& n, const std::vector<double>& v, double scale) {
    for (std::size_t i = 1; i < v.size(); ++i) {
        if (!(v[i] > v[i - 1])) {
            const ConfigNode e = n.is_sequence() ? n.element(i) : n;
            e.fail(fmt::format("does not exceed the previous breakpoint {:g}", v[i - 1] * scale),
                   "strictly increasing breakpoints");
        }
    }
}

/// An axis of breakpoints: a list, or {min, max, count}. Angles under `key` (radians) or
/// `key_deg` (degrees); returns radians for angles. `range` in the unit read (radians or plain).
std::optional<std::vector<double>> read_axis(ConfigMap& m, std::string_view key, bool angle,
                                             double lo, double hi, std::string_view unit,
                                             std::string* where = nullptr) {
    std::string used(key);
    double scale = 1.0;
    if (angle) {
        const std::string deg_key = std::string(key) + "_deg";
        const bool rad = m.has(key), deg = m.has(deg_key);
        if (rad && deg)
            m.fail(deg_key, fmt::format("duplicates '{}'", key),
                   fmt::format("either '{}' (radians) or '{}' (degrees), not both", key, deg_key));
        if (!rad && !deg) return std::nullopt;
        if (deg) {
            used = deg_key;
            scale = core::rad_to_deg;
        }
    } else if (!m.has(key)) {
        return std::nullopt;
    }
    const ConfigNode n = m.node().child(used);
    if (where) *where = n.where();
    const NumberSpec spec =
        NumberSpec::range(lo * scale, hi * scale, scale == 1.0 ? std::string(unit) : "deg");
    std::vector<double> v;
    if (n.is_map()) {
        ConfigMap r(n);
        const double a = r.number("min", spec);
        const double b = r.number("max", spec);
        const long count = r.integer("count", NumberSpec::range(2, 1000, "-"));
        r.finish();
        if (!(b > a)) r.fail("max", fmt::format("is not above min {:g}", a), "max > min");
        v = linspace(a, b, static_cast<int>(count));
    } else if (n.is_sequence()) {
        v = n.to_doubles(0, spec);
    } else {
        n.fail("is neither a list of breakpoints nor a range",
               "a list [a, b, ...] or {min: a, max: b, count: n}");
    }
    check_increasing(n, v, 1.0);
    for (double& x : v) x /= scale;
    return v;
}

surrogate::KrigingOptions read_kriging(ConfigMap& m, std::uint64_t seed) {
    surrogate::KrigingOptions o;
    o.seed = seed;
    const std::string corr = m.choice_or("correlation", "gaussian", {"gaussian", "matern52"});
    o.correlation =
        corr == "gaussian" ? surrogate::Correlation::gaussian : surrogate::Correlation::matern52;
    const std::string trend = m.choice_or("trend", "constant", {"constant", "linear"});
    o.trend = trend == "constant" ? surrogate::Trend::constant : surrogate::Trend::linear;
    if (m.has("nugget")) {
        const ConfigNode n = m.node().child("nugget");
        if (n.is_scalar() && n.value_text() == "estimate") {
            o.estimate_nugget = true;
        } else if (n.is_scalar() && !n.value_text().empty() &&
                   (std::isdigit(static_cast<unsigned char>(n.value_text()[0])) ||
                    n.value_text()[0] == '.')) {
            o.nugget = n.to_double(NumberSpec::range(0.0, 0.1, "-"));
        } else {
            n.fail("is neither a number nor 'estimate'",
                   "a relative nugget in [0, 0.1], or 'estimate' (maximum likelihood)");
        }
    }
    o.restarts =
        static_cast<int>(m.integer_or("restarts", o.restarts, NumberSpec::range(1, 100, "-")));
    m.finish();
    return o;
}

StaticPlan read_static(ConfigMap& m) {
    StaticPlan p;
    p.alpha =
        read_axis(m, "alpha", true, -core::pi / 2, core::pi / 2, "rad").value_or(default_alpha);
    p.mach = read_axis(m, "mach", false, 0.0, 0.95, "-").value_or(default_mach);
    p.beta = read_axis(m, "beta", true, -core::pi / 2, core::pi / 2, "rad").value_or(default_beta);
    if (m.has("initial_design")) {
        ConfigMap d = m.map("initial_design");
        p.initial_size = static_cast<int>(
            d.integer_or("size", p.initial_size, NumberSpec::range(2, 10000, "-")));
        p.seed = static_cast<std::uint64_t>(
            d.integer_or("seed", 1, NumberSpec::range(0, 2147483647.0, "-")));
        d.finish();
    }
    p.budget =
        static_cast<int>(m.integer_or("budget", p.budget, NumberSpec::range(2, 100000, "-")));
    const std::string c = m.choice_or("criterion", "max_mse", {"max_mse", "ei", "random"});
    p.criterion = c == "max_mse" ? InfillCriterion::max_mse
                  : c == "ei"    ? InfillCriterion::ei
                                 : InfillCriterion::random;
    p.batch = static_cast<int>(m.integer_or("batch", 0, NumberSpec::range(0, 1000, "-")));
    p.cv_threshold = m.number_or("cv_threshold", 0.0, NumberSpec::range(0.0, 1.0, "-"));
    if (m.has("ei")) {
        ConfigMap e = m.map("ei");
        p.ei_coefficient = e.choice_or("coefficient", "CL", {"CL", "CD", "CY", "Cl", "Cm", "Cn"});
        p.ei_maximise = e.choice_or("sense", "min", {"min", "max"}) == "max";
        e.finish();
    }
    if (m.has("kriging")) {
        ConfigMap k = m.map("kriging");
        p.kriging = read_kriging(k, p.seed);
    } else {
        p.kriging.seed = p.seed;
    }
    m.finish();
    const std::size_t entries = p.alpha.size() * p.mach.size() * p.beta.size();
    if (static_cast<std::size_t>(p.budget) > entries)
        m.fail("budget", fmt::format("exceeds the {} entries of the table", entries),
               "a budget no larger than the number of table entries");
    if (p.initial_size > p.budget)
        throw ConfigError(
            fmt::format("{}: initial design size {} exceeds the budget {}; expected size <= budget",
                        m.node().where(), p.initial_size, p.budget));
    return p;
}

AnalyticParameters read_analytic(ConfigMap& m) {
    AnalyticParameters p;
    const NumberSpec any = NumberSpec::any("-");
    p.CL_alpha = m.number_or("CL_alpha", p.CL_alpha, any);
    p.stall_alpha = m.angle_or("stall_alpha", p.stall_alpha, NumberSpec::range(0.0, 1.5, "rad"));
    p.stall_lift = m.number_or("stall_lift", p.stall_lift, any);
    p.Cm_alpha = m.number_or("Cm_alpha", p.Cm_alpha, any);
    p.Cm_de = m.number_or("Cm_de", p.Cm_de, any);
    p.Cn_beta = m.number_or("Cn_beta", p.Cn_beta, any);
    if (m.has_angle("fail_above_alpha"))
        p.fail_above_alpha = m.angle("fail_above_alpha", NumberSpec::any("rad"));
    p.delay_s = m.number_or("delay", 0.0, NumberSpec::range(0.0, 60.0, "s"));
    m.finish();
    return p;
}

SourceSpec read_source(ConfigMap& m, const std::filesystem::path& base) {
    SourceSpec s;
    s.where = m.node().where();
    const std::string type = m.choice("type", {"analytic", "vlm", "euler"});
    s.type = type == "vlm"     ? SourceType::vlm
             : type == "euler" ? SourceType::euler
                               : SourceType::analytic;
    auto resolve = [&](const std::filesystem::path& p) {
        return p.is_absolute() || base.empty() ? p : base / p;
    };
    if (s.type == SourceType::euler) {
        const ConfigNode mesh_node = m.child("mesh");
        if (mesh_node.is_map()) {
            // The campaign meshes the aircraft file itself.
            ConfigMap g(mesh_node);
            s.mesh_model = g.choice_or("model", "half", {"half", "full"});
            s.mesh_level = g.choice_or("level", "coarse", {"coarse", "medium", "fine"});
            s.mesh_size_factor = g.number_or("size_factor", 1.0, NumberSpec::range(0.25, 8.0, "-"));
            g.finish();
            if (!m.has("aircraft"))
                m.fail("mesh",
                       "is a mesh to generate ({model, level}) but the source names no "
                       "aircraft",
                       "source.aircraft: the aircraft file to mesh, or mesh: a mesh file");
            s.aircraft = resolve(m.string("aircraft"));
        } else {
            s.mesh = resolve(m.string("mesh"));
            if (m.has("aircraft"))
                m.fail("aircraft", "is given with a mesh file",
                       "aircraft only with mesh: {model, level} (the campaign meshes it)");
        }
        if (m.has("config")) s.cfd_config = resolve(m.string("config"));
        if (m.has("launcher")) {
            s.launcher = m.string("launcher");
            s.launched = true;
        }
    } else if (s.type == SourceType::vlm) {
        s.aircraft = resolve(m.string("aircraft"));
        if (m.has("lattice")) {
            ConfigMap l = m.map("lattice");
            s.n_chord = static_cast<int>(
                l.integer_or("n_chord", s.n_chord, NumberSpec::range(1, 100, "-")));
            s.strip_width =
                l.number_or("strip_width", s.strip_width, NumberSpec::range(0.001, 0.5, "-"));
            l.finish();
        }
        s.viscous = m.boolean_or("viscous", true);
    } else if (m.has("parameters")) {
        ConfigMap p = m.map("parameters");
        s.analytic = read_analytic(p);
    }
    m.finish();
    return s;
}

ControlPlan read_control(ConfigMap& m, aero::Axis axis, const StaticPlan& st) {
    ControlPlan c;
    c.control = axis;
    auto d = read_axis(m, "deflection", true, -core::pi / 2, core::pi / 2, "rad", &c.where);
    if (!d) {
        throw ConfigError(fmt::format(
            "{}: missing required key '{}.deflection_deg' (or 'deflection' in radians); expected "
            "the deflection breakpoints, a list or {{min, max, count}}",
            m.node().where(), m.node().key_path()));
    }
    c.deflection = *d;
    // The increment is zero at zero deflection: the axis always holds 0.
    if (std::find(c.deflection.begin(), c.deflection.end(), 0.0) == c.deflection.end()) {
        c.deflection.push_back(0.0);
        std::sort(c.deflection.begin(), c.deflection.end());
    }
    if (c.deflection.size() < 2)
        m.fail("deflection_deg", "gives only zero deflection", "at least one non-zero deflection");
    c.alpha = read_axis(m, "alpha", true, -core::pi / 2, core::pi / 2, "rad").value_or(st.alpha);
    c.mach = read_axis(m, "mach", false, 0.0, 0.95, "-").value_or(st.mach);
    c.samples =
        static_cast<int>(m.integer_or("samples", c.samples, NumberSpec::range(2, 10000, "-")));
    c.seed = static_cast<std::uint64_t>(
        m.integer_or("seed", static_cast<long>(c.seed), NumberSpec::range(0, 2147483647.0, "-")));
    m.finish();
    const std::size_t deflected = c.alpha.size() * c.mach.size() * (c.deflection.size() - 1);
    if (static_cast<std::size_t>(c.samples) > deflected)
        m.fail("samples", fmt::format("exceeds the {} deflected entries of the table", deflected),
               "no more samples than deflected table entries");
    return c;
}

}  // namespace

std::vector<double> linspace(double lo, double hi, int count) {
    std::vector<double> v(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i)
        v[static_cast<std::size_t>(i)] =
            i == count - 1 ? hi : lo + (hi - lo) * static_cast<double>(i) / (count - 1);
    for (double& x : v)
        if (x == 0.0) x = 0.0;  // no negative zero
    // Snap rounding noise to zero so that a symmetric range holds an exact 0 breakpoint.
    for (double& x : v)
        if (std::abs(x) < 1e-12 * std::max(std::abs(lo), std::abs(hi))) x = 0.0;
    return v;
}

Campaign parse_campaign(std::string_view text, const std::string& source,
                        const std::filesystem::path& base) {
    ConfigMap root(ConfigNode::parse_string(text, source));
    Campaign c;
    const long version = root.integer("schema_version", NumberSpec::any("-"));
    if (version != supported_schema_version)
        root.fail("schema_version", "is an unsupported campaign format version",
                  fmt::format("{} (this MANTA reads version {})", supported_schema_version,
                              supported_schema_version));
    c.name = root.string("name");
    c.description = root.string_or("description", "");
    {
        ConfigMap s = root.map("source");
        c.source = read_source(s, base);
    }
    if (root.has("flight_condition")) {
        ConfigMap f = root.map("flight_condition");
        c.altitude = f.number_or("altitude", 0.0, NumberSpec::range(-5000.0, 86000.0, "m"));
        f.finish();
    }
    if (root.has("static")) {
        ConfigMap s = root.map("static");
        c.static_table = read_static(s);
    } else {
        c.static_table.alpha = default_alpha;
        c.static_table.mach = default_mach;
        c.static_table.beta = default_beta;
        c.static_table.kriging.seed = c.static_table.seed;
    }
    // Every source fills every section: the Euler source deforms its mesh by the CFD
    // configuration's control surfaces and solves rotation rates in the rotating frame, in
    // process or, with source.launcher, each sample a `manta cfd` job with the deflections and
    // rates on its command line.
    if (root.has("controls")) {
        ConfigMap ctl = root.map("controls");
        for (const aero::Axis a : {aero::Axis::elevator, aero::Axis::aileron, aero::Axis::rudder}) {
            const std::string key(aero::to_string(a));
            if (!ctl.has(key)) continue;
            ConfigMap cm = ctl.map(key);
            c.controls.push_back(read_control(cm, a, c.static_table));
        }
        ctl.finish();
    }
    if (root.has("dynamic")) {
        ConfigMap d = root.map("dynamic");
        DynamicPlan p;
        p.alpha = read_axis(d, "alpha", true, -core::pi / 2, core::pi / 2, "rad")
                      .value_or(c.static_table.alpha);
        p.mach = read_axis(d, "mach", false, 0.0, 0.95, "-").value_or(c.static_table.mach);
        p.rate_step = d.number_or("rate_step", p.rate_step, NumberSpec::range(1e-6, 0.2, "-"));
        if (p.rate_step <= 0.0) d.fail("rate_step", "is not positive", "a step > 0");
        d.finish();
        c.dynamic = p;
    }
    if (root.has("output")) {
        ConfigMap o = root.map("output");
        c.output.extrapolation =
            o.choice_or("extrapolation", "clamp", {"clamp", "linear"}) == "clamp"
                ? aero::Extrapolation::clamp
                : aero::Extrapolation::linear;
        if (o.has("plot_mach"))
            c.output.plot_mach = o.numbers("plot_mach", 0, NumberSpec::range(0.0, 0.95, "-"));
        if (const auto b = read_axis(o, "plot_beta", true, -core::pi / 2, core::pi / 2, "rad"))
            c.output.plot_beta = *b;
        o.finish();
    }
    root.finish();
    if (c.output.plot_mach.empty()) {
        const auto& m = c.static_table.mach;
        c.output.plot_mach = {m.front(), m.back()};
        if (m.size() > 2) c.output.plot_mach = {m[1], m[m.size() - 2]};
    }
    if (c.output.plot_beta.empty()) c.output.plot_beta = {0.0};
    return c;
}

Campaign read_campaign(const std::filesystem::path& file) {
    Campaign c = parse_campaign(core::read_file(file), file.string(), file.parent_path());
    c.file = file;
    return c;
}

void check_control_limits(const ControlPlan& plan, double lo, double hi) {
    const double a = plan.deflection.front(), b = plan.deflection.back();
    if (a < lo - 1e-12 || b > hi + 1e-12) {
        throw ConfigError(fmt::format(
            "{}: value '[{:g}, {:g}] deg' leaves the aircraft's {} limits; expected breakpoints "
            "within [{:g}, {:g}] deg",
            plan.where, a * core::rad_to_deg, b * core::rad_to_deg, aero::to_string(plan.control),
            lo * core::rad_to_deg, hi * core::rad_to_deg));
    }
}

}  // namespace manta::tables
