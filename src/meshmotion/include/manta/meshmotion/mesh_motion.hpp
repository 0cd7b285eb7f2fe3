#pragma once
/// @file mesh_motion.hpp
/// `MeshMotion`: the node coordinates (and velocities) of a volume mesh that moves rigidly along
/// an `aero::Motion` and whose control surfaces deflect as mode shapes spread into the volume by
/// inverse-distance weighting (docs/mesh-motion.md, docs/adr/0003-moving-meshes.md items 1, 6, 7).
/// Knows nothing of any flow solver: it turns a time into coordinates.
///
/// Frames. The mesh is given in mesh axes, which are geometry axes (x aft / downstream, y right,
/// z up; docs/conventions.md, docs/euler.md). The moving mesh is written in the *flow frame*: the
/// motion frame of aero::Motion (translating with the entry free stream, x forward, y right,
/// z down) turned by D = diag(-1, 1, -1) into mesh-like axes, with its origin placed so that a
/// motion of zeros leaves the mesh where it is. In it the undisturbed air moves at (+v0, 0, 0),
/// the free stream of the steady solver at alpha = beta = 0. A node at x0 of the reference mesh,
/// displaced by the control-surface deformation to y = x0 + d(t), is at
///     x(t) = g + D r(t) + D C(t)^T D (y - g),
/// g the moment reference point in mesh axes, r(t) = (x_ref, y_ref, z_ref)(t) the reference
/// point in the motion frame, C(t) = R1(phi) R2(theta) R3(psi) the 3-2-1 direction-cosine matrix
/// from the motion frame to body axes (as src/vlm/unsteady.cpp places its lattice in the air).

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/mesh/mesh.hpp"

namespace manta::meshmotion {

/// One control surface: the wall marker whose nodes rotate, its hinge line, the mode that drives
/// it. Several surfaces may share a mode (the two ailerons, with gains +1 and -1).
struct ControlSurfaceSpec {
    std::string mode;    ///< motion mode name without the `mode_` prefix ("elevator")
    std::string marker;  ///< mesh marker of the moving wall
    /// Hinge line, two points in mesh axes [m]. A positive local deflection rotates the surface
    /// right-handedly about the direction hinge[1] - hinge[0] (so for "trailing edge down" on a
    /// horizontal surface the hinge runs toward +y, for "trailing edge left" on a fin toward -z).
    std::array<Eigen::Vector3d, 2> hinge{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()};
    double gain = 1.0;  ///< local deflection = gain * mode value
    /// Largest distance [m] from the hinge segment to the nearest node of the marker
    /// (default: DeformationOptions::hinge_tolerance_fraction of the marker's bounding box).
    std::optional<double> hinge_tolerance;
    /// Width [m] of the blend band next to the hinge line (default hinge_blend_chords * chord).
    std::optional<double> hinge_blend;
    /// Width [m] of the blend band at the trailing edge (default edge_blend_chords * chord);
    /// the band's width grows linearly from hinge_blend at the hinge to edge_blend at one chord.
    std::optional<double> edge_blend;
    /// Distance [m] from the marker's bounding box beyond which the volume does not deform
    /// (default cutoff_chords * chord).
    std::optional<double> cutoff;
    std::string source = "control surface";  ///< where it was defined ("cfd.yaml:12"), for messages
};

/// Settings of the volume deformation and of its checks.
struct DeformationOptions {
    /// The greedy reduction stops when the interpolation of every candidate surface node is
    /// within this fraction of its shortest edge, for both fields of the surface.
    double surface_tolerance = 0.1;
    int max_points = 600;  ///< cap on the reduced point set of one control surface
    /// Default hinge tolerance, as a fraction of the diagonal of the marker's bounding box.
    double hinge_tolerance_fraction = 0.05;
    double hinge_blend_chords = 0.25;  ///< default hinge_blend, in control-surface chords
    double edge_blend_chords = 0.5;    ///< default edge_blend, in control-surface chords
    double cutoff_chords = 5.0;        ///< default cutoff, in control-surface chords
    /// A cell fails the check when one of its sub-tetrahedra has less than this fraction of the
    /// cell's reference volume divided by the number of its sub-tetrahedra.
    double min_volume_ratio = 1e-3;
};

/// How the mesh sits in the motion.
struct MotionPlacement {
    /// Moment reference point in mesh axes [m]: the point the motion's x_ref, y_ref, z_ref and
    /// angles refer to (the CFD configuration's reference.moment_point).
    Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();
    std::string motion_source = "motion";  ///< names the motion (its file) in messages
};

/// The rigid part of the motion at one instant, in the flow frame (mesh-like axes).
struct RigidPose {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< R = D C^T D
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();   ///< x = translation + R y
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();     ///< g + D r: the reference point
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< its velocity D dr/dt [m/s]
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();  ///< angular velocity D C^T (p, q, r) [rad/s]
};

/// The rigid pose for a motion state and the reference point `g` (mesh axes).
[[nodiscard]] RigidPose rigid_pose(const aero::MotionState& state, const Eigen::Vector3d& g);

/// Direction-cosine matrix from the motion frame to body axes for 3-2-1 Euler angles
/// (phi, theta, psi): v_body = C v_motion, C = R1(phi) R2(theta) R3(psi).
[[nodiscard]] Eigen::Matrix3d body_from_motion(const std::array<double, 3>& euler);

/// What the set-up of one control surface found (for reports and tests).
struct ControlSurfaceInfo {
    std::string mode, marker;
    int n_marker_nodes = 0;       ///< nodes of the marker
    int n_seam_nodes = 0;         ///< of them, nodes shared with another marker (held fixed)
    int n_candidates = 0;         ///< boundary nodes within the cut-off (the reduction's test set)
    int n_points = 0;             ///< reduced point set
    int n_affected = 0;           ///< nodes within the cut-off, whose coordinates the surface moves
    double chord = 0.0;           ///< largest distance of a marker node from the hinge axis [m]
    double hinge_distance = 0.0;  ///< distance of the hinge segment from the marker's nodes [m]
    double hinge_blend = 0.0, edge_blend = 0.0, cutoff = 0.0;  ///< [m]
    /// Largest interpolation error on the candidate nodes over the allowed one (<= 1 unless the
    /// point cap was reached).
    double error_ratio = 0.0;
    double setup_seconds = 0.0;  ///< wall time of this surface's set-up
    /// Markers that are planes normal to the hinge (2-D slab planes): the surface's nodes on them
    /// are not seam nodes, and their nodes move with the volume, in their plane.
    int n_sliding_markers = 0;
};

/// Node coordinates of the moving, deforming mesh along a motion.
///
/// Set-up (constructor): for each control surface, its marker's nodes, the two surface fields
/// m1 = w e x r and m2 = w e x (e x r) (e the hinge direction, r the offset from the hinge line,
/// w the blend weight, 0 on the nodes shared with other markers), and their volume fields by
/// inverse-distance weighting from a greedily reduced point set. Per step: the exact rotation
/// by delta, sin(delta) m1 + (1 - cos(delta)) m2, for each surface, a check of the cells near the
/// moving surfaces, then the rigid motion of every node.
class MeshMotion {
public:
    /// InputError (one line) for a marker that is not in the mesh, a hinge line off its surface,
    /// a control surface whose mode the motion lacks, a mode that deflects with no control surface,
    /// and for an invalid motion (aero::Motion::validate). The mesh must be finalized.
    MeshMotion(const mesh::Mesh& mesh, aero::Motion motion, MotionPlacement placement,
               std::vector<ControlSurfaceSpec> surfaces, const DeformationOptions& options = {});

    [[nodiscard]] mesh::Index n_nodes() const { return static_cast<mesh::Index>(x0_.cols()); }
    [[nodiscard]] const aero::Motion& motion() const { return motion_; }
    [[nodiscard]] const std::vector<ControlSurfaceInfo>& info() const { return info_; }
    /// Wall time of the whole set-up [s].
    [[nodiscard]] double setup_seconds() const { return setup_seconds_; }
    /// Number of cells checked each step (those with a node that a control surface moves).
    [[nodiscard]] std::size_t n_checked_cells() const { return checked_type_.size(); }

    /// Coordinates (3 x n_nodes, flow frame) at time t. `out` is resized only if its size is
    /// wrong; otherwise nothing is allocated. Checks the cells the deformation touches (the rigid
    /// motion keeps every volume); an inverted or degenerate one is an InputError naming `step`
    /// (when >= 0), the time, the cell, its most displaced node, the deflections and the largest
    /// fraction of them that keeps every cell valid (bisection). Times outside the motion: as
    /// aero::Motion::at.
    void coordinates_at(double t, Eigen::Matrix3Xd& out, long step = -1) const;
    /// Coordinates and node velocities [m/s] (flow frame) at time t, from the motion's rates;
    /// same checks. For diagnostics: the flux of a moving face comes from swept volumes (ADR 0003).
    void state_at(double t, Eigen::Matrix3Xd& coordinates, Eigen::Matrix3Xd& velocities,
                  long step = -1) const;
    /// The deformation alone (no rigid motion, no check) for local deflections `delta` [rad],
    /// one per control surface in the constructor's order: y = x0 + sum of the surface fields.
    void deformed(const std::vector<double>& delta, Eigen::Matrix3Xd& out) const;
    /// Check the coordinates at every sample time of the motion (as coordinates_at), so that a
    /// motion that folds cells is refused before a solver starts.
    void check_motion() const;

private:
    struct Field {
        int mode = -1;  // index in motion_.mode_names
        double gain = 1.0;
        std::vector<mesh::Index> nodes;  // nodes moved, ascending
        Eigen::Matrix3Xd m1, m2;         // their displacement fields per unit sin / (1 - cos)
    };
    void deform(const aero::MotionState& s, double scale, Eigen::Matrix3Xd& y) const;
    [[nodiscard]] long first_bad_cell(const Eigen::Matrix3Xd& y) const;
    void check(const aero::MotionState& s, const Eigen::Matrix3Xd& y, long step) const;

    Eigen::Matrix3Xd x0_;
    aero::Motion motion_;
    MotionPlacement placement_;
    DeformationOptions options_;
    std::vector<ControlSurfaceSpec> specs_;
    std::vector<Field> fields_;
    std::vector<ControlSurfaceInfo> info_;
    double setup_seconds_ = 0.0;
    // Cells checked each step: type, nodes (CSR) and the volume floor of a sub-tetrahedron.
    std::vector<mesh::CellType> checked_type_;
    std::vector<mesh::Index> checked_cell_;
    std::vector<std::int64_t> checked_offsets_{0};
    std::vector<mesh::Index> checked_nodes_;
    std::vector<double> checked_floor_;
};

}  // namespace manta::meshmotion
