/// @file source.cpp
/// The Euler solver behind aero::AeroSource (source.hpp).

#include "manta/euler/source.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/version.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/output.hpp"

namespace manta::euler {

EulerSource::EulerSource(mesh::Mesh mesh, CaseSetup setup, std::string label)
    : mesh_(std::move(mesh)), dual_(mesh::compute_dual_metrics(mesh_)), setup_(std::move(setup)) {
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
        "gamma={} drop={} ref=({},{},{},{},{},{})",
        core::version(), label, mesh_fingerprint(mesh_, ids, mesh_.n_nodes(), comm), roles, o.order,
        o.flux.scheme == FluxScheme::roe ? std::string("roe")
        : o.flux.scheme == FluxScheme::hllc
            ? std::string("hllc")
            : fmt::format("jst(k2={},k4={})", o.flux.jst_k2, o.flux.jst_k4),
        o.strong_walls() ? "strong" : "weak", o.flux.low_mach_fix,
        o.gradient == GradientMethod::least_squares ? "lsq" : "gg", o.limiter, o.venkatakrishnan_k,
        o.flux.entropy_fix, setup_.flow.gamma, s.residual_drop, r.area, r.chord, r.span,
        r.moment_point.x(), r.moment_point.y(), r.moment_point.z());
}

std::unique_ptr<EulerSource> EulerSource::from_files(const std::filesystem::path& mesh,
                                                     const std::filesystem::path& config) {
    CfdConfig cfg = config.empty() ? CfdConfig{} : read_cfd_config(config);
    apply_mesh_companion(cfg, mesh);
    CaseMesh m = read_case_mesh(mesh);
    CaseSetup setup = case_setup(cfg);
    setup.roles = resolve_roles(m.mesh, cfg);
    return std::make_unique<EulerSource>(std::move(m.mesh), std::move(setup),
                                         mesh.filename().string());
}

EulerSourceStats EulerSource::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

aero::SourceResult EulerSource::evaluate(const aero::AeroQuery<double>& q,
                                         const aero::FlowConditions& /*conditions*/) const {
    if (q.p_hat != 0.0 || q.q_hat != 0.0 || q.r_hat != 0.0 || q.alpha_dot_hat != 0.0 ||
        q.beta_dot_hat != 0.0)
        throw InputError(
            "euler source: rotation rates need a moving mesh, which this version's Euler solver "
            "does not have; take the dynamic derivatives from the vortex-lattice source");
    if (q.elevator != 0.0 || q.aileron != 0.0 || q.rudder != 0.0)
        throw InputError(
            "euler source: control deflections need a deforming mesh, which this version's Euler "
            "solver does not have; take the control increments from the vortex-lattice source");
    CaseSetup setup = setup_;
    setup.flow.mach = q.mach;
    setup.flow.alpha = q.alpha;
    setup.flow.beta = q.beta;
    const Domain domain{&mesh_, &dual_, mesh_.n_nodes(), &halo_};
    SteadySolver solver(domain, comm_, setup);

    // Warm start from the nearest converged solution (distance in degrees and Mach / 0.05).
    bool warm = false;
    {
        std::lock_guard lock(mutex_);
        const Cached* best = nullptr;
        double best_d = std::numeric_limits<double>::infinity();
        for (const Cached& c : cache_) {
            const double d =
                std::hypot((c.alpha - q.alpha) * 57.29577951308232,
                           (c.beta - q.beta) * 57.29577951308232, (c.mach - q.mach) / 0.05);
            if (d < best_d) {
                best_d = d;
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
    const SolveOutcome oc = solver.solve();
    if (!oc.converged)
        throw ConvergenceError(fmt::format(
            "euler source at M {:g}, alpha {:.4g} deg, beta {:.4g} "
            "deg: {}",
            q.mach, q.alpha * 57.29577951308232, q.beta * 57.29577951308232, oc.reason));
    {
        std::lock_guard lock(mutex_);
        ++stats_.evaluations;
        stats_.warm_starts += warm ? 1 : 0;
        stats_.iterations += oc.iterations;
        cache_.push_back({q.mach, q.alpha, q.beta, solver.iteration_state().peak_log10_residual,
                          solver.state()});
        if (cache_.size() > cache_size_) cache_.erase(cache_.begin());
    }
    const ForceCoefficients& f = oc.forces;
    aero::SourceResult r;
    const Eigen::Vector3d F = core::body_from_geometry(Eigen::Vector3d(f.CFx, f.CFy, f.CFz));
    const Eigen::Vector3d M = core::body_from_geometry(Eigen::Vector3d(f.CMx, f.CMy, f.CMz));
    r.body.CX = F.x();
    r.body.CY = F.y();
    r.body.CZ = F.z();
    r.body.Cl = M.x();
    r.body.Cm = M.y();
    r.body.Cn = M.z();
    r.wind.CL = f.CL;
    r.wind.CD = f.CD;
    r.wind.CY = f.CY;
    r.CD_induced = f.CD;
    r.CD_profile = 0.0;
    return r;
}

}  // namespace manta::euler
