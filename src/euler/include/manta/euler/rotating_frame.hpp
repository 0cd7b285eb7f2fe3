#pragma once
/// @file rotating_frame.hpp
/// Steady solutions in a frame rotating with the mesh (docs/euler.md, "Rotation rates"): the
/// quasi-steady rotary derivatives of a body that turns at a constant angular velocity omega
/// about a reference point x_ref while flying at constant incidence (a steady pull-up, roll or
/// turn), the mesh fixed to the body.
///
/// Formulation. In the frame of the undisturbed air the body's points move at V_ref + omega x
/// (x - x_ref); the solver's variables are the velocity relative to the air plus the free
/// stream, w = u_abs + u_inf (u_inf = -V_ref), so the far field stays the uniform free stream.
/// Written in axes turning with the body, the Euler equations on the mesh fixed to the body are
/// the arbitrary Lagrangian-Eulerian form (spatial.hpp) with the grid velocity
///
///     v_g(x) = omega x (x - x_ref)
///
/// and a source per unit volume (on the right-hand side)
///
///     momentum: -omega x rho (w - u_inf),    energy: rho w . (omega x u_inf),    mass: none.
///
/// The momentum term is the turning of the axes (-omega x rho u_abs) plus the fictitious force
/// of the accelerating reference point (rho omega x u_inf); the energy term is that force's work.
/// Both vanish in the uniform free stream, so w = u_inf stays a solution (the residual is
/// round-off with far-field boundaries; `rotation_grid_fluxes` makes the discrete sum of the grid
/// fluxes over every closed dual cell round-off). Compare the absolute-velocity form of
/// turbomachinery solvers with a source -omega x rho u (e.g. Blazek, Computational Fluid
/// Dynamics: Principles and Applications, 3rd ed., 2015, sec. 2.2.3): that form keeps the
/// absolute velocity of a fixed frame in which the air far away is at rest or in solid-body
/// rotation; here the body also translates on its curved path, which adds the u_inf terms.
///
/// The source is linear in U: S(U) = -B U per node volume with B a constant 5x5 block
/// (momentum rows: omega x against rho u and -omega x u_inf against rho; energy row: (u_inf x
/// omega) against rho u). The steady solver adds it to the residual explicitly, evaluated at
/// the current state each pseudo-time step (the step's hook takes a source and a scalar
/// diagonal; B is not a scalar, so it is not in the implicit matrix).

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "manta/euler/block_matrix.hpp"
#include "manta/euler/gas.hpp"
#include "manta/euler/spatial.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/mesh.hpp"

namespace manta::euler {

/// A frame turning with the mesh at a constant angular velocity.
struct RotatingFrame {
    /// Angular velocity in mesh axes, radians per unit of the solver's time (the mesh length
    /// unit over the free-stream speed of sound, gas.hpp): omega_solver = omega [rad/s] * L /
    /// a_inf.
    Vec3 omega = Vec3::Zero();
    Vec3 center = Vec3::Zero();  ///< a point of the rotation axis (m, mesh axes): x_ref
    [[nodiscard]] bool active() const noexcept { return omega.squaredNorm() > 0.0; }
};

/// The grid fluxes of the rigid rotation on every dual face of `dual` (mesh::DualFaceValues,
/// oriented like the area vectors): each face is the sum of the flat triangles that make it
/// (mesh/dual.hpp), and each triangle's flux is v_g(centroid) . (area vector), exact for the
/// linear field v_g. Over a closed dual cell they sum to the integral of div v_g = 0, to
/// round-off. `g` is sized by `resize_for` (no allocation after the first call).
void rotation_grid_fluxes(const mesh::Mesh& mesh, const mesh::DualMetrics& dual,
                          const RotatingFrame& frame, mesh::DualFaceValues& g);

/// v_g at every node (3 x n_nodes), for the strong wall tangency targets
/// (`SpatialOperator::set_grid_fluxes`).
void rotation_node_velocities(const mesh::Mesh& mesh, const RotatingFrame& frame,
                              Eigen::Matrix3Xd& v);

/// The source as the pseudo-time step takes it (`StepTerms::source`, R* = R - S): S_i = -V_i B
/// U_i for the first `n_owned` columns of U (S is resized to U's size; other columns 0).
/// `u_inf`: the free-stream velocity (solver units, mesh axes).
void rotation_source(const NodeStates& U, const std::vector<double>& volumes,
                     const RotatingFrame& frame, const Vec3& u_inf, Index n_owned, NodeStates& S);

/// Non-dimensional body rates p_hat = p b / (2 V), q_hat = q c / (2 V), r_hat = r b / (2 V), in
/// this order (body axes x forward, y right, z down; b and c the reference span and chord).
using BodyRates = std::array<double, 3>;

/// Whether `r` turns the body (a component other than 0).
[[nodiscard]] bool rotates(const BodyRates& r) noexcept;

/// The frame turning with the body at the rates `r`, flying at the Mach number `mach` (the
/// free-stream speed in the solver's units), with the reference span and chord [m] and about
/// `center` (the moment point, mesh axes): omega = (p, q, r) in body axes with p = 2 V p_hat / b,
/// q = 2 V q_hat / c, r = 2 V r_hat / b, turned into mesh axes by core::geometry_from_body. One
/// copy for `EulerSource::evaluate` and `manta cfd --p-hat --q-hat --r-hat` (the case driver).
[[nodiscard]] RotatingFrame body_rate_frame(const BodyRates& r, double mach, double span,
                                            double chord, const Vec3& center);

/// A boundary node of a symmetry plane whose normal is not the rotation axis.
struct SymmetryCrossing {
    std::size_t marker = 0;      ///< the marker (index into the roles)
    Index node = 0;              ///< the node (the mesh's own index)
    Vec3 normal = Vec3::Zero();  ///< its unit normal
};

/// A symmetry plane mirrors the flow: a frame turns a mesh with one consistently only about the
/// plane's normal (pitch on a half model with the plane y = 0). The first node (in marker order,
/// then in the dual's order) of a marker of role symmetry in `roles` (one per marker of the mesh
/// of `dual`) whose normal is more than 1e-6 off the axis of `frame`, or none (also when the
/// frame does not turn).
[[nodiscard]] std::optional<SymmetryCrossing> symmetry_crossing(
    const RotatingFrame& frame, const std::vector<BoundaryKind>& roles,
    const mesh::DualMetrics& dual);

/// The one-line error of a `symmetry_crossing`: "WHO: N0 v0, N1 v1, N2 v2 turn the mesh MESH
/// through its symmetry plane 'MARKER' (normal (...) at node NODE), which mirrors the flow;
/// expected ...". `names`: how the rates are named (p_hat, or --p-hat); `node` as the user
/// numbers it.
[[nodiscard]] std::string symmetry_crossing_message(const std::string& who,
                                                    const std::array<std::string, 3>& names,
                                                    const BodyRates& r, const std::string& mesh,
                                                    const std::string& marker, const Vec3& normal,
                                                    long long node);

}  // namespace manta::euler
