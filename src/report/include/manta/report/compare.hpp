#pragma once
/// @file compare.hpp
/// Two table sets side by side (`manta report --compare-tables`, docs/report.md#comparison):
/// each set evaluated between its breakpoints through the aero database (multilinear
/// interpolation of the entries of tables.csv and dynamic.csv; the Kriging models are not
/// refitted), and the summary numbers of the comparison (lift and pitching-moment slopes, the
/// coefficients at zero incidence, the control powers).

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manta/report/run_data.hpp"

namespace manta::aero {
class AeroDatabase;
}

namespace manta::report {

/// Breakpoints of one table [rad for angles], sorted and distinct.
struct TableGrid {
    std::vector<double> alpha, mach, beta, delta;
};

/// The tables of one `manta tables` directory as aero databases (multilinear interpolation,
/// wind-axis forces), evaluated anywhere inside their breakpoints.
class TablesInterpolant {
public:
    /// InputError naming tables.csv (or dynamic.csv) and the table when its entries are not one
    /// row per point of a full grid over alpha, Mach, sideslip (and the deflection).
    explicit TablesInterpolant(const TablesData& t);

    /// Breakpoints of table `name` ("static" or a control), nullptr if there is none.
    [[nodiscard]] const TableGrid* grid(const std::string& name) const;
    /// True if (alpha, mach, beta, delta) lies within the breakpoints of table `name` (to 1e-9
    /// relative; an axis of one breakpoint only at that value). False for an absent table.
    [[nodiscard]] bool inside(const std::string& name, double alpha, double mach, double beta,
                              double delta = 0.0) const;
    /// Coefficients CL CD CY Cl Cm Cn of table `name` (control tables: the increments at
    /// deflection `delta` [rad]) at the point, interpolated multilinearly between the entries.
    [[nodiscard]] std::array<double, 6> value(const std::string& name, double alpha, double mach,
                                              double beta, double delta = 0.0) const;
    /// The Kriging standard deviations of the entries, interpolated the same way.
    [[nodiscard]] std::array<double, 6> sigma(const std::string& name, double alpha, double mach,
                                              double beta, double delta = 0.0) const;

    /// Breakpoints of the dynamic table (alpha, mach), nullptr if there is none.
    [[nodiscard]] const TableGrid* dynamic_grid() const;
    /// Columns of the dynamic table (`<coef>_<rate>`, rate p, q, r, alphadot or betadot).
    [[nodiscard]] const std::vector<std::string>& dynamic_columns() const { return dyn_columns_; }
    /// A dynamic derivative at (alpha, mach), interpolated; nullopt if the column is absent.
    [[nodiscard]] std::optional<double> dynamic(const std::string& column, double alpha,
                                                double mach) const;

private:
    struct Part {
        TableGrid grid;
        std::shared_ptr<const aero::AeroDatabase> values, sigma;
        std::string control;  ///< "" for the static table
    };
    [[nodiscard]] const Part& part(const std::string& name) const;
    std::map<std::string, Part> parts_;
    std::optional<Part> dynamic_;
    std::vector<std::string> dyn_columns_;
};

/// The quantities of the per-Mach summary, in order: CL_alpha and Cm_alpha [1/rad] (least
/// squares over the fit range), CL, Cm and CD at alpha = 0.
inline constexpr std::array<const char*, 5> summary_names{"CL_alpha", "Cm_alpha", "CL_0", "Cm_0",
                                                          "CD_0"};

/// The summary of both tables at one Mach number of the main table (NaN where a table does not
/// reach the point).
struct MachSummary {
    double mach = 0.0;
    double beta = 0.0;                      ///< sideslip [rad]: the main table's nearest to 0
    std::vector<double> fit_alpha;          ///< alpha points of the slope fit [rad]
    std::array<double, 5> main{}, other{};  ///< summary_names
    [[nodiscard]] double ratio(std::size_t k) const { return other[k] / main[k]; }
};

/// The control power dC/d(delta) [1/rad] of one control at alpha = 0, the main table's middle
/// Mach number and beta = 0, both tables: least squares of the increments over the deflection
/// points.
struct ControlSummary {
    std::string control;
    double mach = 0.0;
    std::vector<double> fit_delta;          ///< deflection points [rad]
    std::array<double, 6> main{}, other{};  ///< CL CD CY Cl Cm Cn
    [[nodiscard]] double ratio(std::size_t k) const { return other[k] / main[k]; }
};

/// How the second table is drawn at one slice (Mach and sideslip) of the main table.
enum class SliceMode {
    exact,         ///< it has that Mach number and sideslip: its own entries and samples
    interpolated,  ///< inside its breakpoints: interpolated at the main table's alphas
    outside,       ///< outside its Mach or sideslip range: not drawn
};

/// The comparison of two table sets.
struct Comparison {
    std::string main_label, other_label;
    std::filesystem::path main_dir, other_dir;
    std::vector<MachSummary> machs;
    std::vector<ControlSummary> controls;
    /// Every static slice of the main table: (Mach, beta [rad]) and how the other table is drawn.
    std::vector<std::pair<std::array<double, 2>, SliceMode>> slices;
    std::vector<std::string> controls_only_main;  ///< controls the other table lacks
    std::vector<std::string> dynamic_columns;     ///< dynamic derivatives of both tables
    /// As JSON (the `comparison` object of --json): labels, directories, the summary numbers
    /// (null where not available), the slices interpolated and outside.
    [[nodiscard]] nlohmann::json to_json() const;
};

[[nodiscard]] const char* to_string(SliceMode m);

/// How the table set of `oi` is drawn at the slice (mach, beta [rad]) of the main table.
[[nodiscard]] SliceMode slice_mode(const TablesInterpolant& oi, double mach, double beta);

/// The comparison numbers of `main` (labelled main.label) against `other`.
[[nodiscard]] Comparison compare_tables(const TablesData& main, const TablesInterpolant& mi,
                                        const TablesData& other, const TablesInterpolant& oi);

/// Least-squares slope of y against x (NaN with fewer than two distinct x).
[[nodiscard]] double least_squares_slope(const std::vector<double>& x,
                                         const std::vector<double>& y);

/// The points of a fit window: those of `points` inside [lo, hi] and inside `common` (the
/// range both tables cover); when fewer than `min_points` lie there, the `min_points` of
/// `points` inside `common` nearest the window's centre.
[[nodiscard]] std::vector<double> fit_points(const std::vector<double>& points, double lo,
                                             double hi, std::array<double, 2> common,
                                             std::size_t min_points);

/// Read the `--compare-tables` directory: a `manta tables --out` directory with a static table.
/// IoError if it is not a directory or holds no tables.csv; InputError if it has no static
/// table or is malformed.
[[nodiscard]] TablesData read_compare_tables(const std::filesystem::path& dir);

/// InputError unless both table sets have the same coefficient columns in tables.csv.
void check_same_coefficients(const TablesData& main, const TablesData& other);

}  // namespace manta::report
