#pragma once
/// @file fast_plan.hpp
/// Private: the multilinear evaluation plan of an `AeroDatabase` as plain data (fixed arrays and
/// raw pointers into the database's own storage, no inline functions), for compiled kernels
/// outside this module that are built for several instruction sets (flightdyn's fused
/// right-hand side, src/flightdyn/fast_rhs_impl.inc). Such a unit may include this header and
/// nothing that defines inline code, so no function compiled for one instruction set can be
/// picked by the linker for callers of another. Not part of the public API.
///
/// Obtained from `AeroDatabase::fast_plan()`; valid as long as the database lives. The rows are
/// the compiled tables' own (no copy): a kernel sums a table's corner rows, then adds each column
/// into an accumulator of six slots per factor (`FastTable::dest`). Rows widened to whole slot
/// groups would save that scatter but take up to three times the memory, and the evaluation is
/// bound by cache misses more than by arithmetic.

#include <cstddef>
#include <cstdint>

namespace manta::aero::detail {

/// Limits of the plain-data plan (equal to those of database_impl.hpp, checked there).
inline constexpr int fast_n_axes = 6;
inline constexpr int fast_max_grids = 30;
inline constexpr int fast_max_tables = 5;
/// Coefficient slots: the database's three force columns (CL CD CY or CX CY CZ), Cl Cm Cn.
inline constexpr int fast_n_slots = 6;
/// Rates of the dynamic table: p q r alphadot betadot (codes 0..4).
inline constexpr int fast_n_rates = 5;
inline constexpr int fast_first_angle_rate = 3;

/// One axis grid: breakpoints x[0..n-1], n >= 2.
struct FastGrid {
    double lo;            ///< x[0]
    double hi;            ///< x[n-1]
    double inv_h;         ///< (n - 1) / (hi - lo)
    double last_d;        ///< n - 2 as a double
    const double* x;      ///< breakpoints
    const double* inv_w;  ///< 1 / (x[i+1] - x[i])
    int last;             ///< n - 2
    int axis;             ///< query input: `Axis` as int
    /// 1: nodes within h/4 of uniform (O(1) guess, then a one-cell correction, as
    /// aero::detail::locate_inside); 2: uniform to 1e-14 h, so the cell is floor((x - lo) / h)
    /// and the local coordinate (x - lo) / h - i, equal to the general formula to rounding;
    /// 0: binary search.
    int uniform;
};

/// Most corners whose offsets a FastTable keeps (four active axes).
inline constexpr int fast_max_corners = 16;
/// Most doubles per stored row a FastTable maps (`dest`).
inline constexpr int fast_max_stored = 32;
/// Length of the accumulator `dest` indexes: a group of six slots for the unit factor, one per
/// rate (p q r alphadot betadot), then room for the padding columns.
inline constexpr int fast_accumulator = 6 * (fast_n_rates + 1) + 4;
/// Where the padding column of a row (odd column counts) goes in the accumulator.
inline constexpr int fast_padding_slot = 6 * (fast_n_rates + 1);

/// One table over its active axes (two or more breakpoints), rows as the compiled TablePlan
/// stores them (grid point major, the columns padded to an even count).
struct FastTable {
    const double* values;             ///< the compiled table's rows (TablePlan::values)
    std::size_t stride[fast_n_axes];  ///< doubles between neighbours per active axis
    /// Offset of each cell corner from the cell's first corner, corner bit k selecting the next
    /// node along active axis k (n_active <= 4).
    std::size_t corner_offset[fast_max_corners];
    int grid[fast_n_axes];  ///< FastGrid index per active axis
    int n_active;           ///< 0..6
    int n_stored;           ///< doubles per row (even)
    /// Nonzero for a static or control table whose six columns are the six slots in order: its
    /// sum adds straight into accumulator[0..6).
    int direct;
    /// Accumulator index of each stored column: 6 g + slot, g = 0 for a unit factor and 1 + rate
    /// for a rated column; fast_padding_slot for the padding.
    std::int8_t dest[fast_max_stored];
};

/// The whole database for the multilinear interpolant.
struct FastPlan {
    int wind;      ///< nonzero: force slots are CL CD CY (else CX CY CZ)
    int n_grids;   ///< distinct grids
    int n_tables;  ///< static and control tables first, the dynamic one last
    /// Nonzero when every table has at least two active axes and the same first two grids
    /// (alpha and Mach, typically): their four corner weights are then shared.
    int shared_pair;
    FastGrid grids[fast_max_grids];
    FastTable tables[fast_max_tables];
};

}  // namespace manta::aero::detail
