#pragma once
/// @file campaign.hpp
/// A table campaign: which aero source to sample, the table axes, the sampling plan of each
/// scenario (static table from scratch, control increments, dynamic derivatives), the Kriging
/// options and the stopping rules. Read from YAML through the validation layer (format:
/// docs/formats.md#campaign-file); every value inside is SI and radians.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/surrogate/kriging.hpp"
#include "manta/tables/analytic_source.hpp"

namespace manta::tables {

enum class SourceType { analytic, vlm, euler };

/// The aero source a campaign samples. The tables module builds only the analytic source; the
/// caller (the CLI) builds the others from these fields.
struct SourceSpec {
    SourceType type = SourceType::analytic;
    std::filesystem::path aircraft;  ///< vlm: aircraft file, resolved against the campaign's folder
    int n_chord = 6;                 ///< vlm lattice: chordwise vortices per strip
    double strip_width = 0.04;       ///< vlm lattice: strip width / reference span
    bool viscous = true;             ///< vlm: add the viscous drag build-up
    std::filesystem::path mesh;      ///< euler: the mesh file, resolved like `aircraft`
    /// euler with `mesh: {model, level}`: the campaign meshes `aircraft` itself (`manta mesh`'s
    /// meshgen) into OUT/mesh/ before the first sample and reuses that mesh afterwards; `mesh`
    /// is then empty until the driver sets it.
    std::string mesh_model;            ///< "half" | "full"; empty: `mesh` is a file
    std::string mesh_level;            ///< "coarse" | "medium" | "fine"
    double mesh_size_factor = 1.0;     ///< every mesh size times this (quick looks, tests)
    std::filesystem::path cfd_config;  ///< euler: `manta cfd` configuration (empty: defaults)
    /// euler: the command each sample's `manta cfd` job is started through ("mpirun -np 4",
    /// "srun -n 64"; split into words as a shell would, without expansions); empty: every
    /// sample solved in process (docs/tables.md#launching-euler-samples).
    std::string launcher;
    bool launched = false;  ///< euler: `launcher:` was given (an empty string: jobs, no launcher)
    AnalyticParameters analytic;  ///< analytic: the test function's parameters
    std::string where;            ///< "file:line: key 'source'" for messages
};

/// How the adaptive static campaign chooses its next samples.
enum class InfillCriterion {
    max_mse,  ///< the table entry of largest combined Kriging MSE (the paper's first criterion)
    ei,       ///< expected improvement of one coefficient (min or max)
    random    ///< no adaptation: one maximin Latin hypercube of the whole budget (for comparison)
};

/// Scenario 1: the static table C(alpha, M, beta) from scratch.
struct StaticPlan {
    std::vector<double> alpha;  ///< breakpoints [rad]
    std::vector<double> mach;   ///< breakpoints [-]
    std::vector<double> beta;   ///< breakpoints [rad]
    int initial_size = 20;      ///< Latin hypercube size of the initial design
    std::uint64_t seed = 1;     ///< of the design and the likelihood restarts
    int budget = 65;            ///< samples at most (done + failed)
    InfillCriterion criterion = InfillCriterion::max_mse;
    int batch = 0;  ///< points per infill round; 0: the number of jobs
    /// Stop early once every coefficient's leave-one-out RMSE over its sampled range is below
    /// this (0: never; run to the budget).
    double cv_threshold = 0.0;
    std::string ei_coefficient = "CL";  ///< the coefficient EI works on
    bool ei_maximise = false;           ///< EI looks for the maximum instead of the minimum
    surrogate::KrigingOptions kriging;  ///< of every coefficient's model
};

/// Scenario 2: the increment table dC(alpha, M, delta) of one control, beta = 0.
struct ControlPlan {
    aero::Axis control = aero::Axis::elevator;  ///< elevator, aileron or rudder
    std::vector<double> deflection;             ///< breakpoints [rad], always containing 0
    std::vector<double> alpha;                  ///< [rad]; default the static alpha axis
    std::vector<double> mach;                   ///< default the static Mach axis
    int samples = 12;  ///< deflected samples (delta != 0): 7 by Latin hypercube, the rest by MSE
    std::uint64_t seed = 2;
    std::string where;  ///< "file:line: key 'controls.elevator.deflection_deg'" for messages
};

/// Dynamic derivatives over (alpha, M) at beta = 0 by central differences in each rate.
struct DynamicPlan {
    std::vector<double> alpha;  ///< [rad]; default the static alpha axis
    std::vector<double> mach;   ///< default the static Mach axis
    double rate_step = 0.01;    ///< step in p_hat, q_hat, r_hat
};

/// Output options.
struct OutputPlan {
    aero::Extrapolation extrapolation = aero::Extrapolation::clamp;  ///< of the database
    std::vector<double> plot_mach;  ///< Mach numbers of the slice plots (default: two)
    std::vector<double> plot_beta;  ///< sideslip angles of the slice plots [rad] (default: 0)
};

/// A whole campaign.
struct Campaign {
    std::filesystem::path file;  ///< where it was read from ("" for text)
    std::string name;
    std::string description;
    SourceSpec source;
    double altitude = 0.0;  ///< [m] of the flight condition that sets the Reynolds number
    StaticPlan static_table;
    std::vector<ControlPlan> controls;
    std::optional<DynamicPlan> dynamic;
    OutputPlan output;
};

/// Read and validate a campaign file. ConfigError (file, line, key, value, expectation) for any
/// unknown key (with the closest valid key), wrong type or value out of range; IoError if
/// unreadable. Paths inside are resolved against the file's folder.
[[nodiscard]] Campaign read_campaign(const std::filesystem::path& file);
/// The same from text; `source` names it in messages, `base` resolves relative paths.
[[nodiscard]] Campaign parse_campaign(std::string_view text, const std::string& source,
                                      const std::filesystem::path& base = {});

/// ConfigError naming the campaign key if a control plan's deflections leave [lo, hi] [rad]
/// (the aircraft's limits).
void check_control_limits(const ControlPlan& plan, double lo, double hi);

/// Evenly spaced breakpoints: count values from lo to hi (count >= 2), the ends exact.
[[nodiscard]] std::vector<double> linspace(double lo, double hi, int count);

/// Name of a coefficient index in the campaign's order CL CD CY Cl Cm Cn.
inline constexpr const char* coefficient_names[6] = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};

}  // namespace manta::tables
