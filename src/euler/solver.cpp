/// @file solver.cpp
/// Settings, the steady solver around `PseudoTimeStep` (pseudo_step.cpp), output fields
/// (solver.hpp, docs/euler.md).

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
    need(preconditioner_blocks >= 0, "preconditioner_blocks", preconditioner_blocks,
         "an integer >= 0 (0: one block per process)");
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
    : step_(domain, comm, setup) {
    const Index n_local = domain.mesh->n_nodes();
    U_.resize(5, n_local);
    const Vec5 U_inf = conservative(step_.free_stream_primitive(), setup.flow.gamma);
    for (Index i = 0; i < n_local; ++i) U_.col(i) = U_inf;
    it_ = step_.initial_state();
    step_.set_backoff_state(U_);
}

void check_state(const NodeStates& U, Index n_local, Index n_owned, double gamma) {
    if (U.cols() != n_local)
        throw InputError(
            fmt::format("initial solution has {} nodes; the mesh has {}", U.cols(), n_local));
    for (Index i = 0; i < n_owned; ++i) {
        const Vec5 W = primitive(U.col(i), gamma);
        if (!(W[0] > 0.0 && W[4] > 0.0 && W.allFinite()))
            throw InputError(fmt::format(
                "initial solution: node {} has density {} and pressure {}; expected positive, "
                "finite values",
                i, W[0], W[4]));
    }
}

void SteadySolver::set_state(const NodeStates& U) {
    const Index n_owned = step_.domain().n_owned;
    check_state(U, U_.cols(), n_owned, setup().flow.gamma);
    U_.leftCols(n_owned) = U.leftCols(n_owned);
    step_.exchange(U_);
    step_.set_backoff_state(U_);
}

void SteadySolver::warm_start(const NodeStates& U, double peak_log10_residual) {
    set_state(U);
    IterationState st = it_;
    st.peak_log10_residual = peak_log10_residual;
    set_iteration_state(st);
}

std::vector<double> pressure_coefficient(const NodeStates& U, const CaseSetup& s) {
    const double gamma = s.flow.gamma;
    const double q = 0.5 * s.flow.mach * s.flow.mach;
    std::vector<double> cp(static_cast<std::size_t>(U.cols()));
    for (Index i = 0; i < U.cols(); ++i)
        cp[static_cast<std::size_t>(i)] = (primitive(U.col(i), gamma)[4] - 1.0 / gamma) / q;
    return cp;
}

std::vector<double> primitive_state(const NodeStates& U, const CaseSetup& s) {
    std::vector<double> w(static_cast<std::size_t>(U.size()));
    for (Index i = 0; i < U.cols(); ++i) {
        const Vec5 W = primitive(U.col(i), s.flow.gamma);
        for (int k = 0; k < 5; ++k) w[5 * static_cast<std::size_t>(i) + k] = W[k];
    }
    return w;
}

std::vector<double> mach_number(const NodeStates& U, const CaseSetup& s) {
    std::vector<double> mach(static_cast<std::size_t>(U.cols()));
    for (Index i = 0; i < U.cols(); ++i) {
        const Vec5 W = primitive(U.col(i), s.flow.gamma);
        mach[static_cast<std::size_t>(i)] = W.segment<3>(1).norm() / sound_speed(W, s.flow.gamma);
    }
    return mach;
}

std::vector<double> SteadySolver::pressure_coefficient() const {
    return euler::pressure_coefficient(U_, setup());
}

std::vector<double> SteadySolver::primitive_state() const {
    return euler::primitive_state(U_, setup());
}

std::vector<double> SteadySolver::mach_number() const {
    return euler::mach_number(U_, setup());
}

std::size_t SteadySolver::memory_bytes() const noexcept {
    return static_cast<std::size_t>(U_.size()) * sizeof(double) + step_.memory_bytes();
}

void SteadySolver::set_rotating_frame(const RotatingFrame& frame) {
    frame_ = frame;
    if (!frame_.active()) {
        step_.set_grid_fluxes(nullptr);
        return;
    }
    const Domain& d = step_.domain();
    rotation_grid_fluxes(*d.mesh, *d.dual, frame_, frame_g_);
    rotation_node_velocities(*d.mesh, frame_, frame_v_);
    step_.set_grid_fluxes(&frame_g_, &frame_v_);
}

void SteadySolver::set_iteration_state(const IterationState& s) {
    it_ = s;
    step_.freeze_limiter(s.limiter_frozen);
}

SolveOutcome SteadySolver::solve(const Monitor& monitor) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const SolverSettings& s = setup().solver;
    const StopRule rule = [&s](const StepStatus& st) { return steady_stop(s, st); };
    SolveOutcome out;
    step_.begin(it_);
    const bool rotating = frame_.active();
    StepTerms terms;
    if (rotating) {
        terms.source = &frame_S_;
        step_.set_grid_fluxes(&frame_g_, &frame_v_);  // this object's arrays (it may have moved)
    }
    const Vec3 u_inf = step_.free_stream_primitive().segment<3>(1);
    const Domain& d = step_.domain();
    while (true) {
        if (rotating) rotation_source(U_, d.dual->dual_volumes, frame_, u_inf, d.n_owned, frame_S_);
        StepOutcome so = step_.step(U_, it_, rule, terms);
        if (so.result == StepResult::backed_off) continue;
        out.residual_drop = so.status.drop;
        out.forces = so.record.forces;
        so.record.wall_s = std::chrono::duration<double>(clock::now() - t0).count();
        if (so.result == StepResult::stopped) {
            out.converged = so.decision.converged;
            out.reason = std::move(so.decision.reason);
            if (monitor) monitor(so.record);
            break;
        }
        if (monitor && !monitor(so.record)) {
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
