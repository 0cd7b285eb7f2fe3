#pragma once
/// @file launched_source.hpp
/// The Euler source with each evaluation run as its own job (docs/tables.md#launching-euler-
/// samples): `LAUNCHER... manta cfd --mesh M [--config C] --mach .. --alpha-deg .. --beta-deg ..
/// [--p-hat .. --q-hat .. --r-hat ..] [--elevator-deg .. --aileron-deg .. --rudder-deg ..]
/// --out WORK/<sample> [--initial <nearest converged sample>/restart.bin]`, the launcher a
/// command the user names (`mpirun -np 4`, a cluster's `srun -n 64`, or none), the coefficients
/// read back from the run folder's summary.json. Rates and deflections are passed only when a
/// component is not 0, so a static sample's job and folder are those of sources before them. A
/// campaign's SQLite store stays the ledger: a sample whose job was killed is run again into the
/// same folder, where `manta cfd` resumes from its restart file; a job that fails leaves its
/// folder and log for the user and the store records the error (retried with `manta tables
/// --retry-failed`).
///
/// Results are those of `EulerSource::evaluate` on the same files: the same solver, the same
/// deformation of the mesh by the control surfaces (deflection.hpp), the same rotating frame
/// (rotating_frame.hpp `body_rate_frame`), and the warm start from the nearest converged
/// solution in (alpha, beta, Mach, rates, deflections) with EulerSource's distance; up to the
/// round-off of the text of the angles and of the partitioning when the launcher runs several
/// processes. The fingerprint is EulerSource's.

#include <array>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "manta/aero/source.hpp"
#include "manta/euler/solver.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace manta::euler {

/// How the jobs are started.
struct LaunchOptions {
    /// The launcher's words before the executable ("mpirun", "-np", "2"); empty: none.
    std::vector<std::string> launcher;
    std::filesystem::path executable;  ///< the `manta` executable the jobs run
    std::filesystem::path work_dir;    ///< one run folder per sample below it
    /// Environment settings added for every job ("NAME=value").
    std::vector<std::string> environment;
};

/// Body and wind coefficients of a source result from the solver's coefficients (mesh axes x
/// aft, y right, z up -> body axes x forward, y right, z down: CX = -CFx, CZ = -CFz, Cl = -CMx,
/// Cm = CMy, Cn = -CMz). Pressure forces only: CD_profile 0.
[[nodiscard]] aero::SourceResult source_result(const ForceCoefficients& f);

class LaunchedEulerSource final : public aero::AeroSource {
public:
    /// Reads the mesh and configuration once for the fingerprint and the control surfaces (as
    /// EulerSource::from_files). InputError, ConfigError or IoError naming the file; InputError
    /// for an empty executable or work folder.
    LaunchedEulerSource(std::filesystem::path mesh, std::filesystem::path config,
                        LaunchOptions options);

    [[nodiscard]] std::string name() const override { return "euler"; }
    [[nodiscard]] std::string fingerprint() const override { return fingerprint_; }
    /// One job per call; thread-safe (several jobs may run at once). Rates p_hat, q_hat, r_hat
    /// and deflections elevator, aileron, rudder [rad] as EulerSource::evaluate. InputError,
    /// before any job, for alpha_dot_hat or beta_dot_hat (they need a time-accurate solution) and
    /// for a deflection of a mode no control surface has (EulerSource's message); InputError when
    /// the sample's folder holds a converged summary of another flow condition. ConvergenceError
    /// naming the sample, the command's exit status, its log and the log's last line when the job
    /// fails (a rotation through a symmetry plane among them) or does not converge.
    [[nodiscard]] aero::SourceResult evaluate(
        const aero::AeroQuery<double>& q, const aero::FlowConditions& conditions) const override;

    /// Whether a control surface of the configuration is driven by `mode` ("elevator").
    [[nodiscard]] bool has_control(const std::string& mode) const;
    /// The run folder of the sample at q: M<mach>_a<alpha deg>_b<beta deg>, then
    /// _p<p_hat>_q<q_hat>_r<r_hat> when a rate is not 0 and _de<deg>_da<deg>_dr<deg> when a
    /// deflection is not 0 (6 decimals each).
    [[nodiscard]] std::filesystem::path sample_folder(const aero::AeroQuery<double>& q) const;
    /// The words of the job for a query (for messages and tests).
    [[nodiscard]] std::vector<std::string> command(const aero::AeroQuery<double>& q,
                                                   const std::filesystem::path& initial) const;
    /// The restart file of the converged sample nearest to q (EulerSource's warm-start
    /// distance: degrees, Mach / 0.05, rates / 0.01, deflections in degrees), or empty.
    [[nodiscard]] std::filesystem::path nearest_done(const aero::AeroQuery<double>& q) const;

private:
    struct Done {
        double mach, alpha, beta;
        std::array<double, 3> rates;       ///< p_hat, q_hat, r_hat
        std::array<double, 3> deflection;  ///< elevator, aileron, rudder [rad]
        std::filesystem::path folder;
    };
    std::filesystem::path mesh_, config_;
    LaunchOptions options_;
    std::string fingerprint_;
    std::vector<meshmotion::ControlSurfaceSpec> surfaces_;  ///< the configuration's
    std::string config_label_;                              ///< names it in messages
    mutable std::mutex mutex_;
    mutable std::vector<Done> done_;  ///< converged samples, found in work_dir and run here
};

}  // namespace manta::euler
