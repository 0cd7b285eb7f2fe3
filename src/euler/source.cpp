/// @file source.cpp
/// The Euler solver behind aero::AeroSource (source.hpp).

#include "manta/euler/source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/version.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/deflection.hpp"
#include "manta/euler/launched_source.hpp"
#include "manta/euler/output.hpp"

namespace manta::euler {

namespace {

constexpr double deg_per_rad = 57.29577951308232;

}  // namespace

EulerSource::EulerSource(mesh::Mesh mesh, CaseSetup setup, std::string label,
                         std::vector<meshmotion::ControlSurfaceSpec> control_surfaces,
                         std::string config_label)
    : mesh_(std::move(mesh)),
      dual_(mesh::compute_dual_metrics(mesh_)),
      setup_(std::move(setup)),
      surfaces_(std::move(control_surfaces)),
      config_label_(std::move(config_label)),
      label_(label) {
    if (static_cast<int>(setup_.roles.size()) != mesh_.n_markers())
        throw InputError(fmt::format("{}: {} boundary roles for {} markers", label,
                                     setup_.roles.size(), mesh_.n_markers()));
    setup_.spatial.validate();
    setup_.solver.validate();
    std::string roles;
    for (std::size_t m = 0; m < setup_.roles.size(); ++m)
        roles +=
            fmt::format("{}{}={}", m ? "," : "", mesh_.markers()[m], euler::name(setup_.roles[m]));
    const SpatialOptions& o = setup_.spatial;
    const SolverSettings& s = setup_.solver;
    const ReferenceValues& r = setup_.reference;
    parallel::SerialCommunicator comm;
    std::vector<std::int64_t> ids(static_cast<std::size_t>(mesh_.n_nodes()));
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::int64_t>(i);
    fingerprint_ = fmt::format(
        "euler {} mesh={} [{}] roles={} order={} flux={} wall={} low_mach={} gradient={} "
        "limiter={} K={} fix={} "
        "gamma={} drop={} ref=({},{},{},{},{},{}){}",
        core::version(), label, mesh_fingerprint(mesh_, ids, mesh_.n_nodes(), comm), roles, o.order,
        o.flux.scheme == FluxScheme::roe ? std::string("roe")
        : o.flux.scheme == FluxScheme::hllc
            ? std::string("hllc")
            : fmt::format("jst(k2={},k4={})", o.flux.jst_k2, o.flux.jst_k4),
        o.strong_walls() ? "strong" : "weak", o.flux.low_mach_fix,
        o.gradient == GradientMethod::least_squares ? "lsq" : "gg", o.limiter, o.venkatakrishnan_k,
        o.flux.entropy_fix, setup_.flow.gamma, s.residual_drop, r.area, r.chord, r.span,
        r.moment_point.x(), r.moment_point.y(), r.moment_point.z(),
        r.half_model ? " half-model" : "");
    // Rotation rates in the rotating frame (rotating_frame.hpp) and deflections by the control
    // surfaces below: samples of sources before them (which refused both) carry other text.
    fingerprint_ += " rates=rotating-frame-1 surfaces=[";
    for (const auto& c : surfaces_)
        fingerprint_ += fmt::format("{}:{}:{},{},{}:{},{},{}:{}:{}:{}:{}:{};", c.mode, c.marker,
                                    c.hinge[0].x(), c.hinge[0].y(), c.hinge[0].z(), c.hinge[1].x(),
                                    c.hinge[1].y(), c.hinge[1].z(), c.gain,
                                    c.hinge_tolerance.value_or(-1), c.hinge_blend.value_or(-1),
                                    c.edge_blend.value_or(-1), c.cutoff.value_or(-1));
    fingerprint_ += "]";
    // Deflections slide on the symmetry planes (deflection.hpp); sources before that held the
    // planes' nodes near a surface as fixed boundary nodes.
    if (!surfaces_.empty() && std::find(setup_.roles.begin(), setup_.roles.end(),
                                        BoundaryKind::symmetry) != setup_.roles.end())
        fingerprint_ += " deflection=sliding-planes";
    motion_ = deflection_motion(mesh_, setup_.roles, r.moment_point, surfaces_, config_label_);
}

std::unique_ptr<EulerSource> EulerSource::from_files(const std::filesystem::path& mesh,
                                                     const std::filesystem::path& config) {
    CfdConfig cfg = config.empty() ? CfdConfig{} : read_cfd_config(config);
    apply_mesh_companion(cfg, mesh);
    CaseMesh m = read_case_mesh(mesh);
    orient_mesh(m.mesh, cfg);
    CaseSetup setup = case_setup(cfg);
    setup.roles = resolve_roles(m.mesh, cfg);
    auto source = std::make_unique<EulerSource>(
        std::move(m.mesh), std::move(setup), mesh.filename().string(), cfg.control_surfaces,
        config.empty() ? std::string("the default CFD configuration") : config.string());
    source->set_unsteady_settings(cfg.mach, cfg.unsteady);
    source->set_unsteady_mesh_motion(cfg.mesh_motion, cfg.rigid_radius, cfg.fixed_radius);
    return source;
}

bool EulerSource::has_control(const std::string& mode) const {
    return std::any_of(surfaces_.begin(), surfaces_.end(),
                       [&](const meshmotion::ControlSurfaceSpec& s) { return s.mode == mode; });
}

EulerSourceStats EulerSource::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

aero::SourceResult EulerSource::evaluate(const aero::AeroQuery<double>& q,
                                         const aero::FlowConditions& /*conditions*/) const {
    if (q.alpha_dot_hat != 0.0 || q.beta_dot_hat != 0.0)
        throw InputError(fmt::format(
            "euler source: alpha_dot_hat {:g}, beta_dot_hat {:g}: the steady evaluation gives "
            "the rotation rates p_hat, q_hat, r_hat only; expected 0 (the alpha_dot and beta_dot "
            "derivatives need a time-accurate solution)",
            q.alpha_dot_hat, q.beta_dot_hat));
    const std::array<double, 3> rates{q.p_hat, q.q_hat, q.r_hat};
    const std::array<double, 3> deflection{q.elevator, q.aileron, q.rudder};
    // Control deflections: each surface by gain times its mode's deflection, on this
    // evaluation's own coordinates and metrics (deflection.hpp).
    DeflectionNaming naming;
    naming.names = {"elevator deflection", "aileron deflection", "rudder deflection"};
    naming.config = config_label_;
    const bool deflected = deflects(deflection);
    std::optional<mesh::Mesh> own_mesh;
    std::optional<mesh::DualMetrics> own_dual;
    if (deflected) {
        own_mesh.emplace(mesh_);
        own_dual.emplace(dual_);
        deflect_mesh(*own_mesh, *own_dual, motion_.get(), surfaces_, deflection, naming);
    }
    const mesh::Mesh& m = deflected ? *own_mesh : mesh_;
    const mesh::DualMetrics& dual = deflected ? *own_dual : dual_;

    CaseSetup setup = setup_;
    setup.flow.mach = q.mach;
    setup.flow.alpha = q.alpha;
    setup.flow.beta = q.beta;
    const Domain domain{&m, &dual, m.n_nodes(), &halo_};
    SteadySolver solver(domain, comm_, setup);
    std::optional<RotatingFrame> frame;
    if (rotates(rates)) {
        // The frame turning with the body (rotating_frame.hpp, shared with manta cfd --p-hat);
        // a symmetry plane mirrors the flow, so the rotation must be about its normal.
        const ReferenceValues& ref = setup_.reference;
        frame = body_rate_frame(rates, q.mach, ref.span, ref.chord, ref.moment_point);
        if (const auto c = symmetry_crossing(*frame, setup_.roles, dual_))
            throw InputError(symmetry_crossing_message("euler source", {"p_hat", "q_hat", "r_hat"},
                                                       rates, label_, mesh_.markers()[c->marker],
                                                       c->normal, static_cast<long long>(c->node)));
        solver.set_rotating_frame(*frame);
    }

    // Warm start from the nearest converged solution (distance in degrees, Mach / 0.05 and
    // rates / 0.01).
    bool warm = false;
    {
        std::lock_guard lock(mutex_);
        const Cached* best = nullptr;
        double best_d = std::numeric_limits<double>::infinity();
        for (const Cached& c : cache_) {
            double d2 = std::pow((c.alpha - q.alpha) * deg_per_rad, 2) +
                        std::pow((c.beta - q.beta) * deg_per_rad, 2) +
                        std::pow((c.mach - q.mach) / 0.05, 2);
            for (std::size_t k = 0; k < 3; ++k)
                d2 += std::pow((c.rates[k] - rates[k]) / 0.01, 2) +
                      std::pow((c.deflection[k] - deflection[k]) * deg_per_rad, 2);
            if (d2 < best_d) {
                best_d = d2;
                best = &c;
            }
        }
        if (best) {
            // The residual drop counts from the peak of the cold run that started the chain, so
            // a warm start converges to the same level, not 6 orders below its own small start.
            solver.warm_start(best->U, best->peak_log10_residual);
            warm = true;
        }
    }
    SolveOutcome oc;
    std::string warm_failure;
    try {
        oc = solver.solve();
        if (!oc.converged && warm) warm_failure = oc.reason;
    } catch (const ConvergenceError& e) {
        if (!warm) throw;
        warm_failure = e.what();
    }
    if (!warm_failure.empty()) {
        // A start from another condition's solution can fail where the free stream does not
        // (the coarse Ranger at M 0.3, alpha 2 deg, started from M 0.2, alpha 6 deg, diverged
        // with six back-offs): solve again from the free stream, and say both when that fails.
        SteadySolver cold(domain, comm_, setup);
        if (frame) cold.set_rotating_frame(*frame);
        try {
            oc = cold.solve();
        } catch (const ConvergenceError& e) {
            throw ConvergenceError(
                fmt::format("{} (from the free stream; warm-started: {})", e.what(), warm_failure));
        }
        if (!oc.converged)
            oc.reason += " (from the free stream; warm-started: " + warm_failure + ")";
        warm = false;
        {
            std::lock_guard lock(mutex_);
            ++stats_.cold_retries;
        }
        return finish(q, rates, deflection, oc, cold, warm);  // the cold solver's state
    }
    return finish(q, rates, deflection, oc, solver, warm);
}

aero::SourceResult EulerSource::finish(const aero::AeroQuery<double>& q,
                                       const std::array<double, 3>& rates,
                                       const std::array<double, 3>& deflection,
                                       const SolveOutcome& oc, const SteadySolver& solver,
                                       bool warm) const {
    if (!oc.converged)
        throw ConvergenceError(fmt::format(
            "euler source at M {:g}, alpha {:.4g} deg, beta {:.4g} deg, p_hat {:g}, q_hat {:g}, "
            "r_hat {:g}, elevator {:.4g} deg, aileron {:.4g} deg, rudder {:.4g} deg: {}",
            q.mach, q.alpha * deg_per_rad, q.beta * deg_per_rad, q.p_hat, q.q_hat, q.r_hat,
            q.elevator * deg_per_rad, q.aileron * deg_per_rad, q.rudder * deg_per_rad, oc.reason));
    {
        std::lock_guard lock(mutex_);
        ++stats_.evaluations;
        stats_.warm_starts += warm ? 1 : 0;
        stats_.iterations += oc.iterations;
        cache_.push_back({q.mach, q.alpha, q.beta, rates, deflection,
                          solver.iteration_state().peak_log10_residual, solver.state()});
        if (cache_.size() > cache_size_) cache_.erase(cache_.begin());
    }
    return source_result(oc.forces);
}

}  // namespace manta::euler
