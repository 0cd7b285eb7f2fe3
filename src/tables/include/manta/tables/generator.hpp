#pragma once
/// @file generator.hpp
/// Running a campaign: sampling an `aero::AeroSource` through the sample store and rebuilding
/// the tables by Kriging (static table), Kriging of the control increments fused with the static
/// model, and central differences (dynamic derivatives). Theory and user guide: docs/tables.md.
///
/// Determinism: every choice (initial design, infill, hyper-parameter starts) depends only on
/// the campaign and on the samples already done, taken in scheduling order, so a campaign
/// interrupted at any point and run again gives the same tables as one run without interruption
/// (for the same batch size; the batch defaults to the number of jobs and is recorded in the
/// store, which then keeps it on resumption).

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/aero/source.hpp"
#include "manta/surrogate/cokriging.hpp"
#include "manta/surrogate/kriging.hpp"
#include "manta/tables/campaign.hpp"
#include "manta/tables/store.hpp"

namespace manta::tables {

/// What a running campaign reports after each sample and each model update.
struct Progress {
    std::string phase;          ///< "static", "control:elevator", "dynamic"
    int done = 0;               ///< samples done or failed in this phase
    int total = 0;              ///< the phase's budget
    double cv_error = -1.0;     ///< largest relative LOO error of the last fit (< 0: none yet)
    double elapsed_s = 0.0;     ///< since the campaign started
    double remaining_s = -1.0;  ///< estimate for the whole campaign (< 0: unknown)
};

struct RunOptions {
    int jobs = 1;               ///< samples evaluated at once (threads)
    bool retry_failed = false;  ///< evaluate failed samples again
    /// Dimensional flow conditions at a Mach number (the Reynolds number of the flight condition);
    /// empty: default FlowConditions.
    std::function<aero::FlowConditions(double mach)> conditions;
    std::function<void(const Progress&)> progress;  ///< may be empty
};

/// A gridded table with the standard deviation of each entry (sqrt of the Kriging MSE; zero for
/// sampled or exact entries). Layout as aero::Table: row-major over `axes`, columns innermost.
struct TableWithSigma {
    aero::Table table;
    std::vector<double> sigma;
};

/// Leave-one-out error of one coefficient's model.
struct LooError {
    std::string coefficient;
    double rmse = 0.0;      ///< LOO root mean square error
    double range = 0.0;     ///< max - min of the sampled values
    double relative = 0.0;  ///< rmse / range (0 for a constant coefficient)
};

/// What one scenario did.
struct ScenarioReport {
    std::string scenario;
    int samples_done = 0;             ///< done samples the tables use
    int samples_failed = 0;           ///< failed samples (not used)
    int evaluated = 0;                ///< evaluated in this run
    int reused = 0;                   ///< found done in the store
    double sample_wall_time_s = 0.0;  ///< summed wall time of the done samples
    std::vector<LooError> loo;        ///< per coefficient (static and control scenarios)
    /// Control scenarios, per coefficient: the trend coefficient ("slope gain") of the static slope
    /// regressor in the model of dC / delta (0 where that model is a constant).
    std::vector<double> rho;
    std::string stop_reason;  ///< "budget", "cv_threshold", "design", "grid"
};

/// The static surrogate: one Kriging per coefficient over the unit cube of (alpha, M, beta).
class StaticModel {
public:
    /// Mean and MSE of CL CD CY Cl Cm Cn at (alpha [rad], M, beta [rad]).
    [[nodiscard]] std::array<surrogate::Prediction, 6> predict(double alpha, double mach,
                                                               double beta) const;
    struct Impl;
    explicit StaticModel(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

private:
    std::shared_ptr<const Impl> impl_;
};

/// The control model of one control, per coefficient over (alpha, M, delta):
/// dC = delta * g(alpha, M, delta), g a Kriging of the samples' (C - C_static(alpha, M, 0)) / delta
/// with the static model's slope (d/dalpha or d/dbeta at beta = 0) as a trend regressor.
class ControlModel {
public:
    /// Increment dC(alpha, M, delta) = delta * g(alpha, M, delta) and its MSE delta^2 MSE_g;
    /// exactly 0 (MSE 0) at delta = 0.
    [[nodiscard]] std::array<surrogate::Prediction, 6> increment(double alpha, double mach,
                                                                 double delta) const;
    [[nodiscard]] aero::Axis control() const;
    struct Impl;
    explicit ControlModel(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

private:
    std::shared_ptr<const Impl> impl_;
};

/// Everything a campaign produced.
struct CampaignResult {
    std::vector<TableWithSigma> tables;  ///< static, then each control, then dynamic
    std::shared_ptr<const StaticModel> static_model;
    std::vector<std::shared_ptr<const ControlModel>> control_models;
    std::vector<ScenarioReport> reports;  ///< one per scenario, in the order run
    int evaluated = 0;                    ///< samples evaluated in this run
    int reused = 0;                       ///< done samples found in the store
    int failed = 0;                       ///< failed samples (stored)
    int batch = 1;                        ///< infill batch size used
    double wall_time_s = 0.0;             ///< of this run
};

/// Run `campaign` on `source`, keeping every sample in `store`. ConvergenceError if a model
/// cannot be fitted (too few done samples, e.g. after failures).
[[nodiscard]] CampaignResult run_campaign(const Campaign& campaign, const aero::AeroSource& source,
                                          SampleStore& store, const RunOptions& options);

/// The aero database of a campaign's tables (wind-axis forces, the campaign's extrapolation).
[[nodiscard]] aero::AeroDatabase make_database(const Campaign& campaign,
                                               const CampaignResult& result,
                                               const std::string& source_name);

/// Evaluate every entry of the static grid of `plan` by brute force (no store): the reference of
/// accuracy studies. Returns the table with zero sigma.
[[nodiscard]] TableWithSigma brute_force_static(const StaticPlan& plan,
                                                const aero::AeroSource& source,
                                                const RunOptions& options);

}  // namespace manta::tables
