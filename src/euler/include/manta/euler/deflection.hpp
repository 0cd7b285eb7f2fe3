#pragma once
/// @file deflection.hpp
/// Steady control deflections (docs/euler.md, "Control deflections"): the mesh deformed by the
/// configuration's control surfaces (`control_surfaces:`, meshmotion::ControlSurfaceSpec), each
/// surface by gain times its mode's deflection, through meshmotion::MeshMotion::deformed, the
/// dual metrics recomputed on the deformed coordinates and checked for a fold. One copy shared
/// by `EulerSource::evaluate` (each query's own coordinates) and `manta cfd --elevator-deg
/// --aileron-deg --rudder-deg` (the case driver, case.hpp), so that both solve on the same mesh.

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "manta/euler/spatial.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace manta::euler {

/// Deflections of the modes elevator, aileron and rudder, in this order [rad].
using ModeDeflections = std::array<double, 3>;

/// The modes of `ModeDeflections`, in its order.
inline constexpr std::array<const char*, 3> deflection_modes{"elevator", "aileron", "rudder"};

/// Whether `d` deflects anything (a component other than 0).
[[nodiscard]] bool deflects(const ModeDeflections& d) noexcept;

/// How the messages of `surface_deflections` and `deflect_mesh` name things.
struct DeflectionNaming {
    std::string who = "euler source";  ///< message prefix
    /// Each mode's deflection, in the `ModeDeflections` order ("elevator", "--elevator-deg").
    std::array<std::string, 3> names{"elevator", "aileron", "rudder"};
    std::string unit = " deg";  ///< after each value in degrees (" deg", or "" after a flag)
    std::string config = "the CFD configuration";  ///< where the control surfaces come from
};

/// The deformation options of a run along a motion (`manta cfd --motion` and the unsteady
/// source alike; the steady deflections use its symmetry planes): the body's motion `body` with its
/// radii, the markers of role `wall` moving with the body (deforming mode), those of role
/// `symmetry` sliding. `roles`: one per mesh marker.
[[nodiscard]] meshmotion::DeformationOptions motion_deformation(
    const mesh::Mesh& mesh, const std::vector<BoundaryKind>& roles, meshmotion::BodyMotion body,
    double rigid_radius, double fixed_radius);

/// The steady deformation of `mesh` (finalized, undeflected) by the control surfaces
/// `surfaces`: a MeshMotion along a motion of zeros with one mode column per mode of the
/// surfaces (elevator, aileron and rudder always), about the reference point `moment_point`
/// (which the deformation alone does not use), named `config` in its messages, with the markers
/// of role symmetry in `roles` (one per marker of the mesh) as sliding planes
/// (DeformationOptions::symmetry_markers, as `manta cfd --motion` moves the mesh): a surface
/// that touches one slides on it, and the plane's nodes near a surface stay in their plane. Null
/// when `surfaces` is empty. InputError (one line) from MeshMotion for a surface that does not
/// fit the mesh (marker, hinge) and a symmetry marker that is not plane.
[[nodiscard]] std::unique_ptr<meshmotion::MeshMotion> deflection_motion(
    const mesh::Mesh& mesh, const std::vector<BoundaryKind>& roles,
    const Eigen::Vector3d& moment_point,
    const std::vector<meshmotion::ControlSurfaceSpec>& surfaces, const std::string& config);

/// The distinct modes of `surfaces` in their order, comma separated ("elevator, aileron"), or
/// "none".
[[nodiscard]] std::string surface_modes(
    const std::vector<meshmotion::ControlSurfaceSpec>& surfaces);

/// The local deflection of each surface of `surfaces` [rad]: gain times its mode's deflection in
/// `d`. InputError (one line, naming the deflection as `naming` says) for a component of `d`
/// that is not finite, and for one other than 0 of a mode no surface has (the message lists the
/// modes the surfaces have).
[[nodiscard]] std::vector<double> surface_deflections(
    const std::vector<meshmotion::ControlSurfaceSpec>& surfaces, const ModeDeflections& d,
    const DeflectionNaming& naming);

/// Deflect `mesh` in place by `d`: its coordinates become the deformation of `motion`
/// (`deflection_motion` of this mesh, undeflected, and `surfaces`) for the local deflections
/// `surface_deflections(surfaces, d, naming)`, and `dual` (the mesh's dual metrics) is updated
/// to them (mesh::update_dual_metrics, bit for bit a fresh computation). Nothing happens when `d`
/// is all zeros. InputError (one line) as `surface_deflections`, when `motion` is null and `d`
/// deflects, and when the deformed mesh has a dual volume that is not positive (a fold): the
/// message names the deflections, the node (as `node_numbers[node]` when given, the mesh's own
/// index otherwise) and its dual volume. On that error the mesh and `dual` are left deformed.
void deflect_mesh(mesh::Mesh& mesh, mesh::DualMetrics& dual, const meshmotion::MeshMotion* motion,
                  const std::vector<meshmotion::ControlSurfaceSpec>& surfaces,
                  const ModeDeflections& d, const DeflectionNaming& naming,
                  std::span<const mesh::Index> node_numbers = {});

}  // namespace manta::euler
