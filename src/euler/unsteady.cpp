/// @file unsteady.cpp
/// Dual time stepping on a fixed mesh (unsteady.hpp, docs/euler.md#dual-time-stepping).

#include "manta/euler/unsteady.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "manta/core/error.hpp"

namespace manta::euler {

namespace {

/// The inner iterations' settings: the steady ones with the time stepping's window, tolerance,
/// cap and drop, and no first-order start (it would spoil the time accuracy).
CaseSetup inner_setup(CaseSetup s, const UnsteadySettings& t) {
    t.validate();
    s.solver.coefficient_window = t.coefficient_window;
    s.solver.coefficient_tolerance = t.coefficient_tolerance;
    s.solver.max_iterations = t.max_inner;
    s.solver.residual_drop = t.inner_drop;
    s.solver.first_order_iterations = 0;
    return s;
}

}  // namespace

void UnsteadySettings::validate() const {
    auto need = [](bool ok, const char* key, double v, const char* expected) {
        if (!ok)
            throw InputError(
                fmt::format("time: {} = {} is out of range; expected {}", key, v, expected));
    };
    need(dt > 0 && std::isfinite(dt), "dt", dt, "a time step > 0");
    need(order == 1 || order == 2, "order", order, "1 or 2");
    need(max_inner >= 1, "max_inner", max_inner, "an integer >= 1");
    need(inner_drop > 0 && inner_drop <= 16, "inner_drop", inner_drop, "0 < orders <= 16");
    need(coefficient_window >= 2, "coefficient_window", coefficient_window, "an integer >= 2");
    need(coefficient_tolerance > 0, "coefficient_tolerance", coefficient_tolerance, "a number > 0");
}

UnsteadySolver::UnsteadySolver(const Domain& domain, const parallel::Communicator& comm,
                               const CaseSetup& setup, const UnsteadySettings& time)
    : time_settings_(time), step_(domain, comm, inner_setup(setup, time)) {
    const Index n_local = domain.mesh->n_nodes();
    U_.resize(5, n_local);
    const Vec5 U_inf = conservative(step_.free_stream_primitive(), setup.flow.gamma);
    for (Index i = 0; i < n_local; ++i) U_.col(i) = U_inf;
    D_.assign(static_cast<std::size_t>(n_local), 0.0);
    S_.setZero(5, n_local);
    cfl_ = setup.solver.cfl_initial;
}

void UnsteadySolver::set_state(const NodeStates& U) {
    const Index n_owned = step_.domain().n_owned;
    check_state(U, U_.cols(), n_owned, setup().flow.gamma);
    U_.leftCols(n_owned) = U.leftCols(n_owned);
    step_.exchange(U_);
    U_prev_.resize(5, 0);
}

TimeStepRecord UnsteadySolver::advance(const Monitor& inner) {
    const UnsteadySettings& t = time_settings_;
    const Domain& d = step_.domain();
    const Index n_local = U_.cols();
    const bool bdf2 = t.order == 2 && U_prev_.cols() == n_local;
    // R(U) + D U - S = 0: BDF2 D = 3 V / (2 dt), S = V (4 U^n - U^(n-1)) / (2 dt);
    // BDF1 D = V / dt, S = V U^n / dt.
    for (Index i = 0; i < n_local; ++i) {
        const double v = d.dual->dual_volumes[static_cast<std::size_t>(i)] / t.dt;
        if (bdf2) {
            D_[static_cast<std::size_t>(i)] = 1.5 * v;
            S_.col(i) = v * (2.0 * U_.col(i) - 0.5 * U_prev_.col(i));
        } else {
            D_[static_cast<std::size_t>(i)] = v;
            S_.col(i) = v * U_.col(i);
        }
    }
    NodeStates U_n = U_;

    // The inner iterations: a fresh iteration state (its peak, window and back-offs are this
    // step's) at the last step's CFL number, from U^n.
    IterationState it = step_.initial_state();
    it.cfl = std::min(cfl_, it.cfl_cap);
    it.cfl_good = it.cfl;
    step_.set_backoff_state(U_);
    step_.begin(it);
    const StopRule rule = [&t](const StepStatus& st) {
        StopDecision dec;
        if ((st.drop >= t.inner_drop && st.settled) || st.at_roundoff) {
            dec.stop = true;
            dec.converged = true;
        } else if (st.iteration >= t.max_inner) {
            dec.stop = true;
        }
        return dec;
    };
    const StepTerms terms{D_, &S_};
    TimeStepRecord rec;
    while (true) {
        const StepOutcome so = step_.step(U_, it, rule, terms);
        if (so.result == StepResult::backed_off) continue;
        rec.residual_drop = so.status.drop;
        if (so.result == StepResult::stopped) {
            rec.converged = so.decision.converged;
            break;
        }
        if (inner && !inner(so.record)) break;
    }
    rec.inner_iterations = it.iteration;
    rec.backoffs = it.backoffs;
    cfl_ = std::min(it.cfl, it.cfl_cap);
    U_prev_ = std::move(U_n);
    time_ += t.dt;
    rec.step = ++steps_;
    rec.time = time_;
    rec.forces = forces();
    return rec;
}

}  // namespace manta::euler
