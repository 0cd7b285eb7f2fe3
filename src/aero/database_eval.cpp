/// @file database_eval.cpp
/// Evaluation kernels of AeroDatabase: the plain-double multilinear kernels (specialised by the
/// table's shape), the stencil sums behind C1 in double and behind first-order AD scalars (values
/// with their partial derivatives), the wind-to-body rotation, and the counters.

#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "manta/aero/database.hpp"
#include "manta/core/fastmath.hpp"

namespace manta::aero::detail {

// ---------------------------------------------------------------- counters

namespace {

/// Which of the EvaluationCounter::n_owned shard indices are held by a live thread. This is the
/// one piece of process-wide mutable state of the module: it lets a thread own a shard in every
/// database and count with plain stores instead of a locked read-modify-write.
std::atomic<std::uint64_t> slots_in_use{0};
static_assert(EvaluationCounter::n_owned == 64, "one bit per shard");

struct SlotLease {
    int slot = EvaluationCounter::n_owned;
    SlotLease() noexcept {
        std::uint64_t used = slots_in_use.load(std::memory_order_relaxed);
        while (used != ~std::uint64_t{0}) {
            const int free = std::countr_one(used);
            if (slots_in_use.compare_exchange_weak(used, used | (std::uint64_t{1} << free),
                                                   std::memory_order_acquire,
                                                   std::memory_order_relaxed)) {
                slot = free;
                break;
            }
        }
    }
    ~SlotLease() {
        if (slot < EvaluationCounter::n_owned) {
            slots_in_use.fetch_and(~(std::uint64_t{1} << slot), std::memory_order_release);
        }
    }
    SlotLease(const SlotLease&) = delete;
    SlotLease& operator=(const SlotLease&) = delete;
};

void atomic_min(std::atomic<double>& a, double x) noexcept {
    double cur = a.load(std::memory_order_relaxed);
    while (x < cur && !a.compare_exchange_weak(cur, x, std::memory_order_relaxed)) {
    }
}

void atomic_max(std::atomic<double>& a, double x) noexcept {
    double cur = a.load(std::memory_order_relaxed);
    while (x > cur && !a.compare_exchange_weak(cur, x, std::memory_order_relaxed)) {
    }
}

}  // namespace

int thread_slot() noexcept {
    thread_local const SlotLease lease;
    return lease.slot;
}

void record_out_of_range(const AeroDatabase::Impl& impl, int g, double x, bool above) noexcept {
    for (const int k : impl.plan.grids[static_cast<std::size_t>(g)].counters) {
        RangeCounter& r = impl.range[static_cast<std::size_t>(k)];
        if (above) {
            r.above.fetch_add(1, std::memory_order_relaxed);
            atomic_max(r.highest, x);
        } else {
            r.below.fetch_add(1, std::memory_order_relaxed);
            atomic_min(r.lowest, x);
        }
    }
}

// ---------------------------------------------------------------- multilinear, double

namespace {

/// Out-of-range (or NaN) coordinate: count it and apply the extrapolation policy.
[[gnu::noinline]] Loc locate_outside(const AeroDatabase::Impl& impl, int g, double xv) {
    const GridPlan& gp = impl.plan.grids[static_cast<std::size_t>(g)];
    const Cell c = locate(gp, xv);
    if (c.where != Where::inside) record_out_of_range(impl, g, xv, c.where == Where::above);
    const auto i = static_cast<std::size_t>(c.i);
    if (c.where == Where::inside || impl.plan.linear) return {i, (xv - gp.x[i]) * gp.inv_w[i]};
    return {i, c.where == Where::below ? 0.0 : 1.0};
}

/// Multilinear sum over the 2^D cell corners, D active axes and NC columns known at compile
/// time: every loop unrolls, the column sums stay in registers, and Eigen's fixed-size arrays
/// turn each corner's row into SIMD pairs (rows are stored padded to an even length). Bit k of a
/// corner index selects t_k (else 1 - t_k) along active axis k. `Rated` tables multiply each
/// column by its factor (and give the angle-rate columns to `angle_rate_out` when asked); the
/// others add straight into their slots.
template <int D, int NC, bool Rated>
void multilinear_kernel(const TablePlan& tp, const Loc* loc, const double* factors, double* out,
                        [[maybe_unused]] double* angle_rate_out) {
    constexpr int n_corners = 1 << D;
    constexpr int NS = NC + NC % 2;
    using Row = Eigen::Array<double, NS, 1>;
    double w[n_corners];
    std::size_t offset[n_corners];
    w[0] = 1.0;
    offset[0] = 0;
    std::size_t base = 0;
#pragma GCC unroll 8
    for (int k = 0; k < D; ++k) {
        const Loc& l = loc[tp.grid[static_cast<std::size_t>(k)]];
        const std::size_t stride = tp.stride[static_cast<std::size_t>(k)];
        base += l.i * stride;
        const int half = 1 << k;
#pragma GCC unroll 64
        for (int c = 0; c < half; ++c) {
            w[c + half] = w[c] * l.t;
            w[c] = w[c] - w[c + half];  // w (1 - t); exactly w or 0 when t is 0 or 1
            offset[c + half] = offset[c] + stride;
        }
    }
    const double* v = tp.values.data() + base;
    // Independent partial sums break the chain of dependent additions, whose latency rather
    // than the arithmetic would bound the loop.
    constexpr int A = n_corners < 2 ? n_corners : 2;
    Row acc[A];
#pragma GCC unroll 2
    for (int a = 0; a < A; ++a) acc[a].setZero();
#pragma GCC unroll 64
    for (int c = 0; c < n_corners; ++c) acc[c % A] += w[c] * Eigen::Map<const Row>(v + offset[c]);
    if constexpr (A > 1) acc[0] += acc[1];
    if constexpr (!Rated && NC == n_slots) {
        // Six distinct coefficient columns sorted into slot order: the slots themselves.
        Eigen::Map<Eigen::Array<double, n_slots, 1>>(out) += acc[0];
        return;
    }
#pragma GCC unroll 16
    for (int j = 0; j < NC; ++j) {
        const auto k = static_cast<std::size_t>(j);
        if constexpr (Rated) {
            out[tp.slot[k]] += acc[0][j] * factors[tp.factor[k]];
        } else {
            out[tp.slot[k]] += acc[0][j];
        }
    }
    if constexpr (Rated) {
        if (angle_rate_out != nullptr) {
#pragma GCC unroll 16
            for (int j = 0; j < NC; ++j) {
                const auto k = static_cast<std::size_t>(j);
                const int r = tp.factor[k] - first_angle_rate;
                if (r >= 0) angle_rate_out[r * n_slots + tp.slot[k]] += acc[0][j];
            }
        }
    }
}

/// Any shape: the same sum with run-time loops.
void multilinear_any(const TablePlan& tp, const Loc* loc, const double* factors, double* out,
                     double* angle_rate_out) {
    const int d = tp.n_active;
    const int n_corners = 1 << d;
    std::array<double, std::size_t{1} << n_axes> w;
    std::array<std::size_t, std::size_t{1} << n_axes> offset;
    w[0] = 1.0;
    offset[0] = 0;
    std::size_t base = 0;
    for (int k = 0; k < d; ++k) {
        const Loc& l = loc[tp.grid[static_cast<std::size_t>(k)]];
        const std::size_t stride = tp.stride[static_cast<std::size_t>(k)];
        base += l.i * stride;
        const auto half = std::size_t{1} << k;
        for (std::size_t c = 0; c < half; ++c) {
            w[c + half] = w[c] * l.t;
            w[c] = w[c] - w[c + half];
            offset[c + half] = offset[c] + stride;
        }
    }
    const double* v = tp.values.data() + base;
    std::array<double, max_columns> acc{};
    const auto nc = static_cast<std::size_t>(tp.n_columns);
    for (std::size_t c = 0; c < static_cast<std::size_t>(n_corners); ++c) {
        const double* p = v + offset[c];
        for (std::size_t j = 0; j < nc; ++j) acc[j] += w[c] * p[j];
    }
    for (std::size_t j = 0; j < nc; ++j) out[tp.slot[j]] += acc[j] * factors[tp.factor[j]];
    if (angle_rate_out != nullptr && tp.rated) {
        for (std::size_t j = 0; j < nc; ++j) {
            const int r = tp.factor[j] - first_angle_rate;
            if (r >= 0 && tp.factor[j] != unit_factor) {
                angle_rate_out[r * n_slots + tp.slot[j]] += acc[j];
            }
        }
    }
}

// Specialised shapes: static and control tables (unit factors) up to four active axes and six
// columns; rated (dynamic) tables up to three active axes and twelve columns.
constexpr int max_unit_axes = 4;
constexpr int max_unit_columns = n_slots;
constexpr int max_rated_axes = 3;
constexpr int max_rated_columns = 12;

template <int D, bool Rated, int... NC>
constexpr auto kernel_row(std::integer_sequence<int, NC...>) {
    return std::array<MultilinearKernel, sizeof...(NC)>{&multilinear_kernel<D, NC + 1, Rated>...};
}

template <bool Rated, int Columns, int... D>
constexpr auto kernel_table(std::integer_sequence<int, D...>) {
    return std::array<std::array<MultilinearKernel, Columns>, sizeof...(D)>{
        kernel_row<D, Rated>(std::make_integer_sequence<int, Columns>{})...};
}

constexpr auto unit_kernels =
    kernel_table<false, max_unit_columns>(std::make_integer_sequence<int, max_unit_axes + 1>{});
constexpr auto rated_kernels =
    kernel_table<true, max_rated_columns>(std::make_integer_sequence<int, max_rated_axes + 1>{});

/// The six slots by the specialised kernels; with `angle_rate_out` (n_angle_rates * n_slots
/// doubles, zeroed by the caller) also their partial derivatives with respect to the angle rates.
std::array<double, n_slots> multilinear_slots(const AeroDatabase::Impl& impl,
                                              const std::array<double, n_inputs>& x,
                                              double* angle_rate_out) {
    const Plan& plan = impl.plan;
    std::array<Loc, max_grids> loc;
    const std::size_t n_grids = plan.grids.size();
    for (std::size_t g = 0; g < n_grids; ++g) {
        const GridPlan& gp = plan.grids[g];
        const double xv = x[static_cast<std::size_t>(gp.axis)];
        if (xv >= gp.lo && xv <= gp.hi) [[likely]] {
            const auto i = static_cast<std::size_t>(locate_inside(gp, xv));
            loc[g] = {i, (xv - gp.xp[i]) * gp.iwp[i]};
        } else {
            loc[g] = locate_outside(impl, static_cast<int>(g), xv);
        }
    }
    // Column factors: the five rates, then 1 for static and control columns.
    const std::array<double, n_rates + 1> factors = {x[n_axes],     x[n_axes + 1], x[n_axes + 2],
                                                     x[n_axes + 3], x[n_axes + 4], 1.0};
    std::array<double, n_slots> out{};
    for (const TablePlan& tp : plan.tables)
        tp.multilinear(tp, loc.data(), factors.data(), out.data(), angle_rate_out);
    return out;
}

}  // namespace

MultilinearKernel select_multilinear_kernel(const TablePlan& tp) {
    const auto d = static_cast<std::size_t>(tp.n_active);
    const auto nc = static_cast<std::size_t>(tp.n_columns);
    if (nc < 1) return &multilinear_any;
    if (!tp.rated && d <= max_unit_axes && nc <= max_unit_columns) return unit_kernels[d][nc - 1];
    if (tp.rated && d <= max_rated_axes && nc <= max_rated_columns) return rated_kernels[d][nc - 1];
    return &multilinear_any;
}

// ---------------------------------------------------------------- stencil sums (C1; gradients)

namespace {

/// Forward-mode dual with one derivative: runs `make_stencil` to get each 1-D weight together
/// with its derivative with respect to the query coordinate.
struct Dual1 {
    double v = 0.0;
    double d = 0.0;
    Dual1() = default;
    explicit Dual1(double value, double derivative = 0.0) : v(value), d(derivative) {}
    friend Dual1 operator+(const Dual1& a, const Dual1& b) { return Dual1(a.v + b.v, a.d + b.d); }
    friend Dual1 operator-(const Dual1& a, const Dual1& b) { return Dual1(a.v - b.v, a.d - b.d); }
    friend Dual1 operator*(const Dual1& a, const Dual1& b) {
        return Dual1(a.v * b.v, a.d * b.v + a.v * b.d);
    }
    friend Dual1 operator-(const Dual1& a, double b) { return Dual1(a.v - b, a.d); }
    friend Dual1 operator*(const Dual1& a, double b) { return Dual1(a.v * b, a.d * b); }
};

/// 1-D weights and, if needed, their derivatives dw/dx along one grid. Deliberately without
/// initialisers: an evaluation keeps an array of them for the largest possible number of grids
/// and writes (then reads) only the entries of its grids, up to `count`.
struct WeightRow {
    int start;
    int count;
    std::array<double, max_stencil> w;
    std::array<double, max_stencil> dw;
};

/// Sum over the tensor stencil of one table with D active axes: acc = sum W v and, with `Grad`,
/// grad[a] = sum dW/dx_a v, where W is the product of the 1-D weights and v a stored row. The
/// depth is a compile-time recursion, so the loops nest without index bookkeeping; NS, the stored
/// row length, is fixed (Eigen fixed-size arrays: SIMD pairs, sums kept in registers) for the
/// common widths and run-time (NS = 0) otherwise.
template <bool Grad, int D, int NS>
struct StencilSum {
    // Run-time length with a fixed maximum: storage on the stack, never on the heap.
    using Row =
        std::conditional_t<NS == 0,
                           Eigen::Array<double, Eigen::Dynamic, 1, Eigen::ColMajor, max_columns, 1>,
                           Eigen::Array<double, NS, 1>>;
    using ConstRowMap = Eigen::Map<const Eigen::Array<double, NS == 0 ? Eigen::Dynamic : NS, 1>>;
    using Weights = std::array<double, D == 0 ? 1 : D>;

    const TablePlan& tp;
    std::array<const WeightRow*, D == 0 ? 1 : D> row{};
    Row acc;
    std::array<Row, (Grad && D > 0) ? D : 1> grad;

    StencilSum(const TablePlan& table, const WeightRow* rows) : tp(table) {
        const auto ns = static_cast<Eigen::Index>(tp.n_stored);
        acc.setZero(ns);
        for (auto& g : grad) g.setZero(ns);
        for (std::size_t a = 0; a < static_cast<std::size_t>(D); ++a) row[a] = &rows[tp.grid[a]];
        level<0>(1.0, Weights{}, 0);
    }

    template <int A>
    void level(double W, const Weights& dW, std::size_t offset) {
        if constexpr (A == D) {
            const ConstRowMap v(tp.values.data() + offset, tp.n_stored);
            acc += W * v;
            if constexpr (Grad) {
                for (std::size_t a = 0; a < static_cast<std::size_t>(D); ++a) grad[a] += dW[a] * v;
            }
        } else {
            const WeightRow& r = *row[A];
            const std::size_t stride = tp.stride[A];
            for (int l = 0; l < r.count; ++l) {
                const auto k = static_cast<std::size_t>(l);
                Weights next{};
                if constexpr (Grad) {
                    for (std::size_t a = 0; a < static_cast<std::size_t>(A); ++a)
                        next[a] = dW[a] * r.w[k];
                    next[A] = W * r.dw[k];
                }
                level<A + 1>(W * r.w[k], next,
                             offset + static_cast<std::size_t>(r.start + l) * stride);
            }
        }
    }
};

/// Adds one table's columns, each times its factor, into `value` (and `gradient`).
template <bool Grad, int D, int NS>
void add_stencil_table(const TablePlan& tp, const WeightRow* rows,
                       const std::array<double, n_inputs>& x, const Plan& plan,
                       std::array<double, n_slots>& value,
                       std::array<std::array<double, n_inputs>, Grad ? n_slots : 0>& gradient) {
    const StencilSum<Grad, D, NS> sum(tp, rows);
    for (std::size_t c = 0; c < static_cast<std::size_t>(tp.n_columns); ++c) {
        const auto slot = static_cast<std::size_t>(tp.slot[c]);
        const int f = tp.factor[c];
        const double factor = f == unit_factor ? 1.0 : x[static_cast<std::size_t>(n_axes + f)];
        const auto ci = static_cast<Eigen::Index>(c);
        value[slot] += sum.acc[ci] * factor;
        if constexpr (Grad) {
            auto& gs = gradient[slot];
            for (std::size_t a = 0; a < static_cast<std::size_t>(D); ++a) {
                gs[static_cast<std::size_t>(
                    plan.grids[static_cast<std::size_t>(tp.grid[a])].axis)] +=
                    sum.grad[a][ci] * factor;
            }
            if (f != unit_factor) gs[static_cast<std::size_t>(n_axes + f)] += sum.acc[ci];
        }
    }
}

/// add_stencil_table for the table's (D, NS): fixed widths 2..12 up to four active axes.
template <bool Grad, int D>
void add_stencil_table_d(const TablePlan& tp, const WeightRow* rows,
                         const std::array<double, n_inputs>& x, const Plan& plan,
                         std::array<double, n_slots>& value,
                         std::array<std::array<double, n_inputs>, Grad ? n_slots : 0>& gradient) {
    if constexpr (D <= 4) {
        switch (tp.n_stored) {
            case 2:
                return add_stencil_table<Grad, D, 2>(tp, rows, x, plan, value, gradient);
            case 4:
                return add_stencil_table<Grad, D, 4>(tp, rows, x, plan, value, gradient);
            case 6:
                return add_stencil_table<Grad, D, 6>(tp, rows, x, plan, value, gradient);
            case 8:
                return add_stencil_table<Grad, D, 8>(tp, rows, x, plan, value, gradient);
            case 10:
                return add_stencil_table<Grad, D, 10>(tp, rows, x, plan, value, gradient);
            case 12:
                return add_stencil_table<Grad, D, 12>(tp, rows, x, plan, value, gradient);
            default:
                break;
        }
    }
    add_stencil_table<Grad, D, 0>(tp, rows, x, plan, value, gradient);
}

template <bool Grad>
struct SlotSums {
    std::array<double, n_slots> value{};
    /// d value / d input, when Grad.
    std::array<std::array<double, n_inputs>, Grad ? n_slots : 0> gradient{};
};

/// The six slots (database force axes) by explicit stencil sums: C1 in double, and values with
/// partial derivatives for the AD path (both interpolants).
template <bool Grad>
SlotSums<Grad> stencil_slots(const AeroDatabase::Impl& impl, const std::array<double, n_inputs>& x,
                             Interpolation method) {
    const Plan& plan = impl.plan;
    std::array<WeightRow, max_grids> rows;
    for (std::size_t g = 0; g < plan.grids.size(); ++g) {
        const GridPlan& gp = plan.grids[g];
        const double xv = x[static_cast<std::size_t>(gp.axis)];
        const Cell c = locate(gp, xv);
        if (c.where != Where::inside)
            record_out_of_range(impl, static_cast<int>(g), xv, c.where == Where::above);
        WeightRow& r = rows[g];
        if constexpr (Grad) {
            const auto st = make_stencil<Dual1>(gp, Dual1(xv, 1.0), c, method, plan.linear);
            r.start = st.start;
            r.count = st.count;
            for (std::size_t l = 0; l < static_cast<std::size_t>(st.count); ++l) {
                r.w[l] = st.w[l].v;
                r.dw[l] = st.w[l].d;
            }
        } else {
            const auto st = make_stencil<double>(gp, xv, c, method, plan.linear);
            r.start = st.start;
            r.count = st.count;
            r.w = st.w;
        }
    }
    SlotSums<Grad> out;
    for (const TablePlan& tp : plan.tables) {
        switch (tp.n_active) {
            case 0:
                add_stencil_table_d<Grad, 0>(tp, rows.data(), x, plan, out.value, out.gradient);
                break;
            case 1:
                add_stencil_table_d<Grad, 1>(tp, rows.data(), x, plan, out.value, out.gradient);
                break;
            case 2:
                add_stencil_table_d<Grad, 2>(tp, rows.data(), x, plan, out.value, out.gradient);
                break;
            case 3:
                add_stencil_table_d<Grad, 3>(tp, rows.data(), x, plan, out.value, out.gradient);
                break;
            case 4:
                add_stencil_table_d<Grad, 4>(tp, rows.data(), x, plan, out.value, out.gradient);
                break;
            case 5:
                add_stencil_table_d<Grad, 5>(tp, rows.data(), x, plan, out.value, out.gradient);
                break;
            default:
                add_stencil_table_d<Grad, 6>(tp, rows.data(), x, plan, out.value, out.gradient);
                break;
        }
    }
    return out;
}

}  // namespace

namespace {

/// d slot / d (alphadot, betadot): the angle-rate columns of the dynamic table, as
/// angle_rate_out of the multilinear kernels gives them.
using RatePartials = std::array<double, n_angle_rates * n_slots>;

/// The six slots at `q` (database force axes), counted as one evaluation; with `rates` also
/// their partial derivatives with respect to alphadot and betadot. C1 takes them from the
/// gradient sums, whose values are those of the plain sums (the same operations on the values).
std::array<double, n_slots> slots_double(const AeroDatabase::Impl& impl, const AeroQuery<double>& q,
                                         Interpolation method, RatePartials* rates) {
    impl.evaluations.add();
    const std::array<double, n_inputs> x = {q.alpha,   q.beta,          q.mach,        q.elevator,
                                            q.aileron, q.rudder,        q.p_hat,       q.q_hat,
                                            q.r_hat,   q.alpha_dot_hat, q.beta_dot_hat};
    if (method == Interpolation::multilinear) {
        if (rates == nullptr) return multilinear_slots(impl, x, nullptr);
        // Zeroed by Eigen's packet stores: `{}` becomes a `rep stos`, whose start-up is slow.
        Eigen::Map<Eigen::Array<double, n_angle_rates * n_slots, 1>>(rates->data()).setZero();
        return multilinear_slots(impl, x, rates->data());
    }
    if (rates == nullptr) return stencil_slots<false>(impl, x, method).value;
    const SlotSums<true> s = stencil_slots<true>(impl, x, method);
    for (std::size_t r = 0; r < n_angle_rates; ++r) {
        for (std::size_t k = 0; k < n_slots; ++k) {
            (*rates)[r * n_slots + k] = s.gradient[k][n_axes + first_angle_rate + r];
        }
    }
    return s.value;
}

/// Body-axis coefficients of six slots: body_from_wind (types.hpp) for wind-axis forces, with the
/// sine and cosine of the angles given. Also applies to slot derivatives, the rotation being
/// linear.
BodyCoefficients<double> body_of_slots(const double* s, bool wind, double sa, double ca, double sb,
                                       double cb) {
    BodyCoefficients<double> b;
    if (wind) {
        const double CL = s[0], CD = s[1], CY = s[2];
        b.CX = -CD * ca * cb - CY * ca * sb + CL * sa;
        b.CY = -CD * sb + CY * cb;
        b.CZ = -CD * sa * cb - CY * sa * sb - CL * ca;
    } else {
        b.CX = s[0];
        b.CY = s[1];
        b.CZ = s[2];
    }
    b.Cl = s[3];
    b.Cm = s[4];
    b.Cn = s[5];
    return b;
}

}  // namespace

BodyCoefficients<double> evaluate_double(const AeroDatabase::Impl& impl, const AeroQuery<double>& q,
                                         Interpolation method) {
    const std::array<double, n_slots> s = slots_double(impl, q, method, nullptr);
    double sa = 0.0, ca = 1.0, sb = 0.0, cb = 1.0;
    if (impl.plan.wind) {
        core::sin_cos(q.alpha, sa, ca);
        core::sin_cos(q.beta, sb, cb);
    }
    return body_of_slots(s.data(), impl.plan.wind, sa, ca, sb, cb);
}

// ---------------------------------------------------------------- jets (first-order AD)

std::array<Jet, n_slots> evaluate_jets(const AeroDatabase::Impl& impl,
                                       const std::array<double, n_inputs>& x,
                                       Interpolation method) {
    impl.evaluations.add();
    const SlotSums<true> s = stencil_slots<true>(impl, x, method);
    std::array<Jet, n_slots> out;
    for (std::size_t k = 0; k < n_slots; ++k) {
        out[k].v = s.value[k];
        out[k].d = s.gradient[k];
    }
    if (!impl.plan.wind) return out;
    // F_body = R(alpha, beta) (CL, CD, CY) with R from body_from_wind (types.hpp); the partials
    // add dR/dalpha and dR/dbeta times the wind-axis forces.
    double sa = 0.0, ca = 1.0, sb = 0.0, cb = 1.0;
    core::sin_cos(x[0], sa, ca);
    core::sin_cos(x[1], sb, cb);
    const double R[3][3] = {{sa, -ca * cb, -ca * sb}, {0.0, -sb, cb}, {-ca, -sa * cb, -sa * sb}};
    const double Ra[3][3] = {{ca, sa * cb, sa * sb}, {0.0, 0.0, 0.0}, {sa, -ca * cb, -ca * sb}};
    const double Rb[3][3] = {{0.0, ca * sb, -ca * cb}, {0.0, -cb, -sb}, {0.0, sa * sb, -sa * cb}};
    const double CL = s.value[0], CD = s.value[1], CY = s.value[2];
    // Values exactly as the double path computes them.
    out[0].v = -CD * ca * cb - CY * ca * sb + CL * sa;
    out[1].v = -CD * sb + CY * cb;
    out[2].v = -CD * sa * cb - CY * sa * sb - CL * ca;
    for (std::size_t r = 0; r < 3; ++r) {
        for (std::size_t k = 0; k < n_inputs; ++k) {
            out[r].d[k] = R[r][0] * s.gradient[0][k] + R[r][1] * s.gradient[1][k] +
                          R[r][2] * s.gradient[2][k];
        }
        out[r].d[0] += Ra[r][0] * CL + Ra[r][1] * CD + Ra[r][2] * CY;
        out[r].d[1] += Rb[r][0] * CL + Rb[r][1] * CD + Rb[r][2] * CY;
    }
    return out;
}

}  // namespace manta::aero::detail

namespace manta::aero {

AngleRateExpansion AeroDatabase::evaluate_with_angle_rates(const AeroQuery<double>& q,
                                                           Interpolation method) const {
    const Impl& impl = *impl_;
    detail::RatePartials rates;
    const std::array<double, detail::n_slots> s = detail::slots_double(impl, q, method, &rates);
    double sa = 0.0, ca = 1.0, sb = 0.0, cb = 1.0;
    if (impl.plan.wind) {
        core::sin_cos(q.alpha, sa, ca);
        core::sin_cos(q.beta, sb, cb);
    }
    const bool wind = impl.plan.wind;
    AngleRateExpansion e;
    e.value = detail::body_of_slots(s.data(), wind, sa, ca, sb, cb);
    e.d_alpha_dot_hat = detail::body_of_slots(rates.data(), wind, sa, ca, sb, cb);
    e.d_beta_dot_hat = detail::body_of_slots(rates.data() + detail::n_slots, wind, sa, ca, sb, cb);
    return e;
}

}  // namespace manta::aero
