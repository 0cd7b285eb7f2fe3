#pragma once
/// @file spatial.hpp
/// The semi-discrete operator of the vertex-centred, edge-based finite-volume scheme on the
/// median dual: R(U), the sum of the numerical fluxes out of every node's dual cell, its
/// first-order Jacobian and the spectral radii for local time steps (docs/euler.md,
/// "Spatial discretisation").
///
/// Interior fluxes: one numerical flux (flux.hpp) per edge (i, j) through the dual face's area
/// vector n_ij, between the states reconstructed at the edge midpoint. First order: the node
/// states. Second order (MUSCL on the primitive variables W = (rho, u, v, w, p); Barth &
/// Jespersen, AIAA 89-0366, 1989): W_L = W_i + phi_i (grad W_i . (x_j - x_i) / 2), W_R = W_j -
/// phi_j (grad W_j . (x_j - x_i) / 2), component by component, with
/// - gradients by inverse-distance-weighted least squares (weights 1 / |x_j - x_i|^2 on the
///   squared differences; the 3x3 normal matrices are inverted once, at construction) or by
///   Green-Gauss on the median dual in its edge form grad W_i = 1 / (2 V_i) sum_j (W_j - W_i)
///   n_ij (equal to the form with midpoint face values and W_i on the boundary faces because
///   every dual cell is closed; exact for linear fields at interior nodes of tetrahedral
///   meshes);
/// - Venkatakrishnan's smooth limiter (V. Venkatakrishnan, "Convergence to steady state
///   solutions of the Euler equations on unstructured grids with limiters", J. Comput. Phys.
///   118, 120-130, 1995), per node and per variable, with eps^2 = (K h)^3,
///   h = V_i^(1/3) (lengths in the mesh's unit, metres);
/// - a positivity fallback: an edge whose reconstructed density or pressure is not positive on
///   either side uses the first-order states (counted, `positivity_fallbacks`).
///
/// Boundary fluxes at each boundary node with the node's own state, once per marker touching the
/// node (a node where a wall meets a symmetry plane gets both faces' fluxes): characteristic far
/// field, slip wall, and symmetry planes treated as slip walls (the weak form: only the pressure
/// flux (0, p n, 0)). At second order the gradients of nodes on a symmetry plane (unit normal
/// n) are made those of the mirrored solution: with the reflection S = I - 2 n n^T, a scalar's
/// gradient g becomes (g + S g) / 2 (its normal component removed) and the velocity gradient G
/// becomes (G + S G S) / 2 (d u_t / dn and d u_n / dt removed), once per symmetry marker at the
/// node. With strong wall tangency (below) the density and pressure gradients of wall nodes
/// lose their component along the node's dual normal n in the same way (n . grad = 0, the
/// reflection condition SU2 v8.1 applies at Euler-wall nodes, su2code/SU2 pull request 2194);
/// the velocity gradient is kept (reflecting it on a curved wall cost the subsonic bump channel
/// its second order: observed 1.42 instead of 2.3, tests/euler/test_bump_order_validation.cpp).
/// The one-sided least-squares normal gradients of p and rho at a coarse mesh's leading edge
/// otherwise extrapolate the stagnation pressure into the first edges: on the coarse ONERA M6
/// mesh, Roe with strong tangency had 12 % entropy error at the leading-edge nodes (4 % with
/// the condition) and CD -0.0098 against SU2's Roe 0.0012 (docs/validation.md).
///
/// JST (`FluxScheme::jst`; Jameson, Schmidt & Turkel, AIAA 81-1259, 1981; the edge form of
/// Mavriplis & Jameson, AIAA J. 28, 1990; the variant of SU2 v8): the order, gradients and
/// limiter are not used. Per edge (i, j) through n_ij the flux is the central flux of the mean
/// density, velocity, pressure and total enthalpy (each the mean of the two nodes' values) plus
/// the dissipation D_ij = (e2 (V_i - V_j) - e4 (L_i - L_j)) S_ij l_ij on
/// V = (rho, rho u, rho v, rho w, rho H), where
/// - L_i = sum_j (V_j - V_i) is the undivided Laplacian and nu_i = |sum_j (p_j - p_i)| /
///   sum_j (p_j + p_i) the pressure sensor; at a boundary node (on any marker) both sums run
///   over its boundary neighbours only, at interior nodes over all neighbours;
/// - e2 = k2 (nu_i + nu_j) / 2 s2, e4 = max(0, k4 - e2) s2^2 / 4, s2 = 3 (N_i + N_j) / (N_i
///   N_j) with N the number of neighbours (all of them);
/// - l_ij = (|u_i.n| + c_i |n| + |u_j.n| + c_j |n|) / 2 the edge's spectral radius and
///   S_ij = 4 phi_i phi_j / (phi_i + phi_j), phi_i = (lambda_i / (4 l_ij))^0.3 the stretching
///   factor, lambda_i the node's summed spectral radius (`spectral_radii`).
/// Its implicit operator (`jacobian`): dF/dU_i = A(U_i) / 2 + c_i T(U_i), dF/dU_j = A(U_j) / 2 -
/// c_j T(U_j), T = dV/dU, c_i = max(k2 s2 / 4, e2 + e4 (NL_i + b_ij)) S_ij l_ij with NL_i the
/// number of Laplacian neighbours of i and b_ij = 1 if U_i enters L_j (else 0), sensor, S and l
/// frozen: the scalar first-order form that SU2 assembles (exact diagonal blocks at a uniform
/// state, the distance-two couplings of the Laplacian dropped), with a lower bound k2 s2 / 4 on
/// the coefficient. Without the bound the coefficient in smooth flow is e4 (N + 1), of order
/// 0.01, the operator is nearly central, and on the bump channel the ILU(0)-preconditioned
/// linear solves stall once the CFL number passes about 100 (docs/euler.md).
///
/// Wall tangency (`SpatialOptions::wall`). Weak (the default of the upwind fluxes): a wall or
/// symmetry node's boundary flux is the pressure flux (0, p n, 0) and u.n = 0 holds only as the
/// discrete solution converges; on a coarse mesh the converged node velocity then points into
/// the wall where the wall turns within one dual cell (ONERA M6 coarse, Roe: u.n up to
/// 0.56 V_inf at the leading-edge nodes). Strong (the default of JST, as SU2 v8.1 does it; Blazek,
/// Computational Fluid Dynamics: Principles and Applications, 3rd ed., 2015, sec. 8.6): at
/// such a node the momentum residual keeps only its part tangent to the node's wall and
/// symmetry normals (orthonormalised when a node lies on two markers), and the removed
/// components are replaced by the conditions lambda_i (rho u . e_k) = 0, so the implicit
/// iteration drives the normal velocity to zero (`apply_wall_tangency`). At a sharp trailing
/// edge the node's normal is the small sum of both sides' normals, nearly streamwise, and the
/// strong condition leaves the node only its velocity normal to the chord: on a 2-D section the
/// flow then turns around the edge and the lift is too high (as in SU2 v8.1; docs/euler.md).
/// Mixed: strong, except at sharp-edge wall nodes (`SpatialOptions::sharp_edge_deg`), where the
/// one wall condition is tangency to the edge's bisector (`WallTangency::mixed`).
///
/// Moving meshes (arbitrary Lagrangian-Eulerian form; docs/euler.md, "Moving meshes"; ADR 0003):
/// `set_grid_fluxes` gives every dual face its grid flux g = integral of v_grid . n dA (m^3/s,
/// oriented like the face's area vector: from i to j on edges, outward on the boundary), and every
/// flux becomes F.n - g U (flux.hpp), so that R_i is the flux out of a dual cell that moves: the
/// semi-discrete equations are d(V_i U_i)/dt + R_i(U) = 0. Walls move with the grid, (u -
/// v_grid).n = 0 (pressure work p g in the energy; strong tangency imposes rho (u - v_grid) . e_k =
/// 0), the spectral radii use |u.n - g| + c |n|. With grid fluxes from the faces' swept volumes
/// (mesh::swept_volumes) a uniform flow stays uniform to round-off. After the mesh moves:
/// Mesh::set_coordinates, mesh::update_dual_metrics, then `update_geometry` here (least-squares
/// matrices, symmetry and wall normals, tangency directions, sharp-edge sides); no allocation.
/// Without grid fluxes (the default) every result is bit for bit the fixed-mesh one.
///
/// Partition-local meshes (docs/parallel.md): nodes [0, n_owned) are owned, the rest ghosts.
/// Edges between two ghosts are skipped; residuals, gradients and limiters are computed for
/// owned nodes, the ghosts' gradients and limiters come from one halo exchange per residual.

#include <array>
#include <cstdint>
#include <vector>

#include "manta/euler/block_matrix.hpp"
#include "manta/euler/flux.hpp"
#include "manta/euler/gas.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/parallel/communicator.hpp"

namespace manta::euler {

/// Boundary condition of a mesh marker.
enum class BoundaryKind {
    farfield,  ///< characteristic far field to the free stream (flux.hpp `farfield_flux`)
    wall,      ///< inviscid slip wall (pressure flux only)
    symmetry,  ///< symmetry plane: slip-wall flux, mirrored gradients
};

/// How the second-order reconstruction's gradients are computed.
enum class GradientMethod {
    green_gauss,    ///< edge-based Green-Gauss on the median dual
    least_squares,  ///< inverse-distance-weighted least squares, 3x3 per node precomputed
};

/// How slip walls and symmetry planes impose u.n = 0 (above).
enum class WallTangency {
    automatic,  ///< strong with JST, weak with the upwind fluxes
    weak,       ///< through the pressure flux only
    strong,     ///< normal momentum residual replaced by the tangency condition
    /// strong, except at sharp-edge wall nodes (`SpatialOptions::sharp_edge_deg`): there the one
    /// condition is u.b = 0, b the difference of the edge's two sides' unit normals (the flow
    /// leaves along the bisector of the edge) instead of tangency to the node's summed normal
    mixed,
};

/// Options of the spatial discretisation.
struct SpatialOptions {
    /// 1 (node states on the edges) or 2 (MUSCL reconstruction of the primitive variables).
    /// Not used by JST, which is second order by construction.
    int order = 2;
    /// Gradient method of the reconstruction (order 2).
    GradientMethod gradient = GradientMethod::least_squares;
    /// Venkatakrishnan's limiter on (order 2); off: unlimited reconstruction.
    bool limiter = true;
    /// Venkatakrishnan's K: eps^2 = (K h)^3 with h = V_i^(1/3) in the mesh's length unit (m).
    /// Larger K limits less (K -> infinity: no limiting); the usual range is 0.3 to 10. As in
    /// the original paper, eps^2 is not scaled by the solution's magnitude, so its effect
    /// depends on the mesh's length unit and on the non-dimensional variables (gas.hpp).
    double venkatakrishnan_k = 5.0;
    /// Interior numerical flux.
    FluxOptions flux;
    /// Wall and symmetry tangency.
    WallTangency wall = WallTangency::automatic;

    /// `mixed` tangency: a wall node is a sharp-edge node when one of its wall faces' unit
    /// normals makes more than this angle (degrees) with the node's wall normal (the sum of its
    /// wall faces' area vectors). On the coarse ONERA M6 wing: at most 40 deg on the smooth
    /// surface, 47-49 deg at 6 tip nodes, 84-137 deg at the 103 trailing-edge nodes.
    double sharp_edge_deg = 45.0;

    /// The tangency these options resolve to (never `automatic`).
    [[nodiscard]] WallTangency resolved_wall() const noexcept {
        if (wall != WallTangency::automatic) return wall;
        return flux.scheme == FluxScheme::jst ? WallTangency::strong : WallTangency::weak;
    }
    /// Whether walls and symmetry planes impose tangency strongly (at some nodes at least).
    [[nodiscard]] bool strong_walls() const noexcept {
        return resolved_wall() != WallTangency::weak;
    }

    /// ConfigError (one line naming the option, the value and what was expected) if the order
    /// is not 1 or 2, K is not positive and finite, the entropy-fix width is not in [0, 1],
    /// jst_k2 not in [0, 2] or jst_k4 not in [0, 0.5].
    void validate() const;
};

/// A partition-local mesh (the whole mesh in a serial run). Borrowed: the pointees must outlive
/// every SpatialOperator built on it.
struct Domain {
    const mesh::Mesh* mesh = nullptr;         ///< finalized mesh, owned nodes first
    const mesh::DualMetrics* dual = nullptr;  ///< its median-dual metrics
    mesh::Index n_owned = 0;                  ///< nodes [0, n_owned) are owned
    const parallel::Halo* halo = nullptr;     ///< owned -> ghost exchange of node values
};

/// The residual R(U) of the semi-discrete equations V_i dU_i/dt + R_i(U) = 0, its first-order
/// Jacobian and the spectral radii. Work arrays are allocated at construction; `residual` does
/// not allocate (after the first call with a given R).
class SpatialOperator {
public:
    /// `kinds`: one per mesh marker (Mesh::markers() order); `W_inf`: free-stream primitive
    /// state (gas.hpp); `gamma`: ratio of specific heats. Precomputes the least-squares
    /// matrices. InputError if the domain is incomplete, `kinds` has the wrong length, the free
    /// stream is not physical or gamma <= 1; ConfigError from `o.validate()`. JST: one halo
    /// exchange (boundary flags, neighbour counts), so every process constructs it together.
    SpatialOperator(const Domain& d, std::vector<BoundaryKind> kinds, const Vec5& W_inf,
                    double gamma, const SpatialOptions& o);

    /// R (5 x n_local, resized if needed): R(:, i) = sum of the fluxes out of node i's dual cell
    /// for owned nodes, ghost columns 0. U: conservative states of all local nodes, ghost columns
    /// current. Gradients and limiter values of the ghosts are obtained by one halo exchange.
    void residual(const NodeStates& U, NodeStates& R);

    /// lambda_i (resized to n_owned) = sum over node i's dual faces of |u.n| + c |n|: the mean
    /// of the two nodes' values on an edge face, the node's own on a boundary face (m^3/s in
    /// the solver's units; local time step dt_i = CFL V_i / lambda_i).
    void spectral_radii(const NodeStates& U, std::vector<double>& lambda) const;

    /// The first-order implicit operator dR/dU: `flux_jacobians` of every edge at the node
    /// states and the boundary flux Jacobians on the diagonal, whatever the order of `residual`
    /// (the usual defect-correction approximation); JST: its own scalar-dissipation Jacobian
    /// (above), with the sensor and spectral radii of the last `residual`, so call `residual`
    /// at the same U first. J must have the pattern of
    /// `make_jacobian_matrix` (dual->edges, n_rows = n_owned); it is set to zero first.
    void jacobian(const NodeStates& U, BlockMatrix& J) const;

    /// Strong wall tangency (above), after `residual`: at every owned wall or symmetry node,
    /// R_m <- P R_m + lambda_i sum_k e_k (e_k . rho u) with P = I - sum_k e_k e_k^T on the
    /// momentum rows. `lambda`: `spectral_radii` at the same U. Nothing with weak tangency.
    void apply_wall_tangency(const NodeStates& U, const std::vector<double>& lambda,
                             NodeStates& R) const;
    /// The same rows of the implicit matrix J = V/dt + dR/dU (time term included, dt_i =
    /// CFL V_i / lambda_i): every block of the row left-multiplied by blockdiag(1, P, 1), and
    /// (1 + 1/CFL) lambda_i sum_k e_k e_k^T added to the diagonal block's momentum part.
    void apply_wall_tangency(const std::vector<double>& lambda, double cfl, BlockMatrix& J) const;

    /// Refresh everything the operator caches from the mesh's coordinates and the dual metrics
    /// (least-squares matrices, symmetry-plane normals, wall tangency directions and targets,
    /// sharp-edge sides), after Mesh::set_coordinates and mesh::update_dual_metrics of the
    /// domain's mesh and metrics; no allocation. Which nodes are sharp-edge nodes (`mixed`) stays
    /// as classified at construction. InputError if the metrics no longer fit the mesh.
    void update_geometry();

    /// Grid fluxes of a moving mesh (above): `g->edges[e]` per edge of dual->edges and
    /// `g->boundary[mk][k]` per boundary vertex (m^3/s; e.g. swept volumes divided by the time
    /// step, combined with the weights of the time scheme); null: a fixed mesh. Borrowed: `g`
    /// must outlive its use; its values may change between residuals, but the strong-tangency
    /// targets are computed here and in `update_geometry`, so call one of them after changing
    /// them. `node_velocities` (3 x n_local, m/s, optional): the grid velocity of each node, used
    /// only for the targets of the strong tangency conditions (rho u . e_k = rho v_grid . e_k);
    /// without it the targets come from the boundary grid fluxes (the normal speed g / |n| of each
    /// marker's dual face, orthonormalised with the directions) and the sharp-edge condition of
    /// `mixed` tangency keeps the target 0. InputError if the sizes do not fit the domain.
    void set_grid_fluxes(const mesh::DualFaceValues* g,
                         const Eigen::Matrix3Xd* node_velocities = nullptr);
    /// The grid fluxes set by `set_grid_fluxes` (null: fixed mesh).
    [[nodiscard]] const mesh::DualFaceValues* grid_fluxes() const noexcept { return grid_; }

    /// A matrix with the pattern `jacobian` expects (n_owned rows, n_local columns).
    [[nodiscard]] BlockMatrix make_jacobian_matrix() const;

    /// Keep the limiter values of the last `residual` (true) instead of recomputing them, a
    /// standard aid to convergence to machine zero; false recomputes them again.
    void freeze_limiter(bool frozen) noexcept { frozen_ = frozen; }
    [[nodiscard]] bool is_limiter_frozen() const noexcept { return frozen_; }

    /// Primitive-variable gradient of node `n` from the last second-order `residual` (row k:
    /// d W_k / d(x, y, z)); zero before it or at order 1. Ghosts: the exchanged values.
    [[nodiscard]] Eigen::Matrix<double, 5, 3> gradient(mesh::Index n) const;
    /// Limiter values phi (0..1, one per primitive variable) of node `n` from the last
    /// second-order `residual`; 1 without a limiter.
    [[nodiscard]] Vec5 limiter(mesh::Index n) const;
    /// Replace the limiter values of local node `n` (a frozen limiter restored from a checkpoint);
    /// nothing without a limiter.
    void set_limiter(mesh::Index n, const Vec5& phi);
    /// Edges that fell back to first order in the last `residual` (non-positive reconstructed
    /// density or pressure).
    [[nodiscard]] std::int64_t positivity_fallbacks() const noexcept { return n_fallbacks_; }
    /// `mixed` tangency: whether owned node `n` is a sharp-edge wall node; false with the other
    /// modes.
    [[nodiscard]] bool is_sharp(mesh::Index n) const noexcept {
        return static_cast<std::size_t>(n) < sharp_.size() &&
               sharp_[static_cast<std::size_t>(n)] != 0;
    }
    /// Number of owned sharp-edge wall nodes (`mixed` tangency; 0 otherwise).
    [[nodiscard]] std::int64_t sharp_edge_nodes() const noexcept;

    [[nodiscard]] const SpatialOptions& options() const noexcept { return options_; }
    [[nodiscard]] const Domain& domain() const noexcept { return domain_; }
    /// Number of local nodes (owned and ghost).
    [[nodiscard]] mesh::Index n_local() const noexcept { return n_local_; }
    /// Bytes of the operator's own arrays (capacity; the mesh and metrics not included).
    [[nodiscard]] std::size_t memory_bytes() const noexcept;

private:
    void compute_primitive(const NodeStates& U);
    void init_jst();
    void compute_jst_node_terms();
    void residual_jst(NodeStates& R);
    void jacobian_jst(const NodeStates& U, BlockMatrix& J) const;
    void add_boundary_jacobians(const NodeStates& U, BlockMatrix& J) const;
    void compute_gradients();
    void mirror_symmetry_gradients();
    void compute_limiter();
    void add_boundary_fluxes(double* r) const;
    void init_wall_tangency();
    void refresh_wall_tangency();
    void init_sharp_edges();
    void refresh_sharp_sides();
    void refresh_symmetry_normals();
    void compute_least_squares();

    Domain domain_;
    std::vector<BoundaryKind> kinds_;
    Vec5 W_inf_;
    double gamma_;
    SpatialOptions options_;
    mesh::Index n_local_ = 0;
    mesh::Index n_edges_active_ = 0;  ///< edges with an owned node: a prefix of dual->edges
    bool frozen_ = false;
    std::int64_t n_fallbacks_ = 0;

    /// Strong tangency: the owned wall and symmetry nodes and their orthonormal normals.
    struct TangencyNode {
        mesh::Index node;
        int count;                  ///< 1 to 3 directions
        std::array<Vec3, 3> e;      ///< orthonormal
        std::array<double, 3> b{};  ///< target grid velocity along each e (0: fixed mesh)
        int sharp = -1;             ///< index in sharp_sides_ of its bisector condition, or -1
        std::int32_t first = 0;     ///< its normals: tangency_sources_[first, first + n)
        std::int32_t n = 0;
    };
    std::vector<TangencyNode> tangency_;
    /// (marker, index in the marker's boundary vertices) of each tangency node's normals.
    std::vector<std::array<mesh::Index, 2>> tangency_sources_;
    const mesh::DualFaceValues* grid_ = nullptr;       ///< grid fluxes, null: fixed mesh
    const Eigen::Matrix3Xd* grid_velocity_ = nullptr;  ///< node grid velocities (optional)
    /// `mixed` tangency: 1 for each owned sharp-edge wall node (weak there), else 0; empty
    /// otherwise.
    std::vector<char> sharp_;
    struct SharpNode {
        mesh::Index node;
        std::array<Vec3, 2> sides;  ///< area-vector sums of the edge's two sides' faces
    };
    std::vector<SharpNode> sharp_sides_;  ///< the sharp nodes, ascending
    /// (index in sharp_sides_, wall face, side 0 or 1) of every wall face at a sharp node.
    std::vector<std::array<mesh::Index, 3>> sharp_faces_;
    std::vector<double> W_;       ///< 5 per local node: primitive states
    std::vector<double> gp_;      ///< 20 per local node: gradient (5x3, row-major) then phi (5)
    std::vector<double> minmax_;  ///< 10 per owned node: neighbourhood min (5), max (5) of W
    std::vector<double> lsq_;     ///< 6 per owned node: inverse normal matrix, xx xy xz yy yz zz
    std::vector<mesh::Index> symmetry_nodes_;  ///< owned nodes on symmetry markers (one per marker)
    std::vector<double> symmetry_normals_;     ///< 3 per entry of symmetry_nodes_: unit normal
    std::vector<char> symmetry_is_wall_;       ///< per entry of symmetry_nodes_: 1 on a wall
    /// per entry of symmetry_nodes_: (marker, index in the marker's boundary vertices)
    std::vector<std::array<mesh::Index, 2>> symmetry_sources_;
    /// JST, 8 per local node: undivided Laplacian of V (5), pressure sensor, summed spectral
    /// radius, number of Laplacian neighbours (ghosts: exchanged).
    std::vector<double> jst_;
    std::vector<double> jst_neighbours_;  ///< JST, per local node: number of neighbours
    std::vector<char> jst_boundary_;      ///< JST, per local node: on a marker (1) or not (0)
    std::vector<double> jst_work_;        ///< JST, per owned node: sensor denominator
};

}  // namespace manta::euler
