#pragma once
/// @file launched_source.hpp
/// The Euler source with each evaluation run as its own job (docs/tables.md#launching-euler-
/// samples): `LAUNCHER... manta cfd --mesh M [--config C] --mach .. --alpha-deg .. --beta-deg ..
/// --out WORK/<sample> [--initial <nearest converged sample>/restart.bin]`, the launcher a command
/// the user names (`mpirun -np 4`, a cluster's `srun -n 64`, or none), the coefficients read back
/// from the run folder's summary.json. A campaign's SQLite store stays the ledger: a sample whose
/// job was killed is run again into the same folder, where `manta cfd` resumes from its restart
/// file; a job that fails leaves its folder and log for the user and the store records the
/// error (retried with `manta tables --retry-failed`).
///
/// Results are those of `EulerSource::evaluate` on the same files (the same solver and warm
/// start from the nearest converged solution), up to the round-off of the partitioning when the
/// launcher runs several processes; the fingerprint is EulerSource's. Static evaluations only:
/// rotation rates and control deflections are refused (one line) until `manta cfd` takes them.

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "manta/aero/source.hpp"
#include "manta/euler/solver.hpp"

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
    /// Reads the mesh and configuration once for the fingerprint (as EulerSource::from_files).
    /// InputError, ConfigError or IoError naming the file; InputError for an empty executable
    /// or work folder.
    LaunchedEulerSource(std::filesystem::path mesh, std::filesystem::path config,
                        LaunchOptions options);

    [[nodiscard]] std::string name() const override { return "euler"; }
    [[nodiscard]] std::string fingerprint() const override { return fingerprint_; }
    /// One job per call; thread-safe (several jobs may run at once). ConvergenceError naming
    /// the sample, the command's exit status, its log and the log's last line when the job
    /// fails or does not converge; InputError for rates or deflections.
    [[nodiscard]] aero::SourceResult evaluate(
        const aero::AeroQuery<double>& q, const aero::FlowConditions& conditions) const override;

    /// The run folder of the sample at (Mach, alpha, beta) [rad].
    [[nodiscard]] std::filesystem::path sample_folder(double mach, double alpha, double beta) const;
    /// The words of the job for a query (for messages and tests).
    [[nodiscard]] std::vector<std::string> command(const aero::AeroQuery<double>& q,
                                                   const std::filesystem::path& initial) const;

private:
    struct Done {
        double mach, alpha, beta;
        std::filesystem::path folder;
    };
    [[nodiscard]] std::filesystem::path nearest_done(const aero::AeroQuery<double>& q) const;
    std::filesystem::path mesh_, config_;
    LaunchOptions options_;
    std::string fingerprint_;
    mutable std::mutex mutex_;
    mutable std::vector<Done> done_;  ///< converged samples, found in work_dir and run here
};

}  // namespace manta::euler
