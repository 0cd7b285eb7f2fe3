#pragma once
/// @file viscous.hpp
/// Viscous (profile) drag of an aircraft by the component build-up of Raymer, *Aircraft Design:
/// A Conceptual Approach*, 6th ed., AIAA 2018, sec. 12.5, eq. 12.24: for each component c
///
///     CD0_c = Cf_c FF_c Q_c Swet_c / Sref,
///
/// the flat-plate skin friction Cf (eqs. 12.26-12.28), a form factor FF for the pressure drag of
/// viscous separation (eq. 12.30 for lifting surfaces, eq. 12.31 and its footnote for the
/// fuselage), an interference factor Q and the wetted area Swet (eq. 7.11/7.12 for lifting
/// surfaces; the integrated perimeter of the elliptic stations for the fuselage). The vortex
/// lattice gives the induced drag; this is what it adds to make CD realistic. Subsonic only.
///
/// Theory, assumptions and the Ranger 2000 breakdown: docs/viscous-drag.md.
///
/// Units: SI (metres, square metres, Reynolds number per metre), angles in radians. The caller
/// supplies Mach number and Reynolds number per metre from its atmosphere (`reynolds_per_metre`),
/// so that this module needs no atmosphere model.

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "manta/geometry/aircraft_geometry.hpp"

namespace manta::vlm {

// ------------------------------------------------------------------------------------ ingredients

/// Reynolds number per metre rho V / mu [1/m] from density [kg/m^3], true airspeed [m/s] and
/// dynamic viscosity [Pa s]. InputError unless all three are positive and finite.
[[nodiscard]] double reynolds_per_metre(double density, double speed, double viscosity);

/// Laminar flat-plate skin friction (Blasius), Cf = 1.328 / sqrt(Re) (Raymer eq. 12.26).
/// InputError unless Re is positive and finite.
[[nodiscard]] double laminar_skin_friction(double reynolds);

/// Turbulent flat-plate skin friction with Raymer's compressibility correction,
/// Cf = 0.455 / ((log10 Re)^2.58 (1 + 0.144 M^2)^0.65) (Raymer eq. 12.27).
/// InputError unless Re > 10 (the fit needs log10 Re > 1) and 0 <= M < 1.
[[nodiscard]] double turbulent_skin_friction(double reynolds, double mach);

/// Cut-off Reynolds number of a surface of roughness height k on length l, subsonic:
/// 38.21 (l/k)^1.053 (Raymer eq. 12.28). Above it the skin friction no longer falls with Re
/// (the roughness, not the boundary layer, sets it). InputError unless l and k are positive.
[[nodiscard]] double cutoff_reynolds(double length, double roughness_height);

/// Skin roughness classes of Raymer's Table 12.5.
enum class SkinRoughness {
    camouflage_paint,         ///< camouflage paint on aluminium, k = 1.015e-5 m
    smooth_paint,             ///< smooth paint, k = 0.634e-5 m (the default)
    production_sheet_metal,   ///< k = 0.405e-5 m
    polished_sheet_metal,     ///< k = 0.152e-5 m
    smooth_molded_composite,  ///< k = 0.052e-5 m
};
/// Roughness height k [m] of a class (Raymer Table 12.5, metric column).
[[nodiscard]] double roughness_height(SkinRoughness roughness);
/// "camouflage_paint", "smooth_paint", ... (the enumerator names).
[[nodiscard]] std::string_view to_string(SkinRoughness roughness);

/// Mixed skin friction of a component of characteristic length l at Reynolds number `reynolds`
/// (on l): Cf = f_lam Cf_lam(Re) + (1 - f_lam) Cf_turb(min(Re, Re_cutoff), M), the laminar and
/// turbulent parts mixed by wetted area (Raymer sec. 12.5, below eq. 12.27). InputError for a
/// laminar fraction outside [0, 1] and as the functions above.
[[nodiscard]] double skin_friction(double reynolds, double mach, double length,
                                   double roughness_height, double laminar_fraction);

/// Compressibility term 1.34 M^0.18 of the lifting-surface form factor (Raymer eq. 12.30). With
/// `floor_at_one` it is held at 1 below M = 0.197, where the fit would fall below the
/// incompressible value (it reaches 0 at M = 0). InputError unless 0 <= M < 1.
[[nodiscard]] double form_factor_mach_term(double mach, bool floor_at_one = true);

/// Form factor of a wing, tail, strut or pylon (Raymer eq. 12.30):
/// [1 + 0.6/(x/c)_m (t/c) + 100 (t/c)^4] [1.34 M^0.18 (cos Lambda_m)^0.28], with (x/c)_m the
/// chordwise position of maximum thickness and Lambda_m the sweep of the line through it.
/// InputError for t/c outside [0, 0.5), (x/c)_m outside (0, 1), |Lambda_m| >= 90 deg, or a Mach
/// number outside [0, 1).
[[nodiscard]] double surface_form_factor(double thickness_ratio, double max_thickness_position,
                                         double max_thickness_sweep, double mach,
                                         bool floor_mach_term = true);

/// Fuselage form-factor correlations.
enum class BodyFormFactor {
    /// FF = 1 + 60/f^3 + f/400: the RAND/DATCOM form of Raymer's earlier editions, quoted in the
    /// 6th edition's footnote to eq. 12.31 as a good correlation for fineness ratios above 6
    /// (high-speed and military aircraft). The default.
    classic,
    /// FF = 0.9 + 5/f^1.5 + f/400: Raymer 6th ed. eq. 12.31, lower for short, fat bodies.
    raymer_2018,
};
/// "classic" or "raymer_2018".
[[nodiscard]] std::string_view to_string(BodyFormFactor law);

/// Fuselage form factor at fineness ratio f = l / d, d = sqrt((4/pi) A_max) (Raymer eq. 12.33).
/// InputError unless f is positive and finite.
[[nodiscard]] double body_form_factor(double fineness_ratio,
                                      BodyFormFactor law = BodyFormFactor::classic);

/// Position of maximum thickness (x/c)_m of a section as a chord fraction: 0.3 for four- and
/// five-digit NACA sections (the four-digit thickness form peaks at 30 % chord), the digit of the
/// minimum-pressure position over 10 for 6-series sections (0.4 for a 64-series, 0.5 for a 65; an
/// estimate, the thickness forms being tabulated), and for coordinate airfoils the position of
/// the largest upper-minus-lower distance.
[[nodiscard]] double max_thickness_position(const geometry::Airfoil& airfoil);

/// Perimeter of an ellipse of full width `width` and height `height` by Ramanujan's first
/// approximation, pi [3(a + b) - sqrt((3a + b)(a + 3b))] with semi-axes a, b: exact for a
/// circle, too short by 3e-6 at an axis ratio of 2, 3.4e-5 at 3 and 0.42 % in the flat limit.
/// InputError for a negative or non-finite width or height.
[[nodiscard]] double ellipse_perimeter(double width, double height);

/// Wetted area of a fuselage of elliptic stations [m^2]: the Ramanujan perimeter integrated along
/// the meridian, sum over the station intervals of the integral of P(x) sqrt(1 + R'^2 + z_c'^2/2)
/// dx (R = P / 2 pi the equivalent radius, z_c the section centre; width, height and z_c linear
/// between stations; 8-point Gauss-Legendre per interval). Exact for a circular cylinder and a
/// straight cone; the slope term adds what Raymer's plain integral of P dx leaves out on the nose
/// and tail cones. 0 for an empty fuselage.
[[nodiscard]] double fuselage_wetted_area(const geometry::Fuselage& fuselage);

/// Width, height and centre z of the fuselage at station x, linear between stations; nullopt if x
/// lies outside the fuselage or there is none.
[[nodiscard]] std::optional<geometry::FuselageStation> fuselage_section_at(
    const geometry::Fuselage& fuselage, double x);

/// The part of a lifting surface outside the fuselage, as the build-up needs it.
struct ExposedPlanform {
    /// Spanwise coordinate (y, or z for fins) where the exposed part starts: the root's, or the
    /// fuselage side (top for fins) at the root's mid-chord station if the root lies inside.
    double start = 0.0;
    double area = 0.0;                    ///< exposed planform area, all copies [m^2]
    double thickness_ratio = 0.0;         ///< t/c weighted by exposed area (ruled between sections)
    double max_thickness_position = 0.0;  ///< (x/c)_m weighted by exposed area
    double max_thickness_sweep = 0.0;     ///< Lambda_m [rad], weighted by exposed panel area
};

/// Exposed planform of `surface` with respect to `fuselage` (see docs/viscous-drag.md): if the
/// root section's point (at its mid-chord x) lies inside the fuselage's elliptic section there,
/// the surface is cut at the body side at the root's height (horizontal surfaces) or at the body
/// top at the root's y (fins), perpendicular to the spanwise coordinate. InputError for a surface
/// with fewer than two sections, a non-positive chord or a spanwise coordinate that does not
/// increase from root to tip.
[[nodiscard]] ExposedPlanform exposed_planform(const geometry::LiftingSurface& surface,
                                               const geometry::Fuselage& fuselage);

// ------------------------------------------------------------------------------------- build-up

/// What a component is, for its defaults (interference factor, laminar fraction).
enum class ComponentKind { wing, tail, fuselage };
/// "wing", "tail", "fuselage".
[[nodiscard]] std::string_view to_string(ComponentKind kind);

/// Settings of the build-up; the defaults are Raymer's for a clean, painted metal aircraft.
struct ViscousDragOptions {
    /// Surface finish; `roughness_height_override` [m], if set, replaces its k.
    SkinRoughness roughness = SkinRoughness::smooth_paint;
    std::optional<double> roughness_height_override;
    /// Fractions of the wetted area with a laminar boundary layer, in [0, 1] (Raymer Table 12.4
    /// suggests 0.1-0.5 for wings, 0-0.35 for fuselages depending on the finish); default fully
    /// turbulent.
    double laminar_fraction_surfaces = 0.0;
    double laminar_fraction_fuselage = 0.0;
    /// Interference factors Q (Raymer sec. 12.5): 1.0 for a high or mid wing or a well-filleted
    /// low wing, 1.04-1.08 for conventional tails, 1.0 for the fuselage. Each > 0.
    double interference_wing = 1.0;
    double interference_tail = 1.05;
    double interference_fuselage = 1.0;
    /// Per-component interference factors by name ("wing", "fin", "fuselage"), overriding the
    /// defaults above. InputError for a name that is not a component.
    std::map<std::string, double, std::less<>> interference_by_name;
    /// Name of the main wing; empty: the horizontal surface of largest planform area. Every other
    /// lifting surface is a tail. InputError if not a surface of the geometry.
    std::string main_wing;
    /// Fuselage form-factor correlation.
    BodyFormFactor body_form_factor = BodyFormFactor::classic;
    /// Hold the 1.34 M^0.18 term of eq. 12.30 at >= 1 (see form_factor_mach_term).
    bool floor_form_factor_mach_term = true;
    /// Leakage-and-protuberance (and other miscellaneous) drag as a fraction of the total
    /// parasite drag (Raymer Table 12.8: 0.02-0.05 for jet transports, 0.05-0.10 for propeller
    /// aircraft), in [0, 0.5]: increment = fraction / (1 - fraction) * (sum of the components).
    double leakage_protuberance_fraction = 0.0;
};

/// One component's share of the viscous drag.
struct ComponentDrag {
    std::string name;  ///< the lifting surface's name, or "fuselage"
    ComponentKind kind = ComponentKind::wing;
    double length = 0.0;           ///< characteristic length: MAC or fuselage length [m]
    double reynolds = 0.0;         ///< Reynolds number on `length`
    double cutoff_reynolds = 0.0;  ///< roughness cut-off (eq. 12.28); the turbulent Cf uses the min
    double laminar_fraction = 0.0;
    double skin_friction = 0.0;  ///< Cf
    double form_factor = 0.0;    ///< FF
    double interference = 1.0;   ///< Q
    double wetted_area = 0.0;    ///< Swet [m^2]
    double cd0 = 0.0;            ///< Cf FF Q Swet / Sref
    // What the form factor and wetted area were computed from.
    double exposed_area = 0.0;     ///< lifting surfaces: exposed planform area [m^2]; fuselage: 0
    double thickness_ratio = 0.0;  ///< lifting surfaces: t/c
    double max_thickness_position = 0.0;  ///< lifting surfaces: (x/c)_m
    double max_thickness_sweep = 0.0;     ///< lifting surfaces: Lambda_m [rad]
    double fineness_ratio = 0.0;          ///< fuselage: l / sqrt((4/pi) A_max)
};

/// The build-up at one flight condition.
struct ViscousDrag {
    double reference_area = 0.0;            ///< Sref [m^2]
    double mach = 0.0;                      ///< Mach number
    double reynolds_per_metre = 0.0;        ///< [1/m]
    std::vector<ComponentDrag> components;  ///< lifting surfaces in geometry order, then fuselage
    double components_cd0 = 0.0;            ///< sum of the components' CD0
    double leakage_protuberance_cd0 = 0.0;  ///< miscellaneous increment
    double cd0 = 0.0;                       ///< total viscous CD0 on Sref

    /// Component by name, or nullptr.
    [[nodiscard]] const ComponentDrag* find(std::string_view name) const;
};

/// Viscous drag build-up of `geometry` on reference area `reference_area` [m^2] at Mach number
/// `mach` and Reynolds number per metre `reynolds_per_metre` [1/m]. InputError (one line naming
/// the value and what was expected) for a non-positive or non-finite area or Re/l, a Mach number
/// outside [0, 1) (the form factors and the build-up are subsonic), invalid options, or a
/// component whose Reynolds number falls below 1e4 or whose geometry is degenerate.
[[nodiscard]] ViscousDrag viscous_drag(const geometry::AircraftGeometry& geometry,
                                       double reference_area, double mach,
                                       double reynolds_per_metre,
                                       const ViscousDragOptions& options = {});

}  // namespace manta::vlm
