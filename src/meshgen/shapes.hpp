#pragma once
/// @file shapes.hpp
/// Internal: the section contours, frames and control-surface regions the CAD is built from, and
/// the error helper that names an aircraft-file key (shared by check.cpp and meshgen.cpp).

#include <Eigen/Core>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/geometry/aircraft_geometry.hpp"

namespace manta::meshgen::detail {

/// ConfigError "file:line: key 'path': value 'v' problem; expected ..." for the aircraft file
/// (the line found by reading the file again; left out where it cannot be found).
[[noreturn]] void fail_key(const aircraft::AircraftDefinition& a, const std::string& key_path,
                           const std::string& value, std::string_view problem,
                           std::string_view expected);

/// Orthonormal section frame: chord direction (leading to trailing edge, twist applied), the
/// section's "up" direction (airfoil y) and the spanwise axis.
struct SectionFrame {
    Eigen::Vector3d leading_edge;
    double chord = 0.0;
    Eigen::Vector3d e_chord, e_up, e_span;
    [[nodiscard]] Eigen::Vector3d at(double x, double y) const {
        return leading_edge + chord * (x * e_chord + y * e_up);
    }
};
/// Frame at fraction eta of the semi-span (linear between sections, as the surface is ruled).
[[nodiscard]] SectionFrame frame_at(const geometry::LiftingSurface& w, double eta);
/// Frame of defining section i.
[[nodiscard]] SectionFrame frame_of(const geometry::LiftingSurface& w, std::size_t i);

/// A section contour in Selig order (trailing edge, upper surface, leading edge, lower surface,
/// trailing edge), chord-normalised, consecutive duplicates removed; `note` is set when the shape
/// had to be approximated (6-series thickness forms).
struct Contour {
    std::vector<Eigen::Vector2d> points;
    std::size_t leading_edge = 0;  ///< index of the point of smallest x
    bool sharp_trailing_edge = false;
    double thickness = 0.0;  ///< t/c
    std::string note;
};
[[nodiscard]] Contour section_contour(const geometry::Airfoil& airfoil);

/// Key of section j of surface i, e.g. "geometry.lifting_surfaces[0].sections[1]".
[[nodiscard]] std::string section_key(std::size_t i, std::size_t j);
/// The airfoil key of a section ("...airfoil" or "...airfoil_file") and its value.
[[nodiscard]] std::pair<std::string, std::string> airfoil_key(const geometry::Airfoil& a,
                                                              std::size_t i, std::size_t j);

/// The region of one copy of a control surface: the hexahedron between its side planes, from its
/// hinge line aft past the trailing edge and `height` chords above and below the chord line.
struct ControlRegion {
    std::string marker;
    std::size_t control_index = 0;
    bool mirrored = false;
    /// Corners: [end (0 inboard, 1 outboard)][corner (hinge-low, hinge-high, aft-high, aft-low)].
    std::array<std::array<Eigen::Vector3d, 4>, 2> corners{};
    SectionFrame frame0, frame1;  ///< frames at the inboard and outboard ends (mirrored if so)
    double hinge_fraction = 0.0;
    /// True if p lies inside (with tolerance tol [m], positive = inside by tol).
    [[nodiscard]] bool contains(const Eigen::Vector3d& p, double tol) const;
};
[[nodiscard]] ControlRegion control_region(const geometry::AircraftGeometry& g, std::size_t k,
                                           bool mirrored, std::string marker);

/// Wall marker name of a control-surface copy: the name alone for a surface that is not
/// mirrored; "<name>_right" / "<name>_left" for the copies of a mirrored one, except in the half
/// model, where the right copy of a surface with equal gains on both sides (it moves
/// symmetrically, as the elevator) keeps the name alone.
[[nodiscard]] std::string marker_name(const geometry::ControlSurface& cs, bool symmetric_surface,
                                      bool mirrored, bool half_model);

}  // namespace manta::meshgen::detail
