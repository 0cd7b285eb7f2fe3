/// @file control_surfaces.cpp
/// Control surfaces from a configuration list or an aircraft geometry (control_surfaces.hpp).

#include "manta/meshmotion/control_surfaces.hpp"

#include <fmt/format.h>

#include "manta/core/error.hpp"

namespace manta::meshmotion {

ControlSurfaceSpec control_surface_from_geometry(const geometry::AircraftGeometry& aircraft,
                                                 const std::string& control_surface, bool mirrored,
                                                 const std::string& marker) {
    const geometry::ControlSurface* cs = aircraft.find_control_surface(control_surface);
    if (cs == nullptr) {
        std::string names;
        for (const auto& c : aircraft.control_surfaces)
            names += (names.empty() ? "" : ", ") + c.name;
        throw InputError(
            fmt::format("control surface '{}' is not in the aircraft geometry; expected one of {}",
                        control_surface, names.empty() ? "(none)" : names));
    }
    if (cs->control == geometry::Control::none)
        throw InputError(fmt::format(
            "control surface '{}' is driven by no control (control: none); expected elevator, "
            "aileron or rudder",
            control_surface));
    const geometry::LiftingSurface& surface = aircraft.surface(cs->surface);
    if (mirrored && !surface.symmetric)
        throw InputError(fmt::format(
            "control surface '{}': side left asks for the mirrored copy, but surface '{}' is not "
            "symmetric; expected side: right",
            control_surface, cs->surface));
    auto [inboard, outboard] = aircraft.hinge_line(*cs);
    if (mirrored) {
        inboard.y() = -inboard.y();
        outboard.y() = -outboard.y();
    }
    ControlSurfaceSpec spec;
    spec.mode = std::string(geometry::to_string(cs->control));
    spec.marker = marker;
    spec.gain = mirrored ? cs->mirror_gain : cs->gain;
    // Trailing edge down is a right-handed rotation about +y; trailing edge toward -y about -z.
    // The defined copy of a horizontal surface runs toward +y, its mirror toward -y; a fin
    // runs toward +z.
    const bool outward = !surface.vertical && !mirrored;
    spec.hinge = outward ? std::array<Eigen::Vector3d, 2>{inboard, outboard}
                         : std::array<Eigen::Vector3d, 2>{outboard, inboard};
    spec.source = fmt::format("control surface '{}'{}", control_surface, mirrored ? " (left)" : "");
    return spec;
}

std::vector<ControlSurfaceSpec> parse_control_surfaces(const core::ConfigNode& sequence,
                                                       const geometry::AircraftGeometry* aircraft) {
    if (!sequence.is_sequence())
        sequence.fail("is not a list",
                      "a list of {mode, marker, hinge} or {control_surface, side, marker} entries");
    std::vector<ControlSurfaceSpec> specs;
    const auto length = core::NumberSpec::positive("m");
    for (std::size_t i = 0; i < sequence.size(); ++i) {
        const core::ConfigNode node = sequence.element(i);
        core::ConfigMap m(node);
        ControlSurfaceSpec spec;
        if (m.has("control_surface")) {
            if (aircraft == nullptr)
                m.fail("control_surface", "needs an aircraft file",
                       "mode, marker and hinge, or an aircraft file with this control surface");
            const std::string name = m.string("control_surface");
            const std::string side = m.choice_or("side", "right", {"right", "left"});
            const std::string marker = m.string("marker");
            try {
                spec = control_surface_from_geometry(*aircraft, name, side == "left", marker);
            } catch (const InputError& e) {
                m.child("control_surface").fail(e.what(), "a control surface of the aircraft");
            }
        } else {
            spec.mode = m.string("mode");
            spec.marker = m.string("marker");
            const core::ConfigNode hinge = m.child("hinge");
            if (!hinge.is_sequence() || hinge.size() != 2)
                hinge.fail("is not a list of two points", "[[x, y, z], [x, y, z]] in metres");
            for (std::size_t k = 0; k < 2; ++k) {
                const auto p = hinge.element(k).to_doubles(3, core::NumberSpec::any("m"));
                spec.hinge[k] = Eigen::Vector3d(p[0], p[1], p[2]);
            }
            if ((spec.hinge[1] - spec.hinge[0]).norm() == 0.0)
                hinge.fail("has two equal points", "two distinct points on the hinge line");
            spec.gain = m.number_or("gain", 1.0, core::NumberSpec::range(-10.0, 10.0, "-"));
            if (spec.gain == 0.0) m.fail("gain", "is 0", "a gain other than 0");
        }
        if (m.has("hinge_tolerance")) spec.hinge_tolerance = m.number("hinge_tolerance", length);
        if (m.has("hinge_blend"))
            spec.hinge_blend = m.number("hinge_blend", core::NumberSpec::non_negative("m"));
        if (m.has("edge_blend"))
            spec.edge_blend = m.number("edge_blend", core::NumberSpec::non_negative("m"));
        if (m.has("cutoff")) spec.cutoff = m.number("cutoff", length);
        m.finish();
        spec.source = node.where();
        specs.push_back(std::move(spec));
    }
    return specs;
}

}  // namespace manta::meshmotion
