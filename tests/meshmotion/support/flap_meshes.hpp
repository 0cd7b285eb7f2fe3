#pragma once
/// @file flap_meshes.hpp
/// Meshes with a control-surface marker for the meshmotion tests, in mesh axes (x downstream,
/// y span, z up). `flap_wing` is made with the gmsh C++ API (Debian libgmsh-dev) and read back
/// through MANTA's MSH 4.1 reader; `flap_plate` is built directly with `mesh::Mesh`. gmsh is
/// initialised and finalised inside the call (one thread, quiet); call from one thread at a time.

#include "manta/mesh/mesh.hpp"

namespace manta::test {

/// Half thickness of the closed-trailing-edge NACA 0012 at chord fraction x in [0, 1], chord 1 m:
/// 0.6 (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 - 0.1036 x^4) (Abbott & von
/// Doenhoff, *Theory of Wing Sections*, 1959, sec. 6.4, last coefficient -0.1036 for y_t(1) = 0).
[[nodiscard]] double naca0012_thickness(double x);

/// Where the flap of `flap_wing` lies.
struct FlapGeometry {
    double hinge_x = 0.75;  ///< hinge chord fraction (the flap is the aft 25 %)
    double y_in = 1.0;      ///< inboard side edge [m]
    double y_out = 2.0;     ///< outboard side edge [m]
};

/// A half model of a rectangular NACA 0012 wing (chord 1 m, leading edge on the y axis, semi-span
/// 3 m, flat tip) in the box x in [-10, 11], y in [0, 10], z in [-10, 10] m, meshed with
/// tetrahedra. The aft 25 % of the chord between y = 1 and y = 2 is the marker `flap`, sealed to
/// the rest of the wing (marker `wing`: upper, lower, tip surfaces) along its hinge line x = 0.75
/// on both skins and its side edges; `symmetry` (y = 0) and `farfield`. Surface sizes 0.02 m
/// (leading edge), 0.04 m (trailing edge), 0.08 m (mid-chord), 0.03 m on the flap, times
/// `size`, growing as size (0.1 + 0.2 d) with the distance d from the wing's box up to 2.5 size
/// at the far field. size 1: about 12 000 nodes; 0.35: about 110 000.
[[nodiscard]] mesh::Mesh flap_wing(double size = 1.0);

/// A flat plate flap in a box: [0, 3] x [0, 1] x [0, 1] m cut into n_x x n_y x n_z cells
/// (hexahedra, or prisms when `prisms`); the wall z = 0 is the marker `flap` for 1 <= x <= 2,
/// 0.25 <= y <= 0.75 (hinge along y at x = 1, z = 0; chord 1 m; sealed to the rest of the
/// wall, marker `wall`, on its four edges), the other faces `farfield`. InputError unless n_x is
/// a multiple of 3 and n_y a multiple of 4.
[[nodiscard]] mesh::Mesh flap_plate(int n_x, int n_y, int n_z, bool prisms = false);

}  // namespace manta::test
