/// @file manoeuvre.cpp
/// Reading and validation of manoeuvre files (manoeuvre.hpp, docs/manoeuvres.md).

#include "manta/manoeuvres/manoeuvre.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numbers>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"

namespace manta::manoeuvres {

namespace {

using core::ConfigMap;
using core::ConfigNode;
using core::NumberSpec;

constexpr double kDeg = std::numbers::pi / 180.0;

/// A final condition written as `key` (SI) or `key_deg` (angles): a number (equality), a pair
/// [lower, upper], `entry` (equal to the entry value) or {entry_offset: [lo, hi]}.
/// Plausible magnitude of a final or intermediate target in its SI unit (issue 16, defect 12):
/// an angle compared on the circle within one turn (a heading change of 488 deg was wrapped to
/// 128 deg), the accumulated roll angle within ten turns (a barrel roll ends near -360 deg), a
/// speed below 1000 m/s, an altitude below 30 km (as the entry's), a distance within 1000 km.
double target_limit(std::string_view key, bool angle) {
    if (angle) return (key == "roll_angle" ? 20.0 : 2.0) * std::numbers::pi;
    if (key == "speed") return 1000.0;
    if (key == "altitude") return 30000.0;
    return 1e6;
}

Target read_target(ConfigMap& m, std::string_view key, bool angle, const std::string& unit) {
    Target t;
    const std::string deg_key = std::string(key) + "_deg";
    const bool plain = m.has(key);
    const bool in_deg = angle && m.has(deg_key);
    if (plain && in_deg) {
        m.fail(deg_key, fmt::format("is given together with '{}'", key), "one of the two");
    }
    if (!plain && !in_deg) return t;
    const std::string used = in_deg ? deg_key : std::string(key);
    const double factor = in_deg ? kDeg : 1.0;
    const std::string u = in_deg ? "deg" : unit;
    const ConfigNode n = m.child(used);
    const double limit =
        angle && in_deg ? (key == "roll_angle" ? 3600.0 : 360.0) : target_limit(key, angle);
    const NumberSpec spec = NumberSpec::range(-limit, limit, u);
    if (n.is_scalar() && n.to_string() == "entry") {
        t.kind = Target::Kind::entry;
        return t;
    }
    if (n.is_map()) {
        ConfigMap e(n);
        const auto off = e.numbers("entry_offset", 2, spec);
        e.finish();
        if (!(off[0] <= off[1])) {
            n.fail("has entry_offset lower above upper", "[lower, upper] with lower <= upper");
        }
        t.kind = Target::Kind::entry;
        t.lower = off[0] * factor;
        t.upper = off[1] * factor;
        return t;
    }
    if (n.is_sequence()) {
        const auto v = n.to_doubles(2, spec);
        if (!(v[0] <= v[1])) n.fail("has lower above upper", "[lower, upper] with lower <= upper");
        t.kind = Target::Kind::range;
        t.lower = v[0] * factor;
        t.upper = v[1] * factor;
        return t;
    }
    if (n.is_scalar() && !n.is_null()) {
        const double v = n.to_double(spec) * factor;
        t.kind = Target::Kind::range;
        t.lower = v;
        t.upper = v;
        return t;
    }
    n.fail("is not a final condition",
           fmt::format(
               "a number [{}], a pair [lower, upper], 'entry' or {{entry_offset: [lo, hi]}}", u));
}

std::array<double, 2> pair_or(ConfigMap& m, std::string_view key, std::array<double, 2> fallback,
                              const NumberSpec& spec) {
    if (!m.has(key)) return fallback;
    const auto v = m.numbers(key, 2, spec);
    if (!(v[0] <= v[1])) {
        m.fail(key, "has lower above upper", "[lower, upper] with lower <= upper");
    }
    return {v[0], v[1]};
}

std::array<double, 2> angle_pair_or(ConfigMap& m, std::string_view key,
                                    std::array<double, 2> fallback, const NumberSpec& spec) {
    if (!m.has_angle(key)) return fallback;
    return m.angle_range(key, spec);
}

ManoeuvreSpec read(const ConfigNode& root) {
    ManoeuvreSpec s;
    ConfigMap m(root);
    s.name = m.string("name");
    s.description = m.string_or("description", "");

    {
        ConfigMap e = m.map("entry");
        s.entry_speed = e.number("speed", NumberSpec::range(10.0, 1000.0, "m/s"));
        s.entry_altitude = e.number("altitude", NumberSpec::range(0.0, 30000.0, "m"));
        s.entry_heading =
            e.angle_or("heading", 0.0,
                       NumberSpec::range(-2.0 * std::numbers::pi, 2.0 * std::numbers::pi, "rad"));
        const std::string kind = e.choice_or("condition", "trimmed", {"trimmed", "given"});
        s.entry_trimmed = kind == "trimmed";
        const NumberSpec any_angle = NumberSpec::range(-7.0, 7.0, "rad");
        s.entry_climb = e.angle_or("climb_angle", 0.0, NumberSpec::range(-1.5, 1.5, "rad"));
        if (!s.entry_trimmed) {
            s.entry_alpha = e.angle_or("alpha", 0.0, any_angle);
            s.entry_beta = e.angle_or("beta", 0.0, any_angle);
            s.entry_bank = e.angle_or("bank", 0.0, any_angle);
            s.entry_pitch = e.angle_or("pitch", 0.0, any_angle);
            s.entry_p = e.angle_or("p", 0.0, NumberSpec::any("rad/s"));
            s.entry_q = e.angle_or("q", 0.0, NumberSpec::any("rad/s"));
            s.entry_r = e.angle_or("r", 0.0, NumberSpec::any("rad/s"));
            s.entry_controls[0] = e.angle_or("elevator", 0.0, any_angle);
            s.entry_controls[1] = e.angle_or("aileron", 0.0, any_angle);
            s.entry_controls[2] = e.angle_or("rudder", 0.0, any_angle);
            s.entry_controls[3] = e.number_or("throttle", 0.5, NumberSpec::range(0.0, 1.0, "-"));
        }
        e.finish();
    }

    if (m.has("final")) {
        ConfigMap f = m.map("final");
        s.speed = read_target(f, "speed", false, "m/s");
        s.altitude = read_target(f, "altitude", false, "m");
        s.heading_change = read_target(f, "heading_change", true, "rad");
        s.bank = read_target(f, "bank", true, "rad");
        s.pitch = read_target(f, "pitch", true, "rad");
        s.flight_path_angle = read_target(f, "flight_path_angle", true, "rad");
        s.sideslip = read_target(f, "sideslip", true, "rad");
        s.north_change = read_target(f, "north_change", false, "m");
        s.east_change = read_target(f, "east_change", false, "m");
        s.roll_angle = read_target(f, "roll_angle", true, "rad");
        s.final_rates_zero = f.boolean_or("rates_zero", true);
        f.finish();
    }

    if (m.has("intermediate")) {
        ConfigMap f = m.map("intermediate");
        s.intermediate.present = true;
        s.intermediate.fraction =
            f.number_or("fraction", 0.5, NumberSpec::range(0.01, 0.99, "fraction of duration"));
        s.intermediate.speed = read_target(f, "speed", false, "m/s");
        s.intermediate.altitude = read_target(f, "altitude", false, "m");
        s.intermediate.heading_change = read_target(f, "heading_change", true, "rad");
        s.intermediate.bank = read_target(f, "bank", true, "rad");
        s.intermediate.pitch = read_target(f, "pitch", true, "rad");
        s.intermediate.flight_path_angle = read_target(f, "flight_path_angle", true, "rad");
        f.finish();
    }
    if (m.has("phases")) {
        const ConfigNode ph = m.sequence("phases");
        const std::size_t want = s.intermediate.present ? 2 : 1;
        if (ph.size() != want) {
            ph.fail(
                fmt::format("lists {} phase name(s)", ph.size()),
                fmt::format("{} name(s) ({})", want,
                            s.intermediate.present ? "before and after the intermediate condition"
                                                   : "no intermediate condition"));
        }
        for (std::size_t i = 0; i < ph.size(); ++i) {
            const std::string name = ph.element(i).to_string();
            if (name.empty() || name.find_first_of(",\n") != std::string::npos) {
                ph.element(i).fail("is not a phase name", "a non-empty name without commas");
            }
            s.phase_names.push_back(name);
        }
    }
    if (s.phase_names.empty()) {
        s.phase_names = s.intermediate.present ? std::vector<std::string>{"phase_0", "phase_1"}
                                               : std::vector<std::string>{"manoeuvre"};
    }

    if (m.has("path")) {
        ConfigMap p = m.map("path");
        const NumberSpec ang = NumberSpec::range(-1.5, 1.5, "rad");
        if (p.has_angle("alpha_max")) s.alpha[1] = p.angle("alpha_max", ang);
        if (p.has_angle("alpha_min")) s.alpha[0] = p.angle("alpha_min", ang);
        if (!(s.alpha[0] < s.alpha[1])) {
            p.fail("alpha_max", "is not above alpha_min", "alpha_min < alpha_max");
        }
        s.beta = angle_pair_or(p, "beta", s.beta, ang);
        s.load_factor = pair_or(p, "load_factor", s.load_factor, NumberSpec::range(-20, 20, "-"));
        s.throttle = pair_or(p, "throttle", s.throttle, NumberSpec::range(0.0, 1.0, "-"));
        s.altitude_range =
            pair_or(p, "altitude", s.altitude_range, NumberSpec::range(-500.0, 30000.0, "m"));
        s.speed_path = p.has("speed");
        s.speed_range = pair_or(p, "speed", s.speed_range, NumberSpec::range(1.0, 1000.0, "m/s"));
        if (p.has("mach_max")) s.mach_max = p.number("mach_max", NumberSpec::range(0.01, 5.0, "-"));
        if (p.has_angle("bank")) {
            // phi = atan2(c32, c33) jumps at +-180 deg: the range must stay inside (-180, 180)
            s.bank_range = p.angle_range("bank", NumberSpec::range(-3.14, 3.14, "rad"));
        }
        s.east_range = pair_or(p, "east", s.east_range, NumberSpec::any("m"));
        if (!(s.east_range[0] <= 0.0 && s.east_range[1] >= 0.0)) {
            p.fail("east", "does not contain the entry position 0", "[lower <= 0, upper >= 0]");
        }
        s.control_rate =
            p.angle_or("control_rate", s.control_rate, NumberSpec::range(1e-3, 100.0, "rad/s"));
        if (p.has("body_rate_max_deg_s")) {
            const auto r =
                p.numbers("body_rate_max_deg_s", 3, NumberSpec::range(0.1, 1000.0, "deg/s"));
            for (int i = 0; i < 3; ++i) s.body_rate_max[i] = r[i] * kDeg;
        }
        const std::string dir =
            p.choice_or("roll_direction", "either", {"either", "left", "right"});
        s.roll_direction = dir == "left" ? -1 : dir == "right" ? 1 : 0;
        s.throttle_rate =
            p.number_or("throttle_rate", s.throttle_rate, NumberSpec::range(1e-3, 100.0, "1/s"));
        p.finish();
    }

    if (m.has("mass")) {
        ConfigMap ms = m.map("mass");
        s.mass_case = ms.string_or("case", "");
        if (ms.has("mass")) s.mass = ms.number("mass", NumberSpec::positive("kg"));
        if (ms.has("cg_mac_fraction")) {
            s.cg_mac_fraction =
                ms.number("cg_mac_fraction", NumberSpec::range(-0.5, 1.5, "fraction of MAC"));
        }
        ms.finish();
    }

    if (m.has("mesh")) {
        ConfigMap me = m.map("mesh");
        s.nodes = static_cast<int>(me.integer_or("nodes", s.nodes, NumberSpec::range(4, 300, "-")));
        s.segments =
            static_cast<int>(me.integer_or("segments", s.segments, NumberSpec::range(1, 50, "-")));
        s.coarse_nodes = static_cast<int>(
            me.integer_or("coarse_nodes", s.coarse_nodes, NumberSpec::range(0, 300, "-")));
        s.tie_breaks = me.choice_or("breaks", "junction", {"junction", "free"}) == "junction";
        me.finish();
    }

    if (m.has("cost")) {
        ConfigMap c = m.map("cost");
        s.cost = c.choice_or("type", "minimum_time", {"minimum_time"});
        s.rate_weight = c.number_or("rate_weight", s.rate_weight, NumberSpec::non_negative("s"));
        c.finish();
    }

    if (m.has("guess")) {
        ConfigMap g = m.map("guess");
        s.duration_guess = g.number_or("duration", s.duration_guess, NumberSpec::positive("s"));
        s.duration = pair_or(g, "duration_bounds", s.duration, NumberSpec::positive("s"));
        if (!(s.duration_guess > s.duration[0] && s.duration_guess < s.duration[1])) {
            g.fail("duration",
                   fmt::format("{} s is outside duration_bounds [{}, {}] s", s.duration_guess,
                               s.duration[0], s.duration[1]),
                   "a duration strictly inside the bounds");
        }
        if (g.has("waypoints")) {
            const ConfigNode w = g.sequence("waypoints");
            for (std::size_t i = 0; i < w.size(); ++i) {
                ConfigMap wm(w.element(i));
                GuessWaypoint p;
                p.fraction = wm.number("fraction", NumberSpec::range(0.0, 1.0, "-"));
                const NumberSpec ang = NumberSpec::range(-7.0, 7.0, "rad");
                p.bank = wm.angle_or("bank", 0.0, ang);
                p.pitch = wm.angle_or("pitch", 0.0, ang);
                p.heading = wm.angle_or("heading", 0.0, ang);
                p.speed = wm.number_or("speed", 0.0, NumberSpec::non_negative("m/s"));
                wm.finish();
                if (!s.guess.empty() && !(p.fraction > s.guess.back().fraction)) {
                    w.element(i).fail("has a fraction not above the previous waypoint's",
                                      "waypoints in increasing fraction");
                }
                s.guess.push_back(p);
            }
        }
        g.finish();
    }

    if (m.has("solver")) {
        ConfigMap so = m.map("solver");
        s.hessian = so.choice_or("hessian", s.hessian, {"exact", "limited-memory"});
        s.tolerance = so.number_or("tolerance", s.tolerance, NumberSpec::positive("-"));
        s.max_iterations = static_cast<int>(
            so.integer_or("max_iterations", s.max_iterations, NumberSpec::range(1, 100000, "-")));
        so.finish();
    }
    m.finish();
    return s;
}

}  // namespace

ManoeuvreSpec load_manoeuvre(const std::filesystem::path& file) {
    ManoeuvreSpec s = read(ConfigNode::parse_file(file));
    s.file = file;
    return s;
}

ManoeuvreSpec parse_manoeuvre(std::string_view yaml_text, const std::string& source) {
    ManoeuvreSpec s = read(ConfigNode::parse_string(yaml_text, source));
    s.file = source;
    return s;
}

}  // namespace manta::manoeuvres
