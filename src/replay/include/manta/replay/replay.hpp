#pragma once
/// @file replay.hpp
/// Replay of a manoeuvre through a time-accurate aerodynamic source and its comparison with the
/// tables (docs/replay.md): the motion built from the trajectory (motion_builder.hpp), the source
/// stepped along it (aero::UnsteadyRun, whichever solver it is), at every step the table
/// prediction at the same instantaneous state, differences, statistics per coefficient and phase,
/// flagged intervals with their state and likely reasons, and checkpoints from which a killed
/// replay continues to the same result bit for bit.
///
/// Outputs in the output directory (docs/replay.md, "Outputs"): motion.csv, comparison.csv,
/// summary.json, and checkpoint/ while running.

#include <array>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/aero/source.hpp"
#include "manta/replay/motion_builder.hpp"
#include "manta/replay/trajectory.hpp"

namespace manta::replay {

/// The six compared coefficients, in output order: wind-axis forces CL CD CY, body-axis moments
/// Cl Cm Cn about the moment reference point.
inline constexpr std::array<const char*, 6> coefficient_names{"CL", "CD", "CY", "Cl", "Cm", "Cn"};

/// Default flag tolerances |replay - table| per coefficient (docs/replay.md, "Flags").
[[nodiscard]] std::array<double, 6> default_tolerances();

/// Progress of a replay, reported after every step.
struct ReplayProgress {
    int step = 0;              ///< steps done
    int n_steps = 0;           ///< steps in all
    double t = 0.0;            ///< flight time reached [s]
    double elapsed_s = 0.0;    ///< wall time of this process [s]
    double remaining_s = 0.0;  ///< estimate [s]
    int resumed_from = -1;     ///< step the run resumed from, -1 if it started afresh
};

struct ReplaySettings {
    /// Time step [s]; 0: choose_time_step(trajectory, rule).
    double dt = 0.0;
    TimeStepRule rule;
    /// Round the chosen time step (dt 0) down to the trajectory's duration / N, for a source
    /// whose run takes whole steps only (euler); a given dt is left as it is.
    bool whole_steps = false;
    /// Motion sample step [s]: the time step divided into equal parts no longer than this.
    double max_sample_dt = 0.01;
    /// Reference span and chord [m] of the rates' non-dimensionalisation (p b / 2V, q c / 2V).
    double span = 0.0, chord = 0.0;
    /// Flag tolerances in coefficient_names order (default_tolerances()).
    std::array<double, 6> tolerances = default_tolerances();
    /// Add the source's viscous drag estimate at the entry Reynolds number (US 1976 atmosphere).
    bool viscous = true;
    /// Checkpoint every this many steps (0: never by count) ...
    int checkpoint_steps = 0;
    /// ... and every this many seconds of wall time (0: never by time).
    double checkpoint_seconds = 30.0;
    /// Discard a checkpoint in the output directory instead of resuming from it.
    bool restart = false;
    /// Keep checkpoint/ when the replay completes.
    bool keep_checkpoint = false;
    /// Replay only the first `until` seconds of flight (first_seconds: the trajectory cut there,
    /// the time step chosen on the cut trajectory); 0: the whole trajectory.
    double until = 0.0;
    /// Stop (after writing a checkpoint) once this many steps have been done in this call, as a
    /// killed process would; -1: run to the end. For tests.
    int stop_after_steps = -1;
    /// Text naming the trajectory in summary.json (its path).
    std::string trajectory_label;
    /// Added to the fingerprint: anything else that changes the result (e.g. lattice options).
    std::string extra_fingerprint;
    /// Surface snapshots (docs/replay.md, "Surface snapshots"): every this many seconds of
    /// flight (snapshot_steps), written by `write_snapshot` into out/surface/step-NNNNNN.csv,
    /// listed in out/surface/index.csv at the end; 0 or no writer: none.
    double snapshot_every = 0.0;
    /// Writes the run's surface at its current instant to the file (atomically); returns false
    /// when the run has no surface to write (then no snapshot is taken).
    std::function<bool(const aero::UnsteadyRun&, const std::filesystem::path&)> write_snapshot;
    std::function<void(const ReplayProgress&)> progress;
    /// Warnings about the inputs (check_tables, check_euler_setup in input_checks.hpp), handed
    /// to `warn` once the replay's own checks (time step, checkpoint) have passed and before
    /// the source's first step, and listed in summary.json `input_warnings`.
    std::vector<std::string> input_warnings;
    std::function<void(const std::string&)> warn;
};

/// What `run_replay` did.
struct ReplayOutcome {
    bool completed = false;  ///< false: stopped by stop_after_steps (checkpoint written)
    int steps = 0;           ///< steps of the whole replay
    int resumed_from = -1;   ///< step resumed from, -1 if none
    double dt = 0.0;
    std::string dt_reason;
    nlohmann::json summary;  ///< summary.json (when completed)
    std::filesystem::path motion_file, comparison_file, summary_file;
    int snapshots = 0;  ///< surface snapshots listed in surface/index.csv (0: none)
};

/// Replay `trajectory` through `source` and compare with `tables` (multilinear), writing the
/// outputs into `out`. Resumes from out/checkpoint when its fingerprint (trajectory, source,
/// tables, time step and settings) matches; InputError naming the checkpoint when it does not
/// (set `restart` to discard it). InputError for a source that cannot move (before anything is
/// written), IoError for unwritable outputs.
ReplayOutcome run_replay(const aero::AeroSource& source, const aero::AeroDatabase& tables,
                         const Trajectory& trajectory, const ReplaySettings& settings,
                         const std::filesystem::path& out);

/// The steps at which a replay of `n_steps` steps of `dt` takes a surface snapshot every `every`
/// seconds of flight: step 0, each first step at or past a whole multiple of `every` after the
/// start, and the last step; empty for `every` <= 0.
[[nodiscard]] std::vector<int> snapshot_steps(int n_steps, double dt, double every);

/// One row of comparison.csv (docs/replay.md): state, then replay, table and difference of each
/// coefficient, and the flag.
struct ComparisonRow {
    double t = 0.0;
    int phase = 0;
    double alpha = 0.0, beta = 0.0, V = 0.0, mach = 0.0;
    std::array<double, 3> rates{};          ///< p q r [rad/s]
    std::array<double, 3> controls{};       ///< elevator aileron rudder [rad]
    std::array<double, 3> control_rates{};  ///< [rad/s]
    std::array<double, 6> replay{}, table{}, diff{};
    bool flag = false;
    bool extrapolated = false;  ///< the table query left the table's range
    /// The source's iterations on this step and whether they converged (UnsteadySample).
    int source_iterations = 0;
    bool source_converged = true;
};

/// A phase of the manoeuvre: [t_start, t_end] and its name.
struct Phase {
    std::string name;
    double t_start = 0.0, t_end = 0.0;
};

/// Phases of a trajectory: its `phase` column with `# phases:` names when the column holds more
/// than one value, else the automatic segmentation of docs/replay.md (steady / pull-up /
/// push-over / roll / yaw by the body rates, runs shorter than min(1 s, duration / 10) merged
/// into a neighbour). Also returns the phase index of every trajectory row (the `phase` column
/// value, or the segment's index).
[[nodiscard]] std::vector<Phase> trajectory_phases(const Trajectory& trajectory,
                                                   std::vector<int>* row_phase = nullptr);

/// summary.json of finished comparison rows (format: docs/replay.md).
[[nodiscard]] nlohmann::json summarise(const std::vector<ComparisonRow>& rows,
                                       const std::vector<Phase>& phases,
                                       const std::array<double, 6>& tolerances, double entry_mach,
                                       double chord, double span);

/// comparison.csv text of `rows`.
[[nodiscard]] std::string comparison_csv(const std::vector<ComparisonRow>& rows);

}  // namespace manta::replay
