/// @file launched_source.cpp
/// The Euler source whose evaluations run as jobs through a launcher (launched_source.hpp).

#include "manta/euler/launched_source.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/process.hpp"
#include "manta/euler/source.hpp"

namespace manta::euler {

namespace {

constexpr double rad_to_deg = 57.29577951308232;

/// The summary of a finished `manta cfd` run folder, or null when there is none (or unreadable).
nlohmann::json read_summary(const std::filesystem::path& folder) {
    std::ifstream in(folder / "summary.json");
    if (!in) return nullptr;
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception&) {
        return nullptr;
    }
}

}  // namespace

aero::SourceResult source_result(const ForceCoefficients& f) {
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

LaunchedEulerSource::LaunchedEulerSource(std::filesystem::path mesh, std::filesystem::path config,
                                         LaunchOptions options)
    : mesh_(std::move(mesh)), config_(std::move(config)), options_(std::move(options)) {
    if (options_.executable.empty())
        throw InputError("launched euler source: no manta executable given");
    if (options_.work_dir.empty()) throw InputError("launched euler source: no work folder given");
    fingerprint_ = EulerSource::from_files(mesh_, config_)->fingerprint();
    // Converged samples of earlier runs, for warm starts.
    std::error_code ec;
    if (std::filesystem::is_directory(options_.work_dir, ec)) {
        for (const auto& e : std::filesystem::directory_iterator(options_.work_dir, ec)) {
            const nlohmann::json s = read_summary(e.path());
            if (s.is_null() || !s.value("converged", false) || !s.contains("flow")) continue;
            const auto& fl = s["flow"];
            done_.push_back({fl.value("mach", 0.0), fl.value("alpha_deg", 0.0) / rad_to_deg,
                             fl.value("beta_deg", 0.0) / rad_to_deg, e.path()});
        }
    }
}

std::filesystem::path LaunchedEulerSource::sample_folder(double mach, double alpha,
                                                         double beta) const {
    return options_.work_dir /
           fmt::format("M{:.6f}_a{:+.6f}_b{:+.6f}", mach, alpha * rad_to_deg, beta * rad_to_deg);
}

std::vector<std::string> LaunchedEulerSource::command(const aero::AeroQuery<double>& q,
                                                      const std::filesystem::path& initial) const {
    std::vector<std::string> w = options_.launcher;
    w.push_back(options_.executable.string());
    w.insert(w.end(), {"cfd", "--mesh", mesh_.string()});
    if (!config_.empty()) w.insert(w.end(), {"--config", config_.string()});
    // Exact decimal text of the query's values (round trip), so the job solves this query.
    w.insert(w.end(), {"--mach", fmt::format("{}", q.mach), "--alpha-deg",
                       fmt::format("{}", q.alpha * rad_to_deg), "--beta-deg",
                       fmt::format("{}", q.beta * rad_to_deg), "--out",
                       sample_folder(q.mach, q.alpha, q.beta).string()});
    if (!initial.empty()) w.insert(w.end(), {"--initial", initial.string()});
    return w;
}

std::filesystem::path LaunchedEulerSource::nearest_done(const aero::AeroQuery<double>& q) const {
    std::lock_guard lock(mutex_);
    const Done* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    for (const Done& d : done_) {
        // The distance of EulerSource's warm start: degrees, and Mach over 0.05.
        const double dist = std::hypot((d.alpha - q.alpha) * rad_to_deg,
                                       (d.beta - q.beta) * rad_to_deg, (d.mach - q.mach) / 0.05);
        if (dist < best_d) {
            best_d = dist;
            best = &d;
        }
    }
    return best ? best->folder / "restart.bin" : std::filesystem::path{};
}

aero::SourceResult LaunchedEulerSource::evaluate(const aero::AeroQuery<double>& q,
                                                 const aero::FlowConditions& /*conditions*/) const {
    if (q.p_hat != 0.0 || q.q_hat != 0.0 || q.r_hat != 0.0 || q.alpha_dot_hat != 0.0 ||
        q.beta_dot_hat != 0.0 || q.elevator != 0.0 || q.aileron != 0.0 || q.rudder != 0.0)
        throw InputError(
            "euler source with a launcher: rotation rates and control deflections are not "
            "passed to manta cfd jobs yet; run those samples without `launcher:` (in process)");
    const std::filesystem::path folder = sample_folder(q.mach, q.alpha, q.beta);
    const std::string where =
        fmt::format("euler sample at M {:g}, alpha {:.4g} deg, beta {:.4g} deg", q.mach,
                    q.alpha * rad_to_deg, q.beta * rad_to_deg);
    nlohmann::json s = read_summary(folder);
    if (s.is_null() || !s.value("converged", false)) {
        // The folder's own restart file, when a killed job left one, wins over --initial
        // (manta cfd resumes from it).
        const std::vector<std::string> cmd = command(q, nearest_done(q));
        std::error_code ec;
        std::filesystem::create_directories(folder, ec);
        const std::filesystem::path log = folder / "job.log";
        const core::ProcessResult r = core::run_process(cmd, log, options_.environment);
        if (r.exit_code != 0)
            throw ConvergenceError(fmt::format("{}: the job exited with status {} (log {}: {})",
                                               where, r.exit_code, log.string(), r.last_line));
        s = read_summary(folder);
        if (s.is_null())
            throw ConvergenceError(fmt::format("{}: the job wrote no readable {}", where,
                                               (folder / "summary.json").string()));
    }
    if (!s.value("converged", false))
        throw ConvergenceError(fmt::format("{}: not converged: {} ({})", where,
                                           s.value("reason", std::string("?")),
                                           (folder / "summary.json").string()));
    const auto& c = s.at("coefficients");
    ForceCoefficients f;
    f.CL = c.at("CL");
    f.CD = c.at("CD");
    f.CY = c.at("CY");
    f.CFx = c.at("CFx");
    f.CFy = c.at("CFy");
    f.CFz = c.at("CFz");
    f.CMx = c.at("CMx");
    f.CMy = c.at("CMy");
    f.CMz = c.at("CMz");
    {
        std::lock_guard lock(mutex_);
        done_.push_back({q.mach, q.alpha, q.beta, folder});
    }
    return source_result(f);
}

}  // namespace manta::euler
