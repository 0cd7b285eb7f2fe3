/// @file companion.cpp
/// The mesh companion file (docs/formats.md#mesh-companion-file): writing and strict reading.

#include "manta/mesh/companion.hpp"

#include <fmt/format.h>

#include <string>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::mesh {

std::filesystem::path companion_path(const std::filesystem::path& mesh_file) {
    std::filesystem::path p = mesh_file;
    if (p.extension() == ".gz") p.replace_extension();
    p.replace_extension(".mesh.yaml");
    return p;
}

namespace {

std::string quote(const std::string& s) {
    std::string out = "\"";
    for (char ch : s) {
        if (ch == '"' || ch == '\\') out += '\\';
        out += ch;
    }
    return out + "\"";
}
std::string vec(const Eigen::Vector3d& v) {
    return fmt::format("[{:.10g}, {:.10g}, {:.10g}]", v.x(), v.y(), v.z());
}

}  // namespace

std::string format_companion(const Companion& c) {
    std::string s;
    s += "# MANTA mesh companion file (docs/formats.md#mesh-companion-file), written by `manta "
         "mesh`.\n";
    s += "# Geometry axes of the aircraft file: x aft, y right, z up, metres.\n";
    s += "schema_version: 1\n";
    s += fmt::format("mesh: {}\n", quote(c.mesh));
    s += fmt::format("aircraft: {}\n", quote(c.aircraft));
    s += fmt::format("aircraft_name: {}\n", quote(c.aircraft_name));
    s += fmt::format("model: {}\n", c.model);
    s += fmt::format("level: {}\n", c.level);
    s += "# Marker roles as in the CFD configuration's `markers:` (farfield, wall, symmetry).\n";
    s += "markers:\n";
    for (const auto& m : c.markers) s += fmt::format("  {}: {}\n", m.name, m.role);
    s +=
        "# Reference values of the whole aircraft's coefficients. Half model: `area` is half the\n";
    s += "# aircraft's reference area, so the half model's forces over q*area are the whole\n";
    s += "# aircraft's CL, CD, Cm (forces are not doubled).\n";
    s += "reference:\n";
    s += fmt::format("  area: {:.10g}\n", c.reference.area);
    s += fmt::format("  aircraft_area: {:.10g}\n", c.reference.aircraft_area);
    s += fmt::format("  chord: {:.10g}\n", c.reference.chord);
    s += fmt::format("  span: {:.10g}\n", c.reference.span);
    s += fmt::format("  moment_point: {}\n", vec(c.reference.moment_point));
    s += fmt::format("  cg_case: {}\n", quote(c.reference.cg_case));
    s += fmt::format("  cg: {}\n", vec(c.reference.cg));
    s += "# Hinge lines in the form meshmotion::parse_control_surfaces reads: positive local\n";
    s += "# deflection rotates right-handedly about hinge[1] - hinge[0].\n";
    if (c.control_surfaces.empty()) {
        s += "control_surfaces: []\n";
    } else {
        s += "control_surfaces:\n";
        for (const auto& cs : c.control_surfaces) {
            s += fmt::format("  - mode: {}\n", cs.mode);
            s += fmt::format("    marker: {}\n", cs.marker);
            s += fmt::format("    hinge: [{}, {}]\n", vec(cs.hinge[0]), vec(cs.hinge[1]));
            s += fmt::format("    gain: {:.10g}\n", cs.gain);
            s += fmt::format("    # control surface '{}'{}\n", cs.control_surface,
                             cs.side.empty() ? "" : fmt::format(", {} copy", cs.side));
        }
    }
    return s;
}

void write_companion(const std::filesystem::path& file, const Companion& c) {
    core::write_file_atomic(file, format_companion(c));
}

Companion read_companion(const std::filesystem::path& file) {
    core::ConfigMap top(core::ConfigNode::parse_file(file));
    Companion c;
    const long v = top.integer("schema_version", core::NumberSpec::range(1, 1, ""));
    (void)v;
    c.mesh = top.string("mesh");
    c.aircraft = top.string_or("aircraft", "");
    c.aircraft_name = top.string_or("aircraft_name", "");
    c.model = top.choice("model", {"half", "full"});
    c.level = top.choice("level", {"coarse", "medium", "fine"});
    {
        const core::ConfigNode m = top.child("markers");
        core::ConfigMap mm(m);  // ConfigError if not a mapping
        for (const auto& name : m.map_keys()) {
            MarkerRole r;
            r.name = name;
            r.role = mm.choice(name, {"wall", "farfield", "symmetry"});
            c.markers.push_back(r);
        }
        mm.finish();
    }
    {
        core::ConfigMap r = top.map("reference");
        c.reference.area = r.number("area", core::NumberSpec::positive("m^2"));
        c.reference.aircraft_area =
            r.number_or("aircraft_area", c.reference.area, core::NumberSpec::positive("m^2"));
        c.reference.chord = r.number("chord", core::NumberSpec::positive("m"));
        c.reference.span = r.number("span", core::NumberSpec::positive("m"));
        const auto mp = r.vec3("moment_point", core::NumberSpec::any("m"));
        c.reference.moment_point = Eigen::Vector3d(mp[0], mp[1], mp[2]);
        c.reference.cg_case = r.string_or("cg_case", "");
        if (r.has("cg")) {
            const auto cg = r.vec3("cg", core::NumberSpec::any("m"));
            c.reference.cg = Eigen::Vector3d(cg[0], cg[1], cg[2]);
        }
        r.finish();
    }
    const core::ConfigNode seq = top.sequence("control_surfaces", true);
    for (std::size_t i = 0; i < seq.size(); ++i) {
        core::ConfigMap e(seq.element(i));
        CompanionControlSurface cs;
        cs.mode = e.choice("mode", {"elevator", "aileron", "rudder"});
        cs.marker = e.string("marker");
        const core::ConfigNode h = e.child("hinge");
        if (!h.is_sequence() || h.size() != 2)
            e.fail("hinge", "is not two points", "[[x, y, z], [x, y, z]] in metres");
        for (std::size_t k = 0; k < 2; ++k) {
            const auto p = h.element(k).to_doubles(3, core::NumberSpec::any("m"));
            cs.hinge[k] = Eigen::Vector3d(p[0], p[1], p[2]);
        }
        cs.gain = e.number_or("gain", 1.0, core::NumberSpec::range(-10.0, 10.0, ""));
        e.finish();
        c.control_surfaces.push_back(cs);
    }
    top.finish();
    bool found = false;
    for (const auto& cs : c.control_surfaces) {
        found = false;
        for (const auto& m : c.markers) found = found || (m.name == cs.marker && m.role == "wall");
        if (!found)
            throw ConfigError(fmt::format(
                "{}: key 'control_surfaces': value '{}' names no wall marker of 'markers'; "
                "expected one of the wall markers",
                file.string(), cs.marker));
    }
    return c;
}

std::optional<Companion> find_companion(const std::filesystem::path& mesh_file) {
    const std::filesystem::path p = companion_path(mesh_file);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec)) return std::nullopt;
    return read_companion(p);
}

}  // namespace manta::mesh
