#pragma once
/// @file simulate.hpp
/// Time simulation of the 6-DoF equations of motion (eom.hpp) driven by a control-input history.
///
/// - Inputs: a CSV time history of the controls (`InputHistory`, format in
///   docs/flight-dynamics.md#input-csv), linearly interpolated, saturated at the model's
///   `ControlLimits`; channels absent from the file hold their initial (trim) value.
/// - Integrators: fixed-step classical Runge-Kutta 4 or adaptive Dormand-Prince 5(4) with dense
///   output (Boost.Odeint, error control on rtol/atol).
/// - State forms: Euler angles (the paper's state; singular at theta = +-90 deg and V = 0) or
///   quaternion (default; no attitude singularity). The trajectory always carries Euler angles.
/// - Output: rows at a fixed interval with the trajectory columns of ARCHITECTURE.md
///   (`trajectory_columns()`), written atomically by `write_trajectory`.
/// - Ends: at the requested duration, on the ground (altitude <= `ground_altitude`), or on leaving
///   the atmosphere model; `SimulationResult::end_reason` says which. NaN/Inf in the state raise
///   NumericalError naming the time and the last finite state (the partial result goes to
///   `SimulationOptions::on_abort` first, so nothing computed is lost).
/// - Ensembles (`simulate_ensemble`): many cases of one model; with RK4 they advance in lock-step
///   and each stage evaluates all cases' derivatives in one batched call (`euler_rhs_batch`,
///   `quaternion_rhs_batch`). Each case's result equals `simulate`'s for that case to rounding; a
///   case that ends (ground, atmosphere, NaN) drops out and the others go on; a NaN is recorded
///   in that case's result (`EndReason::numerical_error`) instead of thrown.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/core/io.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/model.hpp"

namespace manta::flightdyn {

/// Which state vector is integrated.
enum class StateForm {
    euler,  ///< (x, y, z, phi, theta, psi, V, alpha, beta, p, q, r); singular at theta = +-90 deg,
            ///< V = 0
    quaternion,  ///< (x, y, z, q0..q3, u, v, w, p, q, r); no attitude singularity
};

/// Time integrator.
enum class Integrator {
    rk4,     ///< classical fixed-step Runge-Kutta, 4th order (step `dt`)
    dopri5,  ///< Dormand-Prince 5(4), adaptive, dense output (tolerances `rtol`, `atol`)
};

/// "euler" / "quaternion".
[[nodiscard]] std::string_view to_string(StateForm v);
/// "rk4" / "dopri5".
[[nodiscard]] std::string_view to_string(Integrator v);
/// Parse "euler" / "quaternion"; InputError listing the choices (with a suggestion) otherwise.
[[nodiscard]] StateForm parse_state_form(std::string_view text);
/// Parse "rk4" / "dopri5"; InputError listing the choices (with a suggestion) otherwise.
[[nodiscard]] Integrator parse_integrator(std::string_view text);

/// Index of a control channel in per-channel arrays.
enum class Channel : int { elevator = 0, aileron, rudder, throttle };
/// Number of control channels.
inline constexpr int n_channels = 4;
/// "elevator", "aileron", "rudder", "throttle".
[[nodiscard]] std::string_view to_string(Channel c);

/// A control-input time history: per channel either a column of samples (linear interpolation
/// between rows, the first row's value before the first time, the last row's value after the last
/// time) or, for channels the file does not give, a constant (the initial/trim value).
/// Values are commands; saturation at the model's limits is applied by `command_at`.
class InputHistory {
public:
    /// Every channel constant at `initial` (deflections [rad], throttle [0..1]).
    explicit InputHistory(const Controls<double>& initial = {});

    /// Parse CSV text (docs/flight-dynamics.md#input-csv): column `t` [s], strictly increasing;
    /// any of `elevator aileron rudder` [rad] or `elevator_deg aileron_deg rudder_deg` [deg]
    /// (not both forms of one channel) and `throttle` [0..1]. Channels absent hold `initial`.
    /// InputError with "source:line:column" for a bad number, a non-increasing or duplicate `t`,
    /// an unknown column (with the closest valid name) or a channel given twice.
    [[nodiscard]] static InputHistory parse(std::string_view csv_text, const std::string& source,
                                            const Controls<double>& initial);
    /// Read and parse a CSV file (IoError if it cannot be read).
    [[nodiscard]] static InputHistory read(const std::filesystem::path& file,
                                           const Controls<double>& initial);

    /// Commanded (unsaturated) controls at time `t` [s].
    [[nodiscard]] Controls<double> at(double t) const;
    /// True if channel `c` comes from the file (false: held at its initial value).
    [[nodiscard]] bool has(Channel c) const { return present_[static_cast<int>(c)]; }
    /// Sample times [s] (empty when no file was given).
    [[nodiscard]] const std::vector<double>& times() const { return t_; }
    /// Samples of channel `c` in SI units (empty when absent).
    [[nodiscard]] const std::vector<double>& samples(Channel c) const {
        return values_[static_cast<int>(c)];
    }
    /// Source file line of each sample (for messages).
    [[nodiscard]] const std::vector<int>& lines() const { return lines_; }
    /// Where the history came from ("" when constant).
    [[nodiscard]] const std::string& source() const { return source_; }

private:
    std::string source_;
    std::vector<double> t_;
    std::vector<int> lines_;
    std::array<std::vector<double>, n_channels> values_;
    std::array<bool, n_channels> present_{false, false, false, false};
    Controls<double> initial_;
};

/// Controls clipped to the model's limits; `saturated[c]` says which channels were clipped.
struct SaturatedControls {
    Controls<double> controls;                                           ///< clipped controls
    std::array<bool, n_channels> saturated{false, false, false, false};  ///< per Channel
};
/// Clip a command to `limits` (deflections and throttle).
[[nodiscard]] SaturatedControls saturate(const Controls<double>& command,
                                         const ControlLimits& limits);

/// How often each channel hit its limit.
struct SaturationReport {
    /// Input-file rows whose value lies outside the limits, per channel.
    std::array<std::int64_t, n_channels> input_rows{0, 0, 0, 0};
    /// Output samples at which the applied value was clipped, per channel.
    std::array<std::int64_t, n_channels> output_samples{0, 0, 0, 0};
    /// First input row outside the limits, per channel: time [s] and commanded value (SI); valid
    /// when input_rows > 0.
    std::array<double, n_channels> first_time{0, 0, 0, 0};
    std::array<double, n_channels> first_value{0, 0, 0, 0};
    /// Sum of all counts.
    [[nodiscard]] std::int64_t total() const;
    /// One line per saturated channel ("elevator: 12 input rows beyond [-25, 15] deg, first at
    /// t = 3.2 s (-30 deg); 140 output samples clipped"); empty if none.
    [[nodiscard]] std::string summary(const ControlLimits& limits) const;
};

/// Where a simulation is, for progress displays. For an ensemble `t` and `duration` are summed
/// over the cases (case-seconds; a case that ended early counts as done in full), so
/// `fraction()` is the share of the whole ensemble's work done.
struct SimulationProgress {
    double t = 0.0;               ///< simulated time reached [s] (ensemble: case-seconds done)
    double duration = 0.0;        ///< requested duration [s] (ensemble: cases x duration)
    double wall_elapsed = 0.0;    ///< wall time so far [s]
    double wall_remaining = 0.0;  ///< estimate of the wall time left [s]
    std::size_t n_cases = 1;      ///< cases in the run (1 for `simulate`)
    std::size_t cases_ended = 0;  ///< cases that have ended
    /// t / duration.
    [[nodiscard]] double fraction() const { return duration > 0 ? t / duration : 1.0; }
};

struct SimulationResult;

/// Simulation settings. `validate()` throws InputError naming the bad option.
struct SimulationOptions {
    double duration = 60.0;  ///< simulated time [s], > 0
    double dt = 0.01;        ///< RK4 step; dopri5 initial step [s], > 0
    /// Interval between output rows [s]; 0 means `dt`. For rk4 it is rounded to the nearest
    /// positive multiple of dt.
    double output_interval = 0.0;
    Integrator integrator = Integrator::rk4;  ///< time integrator
    StateForm form = StateForm::quaternion;   ///< state vector integrated
    double rtol = 1e-8;                       ///< dopri5 relative tolerance
    double atol = 1e-8;  ///< dopri5 absolute tolerance (state in SI units and radians)
    /// dopri5 largest step [s]; 0 means the output interval (so no input pulse longer than the
    /// output interval is stepped over).
    double max_step = 0.0;
    /// Stop when the altitude falls to this value [m] (the ground); NaN disables the check.
    double ground_altitude = 0.0;
    /// Called with progress at most every `progress_interval` wall seconds (and once at the end).
    std::function<void(const SimulationProgress&)> progress;
    double progress_interval = 0.5;  ///< [s of wall time]
    /// Called by `simulate` with the partial result (rows up to the last finite state, end
    /// reason `numerical_error`) before NumericalError is thrown, so the caller can save it.
    /// `simulate_ensemble` does not call it: the partial result is in its returned vector.
    std::function<void(const SimulationResult&)> on_abort;
    /// Where `simulate` hands each output row (trajectory_columns() order) as it is computed.
    /// With a sink, SimulationResult::rows stays empty (SimulationResult::n_rows counts the
    /// rows), so a run of any length keeps no rows in memory; TrajectoryWriter is such a sink.
    /// `simulate_ensemble` ignores it (its cases keep their rows).
    std::function<void(std::span<const double>)> row_sink;
    std::string aircraft_name;  ///< for the trajectory metadata ("" = the model's name)
    std::string mass_case;      ///< for the trajectory metadata ("" = the model's mass case)

    /// InputError naming the first bad option.
    void validate() const;
};

/// Why a simulation ended.
enum class EndReason {
    completed,        ///< reached the requested duration
    ground,           ///< altitude fell to the ground altitude
    left_atmosphere,  ///< altitude left the atmosphere model's range
    /// the state became NaN/Inf or the integrator failed; `end_message` holds the NumericalError
    /// text. `simulate` throws that error (after `on_abort`); `simulate_ensemble` records it.
    numerical_error,
};
/// "completed", "ground", "left_atmosphere", "numerical_error".
[[nodiscard]] std::string_view to_string(EndReason v);

/// A simulated trajectory and its book-keeping.
struct SimulationResult {
    std::vector<std::string> columns;       ///< trajectory_columns()
    std::vector<std::vector<double>> rows;  ///< one row per output sample (none with a row sink)
    std::int64_t n_rows = 0;                ///< output rows, also those handed to a row sink
    std::vector<std::string> metadata;      ///< '#' lines (without the '#')
    EulerState<double> final_state;         ///< state at final_time (Euler form, angles unwrapped)
    Controls<double> final_controls;        ///< applied (saturated) controls at final_time
    double final_time = 0.0;                ///< [s]
    EndReason end_reason = EndReason::completed;  ///< why the run ended
    std::string end_message;           ///< one line, e.g. "reached the ground at t = 12.3 s"
    std::int64_t steps = 0;            ///< accepted integration steps
    std::int64_t rhs_evaluations = 0;  ///< right-hand-side evaluations
    /// Wall time of the integration [s]; for a lock-step ensemble case, of the whole ensemble
    /// from its start to this case's end (the cases share it).
    double wall_seconds = 0.0;
    SaturationReport saturation;          ///< saturated controls
    aero::OutOfRangeReport out_of_range;  ///< table queries out of range (empty without aero)
};

/// Trajectory CSV columns: t x y z phi theta psi V alpha beta p q r elevator aileron rudder
/// throttle mach altitude nz CL CD CY Cl Cm Cn (ARCHITECTURE.md, SI units and radians).
[[nodiscard]] const std::vector<std::string>& trajectory_columns();

/// Simulate `model` from `initial` (Euler form; converted to the chosen form) with controls from
/// `inputs` (saturated at model.limits). The model is used through a finalized copy (its derived
/// flags recomputed from the tables). The aero database's out-of-range counters are reset at the
/// start and reported in the result. InputError for bad options or a singular initial state in
/// the Euler form, NumericalError on NaN/Inf.
[[nodiscard]] SimulationResult simulate(const FlightModel& model, const EulerState<double>& initial,
                                        const InputHistory& inputs,
                                        const SimulationOptions& options);

/// One case of an ensemble.
struct EnsembleCase {
    std::string name;            ///< label for messages (e.g. "V150_h3000")
    EulerState<double> initial;  ///< initial state, Euler form (converted to options.form)
    InputHistory inputs;         ///< control commands (saturated at the model's limits)
};

/// Simulate every case of `cases` with one model and one set of options; result i belongs to
/// case i and equals `simulate(model, cases[i].initial, cases[i].inputs, options)` to rounding
/// (the batched right-hand side differs from the one-state one by rounding only), with two
/// differences: a NaN/Inf ends that case with `EndReason::numerical_error` and the error text in
/// `end_message` (rows up to the last finite state) instead of throwing, and `wall_seconds` is
/// the ensemble's (see SimulationResult).
/// - rk4: the cases advance in lock-step on the same time and output grid; each RK4 stage
///   evaluates the derivatives of every running case in one `euler_rhs_batch` or
///   `quaternion_rhs_batch` call (a lone running case, and a case whose last evaluation left the
///   aero tables, take the one-state right-hand side); a case that ends drops out, the others go
///   on.
/// - dopri5: adaptive steps differ per case, so the cases run one after another with `simulate`.
/// Out-of-table counts are per case: with more than one case the aero database's counters are
/// used as scratch (reset around each batched stage and attributed to the cases; a stage with an
/// out-of-table query is re-evaluated one case at a time to attribute it) and hold no total
/// afterwards. `options.progress` sees the whole ensemble (SimulationProgress). InputError, naming
/// the case, for bad options or initial states, before anything runs. An empty `cases` gives an
/// empty vector.
[[nodiscard]] std::vector<SimulationResult> simulate_ensemble(const FlightModel& model,
                                                              std::span<const EnsembleCase> cases,
                                                              const SimulationOptions& options);

/// Write a result as trajectory CSV ('#' metadata lines, header, rows), atomically.
void write_trajectory(const std::filesystem::path& file, const SimulationResult& result);

/// A trajectory CSV written as the rows are computed (SimulationOptions::row_sink), the same
/// text as `write_trajectory` of the whole result: the rows go to a spool file beside `file`
/// (unlinked at once, so a killed run leaves nothing behind), and `finish` writes the '#'
/// metadata lines (known only at the end) and the header, then the spooled rows, and renames
/// the whole over `file` atomically. Memory stays bounded whatever the run's length. IoError
/// naming the file when it cannot be written.
class TrajectoryWriter {
public:
    explicit TrajectoryWriter(const std::filesystem::path& file);
    ~TrajectoryWriter();
    TrajectoryWriter(const TrajectoryWriter&) = delete;
    TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;
    /// Append one row (trajectory_columns() order).
    void row(std::span<const double> values);
    /// A sink for SimulationOptions::row_sink that appends to this writer.
    [[nodiscard]] std::function<void(std::span<const double>)> sink();
    /// Write the file: `result`'s metadata and columns, then every row appended so far (it may be
    /// called again after more rows).
    void finish(const SimulationResult& result);
    /// Rows appended so far.
    [[nodiscard]] std::int64_t rows() const { return rows_; }

private:
    void flush_buffer();
    std::filesystem::path file_;
    int spool_ = -1;
    std::string buffer_;
    std::int64_t rows_ = 0;
};

}  // namespace manta::flightdyn
