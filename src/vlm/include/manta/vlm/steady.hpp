#pragma once
/// @file steady.hpp
/// Steady vortex-lattice solution, forces and stability derivatives.
///
/// Boundary condition: flow tangency at every control point, (V_inf - omega x r + v_ind) . n = 0,
/// with the induced velocity normal to the undeflected (cambered) panel and the control
/// deflections tilting the normals of the free-stream term to first order, n0 + delta (axis x n0)
/// (the small-disturbance form of classical vortex-lattice codes; Lattice::linearized_normal).
/// A surface that sheds no wake (Surface::sheds_wake false, AVL NOWAKE) keeps its trailing legs
/// but replaces the tangency condition at the last control point of each strip by zero net
/// circulation of the strip, so that nothing trails behind its last bound vortex. Horseshoes
/// have finite vortex cores (SteadyOptions) and, where the model has symmetry planes
/// (Model::y_symmetry, z_symmetry), their mirror images. Compressibility by the Prandtl-Glauert
/// transformation: the lattice is stretched by 1/beta in x, beta = sqrt(1 - M^2), and the induced
/// x velocity is divided by beta.
///
/// Forces by the Kutta-Joukowski law, rho V x Gamma per unit length, on every bound segment with
/// the local velocity (free stream, rotation and the velocity induced by every horseshoe, taken
/// where the segment crosses the spanwise station of its strip's control points), and on the
/// parts of the trailing legs that lie on the surface (bound vortex to trailing edge) with the
/// free stream and rotation only; the latter carry the chordwise-vorticity loads under sideslip
/// and rotation (a large share of Cl_beta of swept wings). Induced drag in the Trefftz plane.
/// This is the force model of AVL 3.40, which the solver reproduces (tests/vlm).
///
/// The circulation is linear in the free-stream and rotation components, so six unit solutions
/// (u, v, w, p, q, r) per deflection state give the loads at any (alpha, beta, p, q, r) by sums
/// over the panels, and derivatives by differences of those sums are consistent with the discrete
/// solution.
///
/// Axes: the lattice is in geometry axes (x aft, y right, z up); results are the flight-mechanics
/// coefficients of aero/types.hpp (body axes x forward, y right, z down; wind-axis CL CD CY),
/// moments about the model's reference point, rates non-dimensional (p b/2V, q c/2V, r b/2V).

#include <Eigen/Core>
#include <Eigen/LU>
#include <memory>
#include <string>
#include <vector>

#include "manta/aero/types.hpp"
#include "manta/vlm/detail/dense_lu.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/model.hpp"

namespace manta::vlm {

/// A flight state for the steady solver. Rates are body-axis, non-dimensional.
struct FlowState {
    double alpha = 0.0;  ///< [rad]
    double beta = 0.0;   ///< [rad]
    double p_hat = 0.0, q_hat = 0.0, r_hat = 0.0;
    /// Value of each lattice control (Lattice::control_names order) [rad]; empty: all zero.
    Eigen::VectorXd deflection;
};

/// Loads of one strip (for span-loading output).
struct StripLoad {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< geometry axes, per unit q (F / q)
    double circulation = 0.0;                         ///< sum over the strip, per unit V
    double cl = 0.0;                                  ///< section lift coefficient (normal force)
};

/// Result of a steady solution.
struct SteadyResult {
    aero::BodyCoefficients<double> body;  ///< CX CY CZ (body), Cl Cm Cn (body, about the MRP)
    double CL = 0.0, CD = 0.0, CY = 0.0;  ///< wind axes, CD = CD_induced + CD_profile
    double CD_induced = 0.0;              ///< induced drag: the Trefftz-plane value
    double CD_near_field = 0.0;  ///< induced drag by Kutta-Joukowski on the vortex segments
    double CD_trefftz = 0.0;     ///< Trefftz plane
    double CL_trefftz = 0.0;
    /// Profile (viscous) drag: Model::profile_drag plus what add_profile_drag added.
    double CD_profile = 0.0;
    double span_efficiency = 0.0;  ///< CL_trefftz^2 / (pi AR CD_trefftz), AR = b^2 / S
    Eigen::VectorXd gamma;         ///< circulation of every horseshoe per unit free-stream speed
    /// Direction of the trailing legs behind the trailing edge (geometry axes, unit).
    Eigen::Vector3d wake_direction = Eigen::Vector3d::UnitX();
    std::vector<StripLoad> strips;
};

/// Stability and control derivatives at a state: per radian for angles and deflections, per
/// non-dimensional rate for p q r. Two sets: body axes (the flight model's) and stability axes
/// (body axes rotated by alpha about y; the set vortex-lattice codes usually print).
///
/// Comparing with AVL 3.40's `ST` listing: its alpha, beta and rate derivatives are the
/// `stability` set (CY there is the stability-axis side force, as here). Its control
/// derivatives, although printed under the stability-axis headings Cl' and Cn', are the
/// body-axis moments (the `control` set). And its control derivatives leave out the change of
/// the induced velocity at the bound vortices with the deflection (they are dGamma/d delta
/// times the force per unit circulation of the undeflected state); the derivatives here are the
/// complete ones, which equal AVL's own finite differences of its total forces. The two differ
/// where a control's lift acts mainly through induced velocities on other loaded vortices, e.g.
/// a leading-edge slat's CL (6 % on AVL's b737 sample) or an aileron's yawing moment.
struct Derivatives {
    /// d{CL CD CY Cl Cm Cn}/d{alpha beta p q r}: rows coefficient, columns variable (CY, CL, CD
    /// wind axes; moments body axes).
    Eigen::Matrix<double, 6, 5> body;
    /// As `body` with Cl Cn about stability axes, rates about stability axes and CY the
    /// stability-axis (= body-axis) side force.
    Eigen::Matrix<double, 6, 5> stability;
    /// d{CL CD CY Cl Cm Cn}/d control, one column per lattice control (body-axis moments), and
    /// the stability-axis set (stability-axis moments and side force).
    Eigen::Matrix<double, 6, Eigen::Dynamic> control;
    Eigen::Matrix<double, 6, Eigen::Dynamic> control_stability;
    double x_neutral_point = 0.0;  ///< geometry x of the neutral point [m]
    double static_margin = 0.0;    ///< (x_np - x_ref) / c_ref
    SteadyResult state;            ///< the solution at the state itself
};

/// The path of the steady solver's trailing legs. Both run from the bound vortex along the chord
/// (body x) to the trailing edge, over the surface; behind it:
/// * body_axis (default): along the body (geometry) x axis to infinity, the small-angle
///   convention of AVL 3.40 and of classical vortex-lattice codes (the steady limit of the
///   unsteady solver's WakeModel::planar);
/// * freestream: along the free stream of the state solved, V_inf =
/// core::free_stream_geometry(alpha,
///   beta), the direction in which the unsteady solver's wake is convected (WakeModel::prescribed,
///   its default), so that an unsteady run held at a constant state converges to the steady
///   solution (docs/vlm.md, Trailing legs). VlmSource, hence the tables and the replay, uses it.
/// The two coincide at alpha = beta = 0. The influence matrix is built and factorised once with
/// body-axis legs; the bend at the trailing edge changes it by a matrix of rank = number of
/// strips (every horseshoe of a strip bends at the same two trailing-edge points), which each
/// solve adds by a fixed-point iteration with the one factorisation (about 40 ms more per solve
/// on the Ranger 2000's 1 956 vortices). Stability derivatives are taken with the legs frozen at
/// the state's direction. With a z symmetry image (AVL IZsym), or a y symmetry image (IYsym) at
/// non-zero sideslip, the legs stay along body x.
enum class TrailingLegs { freestream, body_axis };

/// Vortex cores of the steady solver (AVL 3.40's defaults). Each horseshoe's bound segment and
/// trailing legs have a finite core of radius r_c (Scully profile: the induced velocity at
/// distance r from a line is scaled by r^2 / (r^2 + r_c^2)), which depends on whether the point
/// where the velocity is wanted lies on a surface of the same component (Surface::component) as
/// the horseshoe:
/// * same component: r_c = core_within_component * w, with w the spanwise (y-z) width of the
///   horseshoe; the default 1e-4 only regularises near-coincident points;
/// * other component: r_c = max(k c, 2 k w), k = core_between_components, c the chord of the
///   horseshoe's strip (AVL VRCORE = 0.25): wakes of one component passing near the lattice of
///   another (a wing's legs over a tailplane) do not induce spikes there.
/// Both 0: singular vortices (points on a vortex line excepted).
///
/// `single_precision`: the horseshoe velocities (influence matrix and induced velocities at the
/// force points) and the LU factorisation in single precision, the circulations refined in
/// double precision against the (single-precision-accurate) influence matrix. About twice as
/// fast; derivatives within about 1e-6 of the largest one of the double-precision path
/// (docs/vlm.md, Performance). false: everything in double precision.
struct SteadyOptions {
    double core_within_component = 1e-4;
    double core_between_components = 0.25;
    bool single_precision = true;
    /// Where the trailing legs go behind the trailing edge (TrailingLegs).
    TrailingLegs trailing_legs = TrailingLegs::body_axis;
};

/// The solver for one lattice and Mach number: influence matrix built and factorised once.
class SteadySolver {
public:
    /// InputError for Mach outside [0, 0.95), negative core factors or a lattice check failure.
    SteadySolver(const Model& model, Lattice lattice, double mach, SteadyOptions options = {});

    [[nodiscard]] const Lattice& lattice() const { return lattice_; }
    [[nodiscard]] double mach() const { return mach_; }

    [[nodiscard]] SteadyResult solve(const FlowState& state) const;
    [[nodiscard]] Derivatives derivatives(const FlowState& state) const;

    /// Circulations of the six unit states (u, v, w, p, q, r in geometry axes) at a deflection:
    /// N x 6. Exposed for the unsteady solver and tests.
    [[nodiscard]] Eigen::MatrixXd unit_circulations(const Eigen::VectorXd& deflection) const;

    /// Direction of the trailing legs behind the trailing edge for a state (geometry axes).
    [[nodiscard]] Eigen::Vector3d wake_direction(const FlowState& state) const;

private:
    struct Units;
    struct Kernel;  // the horseshoes in structure-of-arrays form
    struct Mirror;  // mirror symmetry: the two half systems
    /// Trefftz plane normal to d (every solve uses d = x, solve_units) and the legs direction d:
    /// wash at strip centres per unit strip circulation.
    struct Trefftz {
        Eigen::Vector3d d = Eigen::Vector3d::UnitX(), e1 = Eigen::Vector3d::UnitY(),
                        e2 = Eigen::Vector3d::UnitZ();
        Eigen::MatrixXd wash;            // 2 ns x ns, components along e1, e2
        std::vector<Eigen::Vector3d> l;  // strip vectors projected on the plane
    };
    /// What bending the legs along d at the trailing edges adds: normal wash at the control
    /// points (N x ns) and velocity at the force points (3N x ns) per unit strip circulation.
    struct LegBend {
        Eigen::MatrixXd C, U;
    };
    [[nodiscard]] Trefftz trefftz_plane(const Eigen::Vector3d& d) const;
    [[nodiscard]] LegBend leg_bend(const Eigen::Vector3d& d) const;
    /// Circulations and force-point velocities for the right-hand sides B with legs along d.
    [[nodiscard]] Units solve_units(const Eigen::MatrixXd& B, const Eigen::Vector3d& d) const;
    [[nodiscard]] Units units(const Eigen::VectorXd& deflection, const Eigen::Vector3d& d) const;
    [[nodiscard]] SteadyResult loads(const Units& u, const FlowState& s, bool with_detail) const;
    [[nodiscard]] SteadyResult loads_from(const Eigen::VectorXd& g, const Eigen::VectorXd& vind,
                                          const FlowState& s, const Trefftz& tp,
                                          bool with_detail) const;
    [[nodiscard]] Eigen::MatrixXd induced_at_bound(const Eigen::MatrixXd& gamma) const;
    /// Circulations for the right-hand sides B (N x K): the full factorisation, or the two half
    /// systems of a mirror-symmetric lattice; `refined` false: single-precision factors without
    /// iterative refinement (DenseLU::solve_unrefined).
    [[nodiscard]] Eigen::MatrixXd solve_system(const Eigen::MatrixXd& B, bool refined = true) const;
    [[nodiscard]] Eigen::VectorXd rhs(const Eigen::VectorXd& deflection, const Eigen::Vector3d& v,
                                      const Eigen::Vector3d& w) const;

    Model model_;
    Lattice lattice_;
    double mach_ = 0.0;
    SteadyOptions options_;
    double beta_pg_ = 1.0;
    detail::DenseLU lu_;  // the whole system (no mirror symmetry)
    std::shared_ptr<const Kernel> kernel_;
    std::shared_ptr<const Mirror> mirror_;  // null: no mirror symmetry
    Trefftz trefftz_x_;                     // the Trefftz plane of body-axis legs
    std::vector<Eigen::Vector3d> mid_;  // force points on the bound segments (Lattice::bound_point)
    std::vector<char> closure_row_;     // 1: row states zero net strip circulation (NOWAKE)
};

/// Set the wind-axis forces of a result and its body-axis forces to match.
void set_wind_forces(SteadyResult& r, double CL, double CD, double CY, double alpha, double beta);
/// Add a profile-drag coefficient (along the free stream) to a result: CD, CD_profile and the
/// body-axis forces change, lift and moments do not.
void add_profile_drag(SteadyResult& r, double CD0, double alpha, double beta);

/// Body rates [rad/s per unit speed] -> geometry-axis angular velocity.
[[nodiscard]] Eigen::Vector3d omega_geometry(const Reference& ref, double p_hat, double q_hat,
                                             double r_hat);

}  // namespace manta::vlm
