#pragma once
/// @file test_meshes.hpp
/// Meshes for the Euler solver's tests and validation cases, made at test time with the gmsh C++
/// API (gmsh 4.8, Debian libgmsh-dev) and read back through MANTA's own MSH 4.1 reader, so the
/// tests run on meshes exactly as a user's file would arrive. Each function returns a finalized
/// `mesh::Mesh` in mesh axes (x downstream, y span, z up for the wing; 2-D cases lie in the
/// x-y plane and are extruded along +z into a one-cell slab by `mesh::ReadOptions`).
///
/// gmsh is initialised and finalised inside each call with its terminal output off and one
/// thread; gmsh is not thread-safe, so call these from one thread at a time. Generation times
/// (Release, one core of the 2-core development machine, tests/euler/test_meshes.cpp prints
/// them): NACA 0012 level 0 0.2 s, level 1 0.9 s; bump channel < 0.02 s; wing 1.5 s.

#include <cstdint>
#include <filesystem>

#include "manta/mesh/mesh.hpp"

namespace manta::test {

/// Half thickness of the NACA 0012 section at chord fraction `x` in [0, 1] (chord 1 m), with the
/// closed trailing edge: y_t = 0.6 (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 -
/// 0.1036 x^4) (Abbott and von Doenhoff, *Theory of Wing Sections*, 1959, sec. 6.4, with the
/// last coefficient changed from -0.1015 to -0.1036 so that y_t(1) = 0, the closed-trailing-edge
/// variant). InputError outside [0, 1].
[[nodiscard]] double naca0012_half_thickness(double x);

/// Perimeter of the closed-trailing-edge NACA 0012 of chord 1 m (m), to 1e-9 (arc length of
/// the exact section).
[[nodiscard]] double naca0012_perimeter();

/// A 2-D NACA 0012 (chord 1 m, leading edge at the origin, trailing edge at (1, 0)) at zero
/// incidence in a circular far field of radius 50 chords centred at mid-chord, meshed with
/// triangles and extruded into a slab of `slab_thickness` (m) along +z (prisms).
///
/// Level 0: 160 points on the airfoil (80 intervals per side), spacing 0.0023 c at the leading
/// edge, 0.0054 c at the trailing edge, at most 0.020 c, and 0.010 c on the upper surface
/// around x/c = 0.6 (the shock of the transonic AGARD case; 0.012 c on the lower surface around
/// x/c = 0.4); cell size growing as 0.02 c + 0.12 d with the distance d from the wall, up to
/// 6 c at the far field; 3 863 nodes per plane.
/// Level 1 halves every size (twice as fine per direction; 14 653 nodes per plane). Markers
/// `airfoil`, `farfield`, `symmetry_back` (z = 0, normal -z) and `symmetry_front` (normal +z).
/// InputError if `level` is not 0, 1 or 2.
///
/// With `flap_hinge` (x/c in [0.05, 0.95]; 0: none) the surface point nearest to the hinge station
/// on each side moves onto it, and the wall faces aft of it get their own marker `flap` (the rest
/// stay `airfoil`): a trailing-edge flap for `control_surfaces:` (docs/mesh-motion.md). InputError
/// for a hinge outside that range.
[[nodiscard]] mesh::Mesh naca0012_slab(int level, double slab_thickness = 1.0,
                                       double flap_hinge = 0.0);

/// The 2-D mesh of `naca0012_slab(level, 1, flap_hinge)` written to `file` as MSH 4.1 ASCII, in
/// the x-y plane (y up), for the CFD case driver (`mesh::read_mesh` extrudes it into the slab
/// of thickness 1 m; configuration `mesh: {up: y}` turns it z up).
void write_naca0012_msh(int level, const std::filesystem::path& file, double flap_hinge = 0.0);

/// A copy of the finalized mesh `m` turned +90 deg about the x axis, (x, y, z) -> (x, -z, y):
/// a slab in the x-y plane (y up) becomes one with z up spanning y in [-thickness, 0], as the
/// CFD configuration's `mesh: {up: y}` turns it. A proper rotation: cell orientations are kept.
[[nodiscard]] mesh::Mesh turn_y_up_to_z_up(const mesh::Mesh& m);

/// Lower wall of the bump channel: y = 0.0625 exp(-25 x^2) (m).
[[nodiscard]] double bump_lower_wall(double x);

/// The smooth-bump channel of the inviscid "flow over a bump" case of the 1st International
/// Workshop on High-Order CFD Methods (Wang et al., "High-order CFD methods: current status and
/// perspective", Int. J. Numer. Meth. Fluids 72, 2013, 811-845, "inviscid flow through a
/// channel with a smooth bump"): x in [-1.5, 1.5],
/// lower wall `bump_lower_wall`, upper wall y = 0.8, for the entropy-error study at M 0.5.
///
/// Structured quadrilaterals, (24 x 8) * 2^level cells: node (i, j) at x_i = -1.5 + 3 i / n_x,
/// y = y_wall(x_i) + (0.8 - y_wall(x_i)) j / n_y, so each level holds every node of the level
/// below (nested, spacing halved exactly, 4 times the cells). Extruded into a slab of
/// `slab_thickness` (m) along +z (hexahedra). Markers `inflow` (x = -1.5), `outflow` (x = 1.5),
/// `lower`, `upper`, `symmetry_back`, `symmetry_front`. InputError if `level` is not in 0..3.
[[nodiscard]] mesh::Mesh bump_channel(int level, double slab_thickness = 1.0);

/// A 3-D half model of a rectangular wing: NACA 0012 section (chord 1 m, leading edge along the
/// y axis, at zero incidence), semi-span 3 m (aspect ratio 6), flat tip at y = 3, root on the
/// symmetry plane y = 0, in the box x in [-10, 11], y in [0, 10], z in [-10, 10] m, meshed with
/// tetrahedra. Level 0: wing surface size 0.02 m at the leading edge, 0.04 m at the trailing
/// edge, 0.08 m at x/c = 0.3, growing as 0.1 + 0.2 d with the distance d from the wing's
/// bounding box up to 2.5 m at the far field; 8 881 nodes, 43 122 tetrahedra. Markers `wing`
/// (upper, lower and tip surfaces), `symmetry` (y = 0, normal -y), `farfield` (the five other box
/// faces). Level 1 scales every size by 0.75. InputError if `level` is not 0 or 1 (level 1: 13 594
/// nodes).
[[nodiscard]] mesh::Mesh wing_box(int level = 0);

/// The unit cube [0, 1]^3 cut into n^3 sub-cubes, each a hexahedron, two prisms, six
/// tetrahedra (Kuhn subdivision) or six pyramids (about an added centre node, a pyramid whose
/// base must meet triangles split into two tetrahedra), chosen at random with `seed` and made
/// conforming (every shared face is the same quadrilateral or the same two triangles on both
/// sides, split along the diagonal from its lowest to its highest corner). Every interior node
/// is then moved by a uniform random offset of up to `perturbation` times the sub-cube size in
/// each direction (faces become non-planar). Markers `xmin`, `xmax`, `ymin`, `ymax`, `zmin`,
/// `zmax`. Built directly with `mesh::Mesh` (gmsh 4.8 cannot mix hexahedra and tetrahedra
/// conformally without its pyramid relocation, which aborts: tests/mesh/gmsh_fixtures.hpp).
/// Up to 0.15 no cell inverts (checked for seeds 1-300 and n = 2, 3, 5, 8; at 0.2 some do, and
/// `finalize` reports them). InputError if n < 2 or the perturbation is not in [0, 0.15].
[[nodiscard]] mesh::Mesh irregular_box(int n = 6, double perturbation = 0.15,
                                       std::uint32_t seed = 1);

/// Write `m` as an SU2 file (node orders of mesh.hpp are VTK's, as SU2's; coordinates with 17
/// digits, so the file reads back bit for bit), for the tests that run the case driver on files.
void write_su2(const mesh::Mesh& m, const std::filesystem::path& file);

}  // namespace manta::test
