#pragma once
/// @file aircraft_geometry.hpp
/// The outer shape of an aircraft as the flow solvers and the mesh generator need it: lifting
/// surfaces made of sections (leading-edge point, chord, twist, airfoil), a fuselage given by
/// stations, and control surfaces with their hinge line, span range and sign convention.
///
/// Geometry axes (the three-view): x aft, y toward the right wing, z up, metres; angles in
/// radians. The origin is the user's choice (the Ranger example puts it at the nose, on the
/// fuselage reference line). Flight-mechanics body axes are x forward, y right, z down; the
/// conversion is `core::body_from_geometry` (core/frames.hpp; x and z change sign).
///
/// Read from the `geometry:` section of an aircraft file (docs/aircraft-format.md#geometry) by
/// `parse_geometry`; every quantity derived here (planform area, span, mean aerodynamic chord)
/// follows the textbook definitions for straight-tapered panels (Raymer, *Aircraft Design: A
/// Conceptual Approach*, 6th ed., sec. 7.3; Torenbeek, *Synthesis of Subsonic Airplane Design*,
/// app. A), evaluated exactly panel by panel.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "manta/core/config.hpp"

namespace manta::geometry {

// ---------------------------------------------------------------------------------------- airfoils

/// Families of NACA designations understood by `parse_naca`.
enum class NacaFamily {
    four_digit,  ///< "NACA MPTT": camber M %, at P tenths of chord, thickness TT %
    five_digit,  ///< "NACA LPQTT": design lift 0.15 L, max camber at P/20, Q = 1 reflexed, TT %
    six_series,  ///< "NACA 6S(R)-LTT [a=A]": min pressure at S tenths, design lift L tenths, TT %
};

/// A parsed and validated NACA designation (Abbott & von Doenhoff, *Theory of Wing Sections*,
/// Dover 1959, ch. 6; Jacobs, Ward & Pinkerton, NACA Report 460 and Jacobs & Pinkerton, NACA
/// Report 537 for the four- and five-digit sections). All lengths are fractions of the chord.
struct NacaDesignation {
    NacaFamily family = NacaFamily::four_digit;  ///< which of the three families
    std::string text;                            ///< normalised designation, e.g. "NACA 64(2)-215"
    double thickness = 0.0;                      ///< maximum thickness t/c
    double max_camber = 0.0;                     ///< four-digit: maximum camber m/c
    double camber_position = 0.0;                ///< four- and five-digit: x/c of maximum camber
    double design_lift = 0.0;  ///< five-digit and 6-series: design lift coefficient c_li
    bool reflexed = false;     ///< five-digit: reflexed mean line (third digit 1)
    /// Five-digit mean-line constants (r: x/c where the two polynomial pieces join; k1; k2/k1),
    /// from NACA Report 537 for c_li = 0.3, already scaled to `design_lift`.
    double r = 0.0, k1 = 0.0, k2_over_k1 = 0.0;
    int min_pressure_tenths = 0;  ///< 6-series: x/c of minimum pressure, tenths (the "4" of 64-215)
    int low_drag_range_tenths =
        0;  ///< 6-series: half-width of the low-drag c_l range, tenths; 0 if unstated
    bool a_modified = false;   ///< 6-series 'A' sections (e.g. 64A010)
    double mean_line_a = 1.0;  ///< 6-series mean line parameter a (uniform loading up to x/c = a)
};

/// Parse a NACA designation ("NACA 2412", "naca23012", "NACA 64-215", "NACA 64(2)-215",
/// "NACA 64_2-215", "NACA 642-215", "NACA 65-410 a=0.5", "NACA 64A010"); the word "NACA" is
/// optional and case is ignored. InputError naming the designation and what is expected.
[[nodiscard]] NacaDesignation parse_naca(std::string_view designation);

/// A 2-D section shape, from a NACA designation or from a coordinate file, in chord-normalised
/// coordinates (x from 0 at the leading edge to 1 at the trailing edge, y up).
class Airfoil {
public:
    /// NACA 0012 (a default that is always valid).
    Airfoil();
    /// From a designation (see `parse_naca`); InputError if invalid.
    [[nodiscard]] static Airfoil naca(std::string_view designation);
    /// Read a Selig or Lednicer coordinate file (format detected). IoError if it cannot be read,
    /// InputError naming file and line for a malformed or non-normalised file.
    [[nodiscard]] static Airfoil from_file(const std::filesystem::path& file);
    /// From points in Selig order (trailing edge, upper surface, leading edge, lower surface,
    /// trailing edge). Validated like a file; `source` names the data in messages.
    [[nodiscard]] static Airfoil from_points(std::string name, std::vector<Eigen::Vector2d> points,
                                             const std::string& source);

    [[nodiscard]] bool is_naca() const { return naca_.has_value(); }
    /// The designation; precondition `is_naca()`.
    [[nodiscard]] const NacaDesignation& designation() const;
    /// Coordinate file it was read from (empty for NACA sections and `from_points`).
    [[nodiscard]] const std::filesystem::path& file() const { return file_; }
    /// Designation text or the name line of the file.
    [[nodiscard]] const std::string& name() const { return name_; }

    /// Maximum thickness t/c (for a coordinate airfoil: largest upper-minus-lower distance
    /// sampled at 201 cosine-spaced stations).
    [[nodiscard]] double thickness_ratio() const;
    /// Mean-line ordinate y_c/c at x/c in [0, 1].
    [[nodiscard]] double camber(double x) const;
    /// Mean-line slope dy_c/dx at x/c in (0, 1) (what a vortex-lattice method needs).
    [[nodiscard]] double camber_slope(double x) const;
    /// True if `coordinates()` can produce the shape: files and four/five-digit sections. The
    /// 6-series thickness forms are tabulated, not analytic (Abbott & von Doenhoff app. I), and
    /// are not generated: give such a section as a coordinate file when the surface is needed.
    [[nodiscard]] bool has_coordinates() const {
        return !naca_ || naca_->family != NacaFamily::six_series;
    }
    /// Closed contour in Selig order. Files: the points as read. Four/five-digit: `n_per_side`
    /// cosine-spaced stations per side with the standard (open, 0.1015) thickness polynomial,
    /// thickness laid perpendicular to the mean line. InputError for 6-series sections.
    [[nodiscard]] std::vector<Eigen::Vector2d> coordinates(std::size_t n_per_side = 81) const;

private:
    std::optional<NacaDesignation> naca_;
    std::filesystem::path file_;
    std::string name_;
    std::vector<Eigen::Vector2d> points_;  // Selig order (coordinate airfoils)
    std::vector<Eigen::Vector2d> upper_;   // leading edge to trailing edge, increasing x
    std::vector<Eigen::Vector2d> lower_;   // leading edge to trailing edge, increasing x
};

// ---------------------------------------------------------------------------------- lifting
// surfaces

/// One defining section of a lifting surface; the surface is ruled (straight lines) between
/// consecutive sections.
struct SurfaceSection {
    /// Leading-edge point, geometry axes [m].
    Eigen::Vector3d leading_edge = Eigen::Vector3d::Zero();
    double chord = 0.0;  ///< [m], along geometry x
    /// Incidence of the section [rad], leading edge up positive, about the spanwise axis
    /// through the leading edge (geometric twist plus the surface's setting angle).
    double twist = 0.0;
    Airfoil airfoil;
};

/// A wing, tailplane or fin. Horizontal surfaces run along +y (spanwise coordinate y) and, if
/// `symmetric`, are mirrored about y = 0; vertical surfaces run along +z (spanwise coordinate z).
struct LiftingSurface {
    std::string name;       ///< unique among the aircraft's surfaces ("wing", "fin", ...)
    bool symmetric = true;  ///< mirrored about the plane y = 0
    bool vertical = false;  ///< fin: spanwise coordinate is z and the planform lies in x-z
    std::vector<SurfaceSection> sections;  ///< root to tip, spanwise coordinate increasing

    /// Spanwise coordinate of a section: y for horizontal surfaces, z for vertical ones [m].
    [[nodiscard]] double spanwise(const SurfaceSection& s) const {
        return vertical ? s.leading_edge.z() : s.leading_edge.y();
    }
    /// Copies of the defined panels: 2 if symmetric, else 1.
    [[nodiscard]] int n_copies() const { return symmetric ? 2 : 1; }
    /// Extent of the defined half along the spanwise coordinate, tip minus root [m].
    [[nodiscard]] double semi_span() const;
    /// Span [m]: tip to tip (2 y_tip) for a symmetric horizontal surface, else the spanwise
    /// extent of one copy (the height of a fin).
    [[nodiscard]] double span() const;
    /// Planform area [m^2], projected on the surface's reference plane (x-y, or x-z for fins),
    /// all copies included: sum over panels of (c_i + c_i+1)/2 |ds|.
    [[nodiscard]] double planform_area() const;
    /// Mean aerodynamic chord [m]: integral of c^2 ds over integral of c ds (one copy).
    [[nodiscard]] double mean_aerodynamic_chord() const;
    /// Leading-edge point of the mean aerodynamic chord on the defined copy [m]: x and z
    /// chord-weighted (integral of c x_le ds / integral of c ds), spanwise coordinate likewise.
    [[nodiscard]] Eigen::Vector3d mac_leading_edge() const;
    /// Aspect ratio span^2 / area of one copy for fins and non-symmetric surfaces, span^2 / area
    /// for symmetric horizontal surfaces.
    [[nodiscard]] double aspect_ratio() const;
    /// Chord of the first (root) section [m].
    [[nodiscard]] double root_chord() const { return sections.front().chord; }
    /// Chord of the last (tip) section [m].
    [[nodiscard]] double tip_chord() const { return sections.back().chord; }
    /// Taper ratio tip chord / root chord.
    [[nodiscard]] double taper_ratio() const { return tip_chord() / root_chord(); }
    /// Fraction eta in [0, 1] of the semi-span at spanwise coordinate s.
    [[nodiscard]] double eta_of(double s) const;
    /// Leading-edge point and chord at fraction eta of the semi-span (linear between sections).
    [[nodiscard]] Eigen::Vector3d leading_edge_at(double eta) const;
    [[nodiscard]] double chord_at(double eta) const;
    /// Leading-edge sweep of panel i (between sections i and i+1) [rad], aft positive.
    [[nodiscard]] double leading_edge_sweep(std::size_t panel) const;
    /// Dihedral of panel i [rad], tip up positive (horizontal surfaces only; 0 for fins).
    [[nodiscard]] double dihedral(std::size_t panel) const;
};

// ---------------------------------------------------------------------------------------- fuselage

/// A fuselage cross-section: an ellipse (or a point, at the nose and tail) centred on the plane
/// y = 0.
struct FuselageStation {
    double x = 0.0;         ///< [m]
    double width = 0.0;     ///< [m], along y
    double height = 0.0;    ///< [m], along z
    double z_centre = 0.0;  ///< z of the section centre [m]
};

/// A fuselage given by stations along x (empty for a flying wing).
struct Fuselage {
    std::vector<FuselageStation> stations;  ///< x strictly increasing
    /// True if no fuselage was given.
    [[nodiscard]] bool empty() const { return stations.empty(); }
    /// Largest station width [m]; 0 if empty.
    /// Last minus first station x [m]; 0 if empty.
    [[nodiscard]] double length() const;
    [[nodiscard]] double max_width() const;
    /// Largest station height [m]; 0 if empty.
    [[nodiscard]] double max_height() const;
    /// Volume of the body of elliptic sections [m^3], trapezoidal in x.
    [[nodiscard]] double volume() const;
};

// ---------------------------------------------------------------------------------- control
// surfaces

/// The global control that drives a control surface.
enum class Control { none, elevator, aileron, rudder };
/// "none", "elevator", "aileron", "rudder".
[[nodiscard]] std::string_view to_string(Control c);

/// A hinged trailing-edge surface on a lifting surface. Its local deflection is positive
/// trailing edge down on horizontal surfaces and trailing edge toward the left wing (-y) on
/// vertical ones. Local deflection = gain * global control for the defined copy and
/// mirror_gain * global control for the mirrored copy, so the paper's conventions (elevator
/// trailing edge down +, left aileron trailing edge down +, rudder trailing edge left +) give
/// elevator gains (+1, +1), aileron gains right -1 / left +1 and rudder +1.
struct ControlSurface {
    std::string name;                 ///< unique among the control surfaces
    std::string surface;              ///< name of the lifting surface it belongs to
    Control control = Control::none;  ///< the global control that drives it (none: not driven)
    /// Inboard and outboard ends as fractions of the surface's semi-span (0 root, 1 tip).
    std::array<double, 2> span_fraction{0.0, 1.0};
    /// Hinge line position as a fraction of the local chord from the leading edge (0.7: the
    /// control surface is the aft 30 % of the chord).
    double hinge_chord_fraction = 0.75;
    double gain = 1.0;  ///< defined copy (the right side of a symmetric surface)
    double mirror_gain =
        1.0;  ///< mirrored copy (left side); unused if the surface is not symmetric
    /// Local deflection limits [rad] if stated (the flight model uses the aircraft's control
    /// limits).
    std::optional<std::array<double, 2>> limits;

    /// Local deflection [rad] of the defined (`mirrored` false) or mirrored copy for a value of
    /// the global control [rad].
    [[nodiscard]] double deflection(double control_value, bool mirrored = false) const {
        return (mirrored ? mirror_gain : gain) * control_value;
    }
};

// ---------------------------------------------------------------------------------------- aircraft

/// The whole outer shape.
struct AircraftGeometry {
    double length =
        0.0;  ///< overall length [m] (every surface point lies within [0, length] in x, 1 % slack)
    double height = 0.0;  ///< overall height [m] (documentation; not checked against the parts)
    std::vector<LiftingSurface> surfaces;          ///< wings, tailplanes, fins; names unique
    Fuselage fuselage;                             ///< empty if none was given
    std::vector<ControlSurface> control_surfaces;  ///< each on one of `surfaces`

    /// Surface by name, or nullptr.
    [[nodiscard]] const LiftingSurface* find_surface(std::string_view name) const;
    /// Surface by name; InputError listing the names present.
    [[nodiscard]] const LiftingSurface& surface(std::string_view name) const;
    /// Control surface by name, or nullptr.
    [[nodiscard]] const ControlSurface* find_control_surface(std::string_view name) const;
    /// Planform area of a control surface aft of its hinge line, all copies [m^2].
    [[nodiscard]] double control_surface_area(const ControlSurface& cs) const;
    /// Hinge-line end points (inboard, outboard) of the defined copy, geometry axes [m].
    [[nodiscard]] std::array<Eigen::Vector3d, 2> hinge_line(const ControlSurface& cs) const;
};

/// Read the `geometry:` section. `map` is that section; every key is read and `map.finish()` is
/// called, so unknown keys are rejected. Airfoil files are resolved relative to `base_dir` (the
/// folder of the aircraft file). ConfigError naming file, line, key path, value and expectation;
/// problems inside an airfoil file are reported with the YAML key that names the file.
[[nodiscard]] AircraftGeometry parse_geometry(core::ConfigMap& map,
                                              const std::filesystem::path& base_dir);

}  // namespace manta::geometry
