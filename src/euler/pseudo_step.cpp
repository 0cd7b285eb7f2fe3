/// @file pseudo_step.cpp
/// One implicit pseudo-time step, shared by the steady and the dual-time solvers (solver.hpp,
/// docs/euler.md#the-pseudo-time-step).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "manta/core/error.hpp"
#include "manta/euler/solver.hpp"
#include "manta/parallel/partition.hpp"

namespace manta::euler {

namespace {

bool finite(double v) {
    return std::isfinite(v);
}

}  // namespace

PseudoTimeStep::PseudoTimeStep(const Domain& domain, const parallel::Communicator& comm,
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
    if (setup_.reference.half_model) {
        if (std::abs(setup_.reference.moment_point.y()) > 1e-9)
            throw InputError(fmt::format(
                "{}: reference.moment_point y = {:g} m on a half model; expected 0 (the half "
                "model's symmetry plane y = 0 holds the moment point)",
                m.source(), setup_.reference.moment_point.y()));
        if (setup_.flow.beta != 0.0)
            throw InputError(fmt::format(
                "{}: sideslip {:g} deg on a half model; expected 0 (a half model mirrors the "
                "flow about y = 0: sideslip needs the full model, manta mesh --model full)",
                m.source(), setup_.flow.beta * 57.29577951308232));
    }
    const Index n_local = m.n_nodes();
    R_.setZero(5, n_local);
    // The back-off state until the caller sets its own: the free stream.
    const Vec5 U_inf = conservative(W_inf_, setup_.flow.gamma);
    U_good_.resize(5 * static_cast<std::size_t>(n_local));
    for (std::size_t i = 0; i < static_cast<std::size_t>(n_local); ++i)
        for (int k = 0; k < 5; ++k) U_good_[5 * i + k] = static_cast<float>(U_inf[k]);
    J_ = BlockMatrix(domain_.n_owned, n_local, domain_.dual->edges);
    // Reproducible across process counts: the diagonal blocks summed in double precision.
    if (setup_.solver.preconditioner_blocks >= 1) J_.accumulate_diagonals(true);
    if (setup_.solver.preconditioner == PreconditionerKind::sgs)
        precond_ = std::make_unique<BlockSgs>();
    else
        precond_ = std::make_unique<BlockIlu0>();
    if (const int blocks = setup_.solver.preconditioner_blocks; blocks >= 1) {
        // The parts of an N-process run: on one process its preconditioner's blocks; on N
        // processes each process's nodes are one part already (the same METIS partition of
        // the same mesh, parallel::distribute).
        if (comm_.size() == 1) {
            if (blocks > 1) precond_->set_blocks(parallel::partition_nodes(m, blocks));
        } else if (comm_.size() != blocks) {
            throw InputError(fmt::format(
                "{}: solver.preconditioner_blocks = {} on {} processes; expected 1 or {} "
                "processes, or preconditioner_blocks 0 (one block per process)",
                m.source(), blocks, comm_.size(), blocks));
        }
    }
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

IterationState PseudoTimeStep::initial_state() const {
    IterationState it;
    it.cfl = setup_.solver.cfl_initial;
    it.cfl_good = setup_.solver.cfl_initial;
    it.cfl_cap = setup_.solver.cfl_max;
    return it;
}

void PseudoTimeStep::begin(IterationState& it) {
    op_.freeze_limiter(it.limiter_frozen);
    if (!(it.cfl_cap > 0.0)) it.cfl_cap = setup_.solver.cfl_max;
}

void PseudoTimeStep::update_geometry() {
    matrix_current_ = false;
    op_.update_geometry();
    if (op_first_) op_first_->update_geometry();
}

void PseudoTimeStep::set_grid_fluxes(const mesh::DualFaceValues* g,
                                     const Eigen::Matrix3Xd* node_velocities) {
    matrix_current_ = false;
    op_.set_grid_fluxes(g, node_velocities);
    if (op_first_) op_first_->set_grid_fluxes(g, node_velocities);
}

void PseudoTimeStep::exchange(NodeStates& U) const {
    domain_.halo->exchange(std::span<double>(U.data(), static_cast<std::size_t>(U.size())), 5);
}

std::array<double, 5> PseudoTimeStep::rms_residual() const {
    std::array<double, 5> s{};
    for (Index i = 0; i < domain_.n_owned; ++i)
        for (int k = 0; k < 5; ++k) s[k] += R_(k, i) * R_(k, i);
    comm_.sum(s);
    for (double& v : s)
        v = std::sqrt(v / static_cast<double>(std::max<std::int64_t>(1, n_global_nodes_)));
    return s;
}

void PseudoTimeStep::evaluate(SpatialOperator& op, const NodeStates& U, const StepTerms& terms) {
    const Index n_owned = domain_.n_owned;
    op.residual(U, R_);
    op.spectral_radii(U, lambda_);
    // R* = R + D U - S (before the strong wall tangency, which projects the momentum rows).
    if (!terms.diagonal.empty())
        for (Index i = 0; i < n_owned; ++i)
            R_.col(i) += terms.diagonal[static_cast<std::size_t>(i)] * U.col(i);
    if (terms.source) R_.leftCols(n_owned) -= terms.source->leftCols(n_owned);
    op.apply_wall_tangency(U, lambda_, R_);
}

double PseudoTimeStep::log10_density_residual(const NodeStates& U, const StepTerms& terms) {
    if (U.cols() != R_.cols() || U.rows() != 5)
        throw InputError(fmt::format("pseudo-time step: the state has {} nodes; the mesh has {}",
                                     U.cols(), R_.cols()));
    evaluate(op_, U, terms);
    return std::log10(std::max(rms_residual()[0], 1e-300));
}

ForceCoefficients PseudoTimeStep::forces(const NodeStates& U) const {
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
            const Vec5 W = primitive(U.col(i), gamma);
            const Vec3 F = (W[4] - p_inf) * bv.normals.col(static_cast<Eigen::Index>(k));
            const Vec3 M = (m.node(i) - xref).cross(F);
            for (int d = 0; d < 3; ++d) {
                fm[d] += F[d];
                fm[3 + d] += M[d];
            }
        }
    }
    comm_.sum(fm);
    if (setup_.reference.half_model) {
        // The half and its mirror image about y = 0 (moment point on the plane): the mirror's
        // force is (Fx, -Fy, Fz), its moment (-Mx, My, -Mz).
        fm[1] = 0.0;
        fm[3] = 0.0;
        fm[5] = 0.0;
    }
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

void PseudoTimeStep::set_backoff_state(std::vector<float> U) {
    if (U.size() != static_cast<std::size_t>(R_.size()))
        throw InputError(fmt::format("back-off state has {} values; expected {} (5 per node)",
                                     U.size(), R_.size()));
    U_good_ = std::move(U);
}

void PseudoTimeStep::set_backoff_state(const NodeStates& U) {
    if (U.size() != R_.size())
        throw InputError(
            fmt::format("back-off state has {} nodes; expected {}", U.cols(), R_.cols()));
    U_good_.assign(U.data(), U.data() + U.size());
}

std::vector<double> PseudoTimeStep::limiter_values() const {
    if (!setup_.spatial.limiter || setup_.spatial.order != 2 ||
        setup_.spatial.flux.scheme == FluxScheme::jst)
        return {};
    const Index n = R_.cols();
    std::vector<double> phi(5 * static_cast<std::size_t>(n));
    for (Index i = 0; i < n; ++i)
        Eigen::Map<Vec5>(phi.data() + 5 * static_cast<std::size_t>(i)) = op_.limiter(i);
    return phi;
}

void PseudoTimeStep::set_frozen_limiter(std::span<const double> phi) {
    if (phi.size() != static_cast<std::size_t>(R_.size()))
        throw InputError(fmt::format("frozen limiter has {} values; expected {} (5 per node)",
                                     phi.size(), R_.size()));
    for (Index i = 0; i < R_.cols(); ++i) {
        const Vec5 v = Eigen::Map<const Vec5>(phi.data() + 5 * static_cast<std::size_t>(i));
        if (!(v.minCoeff() >= 0.0 && v.maxCoeff() <= 1.0))
            throw InputError(
                fmt::format("frozen limiter: node {} has values {}..{}; expected values in [0, 1]",
                            i, v.minCoeff(), v.maxCoeff()));
        op_.set_limiter(i, v);
    }
}

std::size_t PseudoTimeStep::memory_bytes() const noexcept {
    const std::size_t states =
        static_cast<std::size_t>(R_.size()) * sizeof(double) + U_good_.capacity() * sizeof(float);
    const std::size_t vecs = (lambda_.capacity() + dU_.capacity()) * sizeof(double);
    return states + vecs + J_.memory_bytes() + precond_->memory_bytes() + krylov_.memory_bytes() +
           op_.memory_bytes() + (op_first_ ? op_first_->memory_bytes() : 0);
}

StopDecision steady_stop(const SolverSettings& s, const StepStatus& st) {
    StopDecision d;
    if (!st.first_order && (st.drop >= s.residual_drop || st.at_roundoff) && st.settled) {
        d.stop = true;
        d.converged = true;
        d.reason = st.drop >= s.residual_drop
                       ? fmt::format(
                             "converged: density residual {:.2f} orders below its peak, CL "
                             "CD CY within {:g} over {} iterations",
                             st.drop, s.coefficient_tolerance, s.coefficient_window)
                       : fmt::format(
                             "converged: density residual 10^{:.2f} at round-off level, CL "
                             "CD CY within {:g} over {} iterations",
                             st.log10_residual[0], s.coefficient_tolerance, s.coefficient_window);
    } else if (st.iteration >= s.max_iterations) {
        d.stop = true;
        d.reason = fmt::format(
            "stopped at the iteration limit {} with the density residual {:.2f} orders below "
            "its peak (asked for {:g}){}",
            s.max_iterations, st.drop, s.residual_drop,
            st.settled ? "" : " and the coefficients still changing");
    }
    return d;
}

StepOutcome PseudoTimeStep::step(NodeStates& U, IterationState& it, const StopRule& stop,
                                 const StepTerms& terms) {
    const SolverSettings& s = setup_.solver;
    const double gamma = setup_.flow.gamma;
    const Index n_owned = domain_.n_owned;
    if (U.cols() != R_.cols() || U.rows() != 5)
        throw InputError(fmt::format("pseudo-time step: the state has {} nodes; the mesh has {}",
                                     U.cols(), R_.cols()));
    if (!terms.diagonal.empty() && terms.diagonal.size() < static_cast<std::size_t>(n_owned))
        throw InputError(
            fmt::format("pseudo-time step: the extra diagonal has {} values; expected {} (one "
                        "per node)",
                        terms.diagonal.size(), R_.cols()));
    if (terms.source && terms.source->cols() < n_owned)
        throw InputError(fmt::format("pseudo-time step: the extra source has {} nodes; expected {}",
                                     terms.source->cols(), R_.cols()));

    // Every decision below reads and writes `it` only (no local state), so a run resumed from
    // a checkpoint of it, U, the back-off state and the frozen limiter takes the same decisions.
    StepOutcome out;
    auto back_off = [&](const std::string& why) {
        ++it.backoffs;
        if (it.backoffs > s.max_backoffs)
            throw ConvergenceError(fmt::format(
                "{}: the iteration diverged at iteration {} ({}) after {} CFL back-offs "
                "(CFL {:.3g}){}; try a smaller solver.cfl_max, first-order start iterations "
                "(solver.first_order_iterations) or order 1",
                domain_.mesh->source(), it.iteration, why, s.max_backoffs, it.cfl,
                out.record.max_residual > 0.0
                    ? fmt::format(", the largest density residual at ({:.4g}, {:.4g}, {:.4g}) "
                                  "in the mesh's coordinates",
                                  out.record.max_residual_at[0], out.record.max_residual_at[1],
                                  out.record.max_residual_at[2])
                    : std::string()));
        std::copy(U_good_.begin(), U_good_.end(), U.data());
        matrix_current_ = false;
        it.cfl_cap = std::max(s.cfl_initial * 0.1, 0.25 * std::min(it.cfl, it.cfl_cap));
        it.cfl = std::max(0.1 * it.cfl_good, 0.1);
        it.cfl_good = it.cfl;
        it.previous_log10_residual = std::numeric_limits<double>::quiet_NaN();
        it.window.clear();
        out.result = StepResult::backed_off;
        return out;
    };

    const bool first_order = op_first_ && it.iteration < s.first_order_iterations;
    SpatialOperator& op = first_order ? *op_first_ : op_;
    evaluate(op, U, terms);
    const std::array<double, 5> rms = rms_residual();
    IterationRecord& rec = out.record;
    rec.iteration = it.iteration;
    bool sound = true;
    for (int k = 0; k < 5; ++k) {
        rec.log10_residual[k] = std::log10(std::max(rms[k], 1e-300));
        sound = sound && finite(rms[k]);
    }
    const double res = rec.log10_residual[0];
    {
        // The node of the largest density residual, over all processes (the owner of the
        // largest gives its coordinates; the others -inf).
        double big = -1.0;
        Index at = -1;
        for (Index i = 0; i < n_owned; ++i)
            if (const double v = std::abs(R_(0, i)); v > big) {
                big = v;
                at = i;
            }
        const double global = comm_.max(big);
        rec.max_residual = global;
        const double inf = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k)
            rec.max_residual_at[static_cast<std::size_t>(k)] =
                comm_.max(at >= 0 && big == global ? domain_.mesh->node(at)[k] : -inf);
    }
    if (!sound || res > it.best_log10_residual + 5.0)
        return back_off(
            !sound ? "NaN in the residual"
                   : fmt::format("density residual 10^{:.2f}, 10^5 times its lowest", res));
    // This step's bookkeeping goes to `next`; `it` takes it only if the step goes on, so a
    // stopped run's state (checkpointed after the stop) stops again the same way.
    IterationState next = it;
    if (res < next.best_log10_residual) next.cycle_since = it.iteration;
    next.best_log10_residual = std::min(next.best_log10_residual, res);
    if (!first_order) next.peak_log10_residual = std::max(next.peak_log10_residual, res);
    const double drop = first_order ? 0.0 : next.peak_log10_residual - res;
    rec.forces = forces(U);
    rec.cfl = it.cfl;

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
    StepStatus& st = out.status;
    st.iteration = it.iteration;
    st.log10_residual = rec.log10_residual;
    st.drop = drop;
    st.first_order = first_order;
    st.at_roundoff = res <= log10_roundoff_;
    st.settled = settled;
    st.forces = rec.forces;
    if (stop) out.decision = stop(st);
    if (out.decision.stop) {
        out.result = StepResult::stopped;
        return out;
    }

    // Freeze the limiter after the set drop, or when the residual has stalled: no gain of
    // 0.1 order over `freeze_limiter_stall` iterations, once it has fallen one order below
    // its peak (a plateau before that is the start-up transient, shocks still moving: a
    // limiter frozen there holds a solution far from the final one, and the transonic
    // NACA 0012 on the finest slab then crawls at a cut CFL number).
    if (res < next.stall_best - 0.1) {
        next.stall_best = res;
        next.stall_since = it.iteration;
    }
    const bool stalled = s.freeze_limiter_stall > 0 && !first_order && drop >= 1.0 &&
                         it.iteration - next.stall_since >= s.freeze_limiter_stall;
    if (!next.limiter_frozen &&
        ((s.freeze_limiter_drop > 0 && drop >= s.freeze_limiter_drop) || stalled)) {
        op_.freeze_limiter(true);
        next.limiter_frozen = true;
        next.stall_best = res;
        next.stall_since = it.iteration;
    } else if (next.limiter_frozen && s.freeze_limiter_stall > 0 && !first_order &&
               (it.iteration - next.cycle_since >= s.freeze_limiter_stall ||
                it.iteration - next.stall_since >= 2 * s.freeze_limiter_stall) &&
               next.cfl_cap > s.cfl_initial) {
        // No new lowest residual for as many iterations with the operator fixed, or less than
        // 0.1 order gained in twice as many: the first-order implicit operator does not steer
        // the second-order residual at this CFL number (a defect-correction cycle; the Ranger
        // with a deflected elevator crept 0.01 order in 250 iterations at CFL 10 and fell 2
        // orders in 10 at CFL 5). A smaller CFL number damps it.
        next.cfl_cap = std::max(s.cfl_initial, 0.1 * next.cfl_cap);
        next.cfl = std::min(next.cfl, next.cfl_cap);
        next.cycle_since = it.iteration;
        next.stall_best = res;
        next.stall_since = it.iteration;
    }

    // CFL: grow while the residual falls, cut when it rises.
    if (finite(next.previous_log10_residual)) {
        if (res > next.previous_log10_residual + std::log10(s.cfl_cut_trigger))
            next.cfl = std::max(s.cfl_initial * 0.1, next.cfl * s.cfl_cut);
        else
            next.cfl = std::min(next.cfl_cap, next.cfl * s.cfl_growth);
    }
    next.previous_log10_residual = res;
    if (res <= next.best_log10_residual + 0.5 && it.iteration % 5 == 0) {
        std::copy(U.data(), U.data() + U.size(), U_good_.begin());
        next.cfl_good = next.cfl;
    }
    it = std::move(next);

    // (V / dt + D + dR/dU) dU = -R* with dt_i = CFL V_i / lambda_i; or the last step's matrix
    // and preconditioner when the caller asks for them and they are current.
    if (!(terms.reuse_matrix && matrix_current_ && !first_order)) {
        matrix_current_ = false;
        op.jacobian(U, J_);
        J_.flush_diagonals();
        if (terms.diagonal.empty()) {
            for (Index i = 0; i < n_owned; ++i)
                J_.add_to_diagonal(i, lambda_[static_cast<std::size_t>(i)] / it.cfl);
        } else {
            for (Index i = 0; i < n_owned; ++i)
                J_.add_to_diagonal(i, lambda_[static_cast<std::size_t>(i)] / it.cfl +
                                          terms.diagonal[static_cast<std::size_t>(i)]);
        }
        op.apply_wall_tangency(lambda_, it.cfl, J_);
        // A singular pivot on any process sends every process back (the same decision on all).
        std::string pivot_error;
        try {
            precond_->factorize(J_);
        } catch (const SingularBlockError& e) {
            // Where the node is, its dual volume and whether its block holds a non-finite
            // entry: a singular block at a small CFL number points at the geometry there.
            const Index r = e.row();
            std::string at;
            if (r >= 0 && r < domain_.mesh->n_nodes()) {
                const auto x = domain_.mesh->node(r);
                const Mat5 b = J_.block(J_.diagonal(r));
                at = fmt::format(
                    "; node at ({:.4g}, {:.4g}, {:.4g}) in the mesh's coordinates, dual volume "
                    "{:.3g}{}",
                    x[0], x[1], x[2], domain_.dual->dual_volumes[static_cast<std::size_t>(r)],
                    b.allFinite() ? "" : ", its block not finite");
            }
            pivot_error = e.what() + at;
        } catch (const NumericalError& e) {
            pivot_error = e.what();
        }
        if (comm_.max(pivot_error.empty() ? 0.0 : 1.0) > 0.0)
            return back_off(pivot_error.empty() ? "singular ILU pivot on another process"
                                                : pivot_error);
        matrix_current_ = true;
    }
    // J dU = R* (R*'s owned columns are the right-hand side), then U -= dU.
    std::fill(dU_.begin(), dU_.end(), 0.0);
    const KrylovResult kr = krylov_.solve(
        J_, *precond_, std::span<const double>(R_.data(), static_cast<std::size_t>(R_.size())), dU_,
        comm_, *domain_.halo, s.linear);
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
        const Vec5 W = primitive(U.col(i), gamma);
        const Vec5 Wn = primitive(U.col(i) + d, gamma);
        const double change =
            std::max(std::abs(Wn[0] - W[0]) / W[0], std::abs(Wn[4] - W[4]) / W[4]);
        double omega = 1.0;
        if (!(Wn[0] > 0.0 && Wn[4] > 0.0) || change > 0.2)
            omega = std::min(1.0, 0.2 / std::max(change, 1e-300));
        U.col(i) += omega * d;
        const Vec5 Wc = primitive(U.col(i), gamma);
        if (!(Wc[0] > 0.0 && Wc[4] > 0.0)) bad = true;
    }
    if (comm_.max(bad ? 1.0 : 0.0) > 0.0) return back_off("non-physical state after the update");
    exchange(U);
    ++it.iteration;
    out.result = StepResult::updated;
    return out;
}

}  // namespace manta::euler
