#pragma once
/// @file model.hpp
/// The vortex-lattice description of an aircraft, independent of where it came from: MANTA's
/// aircraft YAML (`from_aircraft`) or an AVL geometry file (`read_avl`, avl_reader.hpp).
///
/// Axes are the geometry axes of the three-view (x aft, y right, z up), lengths in metres (or the
/// file's length unit for AVL models: the VLM is scale-free), angles in radians.
///
/// A surface is a list of sections joined by straight lines; each pair of consecutive sections
/// bounds a panel of strips, each strip `n_chord` horseshoe vortices deep. The geometry stays in
/// the plane of the sections (incidence, camber and control deflections tilt the normals: the
/// small-disturbance boundary condition of classical vortex-lattice codes). Between two sections
/// the surface is ruled, as in AVL: at a strip, the chord vector (hence the incidence), the
/// camber-line height and the hinge line are the linear interpolations of the two sections' in
/// physical units, i.e. camber slope, hinge fraction and lift-slope factor are chord-weighted.
///
/// Control surfaces are declared on sections: a control acts on the strips between two
/// consecutive sections that both carry it, with a straight hinge line between them and its gain
/// interpolated linearly. A panel cut by the hinge line turns by the fraction of its chord that
/// lies on the control surface. A positive local deflection is a right-handed rotation about the
/// hinge axis; the default axis runs along the hinge line from the section toward the next one, so
/// on a horizontal surface defined from root to tip along +y a positive deflection moves the
/// trailing edge down. The mirror copy of a duplicated surface rotates about the mirror image of
/// the axis taken as an axial vector, (-hx, hy, -hz), by `duplicate_sign` times the deflection: +1
/// moves both trailing edges down (elevator, flap), -1 moves them oppositely (aileron).

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "manta/geometry/aircraft_geometry.hpp"

namespace manta::vlm {

/// Node fractions 0 = f_0 < f_1 < ... < f_n = 1 for `n` intervals with a spacing parameter in
/// [-3, 3] (the convention of AVL, so that AVL models run unchanged): 0 and +-3 equal, 1 and -1
/// cosine (fine at both ends), 2 sine (fine at the start), -2 sine fine at the end; fractional
/// values blend linearly between the neighbouring integer laws. InputError if n < 1 or |p| > 3.
[[nodiscard]] std::vector<double> spacing_fractions(int n, double parameter);
/// The spacing law behind spacing_fractions: node fraction at parameter s in [0, 1]. The lattice
/// places each panel's vortex and control point at the quarter and three-quarter points of its
/// interval in s (not in x): with cosine spacing this is the classical semicircle placement that
/// makes the solution converge quickly with refinement.
[[nodiscard]] double spacing_law(double s, double parameter);
/// Chordwise stations of a strip of `n` panels: panel edges (n + 1), bound-vortex and
/// control-point chord fractions (n each). For cosine spacing the vortex and control point sit
/// at the quarter and three-quarter points of each panel's interval in the semicircle angle,
/// with the angle range divided into 4n + 2 equal steps so a single panel has them at exactly
/// 1/4 and 3/4 of the chord; the control point moves with the lift-slope factor k (at 1/4 + k/2
/// of the panel's interval).
struct ChordStations {
    std::vector<double> edge, vortex, control;
};
[[nodiscard]] ChordStations chord_stations(int n, double parameter, double lift_slope_factor = 1.0);
/// Inverse of spacing_law in s (bisection; the law is increasing).
[[nodiscard]] double spacing_parameter_of(double f, double parameter);

/// A control surface declared on a section.
struct SectionControl {
    std::string name;  ///< control variable: "elevator", "aileron", "rudder" or any other (flap)
    /// Local deflection [rad] per radian of the control variable on the defined copy.
    double gain = 1.0;
    /// Hinge position as a chord fraction from the leading edge; the part aft of it deflects.
    /// Negative: the part ahead of |hinge_chord_fraction| deflects (leading-edge slat).
    double hinge_chord_fraction = 0.75;
    /// Rotation axis (any length); zero: along the hinge line toward the next section.
    Eigen::Vector3d hinge_axis = Eigen::Vector3d::Zero();
    /// Deflection factor on the mirror copy of a duplicated surface (+1 symmetric, -1
    /// antisymmetric).
    double duplicate_sign = 1.0;
};

/// A defining section of a vortex-lattice surface.
struct Section {
    Eigen::Vector3d leading_edge = Eigen::Vector3d::Zero();  ///< [m], geometry axes
    double chord = 0.0;                                      ///< [m], > 0
    /// Incidence [rad], leading edge up positive, about the spanwise direction of the strip.
    double incidence = 0.0;
    /// Mean line (camber slope at the control points); none: flat plate.
    std::optional<geometry::Airfoil> airfoil;
    /// Scale factor on the section lift slope (AVL CLAF), > 0.
    double lift_slope_factor = 1.0;
    /// Strips between this section and the next; 0: the surface's `n_span` distribution applies.
    int n_span = 0;
    double span_spacing = 1.0;  ///< spacing parameter of those strips (see spacing_fractions)
    std::vector<SectionControl> controls;
};

/// A lifting surface of the lattice.
struct Surface {
    std::string name;
    std::vector<Section> sections;  ///< at least two, in spanwise order
    int n_chord = 8;                ///< chordwise vortices per strip, >= 1
    double chord_spacing = 1.0;     ///< chordwise spacing parameter (1: cosine)
    /// Strips over the whole surface distributed by arc length; 0: the per-section counts.
    int n_span = 0;
    double span_spacing = 1.0;
    /// Scale factors the sections were multiplied by (AVL SCALE; the leading edges and chords
    /// above are already scaled). A whole-surface strip distribution (`n_span` > 0) is laid out
    /// along the spanwise arc length of the sections as written, before scaling, as AVL does:
    /// with unequal y and z factors this moves the strips relative to the scaled geometry.
    Eigen::Vector3d section_scale = Eigen::Vector3d::Ones();
    /// Mirror copy about the plane y = y_duplicate (AVL YDUPLICATE; symmetric aircraft: 0).
    std::optional<double> y_duplicate;
    /// false: the surface leaves no trailing vorticity behind it (AVL NOWAKE; e.g. a fuselage
    /// plate): each of its strips carries zero net circulation (see steady.hpp).
    bool sheds_wake = true;
    /// Surfaces with the same component index are one body of the aircraft (AVL COMPONENT): the
    /// steady solver gives vortices seen from another component a large core (SteadyOptions).
    int component = 0;
};

/// A slender body (AVL BODY): axis points with equivalent radii. Read so that AVL models load;
/// see docs/vlm.md for how the lattice represents it.
struct Body {
    std::string name;
    std::vector<Eigen::Vector3d> axis;  ///< centre-line points, x increasing
    std::vector<double> radius;         ///< equivalent radius at each axis point [m]
    std::optional<double> y_duplicate;
};

/// Reference quantities of the coefficients.
struct Reference {
    double area = 1.0;                                ///< S [m^2]
    double span = 1.0;                                ///< b [m]
    double chord = 1.0;                               ///< c [m]
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< moment reference point, geometry axes
};

/// A whole vortex-lattice model.
struct Model {
    std::string name;
    Reference reference;
    double mach = 0.0;  ///< default Mach number (AVL header)
    /// Image about y = 0: +1 symmetric, -1 antisymmetric, 0 none (AVL IYsym). With +1 the
    /// lattice is one half of a symmetric aircraft: the steady solver doubles the symmetric
    /// loads (CL, CD, Cm) and sets the antisymmetric ones (CY, Cl, Cn) to zero, as AVL does.
    /// Image about z = z_symmetry_plane likewise (AVL IZsym): +1 a solid plane (ground effect:
    /// no flow through it), -1 a plane of zero pressure jump (free surface).
    int y_symmetry = 0;
    int z_symmetry = 0;
    double z_symmetry_plane = 0.0;
    std::vector<Surface> surfaces;
    std::vector<Body> bodies;
    /// Profile drag coefficient added at every state (AVL CDp), on the reference area.
    double profile_drag = 0.0;

    /// Names of every control variable on any section, in order of first appearance.
    [[nodiscard]] std::vector<std::string> control_names() const;
};

/// Lattice density used when a model is built from MANTA's aircraft description.
struct LatticeDensity {
    int n_chord = 12;            ///< chordwise vortices per strip
    double chord_spacing = 1.0;  ///< cosine
    /// Target strip width as a fraction of the reference span; strips are distributed per
    /// section panel with cosine spacing so control-surface edges fall on strip edges.
    double strip_width = 0.01;
    double span_spacing = 1.0;
};

/// The vortex-lattice model of an aircraft description. Every lifting surface becomes a surface
/// (mirrored about y = 0 if symmetric), sections are added at the span fractions where control
/// surfaces start and end, and each control surface acts on the strips between them under the
/// name of the global control that drives it (`elevator`, `aileron`, `rudder`; its own name if
/// it is driven by none). The fuselage is not a lattice surface: wings defined to the plane of
/// symmetry carry their lift through it (docs/vlm.md). InputError for a control surface outside
/// its lifting surface or a lattice density out of range.
[[nodiscard]] Model from_geometry(const geometry::AircraftGeometry& geometry,
                                  const Reference& reference, const LatticeDensity& density = {},
                                  std::string name = {});

}  // namespace manta::vlm
