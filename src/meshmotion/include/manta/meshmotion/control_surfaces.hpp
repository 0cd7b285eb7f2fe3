#pragma once
/// @file control_surfaces.hpp
/// Where the control surfaces of a moving mesh come from: a `control_surfaces:` list of a
/// configuration file (docs/mesh-motion.md, "Configuration"), or the control surfaces of an
/// aircraft's geometry (hinge lines from their hinge chord fractions and span fractions).

#include <string>
#include <vector>

#include "manta/core/config.hpp"
#include "manta/geometry/aircraft_geometry.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace manta::meshmotion {

/// Parse a `control_surfaces:` sequence. Each entry is either
///   {mode: elevator, marker: elevator_wall, hinge: [[x, y, z], [x, y, z]], gain: 1}
/// or, when `aircraft` is given, one copy of an aircraft file's control surface
///   {control_surface: aileron, side: right | left, marker: aileron_right}
/// (mode, hinge and gain from `control_surfaces_from_geometry`); both take the optional keys
/// `hinge_tolerance`, `hinge_blend`, `edge_blend`, `cutoff` [m]. ConfigError naming the file,
/// line, key, value and what was expected; unknown keys are rejected.
[[nodiscard]] std::vector<ControlSurfaceSpec> parse_control_surfaces(
    const core::ConfigNode& sequence, const geometry::AircraftGeometry* aircraft = nullptr);

/// The spec of one copy of an aircraft's control surface on the mesh marker `marker`, the mesh in
/// geometry axes. Hinge: `AircraftGeometry::hinge_line` (inboard and outboard ends at the hinge
/// chord fraction), mirrored to -y for the mirrored copy, ordered so that a positive local
/// deflection is the aircraft's (trailing edge down on horizontal surfaces, trailing edge toward
/// -y on vertical ones, docs/conventions.md); mode = the driving control (`elevator`, `aileron`,
/// `rudder`), gain = ControlSurface::gain or mirror_gain. InputError for an unknown name, a
/// surface driven by no control, or the mirrored copy of a surface that is not mirrored.
[[nodiscard]] ControlSurfaceSpec control_surface_from_geometry(
    const geometry::AircraftGeometry& aircraft, const std::string& control_surface, bool mirrored,
    const std::string& marker);

}  // namespace manta::meshmotion
