#pragma once
/// @file database.hpp
/// `AeroDatabase`: tabulated aerodynamics of a whole aircraft.
///
/// A database is a set of gridded tables, each over named axes, summed at evaluation:
///  - one *static* table C(alpha, mach, beta, ...) of the six coefficients;
///  - *control-increment* tables dC(alpha, mach, delta[, beta]) per control (elevator, aileron,
///    rudder), each with that control among its axes; the increment is added to the static value;
///  - one *dynamic-derivative* table over (alpha, mach) whose columns are named `<coef>_<rate>`
///    with rate in {p, q, r, alphadot, betadot}; it adds C_rate * rate_hat.
/// Tables may use any subset of the axes {alpha, beta, mach, elevator, aileron, rudder}; an axis
/// with one breakpoint is constant in that variable. Force columns are wind-axis (CL CD CY) or
/// body-axis (CX CY CZ) for the whole database (`ForceAxes`); moment columns are Cl Cm Cn about the
/// moment reference point. A missing column is zero.
///
/// Interpolation: multilinear (simulation; exact on multilinear data) or C1 (tensor-product
/// cubic Hermite with finite-difference slopes, for optimisation: value and first derivatives
/// continuous). Out-of-table queries follow the database's `Extrapolation` policy (clamp to the
/// edge value, or continue the edge cell linearly); every such query is counted per table and axis
/// and reported by `out_of_range()`, never silent.
///
/// `evaluate` is a template so it runs with automatic-differentiation scalars: the cell is chosen
/// on the plain value, the weights are computed in the scalar type, so derivatives follow the cell.
///
/// Native file format: docs/aero-database.md (YAML, exact round trip).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aero/types.hpp"

namespace manta::aero {

namespace detail {
struct FastPlan;
}

enum class ForceAxes { wind, body };
enum class Interpolation { multilinear, c1 };
enum class Extrapolation { clamp, linear };
enum class Axis { alpha, beta, mach, elevator, aileron, rudder };
enum class TableKind { static_table, control, dynamic };

[[nodiscard]] std::string_view to_string(ForceAxes v);
[[nodiscard]] std::string_view to_string(Interpolation v);
[[nodiscard]] std::string_view to_string(Extrapolation v);
[[nodiscard]] std::string_view to_string(Axis v);
[[nodiscard]] std::string_view to_string(TableKind v);
/// True for axes measured in radians (alpha, beta, deflections).
[[nodiscard]] bool is_angle(Axis v);

/// One axis of a table grid: strictly increasing breakpoints (radians for angles).
struct GridAxis {
    Axis axis = Axis::alpha;
    std::vector<double> breakpoints;
};

/// A gridded table. `values` is row-major over `axes` (last axis fastest) with the columns
/// innermost: values[flat_grid_index * columns.size() + column].
struct Table {
    std::string name;
    TableKind kind = TableKind::static_table;
    std::vector<GridAxis> axes;
    std::vector<std::string> columns;
    std::vector<double> values;

    [[nodiscard]] std::size_t n_points() const;  ///< product of axis sizes
};

/// Counts of out-of-table queries for one (table, axis).
struct OutOfRangeEntry {
    std::string table;
    Axis axis = Axis::alpha;
    std::uint64_t below = 0;  ///< queries under the first breakpoint
    std::uint64_t above = 0;  ///< queries over the last breakpoint
    double lowest = 0.0;      ///< most extreme query values seen (valid when below/above > 0)
    double highest = 0.0;
    double table_min = 0.0;  ///< first breakpoint of the axis (the table's range)
    double table_max = 0.0;  ///< last breakpoint of the axis
};

struct OutOfRangeReport {
    std::uint64_t evaluations = 0;         ///< evaluate() calls since the last reset
    std::vector<OutOfRangeEntry> entries;  ///< only (table, axis) pairs with a count > 0
    [[nodiscard]] std::uint64_t total() const;
    /// One line per entry, e.g. "static/alpha: 12 above 0.2094 (max 0.25)"; empty if none.
    [[nodiscard]] std::string summary() const;
};

/// Descriptive metadata carried in the file.
struct DatabaseInfo {
    std::string name;
    std::string description;  ///< provenance: source, how it was built
    std::string source;       ///< e.g. "linear-derivatives", "vlm", "euler", "NASA TP-1538"
};

/// Classical linear stability and control derivatives (per radian, per non-dimensional rate),
/// with a parabolic drag polar CD = CD_0 + CD_k * (CL - CL_min_drag)^2. Used to build a
/// database when only derivatives are known.
struct LinearDerivatives {
    double CL_0 = 0, CL_alpha = 0, CL_q = 0, CL_alphadot = 0, CL_de = 0;
    double CD_0 = 0, CD_k = 0, CL_min_drag = 0, CD_de = 0;
    double CY_beta = 0, CY_p = 0, CY_r = 0, CY_da = 0, CY_dr = 0;
    double Cl_beta = 0, Cl_p = 0, Cl_r = 0, Cl_da = 0, Cl_dr = 0;
    double Cm_0 = 0, Cm_alpha = 0, Cm_q = 0, Cm_alphadot = 0, Cm_de = 0;
    double Cn_beta = 0, Cn_p = 0, Cn_r = 0, Cn_da = 0, Cn_dr = 0;
    /// Mach at which the derivatives hold; if `prandtl_glauert`, the alpha, beta and control
    /// derivatives scale with sqrt(1 - M_ref^2) / sqrt(1 - M^2) over the Mach axis.
    double mach_ref = 0.0;
    bool prandtl_glauert = false;
};

/// Grids used to tabulate a derivative model.
struct DerivativeGrids {
    std::vector<double> alpha;     ///< [rad]
    std::vector<double> mach;      ///< [-]
    std::vector<double> beta;      ///< [rad]
    std::vector<double> elevator;  ///< [rad]
    std::vector<double> aileron;   ///< [rad]
    std::vector<double> rudder;    ///< [rad]
};

/// Body-axis coefficients at a query with their partial derivatives with respect to the
/// non-dimensional angle rates. The coefficients are affine in alpha_dot_hat and beta_dot_hat
/// (the dynamic table adds C_alphadot alpha_dot_hat + C_betadot beta_dot_hat), so
/// C(a, b) = value + (a - q.alpha_dot_hat) d_alpha_dot_hat + (b - q.beta_dot_hat) d_beta_dot_hat
/// for every a, b.
struct AngleRateExpansion {
    BodyCoefficients<double> value;            ///< at the query, exactly as evaluate() gives them
    BodyCoefficients<double> d_alpha_dot_hat;  ///< dC / d alpha_dot_hat (the alphadot columns)
    BodyCoefficients<double> d_beta_dot_hat;   ///< dC / d beta_dot_hat (the betadot columns)
};

class AeroDatabase {
public:
    /// Validates: exactly one static table; at most one control table per control, containing
    /// that control's axis; at most one dynamic table; axes strictly increasing and not repeated;
    /// values sized and finite; column names valid for `axes`. InputError otherwise.
    AeroDatabase(DatabaseInfo info, ForceAxes force_axes, Extrapolation extrapolation,
                 std::vector<Table> tables);
    AeroDatabase(const AeroDatabase& other);
    AeroDatabase& operator=(const AeroDatabase& other);
    AeroDatabase(AeroDatabase&&) noexcept;
    AeroDatabase& operator=(AeroDatabase&&) noexcept;
    ~AeroDatabase();

    [[nodiscard]] const DatabaseInfo& info() const;
    [[nodiscard]] ForceAxes force_axes() const;
    [[nodiscard]] Extrapolation extrapolation() const;
    [[nodiscard]] const std::vector<Table>& tables() const;

    /// Body-axis coefficients at `q` (forces converted from wind axes if the tables are wind).
    template <class T>
    [[nodiscard]] BodyCoefficients<T> evaluate(const AeroQuery<T>& q, Interpolation method) const;

    /// Plain-double evaluation that also returns the partial derivatives with respect to
    /// alpha_dot_hat and beta_dot_hat, from the same table pass (one evaluation in the counters;
    /// out-of-table queries counted as by evaluate). Lets the equations of motion solve for the
    /// angle rates without evaluating the tables again.
    [[nodiscard]] AngleRateExpansion evaluate_with_angle_rates(const AeroQuery<double>& q,
                                                               Interpolation method) const;

    /// Internal, for compiled kernels of other modules (flightdyn's fused right-hand side): the
    /// multilinear plan as plain data (manta/aero/detail/fast_plan.hpp), valid while the
    /// database lives, or nullptr if the tables exceed its fixed limits. A kernel that uses it
    /// must take every out-of-table query to `evaluate` (which counts it) and report each
    /// evaluation it completes itself with `count_evaluation`.
    [[nodiscard]] const detail::FastPlan* fast_plan() const noexcept;
    /// Internal: count one evaluation done from `fast_plan()` (thread-safe).
    void count_evaluation() const noexcept;

    /// Counters of out-of-table queries since construction or the last reset (thread-safe).
    [[nodiscard]] OutOfRangeReport out_of_range() const;
    void reset_out_of_range() const;

    /// Native file format: text, exact round trip (to_text(from_text(s)) reproduces every double).
    [[nodiscard]] std::string to_text() const;
    [[nodiscard]] static AeroDatabase from_text(std::string_view text, const std::string& source);
    void write(const std::filesystem::path& file) const;  ///< atomic
    [[nodiscard]] static AeroDatabase read(const std::filesystem::path& file);

    /// Tabulate a linear derivative model on `grids` (wind-axis forces). The result reproduces
    /// the linear terms exactly under multilinear interpolation.
    [[nodiscard]] static AeroDatabase from_derivatives(const LinearDerivatives& d,
                                                       const DerivativeGrids& grids,
                                                       DatabaseInfo info);

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace manta::aero

#include "manta/aero/detail/database_eval.hpp"
