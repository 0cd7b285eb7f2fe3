#pragma once
/// @file database_impl.hpp
/// Private: the compiled evaluation plan of an `AeroDatabase` and its counters. Included by
/// database_eval.hpp so the `evaluate` template can run with any scalar type; not part of the
/// public API (names and layout may change at any time).
///
/// The plan is built once at construction (database.cpp):
///  - every distinct (axis, breakpoints) pair with two or more breakpoints becomes a `GridPlan`,
///    so an axis shared by several tables (alpha and mach, typically) is located once per
///    evaluation; uniform grids are detected and located in O(1), the others by a branch-free
///    binary search;
///  - every table becomes a `TablePlan` over its *active* axes (two or more breakpoints; a
///    one-breakpoint axis is constant and contributes nothing), with precomputed strides, a
///    (slot, factor) pair per column (factor: the rate of a dynamic column, 1 otherwise) and a
///    multilinear kernel specialised for its number of active axes and columns.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/aero/detail/fast_plan.hpp"

namespace manta::aero::detail {

/// Coefficient slots of every evaluation: the database's three force columns (CL CD CY for wind
/// axes, CX CY CZ for body axes) then Cl Cm Cn.
inline constexpr int n_slots = 6;
/// Rates of the dynamic table, in the order p, q, r, alphadot, betadot.
inline constexpr int n_rates = 5;
/// Table axes; `Axis` values 0..5 index them.
inline constexpr int n_axes = 6;
/// Inputs of a query: the six axes (in `Axis` order) then the five rates.
inline constexpr int n_inputs = n_axes + n_rates;
/// Most columns a table can have: a dynamic table with every (coefficient, rate) pair.
inline constexpr int max_columns = n_slots * n_rates;
/// Largest C1 stencil along one axis.
inline constexpr int max_stencil = 4;

/// One distinct axis grid (two or more breakpoints) and its precomputed interpolation data.
/// The members read by every evaluation come first, within one cache line.
struct GridPlan {
    double lo = 0.0;              ///< first breakpoint
    double hi = 0.0;              ///< last breakpoint
    double inv_h = 0.0;           ///< (n - 1) / (hi - lo), for the uniform cell guess
    double last_d = 0.0;          ///< n - 2 as a double
    const double* xp = nullptr;   ///< x.data()
    const double* iwp = nullptr;  ///< inv_w.data()
    int last = 0;                 ///< last cell index, n - 2
    int axis = 0;                 ///< `Axis` as int: the query input this grid reads
    bool uniform = false;         ///< spacing uniform to h/4: O(1) cell search
    int n = 0;                    ///< breakpoints, >= 2
    std::vector<double> x;        ///< breakpoints
    std::vector<double> inv_w;    ///< 1 / (x[i+1] - x[i]) per cell
    // C1 (cubic Hermite with linear finite-difference slopes). For cell i the stencil is the
    // window of `c1_count` nodes starting at c1_start[i]; the Hermite slope terms are
    // h_i * m_i = sum_l c1_left[i][l] f[start + l] and h_i * m_{i+1} = sum_l c1_right[i][l] f[..].
    int c1_count = 0;
    std::vector<int> c1_start;
    std::vector<std::array<double, max_stencil>> c1_left;
    std::vector<std::array<double, max_stencil>> c1_right;
    std::array<double, max_stencil> slope_lo{};  ///< m_0 over the window of cell 0
    std::array<double, max_stencil> slope_hi{};  ///< m_{n-1} over the window of cell n-2
    std::vector<int> counters;  ///< out-of-range counters fed by this grid, one per (table, axis)
};

/// Cell index and local coordinate along one grid, for the plain-double multilinear kernels.
struct Loc {
    std::size_t i;
    double t;
};

/// The angle rates alphadot and betadot: rates first_angle_rate and first_angle_rate + 1.
inline constexpr int first_angle_rate = 3;
inline constexpr int n_angle_rates = 2;

struct TablePlan;
/// Multilinear kernel of one table shape: adds the table's columns, each times its factor
/// (factors: p q r alphadot betadot, then 1), into the six slots `out`. If `angle_rate_out` is
/// not null, the alphadot and betadot columns are also added, without their factor, into
/// angle_rate_out[(rate - first_angle_rate) * n_slots + slot]: the partial derivatives of the
/// slots with respect to the two angle rates (the sum is affine in them). Tables without such
/// columns leave `angle_rate_out` alone.
using MultilinearKernel = void (*)(const TablePlan& tp, const Loc* loc, const double* factors,
                                   double* out, double* angle_rate_out);

/// Index of the unit factor that static and control columns multiply (after the five rates).
inline constexpr int unit_factor = n_rates;

/// One table, compiled.
struct TablePlan {
    int n_active = 0;                          ///< axes with >= 2 breakpoints
    std::array<int, n_axes> grid{};            ///< GridPlan index per active axis
    std::array<std::size_t, n_axes> stride{};  ///< doubles between neighbours per active axis
    int n_columns = 0;   ///< the table's columns (static tables: sorted into slot order)
    int n_stored = 0;    ///< doubles per grid point: n_columns rounded up to even (SIMD pairs)
    bool rated = false;  ///< some column multiplies a rate (the dynamic table)
    std::array<std::int8_t, max_columns> slot{};    ///< coefficient slot of each column
    std::array<std::int8_t, max_columns> factor{};  ///< rate of each column, or unit_factor
    std::vector<double> values;                     ///< grid point major, n_stored per point
    MultilinearKernel multilinear = nullptr;        ///< specialised for this table's shape
};

/// The multilinear kernel for a table's shape (database_eval.cpp): compile-time specialised for
/// up to four active axes and twelve stored columns, a run-time loop otherwise.
[[nodiscard]] MultilinearKernel select_multilinear_kernel(const TablePlan& tp);

/// Everything `evaluate` needs.
struct Plan {
    bool wind = true;     ///< force slots are CL CD CY (else CX CY CZ)
    bool linear = false;  ///< linear extrapolation (else clamp)
    std::vector<GridPlan> grids;
    std::vector<TablePlan> tables;  ///< static and control tables first, the dynamic one last
};

/// Per (table, axis) out-of-range tally. Updated only on the (rare) out-of-range path.
struct RangeCounter {
    std::atomic<std::uint64_t> below{0};
    std::atomic<std::uint64_t> above{0};
    std::atomic<double> lowest{0.0};
    std::atomic<double> highest{0.0};
};

/// Index in [0, EvaluationCounter::n_owned) owned by the calling thread while it lives, or
/// n_owned when every index is taken (database_eval.cpp).
[[nodiscard]] int thread_slot() noexcept;

/// Evaluation count, sharded so that concurrent evaluations neither contend for one cache line
/// nor pay a locked read-modify-write: a thread that owns a shard increments it with a plain
/// (relaxed atomic) load and store; threads beyond `n_owned` share one fetch_add shard.
struct EvaluationCounter {
    static constexpr int n_owned = 64;
    struct alignas(64) Shard {
        std::atomic<std::uint64_t> n{0};
    };
    std::array<Shard, n_owned + 1> shards;

    void add() noexcept {
        const int s = thread_slot();
        auto& c = shards[static_cast<std::size_t>(s)].n;
        if (s < n_owned) {
            c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
        } else {
            c.fetch_add(1, std::memory_order_relaxed);
        }
    }
    [[nodiscard]] std::uint64_t total() const noexcept {
        std::uint64_t t = 0;
        for (const auto& s : shards) t += s.n.load(std::memory_order_relaxed);
        return t;
    }
    void reset() noexcept {
        for (auto& s : shards) s.n.store(0, std::memory_order_relaxed);
    }
};

}  // namespace manta::aero::detail

namespace manta::aero {

/// Private state of an `AeroDatabase`: the tables as given, the compiled plan and the counters.
struct AeroDatabase::Impl {
    DatabaseInfo info;
    ForceAxes force_axes = ForceAxes::wind;
    Extrapolation extrapolation = Extrapolation::clamp;
    std::vector<Table> tables;
    detail::Plan plan;
    /// (table, axis) of each out-of-range counter, in table then axis order.
    std::vector<std::pair<int, int>> counter_owner;
    std::unique_ptr<detail::RangeCounter[]> range;
    mutable detail::EvaluationCounter evaluations;
    /// The multilinear plan as plain data, pointing into `plan` (valid when has_fast_plan).
    detail::FastPlan fast{};
    bool has_fast_plan = false;
};

namespace detail {
/// Count one out-of-table coordinate `x` on grid `g` (below its first breakpoint unless `above`)
/// in every (table, axis) counter fed by that grid. Thread-safe; not inlined (rare path).
void record_out_of_range(const AeroDatabase::Impl& impl, int g, double x, bool above) noexcept;
}  // namespace detail

}  // namespace manta::aero
