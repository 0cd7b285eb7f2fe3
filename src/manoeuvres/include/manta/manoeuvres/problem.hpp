#pragma once
/// @file problem.hpp
/// A manoeuvre as a time-optimal control problem over the 6-DoF equations of motion
/// (docs/manoeuvres.md): quaternion attitude (no singularity at pitch +-90 deg), body
/// velocities and rates from flightdyn::quaternion_rhs with the C1 table interpolant and the
/// dynamic derivatives, plus the accumulated roll angle; controls elevator, aileron, rudder,
/// throttle; path constraints on alpha, beta and load factor; final conditions as events.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/model.hpp"
#include "manta/manoeuvres/manoeuvre.hpp"
#include "manta/optimal/model.hpp"
#include "manta/optimal/problem.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::manoeuvres {

/// State layout: flightdyn's quaternion state (x, y, z, q0..q3, u, v, w, p, q, r), the
/// accumulated roll angle (integral of p), then the control positions (elevator, aileron,
/// rudder [rad], throttle) whose rates are the problem's controls (smooth deflections).
namespace state {
enum Index : int { roll = flightdyn::quat::size, elevator, aileron, rudder, throttle, size };
}

/// One event (final condition) of the problem.
struct EventDef {
    enum class Quantity {
        speed,        ///< |v| [m/s]
        altitude,     ///< -z [m]
        heading_sin,  ///< sin(psi - centre)
        heading_cos,  ///< cos(psi - centre) >= 0
        bank_sin,     ///< sin(phi - centre)
        bank_cos,     ///< cos(phi - centre) >= 0
        pitch_sin,    ///< sin(theta)
        gamma_sin,    ///< sin(gamma)
        sideslip_sin  ///< sin(beta)
    };
    Quantity quantity = Quantity::speed;
    double centre = 0.0;  ///< reference angle of the *_sin/_cos forms [rad]
};

/// The optimal-control problem of a manoeuvre (satisfies optimal::OptimalControlProblem).
class ManoeuvreProblem {
public:
    /// The manoeuvre models fit the fixed-size derivative types (40 directions): the run-time-sized
    /// path of optimal (larger problems) is not compiled for them (compile time).
    static constexpr bool fixed_size_ad = true;
    /// Trims the entry (if asked), resolves the final conditions against it and sets bounds.
    /// InputError/ConvergenceError when the entry cannot be trimmed or a setting is inconsistent.
    ManoeuvreProblem(flightdyn::FlightModel model, ManoeuvreSpec spec);

    [[nodiscard]] optimal::ProblemInfo info() const { return info_; }
    [[nodiscard]] const flightdyn::FlightModel& model() const { return model_; }
    [[nodiscard]] const ManoeuvreSpec& spec() const { return spec_; }
    /// Entry state (state::size) and controls (4).
    [[nodiscard]] const Eigen::VectorXd& entry_state() const { return x0_; }
    [[nodiscard]] const Eigen::VectorXd& entry_controls() const { return u0_; }
    /// Names of the manoeuvre's phases (one without an intermediate condition, else two; the
    /// `phase` column of a trajectory indexes them).
    [[nodiscard]] std::vector<std::string> phase_names() const;
    /// Phase of mesh segment `segment` of `n_segments` (the first half of the segments is the
    /// phase before the intermediate condition).
    [[nodiscard]] int phase_of_segment(int segment, int n_segments) const;

    template <class T>
    void dynamics(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/,
                  const T& /*t*/, std::span<T> xdot) const {
        flightdyn::QuatState<T> s;
        for (int i = 0; i < flightdyn::quat::size; ++i) s[i] = x[i];
        const flightdyn::Controls<T> c{x[state::elevator], x[state::aileron], x[state::rudder],
                                       x[state::throttle]};
        const flightdyn::QuatState<T> d = flightdyn::quaternion_rhs(model_, s, c);
        for (int i = 0; i < flightdyn::quat::size; ++i) xdot[i] = d[i];
        xdot[state::roll] = x[flightdyn::quat::p];
        for (int i = 0; i < 4; ++i) xdot[state::elevator + i] = u[i];
    }

    /// alpha, beta, load factor nz (body -z force of aerodynamics and thrust over m g), and the
    /// Mach number, the true airspeed and the bank angle when the file limits them
    /// (`path.mach_max`, `path.speed`, `path.bank_deg`).
    template <class T>
    void path(std::span<const T> x, std::span<const T> u, std::span<const T> p, const T& t,
              std::span<T> g) const {
        std::array<T, state::size> xdot;
        node(x, u, p, t, std::span<T>(xdot), g);
    }

    /// Dynamics and path constraints in one evaluation of the equations of motion.
    template <class T>
    void node(std::span<const T> x, std::span<const T> u, std::span<const T> /*p*/, const T& /*t*/,
              std::span<T> xdot, std::span<T> g) const {
        using std::asin;
        using std::atan2;
        using std::sqrt;
        flightdyn::QuatState<T> s;
        for (int i = 0; i < flightdyn::quat::size; ++i) s[i] = x[i];
        const flightdyn::Controls<T> c{x[state::elevator], x[state::aileron], x[state::rudder],
                                       x[state::throttle]};
        flightdyn::Loads<T> L;
        const flightdyn::QuatState<T> d = flightdyn::quaternion_rhs(model_, s, c, &L);
        for (int i = 0; i < flightdyn::quat::size; ++i) xdot[i] = d[i];
        xdot[state::roll] = x[flightdyn::quat::p];
        for (int i = 0; i < 4; ++i) xdot[state::elevator + i] = u[i];
        const T& uu = x[flightdyn::quat::u];
        const T& vv = x[flightdyn::quat::v];
        const T& ww = x[flightdyn::quat::w];
        const T V = sqrt(T(uu * uu + vv * vv + ww * ww));
        g[0] = atan2(ww, uu);
        g[1] = asin(T(vv / V));
        g[2] = -L.force_body.z() / (model_.mass.mass * model_.environment.gravity);
        int k = 3;
        if (spec_.mach_max > 0.0) g[k++] = L.mach;
        if (spec_.speed_path) g[k++] = V;
        if (spec_.bank_range) {
            namespace Q = flightdyn::quat;
            const T &q0 = x[Q::q0], &q1 = x[Q::q1], &q2 = x[Q::q2], &q3 = x[Q::q3];
            g[k++] = atan2(T(2.0 * (q2 * q3 + q0 * q1)), T(q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3));
        }
    }

    /// Smoothing term rate_weight * sum (control rate / rate limit)^2.
    template <class T>
    T lagrange(std::span<const T> /*x*/, std::span<const T> u, std::span<const T> /*p*/,
               const T& /*t*/) const {
        T sum = 0.0;
        for (int i = 0; i < 4; ++i) {
            const T r = u[i] * rate_inverse_[i];
            sum = sum + r * r;
        }
        return spec_.rate_weight * sum;
    }

    template <class T>
    void events(std::span<const T> /*x0*/, std::span<const T> xf, std::span<const T> /*p*/,
                const T& /*t0*/, const T& /*tf*/, std::span<T> e) const {
        evaluate(events_, xf, e);
    }

    /// The intermediate condition (interior events at the junction of the two phases).
    template <class T>
    void interior(int /*junction*/, std::span<const T> x, std::span<const T> /*p*/, const T& /*t*/,
                  std::span<T> e) const {
        evaluate(interior_events_, x, e);
    }

    template <class T>
    T mayer(std::span<const T> /*x0*/, std::span<const T> /*xf*/, std::span<const T> /*p*/,
            const T& /*t0*/, const T& tf) const {
        return tf;
    }

    /// The initial guess: attitude waypoints of the file (quaternions, sign-aligned, linearly
    /// interpolated and normalised), speed interpolated, alpha of the entry trim, body rates
    /// from the quaternion rate, position integrated from the velocity, entry controls.
    [[nodiscard]] optimal::Guess guess() const;

private:
    /// Values of the event quantities `defs` at state x.
    template <class T>
    static void evaluate(const std::vector<EventDef>& defs, std::span<const T> x, std::span<T> e) {
        using std::sqrt;
        namespace Q = flightdyn::quat;
        const T &q0 = x[Q::q0], &q1 = x[Q::q1], &q2 = x[Q::q2], &q3 = x[Q::q3];
        const T n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3;
        const T c11 = (q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3) / n2;
        const T c21 = 2.0 * (q1 * q2 + q0 * q3) / n2;
        const T c31 = 2.0 * (q1 * q3 - q0 * q2) / n2;
        const T c32 = 2.0 * (q2 * q3 + q0 * q1) / n2;
        const T c33 = (q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3) / n2;
        const T &uu = x[Q::u], &vv = x[Q::v], &ww = x[Q::w];
        const T V = sqrt(T(uu * uu + vv * vv + ww * ww));
        for (std::size_t k = 0; k < defs.size(); ++k) {
            const EventDef& d = defs[k];
            const double sc = std::sin(d.centre), cc = std::cos(d.centre);
            switch (d.quantity) {
                case EventDef::Quantity::speed:
                    e[k] = V;
                    break;
                case EventDef::Quantity::altitude:
                    e[k] = -x[Q::z];
                    break;
                case EventDef::Quantity::heading_sin:
                    e[k] = (c21 * cc - c11 * sc) / sqrt(T(c11 * c11 + c21 * c21));
                    break;
                case EventDef::Quantity::heading_cos:
                    e[k] = (c11 * cc + c21 * sc) / sqrt(T(c11 * c11 + c21 * c21));
                    break;
                case EventDef::Quantity::bank_sin:
                    e[k] = (c32 * cc - c33 * sc) / sqrt(T(c32 * c32 + c33 * c33));
                    break;
                case EventDef::Quantity::bank_cos:
                    e[k] = (c33 * cc + c32 * sc) / sqrt(T(c32 * c32 + c33 * c33));
                    break;
                case EventDef::Quantity::pitch_sin:
                    e[k] = -c31;
                    break;
                case EventDef::Quantity::gamma_sin:
                    e[k] = -(c31 * uu + c32 * vv + c33 * ww) / V;
                    break;
                case EventDef::Quantity::sideslip_sin:
                    e[k] = vv / V;
                    break;
            }
        }
    }

    flightdyn::FlightModel model_;
    ManoeuvreSpec spec_;
    optimal::ProblemInfo info_;
    std::vector<EventDef> events_;
    std::vector<EventDef> interior_events_;  ///< the intermediate condition, if any
    Eigen::VectorXd x0_;
    Eigen::VectorXd u0_;
    std::array<double, 4> rate_inverse_{1.0, 1.0, 1.0, 1.0};
};

/// The flight model of a manoeuvre: the aircraft's mass case (with the file's mass and CG
/// overrides), the C1 table interpolant, `tables` replacing the aircraft's aero database when
/// given. InputError when a CG override needs a lifting surface named `wing` and there is none.
[[nodiscard]] flightdyn::FlightModel manoeuvre_model(
    const aircraft::AircraftDefinition& aircraft, const ManoeuvreSpec& spec,
    std::shared_ptr<const aero::AeroDatabase> tables = nullptr);

/// The type-erased, AD-differentiated model of a manoeuvre problem (instantiated in this
/// library only: see src/manoeuvres/CMakeLists.txt).
[[nodiscard]] std::unique_ptr<optimal::Model> make_model(const ManoeuvreProblem& problem);

/// Outcome of `fly`.
struct ManoeuvreResult {
    optimal::Solution solution;  ///< the NLP solution (or best iterate)
    optimal::Mesh mesh;          ///< the mesh solved on
    int coarse_iterations = 0;   ///< IPOPT iterations of the coarse-mesh stage (0: none)
};

/// Solve the manoeuvre (mesh from the spec, unless `nodes` > 0 overrides the points per segment):
/// first on `spec.coarse_nodes` points per segment when that is smaller (tolerance 1e-5), then
/// on the full mesh from the coarse solution. Iterations and times in the solution are the sum
/// of both stages.
[[nodiscard]] ManoeuvreResult fly(const ManoeuvreProblem& problem,
                                  const optimal::SolverOptions& options, int nodes = 0);

/// A sampled trajectory in the shared trajectory format (docs/manoeuvres.md#trajectory-csv):
/// one row per sample, columns named in `columns` (SI units and radians; the required columns
/// t x y z phi theta psi V alpha beta p q r elevator aileron rudder throttle first, then phase,
/// mach, altitude, nz, u v w, q0..q3, control rates, thrust, coefficients, gamma, roll_angle),
/// and `# key: value` metadata (manoeuvre, mass_case, phases, nodes, final_time, ...).
struct Trajectory {
    std::vector<std::pair<std::string, std::string>> metadata;  ///< written as `# key: value`
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
    /// Column by name (InputError if absent).
    [[nodiscard]] std::vector<double> column(const std::string& name) const;
    /// Metadata value by key ("" if absent).
    [[nodiscard]] std::string meta(const std::string& key) const;
};
/// The trajectory at every LGL node of the solution (interface nodes once, with the controls of
/// the segment they end); psi is unwrapped (continuous).
[[nodiscard]] Trajectory trajectory(const ManoeuvreProblem& problem,
                                    const optimal::Solution& solution);
/// The trajectory sampled every `step` seconds from t0 by the solution's Lagrange polynomials,
/// plus the final time. InputError for a step that is not positive.
[[nodiscard]] Trajectory dense_trajectory(const ManoeuvreProblem& problem,
                                          const optimal::Solution& solution, double step = 0.02);
/// Write a trajectory as CSV (metadata lines, header, rows). IoError on failure.
void write_trajectory_csv(const Trajectory& t, const std::filesystem::path& file);

/// Largest violations of the manoeuvre's own requirements in a trajectory.
struct ConstraintCheck {
    double alpha_max_deg = 0.0;             ///< largest alpha [deg]
    double mach_max = 0.0;                  ///< largest Mach number
    double altitude_min = 0.0;              ///< lowest altitude [m]
    double altitude_max = 0.0;              ///< highest altitude [m]
    double load_factor_max = 0.0;           ///< largest nz
    double load_factor_min = 0.0;           ///< smallest nz
    double control_limit_excess = 0.0;      ///< largest excess over a control limit [rad or -]
    double final_heading_change_deg = 0.0;  ///< psi(tf) - psi(t0) wrapped to (-180, 180]
    double final_bank_deg = 0.0;
    double final_speed = 0.0;
    double final_altitude = 0.0;
};
[[nodiscard]] ConstraintCheck check(const ManoeuvreProblem& problem, const Trajectory& t);

}  // namespace manta::manoeuvres
