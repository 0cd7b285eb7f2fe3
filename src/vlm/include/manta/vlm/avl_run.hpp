#pragma once
/// @file avl_run.hpp
/// Reader of AVL's run-case file (`.run`, AVL 3.40), the choice of the moment reference point
/// from the command line, run case, mass file and .avl header, and the solution of a run case's
/// constraints (AVL's OPER "X": alpha trimmed to a CL, a control to zero pitching moment, ...).
/// docs/avl-input.md ("Run-case file") lists what is read and how.
///
/// A run case starts at a line "Run case N: name" and holds
/// * constraint lines "variable -> constraint = value": the variable (alpha, beta, pb/2V, qc/2V,
///   rb/2V or a control) is set so that the constraint (alpha, beta, pb/2V, qc/2V, rb/2V, CL,
///   CY, "Cl roll mom", "Cm pitchmom", "Cn yaw mom" or a control) has the value; angles and
///   deflections in degrees;
/// * parameter lines "name = value [unit]": of these Mach, CDo and X_cg, Y_cg, Z_cg change the
///   steady solution (as in AVL, whose documentation says that only a few parameters "such as
///   Mach and XYZ_cg" affect OPER's solution); alpha, beta and the rates are the starting point
///   of the solution; the rest (bank, velocity, density, mass, inertias, visc CL_a, ...) serve
///   AVL's trim set-up and eigenmode analysis and are read and checked only.
/// Rates and the rolling and yawing moments of the constraints are about the stability axes
/// (AVL's default, its option "stability-axis rates"); CL, CY and Cm as AVL prints them.
///
/// Every malformed line is an InputError of one line naming file, line and the key: an unknown
/// variable, constraint or parameter, a constraint used twice, a value that is not a finite
/// number or is implausible. (AVL ignores unknown names with a message.)

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "manta/vlm/avl_mass.hpp"
#include "manta/vlm/model.hpp"
#include "manta/vlm/steady.hpp"

namespace manta::vlm {

/// One line "variable -> constraint = value" of a run case.
struct RunConstraint {
    /// "alpha", "beta", "pb/2V", "qc/2V", "rb/2V" or a control name (lower case, as the model's).
    std::string variable;
    /// "alpha", "beta", "pb/2V", "qc/2V", "rb/2V", "CL", "CY", "Cl", "Cm", "Cn" (the moments,
    /// written "Cl roll mom" etc. in the file) or a control name (lower case).
    std::string constraint;
    double value = 0.0;  ///< as in the file: degrees for alpha, beta and controls
    int line = 0;
};

/// One run case of a .run file.
struct RunCase {
    int number = 0;    ///< N of "Run case N:"
    std::string name;  ///< the text after the colon
    int line = 0;      ///< line of "Run case N:"
    std::string source;
    std::vector<RunConstraint> constraints;  ///< in file order
    /// Parameter lines by AVL's name ("alpha", "Mach", "X_cg", "visc CL_a", ...): value as
    /// written (degrees for the angles, the file's units otherwise) and line.
    std::map<std::string, std::pair<double, int>> parameters;

    [[nodiscard]] std::optional<double> parameter(const std::string& name) const;
    /// "FILE:LINE" of a parameter (or of the case line if the parameter is absent).
    [[nodiscard]] std::string where(const std::string& parameter) const;
};

/// Read a run-case file: every run case in it, in file order. IoError if it cannot be read,
/// InputError for malformed content or a file without run cases.
[[nodiscard]] std::vector<RunCase> read_avl_run(const std::filesystem::path& file);
/// Parse the text of a run-case file; `source` names it in messages.
[[nodiscard]] std::vector<RunCase> parse_avl_run(std::string_view text, const std::string& source);
/// The run case numbered `number`; InputError naming the file and the numbers it has if none.
[[nodiscard]] const RunCase& find_run_case(const std::vector<RunCase>& cases, int number,
                                           const std::string& source);

/// The moment reference point and where it came from.
struct ReferenceChoice {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    std::string from;  ///< e.g. "b737.run:44-46 (run case 1 X_cg Y_cg Z_cg)"
};

/// The moment reference point of an AVL model, by precedence: `xref` (the command line) over the
/// run case's X_cg, Y_cg, Z_cg (each one that it gives) over the mass file's centre of gravity
/// over the .avl header's Xref Yref Zref (already in `model`). This is AVL's own order at start
/// up (the mass file is read, then the run file overwrites the run cases' CG) plus the command
/// line on top. All in the .avl file's length unit.
[[nodiscard]] ReferenceChoice choose_reference_point(const Model& model, const AvlMass* mass,
                                                     const RunCase* run,
                                                     const std::optional<Eigen::Vector3d>& xref);

/// Apply a run case's Mach (as the model's default Mach) and CDo (as its profile drag) to a model.
void apply_run_case(Model& model, const RunCase& run);

/// Result of solving a run case.
struct RunCaseSolution {
    FlowState state;          ///< the state that meets the constraints (body-axis rates)
    Derivatives derivatives;  ///< at `state`
    int iterations = 0;       ///< Newton iterations
    double residual = 0.0;    ///< largest constraint residual at the end
};

/// Solve a run case's constraints with Newton's method on the solver's derivatives (as AVL's
/// OPER "X"). Variables without a constraint line are held at 0, as AVL's defaults. InputError
/// (naming file and line) for a control the model does not have or a variable or constraint given
/// twice; ConvergenceError if the constraints do not determine the variables (a singular
/// Jacobian, e.g. "alpha -> Cl roll mom" on a symmetric aircraft) or Newton does not converge.
[[nodiscard]] RunCaseSolution solve_run_case(const SteadySolver& solver, const RunCase& run);

}  // namespace manta::vlm
