#pragma once
/// @file database_validate.hpp
/// Private to the aero module: validation of a set of tables, shared by the `AeroDatabase`
/// constructor (which throws the message as it is) and the file reader (which prefixes the
/// file:line of the offending YAML node).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aero/database.hpp"

namespace manta::aero::detail {

/// What a validation issue is about, so a reader can point at the right node.
enum class IssuePart {
    database,    ///< the set of tables as a whole (no single node)
    table,       ///< tables[table]
    table_name,  ///< tables[table].name
    axis,        ///< tables[table].axes[index]
    breakpoint,  ///< tables[table].axes[index].values[sub]
    column,      ///< tables[table].columns[index]
    values,      ///< tables[table].data (the whole block)
    value,  ///< value number `index` of tables[table] (row index / n_columns, column index % n)
};

/// First problem found in a set of tables; `message` is one line without location.
struct Issue {
    IssuePart part = IssuePart::database;
    int table = -1;
    int index = -1;
    int sub = -1;
    std::string message;
};

/// The first problem of one table on its own (axes, columns, and the values if `with_values`);
/// `index` is the table's position, carried into the issue.
[[nodiscard]] std::optional<Issue> validate_table(const Table& table, int index,
                                                  ForceAxes force_axes, bool with_values);

/// The first problem of `tables` under `force_axes`, or nothing if they form a valid database.
[[nodiscard]] std::optional<Issue> validate(const std::vector<Table>& tables, ForceAxes force_axes);

/// Valid static/control column names for `force_axes`, in slot order (F1 F2 F3 Cl Cm Cn).
[[nodiscard]] std::vector<std::string> coefficient_names(ForceAxes force_axes);
/// Rate names of dynamic columns, in the order p q r alphadot betadot.
[[nodiscard]] std::vector<std::string> rate_names();
/// Axis of `name` ("alpha", ...), if any.
[[nodiscard]] std::optional<Axis> axis_from_string(std::string_view name);
/// Table kind of `name` ("static", "control", "dynamic"), if any.
[[nodiscard]] std::optional<TableKind> kind_from_string(std::string_view name);

}  // namespace manta::aero::detail
