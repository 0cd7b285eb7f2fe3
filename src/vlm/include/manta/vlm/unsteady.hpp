#pragma once
/// @file unsteady.hpp
/// Unsteady vortex-lattice method (UVLM): the lattice of a `Model` as vortex rings, driven by a
/// prescribed rigid-body and control-surface history (`aero::Motion`), shedding a wake of vortex
/// rings from every trailing edge. Theory, conventions and validation: docs/uvlm.md (Katz &
/// Plotkin, Low-Speed Aerodynamics, 2nd ed. 2001, ch. 13).
///
/// Lattice: one vortex ring per panel of `build_lattice`, its leading segment on the panel's
/// bound segment (quarter point), its trailing segment on the next panel's bound segment; the
/// last ring of a strip runs to the trailing edge and on to the shed line, a quarter of the
/// distance flown in one step (UnsteadyOptions::shed_offset) behind the trailing edge along the
/// free stream of the motion's first instant (body x for the planar wake), where the newest wake
/// row starts (Katz & Plotkin ch. 13; with uniform chordwise spacing and the default time step
/// this is their quarter panel). In steady flight the geometry is then that of the steady
/// solver's trailing legs with TrailingLegs::freestream (body_axis for the planar wake).
/// The control points, normals and control surfaces are the lattice's, with the same
/// small-disturbance boundary condition as the steady solver: the geometry stays planar, control
/// deflections rotate the normals of the kinematic term, and the deflection rate adds the
/// velocity of the control point rotating about its hinge line.
///
/// Time stepping (Katz & Plotkin ch. 13): at each step the wake moves (prescribed: it stays
/// where the air put it, i.e. it is convected with the free stream; free: with the local velocity,
/// force-free), the trailing-edge rings shed a new row of wake rings carrying their circulation of
/// the previous step, the wake's induced velocity is added to the right-hand side, and one back
/// substitution with the influence matrix factorised once gives the new circulations (the lattice
/// is rigid and the computation body-fixed). The oldest wake rows beyond the truncation length are
/// dropped. Loads: Kutta-Joukowski on every bound segment with the local velocity (kinematic,
/// lattice- and wake-induced) and on every chordwise segment up to the trailing edge with the
/// kinematic velocity (the steady solver's and AVL's legs; UnsteadyOptions::chordwise_induced),
/// plus the unsteady term rho dGamma/dt A n of each ring (the unsteady Bernoulli equation, Katz &
/// Plotkin ch. 13).
///
/// Frames: the motion is given in the motion frame of aero::Motion (x forward, y right, z down,
/// translating at the entry speed v0 through still air); the lattice is in geometry axes (x aft,
/// y right, z up). The body point at geometry position g sits at r_ref + C^T D (g - g_ref) in the
/// motion frame, C the 3-2-1 direction-cosine matrix of the Euler angles, D = diag(-1, 1, -1) and
/// g_ref = Model::reference.point (the motion's reference point); the wake is stored in the frame
/// of the still air. Coefficients follow the steady solver (aero/types.hpp): CL CD CY in wind axes
/// at the instantaneous angles of attack and sideslip of the reference point, Cl Cm Cn in body
/// axes about the reference point, all on the dynamic pressure of the reference point's airspeed
/// (rho V^2 / 2; V = v0 unless the motion changes the speed).

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/aero/types.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/model.hpp"
#include "manta/vlm/steady.hpp"

namespace manta::vlm {

/// How the wake moves.
enum class WakeModel {
    prescribed,  ///< convected with the free stream: fixed in the still air (default)
    free,        ///< convected with the local velocity (force-free; explicit Euler)
    /// Carried straight aft along the body x axis at the airspeed: the planar wake of
    /// small-disturbance lifting-surface theory and of the steady solver's trailing legs (its
    /// steady limit is the steady solution exactly). For configurations whose wake would pass
    /// close to another surface's control points, such as AVL fuselage plates in the wing plane.
    planar,
};

/// How the solution starts.
enum class StartMode {
    steady,     ///< the steady solution of the state at the first instant, with a full wake
    impulsive,  ///< the body set in motion at the first instant: no wake yet (Wagner's problem)
};

struct UnsteadyOptions {
    /// Time step [s]; 0: the time the free stream takes to cross one chordwise panel of the
    /// reference chord, c_ref / (n_chord v0), n_chord the largest strip depth.
    double dt = 0.0;
    /// Entry free-stream speed v0 [m/s]; unset: the motion's metadata `v0` (one must be given).
    std::optional<double> speed;
    /// Mach number of the Prandtl-Glauert correction, in [0, 0.95); unset: Model::mach. Fixed at
    /// construction (the influence matrix depends on it).
    std::optional<double> mach;
    /// Wake rows kept; 0: as many as cover `wake_length`.
    int wake_rows = 0;
    /// Wake length kept [reference chords] when `wake_rows` is 0 (rows of v0 dt each).
    double wake_length = 20.0;
    /// Once rows are dropped, continue the oldest row's side vortices to infinity along the wake
    /// instead of closing it (so the cut end does not act as a starting vortex).
    bool wake_tail = true;
    WakeModel wake = WakeModel::prescribed;
    /// Distance of the shed line (the last lattice rings' trailing segment and the newest wake
    /// row's leading segment) behind the trailing edge, as a fraction of v0 dt: Katz & Plotkin
    /// place the latest shed vortex 0.2 to 0.3 of the distance travelled in a step behind the
    /// trailing edge; with uniform chordwise spacing and the default dt, 0.25 is the classical
    /// quarter panel. In [0, 1].
    double shed_offset = 0.25;
    /// Vortex cores as SteadyOptions (the steady solver's, after AVL): a segment's core radius
    /// is core_within_component x its strip's width at field points of its own component
    /// (Surface::component), core_between_components x max(chord, 2 width) at the others'.
    double core_within_component = 1e-4;
    double core_between_components = 0.25;
    /// Vortex core radius [reference chords] of every segment at the free wake's own points.
    double core_radius = 0.05;
    StartMode start = StartMode::steady;
    /// Non-zero motion modes that the lattice lacks are an InputError unless this is set (modes
    /// that are zero throughout, such as the mandatory elevator, aileron and rudder columns of a
    /// wing without controls, are always ignored; lattice controls the motion lacks stay at 0).
    bool ignore_missing_controls = false;
    /// Include the velocity of control points rotating about their hinge (deflection rate).
    bool hinge_rate = true;
    /// Kutta-Joukowski loads of the chordwise segments (the rings' sides, from one bound segment
    /// to the next, the last to the trailing edge) with the velocity induced by the lattice and
    /// the wake added to the onset flow. false: the onset flow only (free stream, rotation), as
    /// the steady solver's legs and AVL's, so that a steady run gives the steady solution.
    bool chordwise_induced = false;
    /// Record the span loading in every step.
    bool span_loading = true;
    /// Wake length [reference chords] behind the trailing edge whose velocity at the bound
    /// segments (loads) is summed exactly; the rest, smooth there, is interpolated along the
    /// chord from the control points (where the boundary condition needs the whole wake anyway).
    /// Halves the cost of a step with a long wake; a large value sums everything exactly.
    double near_wake = 2.0;
    /// Worker threads for the induced-velocity sums (0: one per hardware thread); the results do
    /// not depend on it.
    int threads = 1;
};

/// Loads at one instant.
struct UnsteadyStep {
    int index = 0;    ///< step number, 0 the start
    double t = 0.0;   ///< time [s] (the motion's clock)
    double CL = 0.0;  ///< wind axes, total (CD includes Model::profile_drag)
    double CD = 0.0;
    double CY = 0.0;
    aero::BodyCoefficients<double> body;  ///< CX CY CZ, Cl Cm Cn (body axes, about the MRP)
    /// Split of CL and CD: Kutta-Joukowski (circulatory) and rho dGamma/dt A n (added mass);
    /// CL = CL_circulatory + CL_added_mass, CD = CD_circulatory + CD_added_mass + CD_profile.
    double CL_circulatory = 0.0, CL_added_mass = 0.0;
    double CD_circulatory = 0.0, CD_added_mass = 0.0;
    double alpha = 0.0, beta = 0.0;  ///< of the reference point's air-relative velocity [rad]
    double airspeed = 0.0;           ///< of the reference point [m/s]
    Eigen::VectorXd deflection;      ///< lattice controls [rad] (Lattice::control_names order)
    int wake_rows = 0;               ///< wake rows present
    /// Span loading (UnsteadyOptions::span_loading): per strip, force / q in geometry axes,
    /// circulation of the strip's trailing-edge ring / V, section normal-force coefficient.
    std::vector<StripLoad> strips;
};

/// The whole run.
struct UnsteadyHistory {
    std::vector<UnsteadyStep> steps;  ///< the start and every step
    double dt = 0.0;                  ///< time step [s]
    double speed = 0.0;               ///< v0 [m/s]
    double mach = 0.0;
    int max_wake_rows = 0;
    /// One member of every step, e.g. column(&UnsteadyStep::CL).
    [[nodiscard]] std::vector<double> column(double UnsteadyStep::*member) const;
    [[nodiscard]] std::vector<double> time() const { return column(&UnsteadyStep::t); }
};

/// The wake (and the lattice circulations) at one instant, for output.
struct UnsteadyWake {
    double t = 0.0;
    int rows = 0;  ///< ring rows, newest (at the trailing edge) first
    int cols = 0;  ///< grid columns: the strip edges of every shedding strip chain, side by side
    /// (rows + 1) x cols grid points [m], geometry axes at t, row 0 on the shed line.
    std::vector<Eigen::Vector3d> points;
    std::vector<double> gamma;  ///< rows x cols ring circulations [m^2/s]
    std::vector<char> ring;     ///< per column: 1 if columns e and e + 1 bound a ring
    bool tail = false;          ///< oldest row continued to infinity (UnsteadyOptions::wake_tail)
    Eigen::VectorXd lattice_gamma;  ///< circulation of the lattice's rings [m^2/s], panel order
    double shed_distance = 0.0;     ///< shed line behind the trailing edges [m] (last rings' end)
    /// Direction of the shed line from the trailing edges (geometry axes, unit).
    Eigen::Vector3d shed_direction = Eigen::Vector3d::UnitX();
};

/// The unsteady solver for one lattice. The geometry is prepared at construction; the influence
/// matrix depends on the shed line, hence on v0 dt, and is built and factorised by the first
/// `start` (again only when v0 dt changes). `start` (re)initialises with a motion, `step`
/// advances one time step; both may be called again for another motion (the object is
/// re-entrant: it keeps no state but the run in progress).
class UnsteadySolver {
public:
    /// InputError for a Mach number outside [0, 0.95), options out of range, or a lattice check
    /// failure.
    UnsteadySolver(const Model& model, Lattice lattice, UnsteadyOptions options = {});
    ~UnsteadySolver();
    UnsteadySolver(UnsteadySolver&&) noexcept;
    UnsteadySolver& operator=(UnsteadySolver&&) noexcept;
    UnsteadySolver(const UnsteadySolver&) = delete;
    UnsteadySolver& operator=(const UnsteadySolver&) = delete;

    /// Initialise at the motion's first instant (validated first): InputError for an invalid
    /// motion, no speed, a time step out of range, or non-zero modes the lattice lacks (listed).
    /// Returns the loads at the start.
    const UnsteadyStep& start(const aero::Motion& motion);
    /// Advance one time step. InputError before `start` or past the end of the motion.
    const UnsteadyStep& step();
    /// True when no whole time step is left before the motion's end.
    [[nodiscard]] bool finished() const;
    /// Number of steps from the motion's start to its end.
    [[nodiscard]] int n_steps() const;

    /// Called after the start and after every step; the solver gives the current state.
    using Progress = std::function<void(const UnsteadySolver& solver)>;
    /// The run state after `start` or a step, as bytes (binary): step index, wake points and
    /// circulations, the lattice circulations of the last three levels and dGamma/dt, with the
    /// sizes and time step that identify the run. InputError before `start`.
    [[nodiscard]] std::string save_state() const;
    /// `start(motion)`, then the run state replaced by `state` (from `save_state` of a solver
    /// with the same lattice and options on the same motion): stepping on gives, bit for bit,
    /// what the uninterrupted run gives. Returns the loads at the restored instant. InputError
    /// if the state is truncated or belongs to another lattice, time step or wake length.
    const UnsteadyStep& restore_state(const aero::Motion& motion, std::string_view state);

    /// start(motion), then step() to the end, recording every step.
    UnsteadyHistory run(const aero::Motion& motion, const Progress& progress = {});

    [[nodiscard]] const UnsteadyStep& current() const;
    [[nodiscard]] const Lattice& lattice() const;
    [[nodiscard]] const UnsteadyOptions& options() const;
    [[nodiscard]] double dt() const;     ///< time step of the current run [s]
    [[nodiscard]] double speed() const;  ///< v0 of the current run [m/s]
    [[nodiscard]] double mach() const;
    [[nodiscard]] int max_wake_rows() const;
    /// Ring circulations [m^2/s], lattice panel order.
    [[nodiscard]] const Eigen::VectorXd& gamma() const;
    /// The wake now (geometry axes).
    [[nodiscard]] UnsteadyWake wake() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Write the lattice's vortex rings (with `wake.lattice_gamma`) and the wake rings as a VTK
/// unstructured grid (ASCII .vtu; quads with cell data `gamma` [m^2/s] and `wake` 0/1), geometry
/// axes. Atomic write; IoError if it cannot be written, InputError if `wake` does not fit the
/// lattice.
void write_vtu(const std::filesystem::path& path, const Lattice& lattice, const UnsteadyWake& wake);

}  // namespace manta::vlm
