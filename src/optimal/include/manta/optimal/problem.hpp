#pragma once
/// @file problem.hpp
/// Definition of a single-phase optimal-control problem (docs/optimal-control.md):
///
///     minimise (or maximise)  Φ(x(t0), x(tf), p, t0, tf) + ∫ L(x, u, p, t) dt
///     subject to  ẋ = f(x, u, p, t),  g_lo <= g(x, u, p, t) <= g_hi (path),
///                 e_lo <= e(x(t0), x(tf), p, t0, tf) <= e_hi (events),
///                 q_lo <= ∫ q(x, u, p, t) dt <= q_hi (integral constraints),
///                 r_lo <= du/dt <= r_hi (control rates, at every node),
///                 bounds on x, u, p, t0, tf and on x(t0), x(tf).
///
/// The user's problem is a type with `ProblemInfo info() const` and member templates
/// evaluated on `double` and on the AD scalars of ad.hpp:
///
///     template <class T> void dynamics(std::span<const T> x, std::span<const T> u,
///                                      std::span<const T> p, const T& t, std::span<T> xdot) const;
///     template <class T> void path(x, u, p, t, std::span<T> g) const;            // optional
///     template <class T> T lagrange(x, u, p, t) const;                            // optional
///     template <class T> void events(std::span<const T> x0, std::span<const T> xf,
///                                    std::span<const T> p, const T& t0, const T& tf,
///                                    std::span<T> e) const;                       // optional
///     template <class T> T mayer(x0, xf, p, t0, tf) const;                        // optional
///     template <class T> void interior(int junction, std::span<const T> x,
///                                      std::span<const T> p, const T& t,
///                                      std::span<T> e) const;                     // optional
///
///     template <class T> void node(x, u, p, t, std::span<T> xdot, std::span<T> g) const;
///                                                                              // optional
///     template <class T> void integrand(x, u, p, t, std::span<T> q) const;        // optional
///
/// `integrand`, required when ProblemInfo::integrals is not empty, gives the functions whose
/// integrals over [t0, tf] (by the LGL quadrature of each segment) the integral constraints bound.
/// `node`, when present, replaces dynamics + path at the collocation nodes: both in one pass,
/// for problems whose path constraints reuse the dynamics' intermediate results.
/// `interior` evaluates the interior events (ProblemInfo::interior_events) of one mesh junction
/// (the point shared by segments junction-1 and junction; its time is free with free breaks), in
/// their order of declaration: intermediate conditions such as "90 deg of bank at the top".
///
/// Branch on `core::value_of(x)` (or `optimal::primal`) and compute in T, so derivatives follow
/// the branch taken at each evaluation.

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace manta::optimal {

/// +infinity, for an absent bound.
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A closed interval [lower, upper]; lower == upper fixes the quantity.
struct Bounds {
    double lower = -kInf;  ///< lower bound (-kInf: none)
    double upper = kInf;   ///< upper bound (+kInf: none)
    [[nodiscard]] bool is_fixed() const { return lower == upper; }
};
/// The interval [v, v].
[[nodiscard]] inline Bounds fixed(double v) {
    return {v, v};
}

/// A named decision quantity (state, control, static parameter) with bounds and scale.
struct Variable {
    std::string name;      ///< used in reports and CSV headers (include the unit: "h_ft")
    double lower = -kInf;  ///< lower bound at every node
    double upper = kInf;   ///< upper bound at every node
    double scale = 0.0;    ///< typical magnitude; 0: automatic (from bounds, else from the guess)
    /// Reference scaling with an offset (as Dymos): the solver sees (v - ref0) / (ref - ref0),
    /// so ref0 maps to 0 and ref to 1. Unset `ref`: magnitude scaling by `scale` (ref0 must
    /// then be unset too); unset `ref0` with `ref` set: 0. Defect rows of a state so scaled are
    /// scaled by |ref - ref0|.
    std::optional<double> ref0 = std::nullopt;
    std::optional<double> ref = std::nullopt;  ///< see ref0
    /// Controls only: bounds on du/dt at every collocation node, from the LGL differentiation
    /// matrix of the node's segment (du/dt = (2/h_k) sum_l D_il u_l).
    Bounds rate{};
    /// True when ref (and so reference scaling) is given.
    [[nodiscard]] bool has_reference() const { return ref.has_value(); }
    /// True when rate bounds are given (a finite bound).
    [[nodiscard]] bool has_rate_bounds() const { return rate.lower > -kInf || rate.upper < kInf; }
};

/// A named constraint function with its bounds (equality when lower == upper).
struct Constraint {
    std::string name;    ///< used in reports ("most violated constraints")
    double lower = 0.0;  ///< lower bound (-kInf: none)
    double upper = 0.0;  ///< upper bound (+kInf: none)
    double scale = 0.0;  ///< typical magnitude; 0: automatic (from the bounds, else 1)
};

/// A constraint on the state at an interior mesh point (an interior event): it holds at the
/// junction of segments `junction - 1` and `junction` (1 <= junction <= K - 1), whose time is a
/// decision variable when the mesh has free breaks. Segments before and after it form phases.
struct InteriorEvent {
    Constraint constraint;  ///< name, bounds, scale
    int junction = 1;       ///< mesh break index
};

/// Sizes, names, bounds and scales of a problem. Sizes: at least one state; any number of
/// variables (beyond kMaxDirections local variables per node, states + controls + parameters
/// + 4, or per boundary function, 2 states + parameters + 2, the derivatives use the
/// run-time-sized AD scalars, model.hpp). Names are unique over states, controls and
/// parameters; everything can be addressed by name (state(), set_initial(), Solution::state()).
struct ProblemInfo {
    std::string name;                            ///< problem name (reports, CSV)
    std::vector<Variable> states;                ///< x
    std::vector<Variable> controls;              ///< u (may be empty)
    std::vector<Variable> parameters;            ///< p, static (may be empty)
    std::vector<Constraint> path;                ///< g(x, u, p, t), enforced at every node
    std::vector<Constraint> events;              ///< e(x(t0), x(tf), p, t0, tf)
    std::vector<InteriorEvent> interior_events;  ///< conditions at interior mesh junctions
    Bounds initial_time{0.0, 0.0};               ///< t0 (fixed at 0 by default)
    Bounds final_time{0.0, kInf};                ///< tf (free, positive, by default)
    double time_scale = 0.0;                     ///< typical duration; 0: automatic
    std::vector<Bounds> initial_states;          ///< bounds on x(t0) (empty: those of `states`)
    std::vector<Bounds> final_states;            ///< bounds on x(tf) (empty: those of `states`)
    double objective_scale = 0.0;  ///< typical |objective|; 0: |objective at the guess|
    /// Maximise the objective instead of minimising it (the NLP minimises its negative; the
    /// solution reports the objective with the user's sign).
    bool maximise = false;
    /// Bounds on the integrals over [t0, tf] of integrand() (one per integrand output).
    std::vector<Constraint> integrals;

    [[nodiscard]] int n_states() const { return static_cast<int>(states.size()); }
    [[nodiscard]] int n_controls() const { return static_cast<int>(controls.size()); }
    [[nodiscard]] int n_parameters() const { return static_cast<int>(parameters.size()); }
    [[nodiscard]] int n_path() const { return static_cast<int>(path.size()); }
    [[nodiscard]] int n_events() const { return static_cast<int>(events.size()); }
    [[nodiscard]] int n_interior_events() const { return static_cast<int>(interior_events.size()); }
    [[nodiscard]] int n_integrals() const { return static_cast<int>(integrals.size()); }
    /// Number of controls with rate bounds.
    [[nodiscard]] int n_rate_bounded_controls() const {
        int n = 0;
        for (const auto& c : controls) n += c.has_rate_bounds() ? 1 : 0;
        return n;
    }

    // ---- by name ------------------------------------------------------------------------------
    /// Index of the state, control, parameter or integral constraint of that name; InputError
    /// naming it and listing the known names when there is none.
    [[nodiscard]] int state_index(std::string_view name) const;
    [[nodiscard]] int control_index(std::string_view name) const;
    [[nodiscard]] int parameter_index(std::string_view name) const;
    [[nodiscard]] int integral_index(std::string_view name) const;
    /// The state, control or parameter of that name (InputError when there is none).
    [[nodiscard]] Variable& state(std::string_view name) { return states[idx(state_index(name))]; }
    [[nodiscard]] Variable& control(std::string_view name) {
        return controls[idx(control_index(name))];
    }
    [[nodiscard]] Variable& parameter(std::string_view name) {
        return parameters[idx(parameter_index(name))];
    }
    /// Bound (or with fixed(v), fix) one component of x(t0) or x(tf) by the state's name; the
    /// others stay free (within the state's own bounds) unless set too. Creates initial_states
    /// or final_states (all free) when they are empty.
    void set_initial(std::string_view state, Bounds b);
    void set_final(std::string_view state, Bounds b);
    void set_initial(std::string_view state, double value) { set_initial(state, fixed(value)); }
    void set_final(std::string_view state, double value) { set_final(state, fixed(value)); }

    /// Number of interior events at mesh junction j.
    [[nodiscard]] int n_interior_events_at(int j) const {
        int n = 0;
        for (const auto& e : interior_events) n += e.junction == j ? 1 : 0;
        return n;
    }
    /// Check sizes, names and bounds; throws InputError naming the offending item and the
    /// values in conflict: lower > upper, initial/final bounds outside the state's bounds,
    /// ref == ref0 or ref0 without ref, rate bounds on a state or parameter.
    void validate() const;

private:
    static std::size_t idx(int i) { return static_cast<std::size_t>(i); }
};

/// What a problem type must provide (dynamics on double; the rest is optional).
template <class P>
concept OptimalControlProblem = requires(const P& p, std::span<const double> x, double t,
                                         std::span<double> out) {
    { p.info() } -> std::convertible_to<ProblemInfo>;
    p.dynamics(x, x, x, t, out);
};

}  // namespace manta::optimal
