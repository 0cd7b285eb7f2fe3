/// @file config.cpp
/// Reading the `manta cfd` configuration (config.hpp).

#include "manta/euler/config.hpp"

#include <fmt/format.h>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/meshmotion/control_surfaces.hpp"

namespace manta::euler {

namespace {

using core::ConfigMap;
using core::ConfigNode;
using core::NumberSpec;

constexpr double deg = 3.14159265358979323846 / 180.0;

BoundaryKind role_from(const ConfigNode& n) {
    const std::string v = n.to_string();
    if (v == "farfield") return BoundaryKind::farfield;
    if (v == "wall") return BoundaryKind::wall;
    if (v == "symmetry") return BoundaryKind::symmetry;
    n.fail("is not a boundary role", "one of farfield, wall, symmetry");
}

CfdConfig read(const ConfigNode& root) {
    CfdConfig c;
    c.source = root.source();
    if (!root.is_defined() || root.is_null()) return c;
    ConfigMap top(root);
    if (auto n = top.optional_child("flow")) {
        ConfigMap f(*n);
        if (f.has("mach")) c.mach = f.number("mach", NumberSpec{0.0, 10.0, true, false, "-"});
        if (f.has_angle("alpha"))
            c.alpha = f.angle("alpha", NumberSpec::range(-90 * deg, 90 * deg, "rad"));
        if (f.has_angle("beta"))
            c.beta = f.angle("beta", NumberSpec::range(-90 * deg, 90 * deg, "rad"));
        // Body rates (docs/euler.md, "Rotation rates"): p_hat = 1 turns the wing tip at the flight
        // speed, far beyond a quasi-steady table.
        if (f.has("p_hat")) c.p_hat = f.number("p_hat", NumberSpec::range(-1.0, 1.0, "-"));
        if (f.has("q_hat")) c.q_hat = f.number("q_hat", NumberSpec::range(-1.0, 1.0, "-"));
        if (f.has("r_hat")) c.r_hat = f.number("r_hat", NumberSpec::range(-1.0, 1.0, "-"));
        c.gamma = f.number_or("gamma", 1.4, NumberSpec{1.0, 2.0, true, false, "-"});
        f.finish();
    }
    if (auto n = top.optional_child("markers")) {
        if (!n->is_map())
            n->fail("is not a mapping", "marker: role pairs (farfield, wall, symmetry)");
        for (const std::string& k : n->map_keys()) c.markers[k] = role_from(n->child(k));
    }
    if (auto n = top.optional_child("reference")) {
        c.reference_given = true;
        ConfigMap r(*n);
        c.reference.area = r.number_or("area", 0.0, NumberSpec::non_negative("m^2"));
        c.reference.chord = r.number_or("chord", 1.0, NumberSpec::positive("m"));
        c.reference.span = r.number_or("span", 1.0, NumberSpec::positive("m"));
        if (r.has("moment_point")) {
            const auto p = r.vec3("moment_point", NumberSpec::any("m"));
            c.reference.moment_point = Vec3(p[0], p[1], p[2]);
        }
        c.reference.half_model = r.boolean_or("half_model", false);
        r.finish();
    }
    if (auto n = top.optional_child("numerics")) {
        ConfigMap m(*n);
        const std::string flux = m.choice_or("flux", "roe", {"roe", "hllc", "jst"});
        c.spatial.flux.scheme = flux == "hllc"  ? FluxScheme::hllc
                                : flux == "jst" ? FluxScheme::jst
                                                : FluxScheme::roe;
        const std::string wall = m.choice_or("wall", "auto", {"auto", "weak", "strong", "mixed"});
        c.spatial.wall = wall == "weak"     ? WallTangency::weak
                         : wall == "strong" ? WallTangency::strong
                         : wall == "mixed"  ? WallTangency::mixed
                                            : WallTangency::automatic;
        c.spatial.flux.jst_k2 =
            m.number_or("jst_k2", c.spatial.flux.jst_k2, NumberSpec::range(0, 2, "-"));
        c.spatial.flux.jst_k4 =
            m.number_or("jst_k4", c.spatial.flux.jst_k4, NumberSpec::range(0, 0.5, "-"));
        c.spatial.flux.low_mach_fix = m.boolean_or("low_mach_fix", c.spatial.flux.low_mach_fix);
        c.spatial.flux.entropy_fix =
            m.number_or("entropy_fix", c.spatial.flux.entropy_fix, NumberSpec::range(0, 1, "-"));
        c.spatial.order = static_cast<int>(m.integer_or("order", 2, NumberSpec::range(1, 2, "-")));
        const std::string g =
            m.choice_or("gradient", "least_squares", {"least_squares", "green_gauss"});
        c.spatial.gradient =
            g == "green_gauss" ? GradientMethod::green_gauss : GradientMethod::least_squares;
        const std::string lim =
            m.choice_or("limiter", "venkatakrishnan", {"venkatakrishnan", "none"});
        c.spatial.limiter = lim == "venkatakrishnan";
        c.spatial.venkatakrishnan_k = m.number_or("venkatakrishnan_k", c.spatial.venkatakrishnan_k,
                                                  NumberSpec::positive("-"));
        c.spatial.sharp_edge_deg =
            m.number_or("sharp_edge_deg", c.spatial.sharp_edge_deg, NumberSpec::positive("deg"));
        m.finish();
    }
    if (auto n = top.optional_child("solver")) {
        ConfigMap s(*n);
        SolverSettings& v = c.solver;
        v.cfl_initial = s.number_or("cfl", v.cfl_initial, NumberSpec::positive("-"));
        v.cfl_max = s.number_or("cfl_max", v.cfl_max, NumberSpec::positive("-"));
        v.cfl_growth = s.number_or("cfl_growth", v.cfl_growth, NumberSpec::range(1, 10, "-"));
        v.max_iterations = static_cast<int>(
            s.integer_or("max_iterations", v.max_iterations, NumberSpec::range(1, 1e9, "-")));
        v.residual_drop =
            s.number_or("residual_drop", v.residual_drop, NumberSpec::range(0.1, 16, "orders"));
        v.coefficient_tolerance = s.number_or("coefficient_tolerance", v.coefficient_tolerance,
                                              NumberSpec::positive("-"));
        v.coefficient_window = static_cast<int>(s.integer_or(
            "coefficient_window", v.coefficient_window, NumberSpec::range(2, 1e6, "-")));
        v.freeze_limiter_drop = s.number_or("freeze_limiter_drop", v.freeze_limiter_drop,
                                            NumberSpec::range(0, 16, "orders"));
        v.freeze_limiter_stall = static_cast<int>(s.integer_or(
            "freeze_limiter_stall", v.freeze_limiter_stall, NumberSpec::range(0, 1e9, "-")));
        v.first_order_iterations = static_cast<int>(s.integer_or(
            "first_order_iterations", v.first_order_iterations, NumberSpec::range(0, 1e9, "-")));
        v.linear.max_iterations = static_cast<int>(s.integer_or(
            "linear_iterations", v.linear.max_iterations, NumberSpec::range(1, 1000, "-")));
        v.linear.restart = static_cast<int>(
            s.integer_or("linear_restart", v.linear.restart, NumberSpec::range(1, 1000, "-")));
        v.linear.relative_tolerance = s.number_or("linear_tolerance", v.linear.relative_tolerance,
                                                  NumberSpec{0.0, 1.0, true, true, "-"});
        v.max_backoffs = static_cast<int>(
            s.integer_or("max_backoffs", v.max_backoffs, NumberSpec::range(0, 100, "-")));
        v.preconditioner = s.choice_or("preconditioner", "sgs", {"sgs", "ilu0"}) == "sgs"
                               ? PreconditionerKind::sgs
                               : PreconditionerKind::ilu0;
        v.preconditioner_blocks = static_cast<int>(s.integer_or(
            "preconditioner_blocks", v.preconditioner_blocks, NumberSpec::range(0, 1e6, "-")));
        s.finish();
        if (v.cfl_max < v.cfl_initial)
            s.fail("cfl_max", fmt::format("is below cfl = {}", v.cfl_initial), "cfl_max >= cfl");
    }
    if (auto n = top.optional_child("output")) {
        ConfigMap o(*n);
        c.output.checkpoint_interval_s = o.number_or(
            "checkpoint_interval_s", c.output.checkpoint_interval_s, NumberSpec::non_negative("s"));
        c.output.volume = o.boolean_or("volume", c.output.volume);
        c.output.surface = o.boolean_or("surface", c.output.surface);
        o.finish();
    }
    if (auto n = top.optional_child("mesh")) {
        ConfigMap m(*n);
        c.mesh_up = m.choice_or("up", "z", {"z", "y"});
        m.finish();
    }
    if (auto n = top.optional_child("unsteady")) {
        ConfigMap u(*n);
        UnsteadySettings& t = c.unsteady;
        t.order = static_cast<int>(u.integer_or("order", t.order, NumberSpec::range(1, 2, "-")));
        t.max_inner = static_cast<int>(
            u.integer_or("max_inner", t.max_inner, NumberSpec::range(1, 1e6, "-")));
        t.inner_drop =
            u.number_or("inner_drop", t.inner_drop, NumberSpec::range(0.1, 16, "orders"));
        t.coefficient_window = static_cast<int>(u.integer_or(
            "coefficient_window", t.coefficient_window, NumberSpec::range(2, 1e6, "-")));
        t.coefficient_tolerance = u.number_or("coefficient_tolerance", t.coefficient_tolerance,
                                              NumberSpec::positive("-"));
        t.extrapolate = u.boolean_or("extrapolate", t.extrapolate);
        t.jacobian_interval = static_cast<int>(u.integer_or(
            "jacobian_interval", t.jacobian_interval, NumberSpec::range(1, 1000, "-")));
        t.cfl_max = u.number_or("cfl_max", t.cfl_max, NumberSpec::non_negative("-"));
        t.cfl_growth = u.number_or("cfl_growth", t.cfl_growth, NumberSpec::non_negative("-"));
        t.freeze_limiter_inner = static_cast<int>(u.integer_or(
            "freeze_limiter_inner", t.freeze_limiter_inner, NumberSpec::range(0, 1e6, "-")));
        c.output_every = static_cast<int>(
            u.integer_or("output_every", c.output_every, NumberSpec::range(0, 1e9, "steps")));
        c.mesh_motion = u.choice_or("mesh_motion", "rigid", {"rigid", "deforming"}) == "deforming"
                            ? meshmotion::BodyMotion::deforming
                            : meshmotion::BodyMotion::rigid;
        c.rigid_radius = u.number_or("rigid_radius", c.rigid_radius, NumberSpec::non_negative("m"));
        c.fixed_radius = u.number_or("fixed_radius", c.fixed_radius, NumberSpec::non_negative("m"));
        u.finish();
    }
    if (auto n = top.optional_child("control_surfaces")) {
        c.control_surfaces_given = true;
        c.control_surfaces = meshmotion::parse_control_surfaces(*n);
    }
    top.finish();
    return c;
}

}  // namespace

CfdConfig read_cfd_config(const std::filesystem::path& file) {
    return read(ConfigNode::parse_file(file));
}

CfdConfig parse_cfd_config(std::string_view text, const std::string& source) {
    return read(ConfigNode::parse_string(text, source));
}

void apply_companion(CfdConfig& config, const mesh::Companion& companion,
                     const std::filesystem::path& file) {
    for (const mesh::MarkerRole& m : companion.markers) {
        if (config.markers.count(m.name)) continue;
        if (m.role == "wall")
            config.markers[m.name] = BoundaryKind::wall;
        else if (m.role == "farfield")
            config.markers[m.name] = BoundaryKind::farfield;
        else if (m.role == "symmetry")
            config.markers[m.name] = BoundaryKind::symmetry;
        else
            throw ConfigError(fmt::format(
                "{}: markers: '{}' has the role '{}'; expected farfield, wall or symmetry",
                file.string(), m.name, m.role));
    }
    if (!config.reference_given) {
        config.reference.area = companion.reference.area;
        config.reference.chord = companion.reference.chord;
        config.reference.span = companion.reference.span;
        config.reference.moment_point = companion.reference.moment_point;
    }
    // The mesh is a half model whatever reference values the configuration gives.
    if (companion.model == "half") config.reference.half_model = true;
    if (!config.control_surfaces_given) {
        config.control_surfaces.clear();
        for (std::size_t i = 0; i < companion.control_surfaces.size(); ++i) {
            const mesh::CompanionControlSurface& s = companion.control_surfaces[i];
            meshmotion::ControlSurfaceSpec spec;
            spec.mode = s.mode;
            spec.marker = s.marker;
            spec.hinge = s.hinge;
            spec.gain = s.gain;
            spec.source = fmt::format("{}: control_surfaces[{}]", file.string(), i);
            config.control_surfaces.push_back(std::move(spec));
        }
    }
    config.companion = file;
}

void apply_mesh_companion(CfdConfig& config, const std::filesystem::path& mesh_file) {
    if (const auto c = mesh::find_companion(mesh_file))
        apply_companion(config, *c, mesh::companion_path(mesh_file));
}

std::vector<BoundaryKind> resolve_roles(const mesh::Mesh& mesh, const CfdConfig& config) {
    for (const auto& [name, role] : config.markers)
        if (mesh.find_marker(name) < 0) {
            std::string known;
            for (const std::string& m : mesh.markers()) known += (known.empty() ? "" : ", ") + m;
            throw InputError(
                fmt::format("{}: markers: '{}' is not a marker of the mesh {}; expected one of {}",
                            config.source, name, mesh.source(), known));
        }
    std::vector<BoundaryKind> roles;
    for (const std::string& m : mesh.markers()) {
        const auto it = config.markers.find(m);
        BoundaryKind k{};
        if (it != config.markers.end())
            k = it->second;
        else if (!default_role(m, k))
            throw InputError(fmt::format(
                "{}: marker '{}' has no boundary role; give it in the configuration file "
                "(markers: {{{}: wall}}; roles farfield, wall, symmetry)",
                mesh.source(), m, m));
        roles.push_back(k);
    }
    return roles;
}

}  // namespace manta::euler
