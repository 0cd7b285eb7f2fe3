#pragma once
/// @file lattice.hpp
/// The horseshoe-vortex lattice of a `Model`: one horseshoe per panel, its bound segment on the
/// panel's quarter-chord line, its control point at the three-quarter-chord point of the strip's
/// mid-span, and two trailing legs running from the bound segment's ends to infinity along +x
/// (geometry axes: x aft, y right, z up). Panels are grouped in strips (one spanwise element,
/// `n_chord` panels deep), strips in surface copies.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "manta/vlm/model.hpp"

namespace manta::vlm {

/// A control surface acting on a panel: the normal rotates by `gain * value` of control
/// `control` (index into Lattice::control_names) about the unit axis `axis`. A panel cut by the
/// hinge line has its gain scaled by the fraction of its chord on the control surface.
struct PanelControl {
    int control = 0;
    double gain = 1.0;
    Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
    double duplicate_sign = 1.0;  ///< factor applied on the mirror copy (see SectionControl)
};

/// One strip: a spanwise element of a surface copy, `n_chord` panels deep.
struct Strip {
    int surface = 0;        ///< index into Model::surfaces
    bool mirrored = false;  ///< on the mirror copy of a duplicated surface
    int first_panel = 0;  ///< panels first_panel .. first_panel + n_panels - 1, leading edge first
    int n_panels = 0;
    Eigen::Vector3d le_a, le_b;  ///< leading-edge points of the strip's two edges
    /// Leading-edge point at the station of the control points (the middle of the strip in the
    /// spacing parameter; the Trefftz-plane wash is evaluated there too).
    Eigen::Vector3d le_mid;
    double chord_a = 0.0, chord_b = 0.0;
    double chord = 0.0;  ///< mid-span chord
    double area = 0.0;   ///< planform area (in the strip's plane)
    double width = 0.0;  ///< |edge b - edge a| at the leading edge
    bool sheds_wake = true;
};

struct Lattice {
    std::vector<std::string> control_names;
    std::vector<Strip> strips;
    // Per panel:
    std::vector<Eigen::Vector3d> a, b;  ///< bound segment ends; positive circulation a -> b
    std::vector<Eigen::Vector3d> control_point;  ///< three-quarter-chord point at mid-span
    /// Point of the bound segment at the spanwise station of the control point (where the steady
    /// solver evaluates the local velocity and applies the Kutta-Joukowski force).
    std::vector<Eigen::Vector3d> bound_point;
    std::vector<Eigen::Vector3d> normal;  ///< undeflected unit normal (incidence, camber)
    std::vector<double> area;             ///< panel area
    /// Panel corners: leading edge on side a, leading edge on side b, trailing edge on side b,
    /// trailing edge on side a (for output).
    std::vector<std::array<Eigen::Vector3d, 4>> corners;
    std::vector<double> chord_fraction;  ///< x/c of the control point in its strip
    std::vector<int> strip;              ///< owning strip
    /// The panel's surface sheds a wake (false: NOWAKE surface; the steady solver keeps its
    /// trailing legs but gives each of its strips zero net circulation, see steady.hpp).
    std::vector<bool> wake;
    std::vector<std::vector<PanelControl>> controls;

    [[nodiscard]] int size() const { return static_cast<int>(a.size()); }
    /// Normal of panel i with the control values `deflection` (one per control name) [rad]:
    /// the undeflected normal rotated by each acting control.
    [[nodiscard]] Eigen::Vector3d deflected_normal(int i, const Eigen::VectorXd& deflection) const;
    /// Normal of panel i to first order in the control values: the undeflected normal plus, for
    /// each acting control, gain * value * (axis x normal). Not of unit length; the steady solver
    /// uses it (as AVL does), so that loads are linear in the deflections.
    [[nodiscard]] Eigen::Vector3d linearized_normal(int i, const Eigen::VectorXd& deflection) const;
    /// d normal / d control k at `deflection` (zero if control k does not act on panel i).
    [[nodiscard]] Eigen::Vector3d normal_derivative(int i, const Eigen::VectorXd& deflection,
                                                    int k) const;
    /// Index of a control by name, or -1.
    [[nodiscard]] int control_index(std::string_view name) const;
};

/// Build the lattice. InputError naming the surface and section for degenerate input: fewer than
/// two sections, zero or negative chord, coincident consecutive sections, a strip count < 1.
[[nodiscard]] Lattice build_lattice(const Model& model);

/// Check a lattice for geometric faults: zero-area panels, non-finite points, and bound segments
/// of different surfaces crossing (intersecting within a tolerance). InputError naming the two
/// surfaces.
void check_lattice(const Model& model, const Lattice& lattice);

}  // namespace manta::vlm
