/// @file unsteady.cpp
/// Dual time stepping on fixed and moving meshes (unsteady.hpp, docs/euler.md#dual-time-stepping).

#include "manta/euler/unsteady.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <span>

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
    if (t.cfl_max > 0.0) s.solver.cfl_max = t.cfl_max;
    if (t.cfl_growth > 0.0) s.solver.cfl_growth = t.cfl_growth;
    return s;
}

double comm_max(const parallel::Communicator& comm, double v) {
    return comm.max(v);
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
    need(jacobian_interval >= 1, "jacobian_interval", jacobian_interval, "an integer >= 1");
    need(cfl_max == 0.0 || (cfl_max >= 0.1 && cfl_max <= 1e12), "cfl_max", cfl_max,
         "0 (the solver's) or 0.1 .. 1e12");
    need(freeze_limiter_inner >= 0 && freeze_limiter_inner <= 1000000, "freeze_limiter_inner",
         freeze_limiter_inner, "0 (the solver's rules) or an integer >= 1");
    need(cfl_growth == 0.0 || (cfl_growth >= 1.0 && cfl_growth <= 100.0), "cfl_growth", cfl_growth,
         "0 (the solver's) or 1 .. 100");
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
    x_prev_.resize(3, 0);
    V_prev_.clear();
}

void UnsteadySolver::set_start_time(double t0) {
    if (!std::isfinite(t0)) throw InputError(fmt::format("time: start time {} is not finite", t0));
    t0_ = t0;
}

void UnsteadySolver::place_mesh(const Eigen::Matrix3Xd& x) {
    moving_.mesh->set_coordinates(
        std::span<const double>(x.data(), static_cast<std::size_t>(x.size())));
    mesh::update_dual_metrics(*moving_.mesh, *moving_.dual);
    step_.update_geometry();
}

void UnsteadySolver::set_moving_mesh(MovingMesh m) {
    const Domain& d = step_.domain();
    if (m.mesh != d.mesh || m.dual != d.dual || !m.coordinates)
        throw InputError(
            "UnsteadySolver::set_moving_mesh: the moving mesh must be the domain's mesh and "
            "metrics, with a coordinates callback");
    moving_ = std::move(m);
    const auto n_local = static_cast<Index>(U_.cols());
    moving_.coordinates(time(), steps_, x_);
    if (x_.cols() != n_local)
        throw InputError(
            fmt::format("UnsteadySolver: the coordinates callback gave {} nodes; the mesh has {}",
                        x_.cols(), n_local));
    place_mesh(x_);
    V_ = d.dual->dual_volumes;
    x_prev_.resize(3, 0);
    V_prev_.clear();
    U_prev_.resize(5, 0);
    swept_.resize_for(*d.dual);
    swept_prev_.resize_for(*d.dual);
    g_.resize_for(*d.dual);
    velocities_.setZero(3, n_local);
    x_next_.resize(3, n_local);
}

TimeLevels UnsteadySolver::time_levels() const {
    TimeLevels l;
    l.steps = steps_;
    l.cfl = cfl_;
    l.U_prev = U_prev_;
    if (moving()) {
        l.x = x_;
        l.x_prev = x_prev_;
        if (x_prev_.cols() > 0) l.swept_prev = swept_prev_;
    }
    return l;
}

void UnsteadySolver::restore(const NodeStates& U, const TimeLevels& l) {
    set_state(U);
    const Index n_local = U_.cols();
    auto fail = [](const char* what) {
        throw InputError(fmt::format("UnsteadySolver::restore: {} does not fit the mesh", what));
    };
    if (l.U_prev.cols() != 0 && (l.U_prev.cols() != n_local || l.U_prev.rows() != 5))
        fail("U^(n-1)");
    if (l.steps < 0) fail("the step count");
    steps_ = l.steps;
    cfl_ = l.cfl;
    U_prev_ = l.U_prev;
    if (!moving()) return;
    if (l.x.cols() != n_local) fail("the coordinates at t^n");
    const Domain& d = step_.domain();
    if (l.x_prev.cols() != 0) {
        if (l.x_prev.cols() != n_local) fail("the coordinates at t^(n-1)");
        const bool recompute = l.swept_prev.edges.empty() && l.swept_prev.boundary.empty();
        if (!recompute && !l.swept_prev.fits(*d.dual)) fail("the swept volumes");
        // The volumes of level n-1 from its coordinates (the same arithmetic as when it was
        // the current level, so bit for bit).
        place_mesh(l.x_prev);
        V_prev_ = d.dual->dual_volumes;
        x_prev_ = l.x_prev;
        if (recompute)  // S(n-1 -> n) from the two levels, as the step computed it
            mesh::swept_volumes(
                *moving_.mesh, *d.dual,
                std::span<const double>(l.x_prev.data(), static_cast<std::size_t>(l.x_prev.size())),
                std::span<const double>(l.x.data(), static_cast<std::size_t>(l.x.size())),
                swept_prev_);
        else
            swept_prev_ = l.swept_prev;
    } else {
        x_prev_.resize(3, 0);
        V_prev_.clear();
    }
    x_ = l.x;
    place_mesh(x_);
    V_ = d.dual->dual_volumes;
}

TimeStepRecord UnsteadySolver::advance(const Monitor& inner) {
    const UnsteadySettings& t = time_settings_;
    const Domain& d = step_.domain();
    const Index n_local = U_.cols();
    const bool mv = moving();
    const bool bdf2 =
        t.order == 2 && U_prev_.cols() == n_local && (!mv || x_prev_.cols() == n_local);
    double gcl_defect = 0.0;
    if (mv) {
        // Move to t^(n+1): swept volumes of the step, the new metrics and geometry.
        x_next_.resize(3, n_local);
        moving_.coordinates(t0_ + (steps_ + 1) * t.dt, steps_ + 1, x_next_);
        if (x_next_.cols() != n_local)
            throw InputError(fmt::format(
                "UnsteadySolver: the coordinates callback gave {} nodes; the mesh has {}",
                x_next_.cols(), n_local));
        mesh::swept_volumes(
            *moving_.mesh, *d.dual,
            std::span<const double>(x_.data(), static_cast<std::size_t>(x_.size())),
            std::span<const double>(x_next_.data(), static_cast<std::size_t>(x_next_.size())),
            swept_);
        place_mesh(x_next_);
        // Grid fluxes and node velocities with the scheme's weights.
        const double a = bdf2 ? 1.5 / t.dt : 1.0 / t.dt;
        const double b = bdf2 ? -0.5 / t.dt : 0.0;
        for (std::size_t e = 0; e < g_.edges.size(); ++e)
            g_.edges[e] = a * swept_.edges[e] + (bdf2 ? b * swept_prev_.edges[e] : 0.0);
        for (std::size_t m = 0; m < g_.boundary.size(); ++m)
            for (std::size_t k = 0; k < g_.boundary[m].size(); ++k)
                g_.boundary[m][k] =
                    a * swept_.boundary[m][k] + (bdf2 ? b * swept_prev_.boundary[m][k] : 0.0);
        if (bdf2)
            velocities_ = (1.5 * x_next_ - 2.0 * x_ + 0.5 * x_prev_) / t.dt;
        else
            velocities_ = (x_next_ - x_) / t.dt;
        step_.set_grid_fluxes(&g_, &velocities_);
        // The discrete geometric conservation law of this step.
        std::vector<double> sum(static_cast<std::size_t>(n_local), 0.0);
        for (std::size_t e = 0; e < g_.edges.size(); ++e) {
            sum[static_cast<std::size_t>(d.dual->edges[e][0])] += g_.edges[e];
            sum[static_cast<std::size_t>(d.dual->edges[e][1])] -= g_.edges[e];
        }
        for (std::size_t m = 0; m < g_.boundary.size(); ++m)
            for (std::size_t k = 0; k < g_.boundary[m].size(); ++k)
                sum[static_cast<std::size_t>(d.dual->boundary[m].nodes[k])] += g_.boundary[m][k];
        double vmax = 0.0;
        const std::vector<double>& V1 = d.dual->dual_volumes;
        for (Index i = 0; i < d.n_owned; ++i) {
            const auto k = static_cast<std::size_t>(i);
            const double dv = bdf2 ? 1.5 * V1[k] - 2.0 * V_[k] + 0.5 * V_prev_[k] : V1[k] - V_[k];
            gcl_defect = std::max(gcl_defect, std::abs(dv - t.dt * sum[k]));
            vmax = std::max(vmax, V1[k]);
        }
        gcl_defect = vmax > 0 ? comm_max(step_.communicator(), gcl_defect / vmax) : 0.0;
    }
    // R(U) + D U - S = 0: BDF2 D = 3 V / (2 dt), S = V (4 U^n - U^(n-1)) / (2 dt);
    // BDF1 D = V / dt, S = V U^n / dt; on a moving mesh each level with its own volumes.
    if (mv) {
        const std::vector<double>& V1 = d.dual->dual_volumes;
        for (Index i = 0; i < n_local; ++i) {
            const auto k = static_cast<std::size_t>(i);
            if (bdf2) {
                D_[k] = 1.5 * V1[k] / t.dt;
                S_.col(i) = (2.0 * V_[k] * U_.col(i) - 0.5 * V_prev_[k] * U_prev_.col(i)) / t.dt;
            } else {
                D_[k] = V1[k] / t.dt;
                S_.col(i) = V_[k] * U_.col(i) / t.dt;
            }
        }
    } else
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
    // step's) at the last step's CFL number, from U^n or its extrapolation.
    IterationState it = step_.initial_state();
    it.cfl = std::min(cfl_, it.cfl_cap);
    it.cfl_good = it.cfl;
    step_.set_backoff_state(U_);
    step_.begin(it);
    StepTerms terms{D_, &S_};
    if (t.extrapolate && bdf2) {
        // The drop counts from R*(U^n), the residual the step would start from.
        it.peak_log10_residual = step_.log10_density_residual(U_, terms);
        const double gamma = setup().flow.gamma;
        for (Index i = 0; i < d.n_owned; ++i) {
            const Vec5 Ue = 2.0 * U_n.col(i) - U_prev_.col(i);
            const Vec5 W = primitive(Ue, gamma);
            if (W[0] > 0.0 && W[4] > 0.0 && Ue.allFinite()) U_.col(i) = Ue;
        }
        step_.exchange(U_);
    }
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
    TimeStepRecord rec;
    while (true) {
        terms.reuse_matrix = it.iteration % t.jacobian_interval != 0;
        const StepOutcome so = step_.step(U_, it, rule, terms);
        if (so.result == StepResult::backed_off) continue;
        if (t.freeze_limiter_inner > 0 && !it.limiter_frozen &&
            it.iteration >= t.freeze_limiter_inner) {
            step_.freeze_limiter(true);
            it.limiter_frozen = true;
        }
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
    if (mv) {
        // Level n+1 becomes n.
        x_prev_.swap(x_);
        x_.swap(x_next_);
        V_prev_.swap(V_);
        V_ = d.dual->dual_volumes;
        std::swap(swept_prev_, swept_);
    }
    rec.step = ++steps_;
    rec.time = time();
    rec.gcl_defect = gcl_defect;
    rec.forces = forces();
    return rec;
}

}  // namespace manta::euler
