/// @file solver.cpp
/// The steady implicit iteration (solver.hpp, docs/euler.md).

#include "manta/euler/solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "manta/core/error.hpp"

namespace manta::euler {

namespace {

constexpr double pi = 3.14159265358979323846;

bool finite(double v) {
    return std::isfinite(v);
}

}  // namespace

void FlowCondition::validate() const {
    if (!(mach > 0.0 && mach <= 10.0))
        throw InputError(
            fmt::format("flow: Mach number {} is not physical for this solver; "
                        "expected 0 < Mach <= 10",
                        mach));
    if (!(std::abs(alpha) <= 0.5 * pi))
        throw InputError(fmt::format(
            "flow: angle of attack {:.6g} deg is out of range; expected |alpha| <= 90 deg",
            alpha * 180.0 / pi));
    if (!(std::abs(beta) <= 0.5 * pi))
        throw InputError(
            fmt::format("flow: sideslip {:.6g} deg is out of range; expected |beta| <= 90 deg",
                        beta * 180.0 / pi));
    if (!(gamma > 1.0 && gamma <= 2.0))
        throw InputError(fmt::format(
            "flow: ratio of specific heats {} is not physical; expected 1 < gamma <= 2", gamma));
}

void SolverSettings::validate() const {
    auto need = [](bool ok, const char* key, double v, const char* expected) {
        if (!ok)
            throw InputError(
                fmt::format("solver: {} = {} is out of range; expected {}", key, v, expected));
    };
    need(cfl_initial > 0 && finite(cfl_initial), "cfl", cfl_initial, "a number > 0");
    need(cfl_max >= cfl_initial && finite(cfl_max), "cfl_max", cfl_max, "a number >= cfl");
    need(cfl_growth >= 1.0 && cfl_growth <= 10.0, "cfl_growth", cfl_growth, "1 <= value <= 10");
    need(cfl_cut > 0.0 && cfl_cut < 1.0, "cfl_cut", cfl_cut, "0 < value < 1");
    need(cfl_cut_trigger >= 1.0, "cfl_cut_trigger", cfl_cut_trigger, "a number >= 1");
    need(max_iterations >= 1, "max_iterations", max_iterations, "an integer >= 1");
    need(residual_drop > 0 && residual_drop <= 16, "residual_drop", residual_drop,
         "0 < orders <= 16");
    need(coefficient_tolerance > 0, "coefficient_tolerance", coefficient_tolerance, "a number > 0");
    need(coefficient_window >= 2, "coefficient_window", coefficient_window, "an integer >= 2");
    need(freeze_limiter_stall >= 0, "freeze_limiter_stall", freeze_limiter_stall,
         "an integer >= 0 (0: never)");
    need(freeze_limiter_drop >= 0, "freeze_limiter_drop", freeze_limiter_drop,
         "a number >= 0 (0: never)");
    need(first_order_iterations >= 0, "first_order_iterations", first_order_iterations,
         "an integer >= 0");
    need(linear.restart >= 1, "linear_restart", linear.restart, "an integer >= 1");
    need(linear.max_iterations >= 1, "linear_iterations", linear.max_iterations, "an integer >= 1");
    need(linear.relative_tolerance > 0 && linear.relative_tolerance < 1, "linear_tolerance",
         linear.relative_tolerance, "0 < value < 1");
    need(max_backoffs >= 0, "max_backoffs", max_backoffs, "an integer >= 0");
}

const char* name(BoundaryKind k) noexcept {
    switch (k) {
        case BoundaryKind::farfield:
            return "farfield";
        case BoundaryKind::wall:
            return "wall";
        case BoundaryKind::symmetry:
            return "symmetry";
    }
    return "?";
}

bool default_role(const std::string& marker, BoundaryKind& role) {
    std::string m = marker;
    for (char& c : m) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    auto has = [&](const char* s) { return m.find(s) != std::string::npos; };
    if (has("far") || has("inlet") || has("outlet") || has("inflow") || has("outflow")) {
        role = BoundaryKind::farfield;
        return true;
    }
    if (has("sym")) {
        role = BoundaryKind::symmetry;
        return true;
    }
    for (const char* w : {"wall", "wing", "airfoil", "aerofoil", "body", "fuselage", "tail", "fin",
                          "nacelle", "blade"})
        if (has(w)) {
            role = BoundaryKind::wall;
            return true;
        }
    return false;
}

SteadySolver::SteadySolver(const Domain& domain, const parallel::Communicator& comm,
                           const CaseSetup& setup)
    : domain_(domain),
      comm_(comm),
      setup_((setup.flow.validate(), setup.solver.validate(), setup.spatial.validate(), setup)),
      W_inf_(free_stream(setup.flow.mach, setup.flow.alpha, setup.flow.beta, setup.flow.gamma)),
      op_(domain, setup.roles, W_inf_, setup.flow.gamma, setup.spatial) {
    const mesh::Mesh& m = *domain_.mesh;
    if (static_cast<int>(setup_.roles.size()) != m.n_markers())
        throw InputError(fmt::format("{}: {} boundary roles given for {} markers", m.source(),
                                     setup_.roles.size(), m.n_markers()));
    if (setup_.solver.first_order_iterations > 0 && setup_.spatial.order == 2) {
        SpatialOptions first = setup_.spatial;
        first.order = 1;
        op_first_ = std::make_unique<SpatialOperator>(domain, setup_.roles, W_inf_,
                                                      setup_.flow.gamma, first);
    }
    const Index n_local = m.n_nodes();
    U_.resize(5, n_local);
    const Vec5 U_inf = conservative(W_inf_, setup_.flow.gamma);
    for (Index i = 0; i < n_local; ++i) U_.col(i) = U_inf;
    R_.setZero(5, n_local);
    J_ = BlockMatrix(domain_.n_owned, n_local, domain_.dual->edges);
    if (setup_.solver.preconditioner == PreconditionerKind::sgs)
        precond_ = std::make_unique<BlockSgs>();
    else
        precond_ = std::make_unique<BlockIlu0>();
    lambda_.assign(static_cast<std::size_t>(n_local), 0.0);
    dU_.assign(5 * static_cast<std::size_t>(n_local), 0.0);
    n_global_nodes_ = static_cast<std::int64_t>(comm_.sum(static_cast<double>(domain_.n_owned)));
    // Round-off level of the density residual: 1e-12 of the free-stream mass flux through a
    // face of the mean dual cell's size.
    double volume = 0.0;
    for (Index i = 0; i < domain_.n_owned; ++i)
        volume += domain_.dual->dual_volumes[static_cast<std::size_t>(i)];
    volume = comm_.sum(volume);
    const double face = std::pow(
        volume / static_cast<double>(std::max<std::int64_t>(1, n_global_nodes_)), 2.0 / 3.0);
    log10_roundoff_ = std::log10(1e-12 * setup_.flow.mach * face);
    it_.cfl = setup_.solver.cfl_initial;
    it_.cfl_good = setup_.solver.cfl_initial;
    it_.cfl_cap = setup_.solver.cfl_max;
    U_good_.assign(U_.data(), U_.data() + U_.size());

    // Reference area: the configured one or the wall area projected on the z-normal plane,
    // from the wall nodes' dual boundary faces (so a node's upper and lower parts at a sharp
    // edge partly cancel, as in SU2's REF_AREA = 0).
    if (setup_.reference.area > 0.0) {
        area_ = setup_.reference.area;
    } else {
        double a = 0.0;
        for (const mesh::BoundaryVertices& bv : domain_.dual->boundary) {
            if (setup_.roles[static_cast<std::size_t>(bv.marker)] != BoundaryKind::wall) continue;
            for (std::size_t k = 0; k < bv.nodes.size(); ++k)
                if (bv.nodes[k] < domain_.n_owned)
                    a += std::max(0.0, bv.normals(2, static_cast<Eigen::Index>(k)));
        }
        area_ = comm_.sum(a);
        if (!(area_ > 0.0))
            throw InputError(fmt::format(
                "{}: the reference area from the walls' projection is {} (no wall marker, or "
                "walls with no area seen from above); give reference.area in the configuration",
                m.source(), area_));
    }
}

void SteadySolver::exchange(NodeStates& U) const {
    domain_.halo->exchange(std::span<double>(U.data(), static_cast<std::size_t>(U.size())), 5);
}

void SteadySolver::set_state(const NodeStates& U) {
    if (U.cols() != U_.cols())
        throw InputError(
            fmt::format("initial solution has {} nodes; the mesh has {}", U.cols(), U_.cols()));
    const double gamma = setup_.flow.gamma;
    for (Index i = 0; i < domain_.n_owned; ++i) {
        const Vec5 W = primitive(U.col(i), gamma);
        if (!(W[0] > 0.0 && W[4] > 0.0 && W.allFinite()))
            throw InputError(fmt::format(
                "initial solution: node {} has density {} and pressure {}; expected positive, "
                "finite values",
                i, W[0], W[4]));
    }
    U_.leftCols(domain_.n_owned) = U.leftCols(domain_.n_owned);
    exchange(U_);
    U_good_.assign(U_.data(), U_.data() + U_.size());
}

std::array<double, 5> SteadySolver::rms_residual() const {
    std::array<double, 5> s{};
    for (Index i = 0; i < domain_.n_owned; ++i)
        for (int k = 0; k < 5; ++k) s[k] += R_(k, i) * R_(k, i);
    comm_.sum(s);
    for (double& v : s)
        v = std::sqrt(v / static_cast<double>(std::max<std::int64_t>(1, n_global_nodes_)));
    return s;
}

ForceCoefficients SteadySolver::forces() const {
    const mesh::Mesh& m = *domain_.mesh;
    const double gamma = setup_.flow.gamma;
    const double p_inf = 1.0 / gamma;
    const Vec3& xref = setup_.reference.moment_point;
    std::array<double, 6> fm{};
    for (const mesh::BoundaryVertices& bv : domain_.dual->boundary) {
        if (setup_.roles[static_cast<std::size_t>(bv.marker)] != BoundaryKind::wall) continue;
        for (std::size_t k = 0; k < bv.nodes.size(); ++k) {
            const Index i = bv.nodes[k];
            if (i >= domain_.n_owned) continue;
            const Vec5 W = primitive(U_.col(i), gamma);
            const Vec3 F = (W[4] - p_inf) * bv.normals.col(static_cast<Eigen::Index>(k));
            const Vec3 M = (m.node(i) - xref).cross(F);
            for (int d = 0; d < 3; ++d) {
                fm[d] += F[d];
                fm[3 + d] += M[d];
            }
        }
    }
    comm_.sum(fm);
    const double q = 0.5 * setup_.flow.mach * setup_.flow.mach;  // rho_inf = 1, V = M
    const double qs = q * area_;
    ForceCoefficients c;
    c.area = area_;
    const Vec3 CF(fm[0] / qs, fm[1] / qs, fm[2] / qs);
    c.CFx = CF.x();
    c.CFy = CF.y();
    c.CFz = CF.z();
    c.CMx = fm[3] / (qs * setup_.reference.span);
    c.CMy = fm[4] / (qs * setup_.reference.chord);
    c.CMz = fm[5] / (qs * setup_.reference.span);
    const double a = setup_.flow.alpha;
    const Vec3 d = free_stream_direction(a, setup_.flow.beta);
    const Vec3 lift(-std::sin(a), 0.0, std::cos(a));
    c.CD = CF.dot(d);
    c.CL = CF.dot(lift);
    c.CY = CF.dot(lift.cross(d));
    return c;
}

std::vector<double> SteadySolver::pressure_coefficient() const {
    const double gamma = setup_.flow.gamma;
    const double q = 0.5 * setup_.flow.mach * setup_.flow.mach;
    std::vector<double> cp(static_cast<std::size_t>(U_.cols()));
    for (Index i = 0; i < U_.cols(); ++i)
        cp[static_cast<std::size_t>(i)] = (primitive(U_.col(i), gamma)[4] - 1.0 / gamma) / q;
    return cp;
}

std::vector<double> SteadySolver::primitive_state() const {
    std::vector<double> w(static_cast<std::size_t>(U_.size()));
    for (Index i = 0; i < U_.cols(); ++i) {
        const Vec5 W = primitive(U_.col(i), setup_.flow.gamma);
        for (int k = 0; k < 5; ++k) w[5 * static_cast<std::size_t>(i) + k] = W[k];
    }
    return w;
}

std::vector<double> SteadySolver::mach_number() const {
    std::vector<double> mach(static_cast<std::size_t>(U_.cols()));
    for (Index i = 0; i < U_.cols(); ++i) {
        const Vec5 W = primitive(U_.col(i), setup_.flow.gamma);
        mach[static_cast<std::size_t>(i)] =
            W.segment<3>(1).norm() / sound_speed(W, setup_.flow.gamma);
    }
    return mach;
}

std::size_t SteadySolver::memory_bytes() const noexcept {
    const std::size_t states = 2 * static_cast<std::size_t>(U_.size()) * sizeof(double) +
                               U_good_.capacity() * sizeof(float);
    const std::size_t vecs = (lambda_.capacity() + dU_.capacity()) * sizeof(double);
    return states + vecs + J_.memory_bytes() + precond_->memory_bytes() + krylov_.memory_bytes() +
           op_.memory_bytes() + (op_first_ ? op_first_->memory_bytes() : 0);
}

void SteadySolver::set_iteration_state(const IterationState& s) {
    it_ = s;
    op_.freeze_limiter(s.limiter_frozen);
}

void SteadySolver::set_backoff_state(std::vector<float> U) {
    if (U.size() != static_cast<std::size_t>(U_.size()))
        throw InputError(fmt::format("back-off state has {} values; expected {} (5 per node)",
                                     U.size(), U_.size()));
    U_good_ = std::move(U);
}

std::vector<double> SteadySolver::limiter_values() const {
    if (!setup_.spatial.limiter || setup_.spatial.order != 2 ||
        setup_.spatial.flux.scheme == FluxScheme::jst)
        return {};
    std::vector<double> phi(static_cast<std::size_t>(U_.size()));
    for (Index i = 0; i < U_.cols(); ++i)
        Eigen::Map<Vec5>(phi.data() + 5 * static_cast<std::size_t>(i)) = op_.limiter(i);
    return phi;
}

void SteadySolver::set_frozen_limiter(std::span<const double> phi) {
    if (phi.size() != static_cast<std::size_t>(U_.size()))
        throw InputError(fmt::format("frozen limiter has {} values; expected {} (5 per node)",
                                     phi.size(), U_.size()));
    for (Index i = 0; i < U_.cols(); ++i) {
        const Vec5 v = Eigen::Map<const Vec5>(phi.data() + 5 * static_cast<std::size_t>(i));
        if (!(v.minCoeff() >= 0.0 && v.maxCoeff() <= 1.0))
            throw InputError(
                fmt::format("frozen limiter: node {} has values {}..{}; expected values in [0, 1]",
                            i, v.minCoeff(), v.maxCoeff()));
        op_.set_limiter(i, v);
    }
}

SolveOutcome SteadySolver::solve(const Monitor& monitor) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const SolverSettings& s = setup_.solver;
    const double gamma = setup_.flow.gamma;
    const Index n_owned = domain_.n_owned;

    // Every decision below reads and writes it_ only (no local state), so a run resumed from a
    // checkpoint of it_, U_, U_good_ and the frozen limiter takes the same decisions.
    SolveOutcome out;
    op_.freeze_limiter(it_.limiter_frozen);
    if (!(it_.cfl_cap > 0.0)) it_.cfl_cap = s.cfl_max;

    auto back_off = [&](const std::string& why) {
        ++it_.backoffs;
        out.backoffs = it_.backoffs;
        if (it_.backoffs > s.max_backoffs)
            throw ConvergenceError(fmt::format(
                "{}: the iteration diverged at iteration {} ({}) after {} CFL back-offs "
                "(CFL {:.3g}); try a smaller solver.cfl_max, first-order start iterations "
                "(solver.first_order_iterations) or order 1",
                domain_.mesh->source(), it_.iteration, why, s.max_backoffs, it_.cfl));
        std::copy(U_good_.begin(), U_good_.end(), U_.data());
        it_.cfl_cap = std::max(s.cfl_initial * 0.1, 0.25 * std::min(it_.cfl, it_.cfl_cap));
        it_.cfl = std::max(0.1 * it_.cfl_good, 0.1);
        it_.cfl_good = it_.cfl;
        it_.previous_log10_residual = std::numeric_limits<double>::quiet_NaN();
        it_.window.clear();
    };

    while (true) {
        out.backoffs = it_.backoffs;
        const bool first_order = op_first_ && it_.iteration < s.first_order_iterations;
        SpatialOperator& op = first_order ? *op_first_ : op_;
        op.residual(U_, R_);
        op.spectral_radii(U_, lambda_);
        op.apply_wall_tangency(U_, lambda_, R_);
        const std::array<double, 5> rms = rms_residual();
        IterationRecord rec;
        rec.iteration = it_.iteration;
        bool sound = true;
        for (int k = 0; k < 5; ++k) {
            rec.log10_residual[k] = std::log10(std::max(rms[k], 1e-300));
            sound = sound && finite(rms[k]);
        }
        const double res = rec.log10_residual[0];
        if (!sound || res > it_.best_log10_residual + 5.0) {
            back_off(!sound
                         ? "NaN in the residual"
                         : fmt::format("density residual 10^{:.2f}, 10^5 times its lowest", res));
            continue;
        }
        // This iteration's bookkeeping goes to `next`; it_ takes it only if the iteration goes
        // on, so a stopped run's state (checkpointed after solve) stops again the same way.
        IterationState next = it_;
        if (res < next.best_log10_residual) next.cycle_since = it_.iteration;
        next.best_log10_residual = std::min(next.best_log10_residual, res);
        if (!first_order) next.peak_log10_residual = std::max(next.peak_log10_residual, res);
        const double drop = first_order ? 0.0 : next.peak_log10_residual - res;
        rec.forces = forces();
        rec.cfl = it_.cfl;

        // Settled coefficients over the window.
        next.window.push_back({rec.forces.CL, rec.forces.CD, rec.forces.CY});
        if (static_cast<int>(next.window.size()) > s.coefficient_window)
            next.window.erase(next.window.begin());
        bool settled = static_cast<int>(next.window.size()) == s.coefficient_window;
        for (int c = 0; c < 3 && settled; ++c) {
            double lo = next.window.front()[c], hi = lo;
            for (const auto& w : next.window) {
                lo = std::min(lo, w[c]);
                hi = std::max(hi, w[c]);
            }
            settled = hi - lo <= s.coefficient_tolerance;
        }
        out.residual_drop = drop;
        out.forces = rec.forces;
        const bool roundoff = res <= log10_roundoff_;
        if (!first_order && (drop >= s.residual_drop || roundoff) && settled) {
            out.converged = true;
            out.reason = drop >= s.residual_drop
                             ? fmt::format(
                                   "converged: density residual {:.2f} orders below its peak, CL "
                                   "CD CY within {:g} over {} iterations",
                                   drop, s.coefficient_tolerance, s.coefficient_window)
                             : fmt::format(
                                   "converged: density residual 10^{:.2f} at round-off level, CL "
                                   "CD CY within {:g} over {} iterations",
                                   res, s.coefficient_tolerance, s.coefficient_window);
            rec.wall_s = std::chrono::duration<double>(clock::now() - t0).count();
            if (monitor) monitor(rec);
            break;
        }
        if (it_.iteration >= s.max_iterations) {
            out.reason = fmt::format(
                "stopped at the iteration limit {} with the density residual {:.2f} orders below "
                "its peak (asked for {:g}){}",
                s.max_iterations, drop, s.residual_drop,
                settled ? "" : " and the coefficients still changing");
            rec.wall_s = std::chrono::duration<double>(clock::now() - t0).count();
            if (monitor) monitor(rec);
            break;
        }
        // Freeze the limiter after the set drop, or when the residual has stalled: no gain of
        // 0.1 order over `freeze_limiter_stall` iterations, once it has fallen one order below
        // its peak (a plateau before that is the start-up transient, shocks still moving: a
        // limiter frozen there holds a solution far from the final one, and the transonic
        // NACA 0012 on the finest slab then crawls at a cut CFL number).
        if (res < next.stall_best - 0.1) {
            next.stall_best = res;
            next.stall_since = it_.iteration;
        }
        const bool stalled = s.freeze_limiter_stall > 0 && !first_order && drop >= 1.0 &&
                             it_.iteration - next.stall_since >= s.freeze_limiter_stall;
        if (!next.limiter_frozen &&
            ((s.freeze_limiter_drop > 0 && drop >= s.freeze_limiter_drop) || stalled)) {
            op_.freeze_limiter(true);
            next.limiter_frozen = true;
            next.stall_best = res;
            next.stall_since = it_.iteration;
        } else if (next.limiter_frozen && s.freeze_limiter_stall > 0 && !first_order &&
                   it_.iteration - next.cycle_since >= s.freeze_limiter_stall &&
                   next.cfl_cap > s.cfl_initial) {
            // No new lowest residual for as many iterations with the operator fixed: the
            // first-order implicit operator does not steer the second-order residual at this
            // CFL number (a defect-correction cycle; slow but steady progress is not one). A
            // smaller CFL number damps it.
            next.cfl_cap = std::max(s.cfl_initial, 0.1 * next.cfl_cap);
            next.cfl = std::min(next.cfl, next.cfl_cap);
            next.cycle_since = it_.iteration;
        }

        // CFL: grow while the residual falls, cut when it rises.
        if (finite(next.previous_log10_residual)) {
            if (res > next.previous_log10_residual + std::log10(s.cfl_cut_trigger))
                next.cfl = std::max(s.cfl_initial * 0.1, next.cfl * s.cfl_cut);
            else
                next.cfl = std::min(next.cfl_cap, next.cfl * s.cfl_growth);
        }
        next.previous_log10_residual = res;
        if (res <= next.best_log10_residual + 0.5 && it_.iteration % 5 == 0) {
            std::copy(U_.data(), U_.data() + U_.size(), U_good_.begin());
            next.cfl_good = next.cfl;
        }
        it_ = std::move(next);

        // (V / dt + dR/dU) dU = -R with dt_i = CFL V_i / lambda_i.
        op.jacobian(U_, J_);
        for (Index i = 0; i < n_owned; ++i)
            J_.add_to_diagonal(i, lambda_[static_cast<std::size_t>(i)] / it_.cfl);
        op.apply_wall_tangency(lambda_, it_.cfl, J_);
        // A singular pivot on any process sends every process back (the same decision on all).
        std::string pivot_error;
        try {
            precond_->factorize(J_);
        } catch (const NumericalError& e) {
            pivot_error = e.what();
        }
        if (comm_.max(pivot_error.empty() ? 0.0 : 1.0) > 0.0) {
            back_off(pivot_error.empty() ? "singular ILU pivot on another process" : pivot_error);
            continue;
        }
        // J dU = R (R's owned columns are the right-hand side), then U -= dU.
        std::fill(dU_.begin(), dU_.end(), 0.0);
        const KrylovResult kr = krylov_.solve(
            J_, *precond_, std::span<const double>(R_.data(), static_cast<std::size_t>(R_.size())),
            dU_, comm_, *domain_.halo, s.linear);
        rec.linear_iterations = kr.iterations;
        rec.linear_residual = kr.relative_residual;

        // Update with a per-node relaxation that keeps density and pressure positive (changes
        // above 20 % are scaled down).
        bool bad = false;
        for (Index i = 0; i < n_owned; ++i) {
            const Vec5 d = -Eigen::Map<const Vec5>(dU_.data() + 5 * static_cast<std::size_t>(i));
            if (!d.allFinite()) {
                bad = true;
                break;
            }
            const Vec5 W = primitive(U_.col(i), gamma);
            const Vec5 Wn = primitive(U_.col(i) + d, gamma);
            const double change =
                std::max(std::abs(Wn[0] - W[0]) / W[0], std::abs(Wn[4] - W[4]) / W[4]);
            double omega = 1.0;
            if (!(Wn[0] > 0.0 && Wn[4] > 0.0) || change > 0.2)
                omega = std::min(1.0, 0.2 / std::max(change, 1e-300));
            U_.col(i) += omega * d;
            const Vec5 Wc = primitive(U_.col(i), gamma);
            if (!(Wc[0] > 0.0 && Wc[4] > 0.0)) bad = true;
        }
        if (comm_.max(bad ? 1.0 : 0.0) > 0.0) {
            back_off("non-physical state after the update");
            continue;
        }
        exchange(U_);
        rec.wall_s = std::chrono::duration<double>(clock::now() - t0).count();
        ++it_.iteration;
        if (monitor && !monitor(rec)) {
            out.reason = "stopped by the caller";
            break;
        }
    }
    out.iterations = it_.iteration;
    out.backoffs = it_.backoffs;
    out.wall_s = std::chrono::duration<double>(clock::now() - t0).count();
    return out;
}

}  // namespace manta::euler
