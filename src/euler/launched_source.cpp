/// @file launched_source.cpp
/// The Euler source whose evaluations run as jobs through a launcher (launched_source.hpp).

#include "manta/euler/launched_source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/process.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/deflection.hpp"
#include "manta/euler/rotating_frame.hpp"
#include "manta/euler/source.hpp"

namespace manta::euler {

namespace {

constexpr double rad_to_deg = 57.29577951308232;
constexpr std::array<const char*, 3> rate_names{"p_hat", "q_hat",
                                                "r_hat"};  ///< summary.json `rates`

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

/// A value of a summary's object `key` (0 when absent: summaries before rates and deflections).
double summary_value(const nlohmann::json& s, const char* key, const char* name) {
    if (!s.contains(key) || !s[key].is_object()) return 0.0;
    const auto& o = s[key];
    return o.contains(name) && o[name].is_number() ? o[name].get<double>() : 0.0;
}

BodyRates query_rates(const aero::AeroQuery<double>& q) {
    return {q.p_hat, q.q_hat, q.r_hat};
}
ModeDeflections query_deflections(const aero::AeroQuery<double>& q) {
    return {q.elevator, q.aileron, q.rudder};
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
    // The control surfaces the jobs deflect (configuration, then the mesh's companion), as
    // EulerSource::from_files reads them.
    CfdConfig cfg = config_.empty() ? CfdConfig{} : read_cfd_config(config_);
    apply_mesh_companion(cfg, mesh_);
    surfaces_ = cfg.control_surfaces;
    config_label_ =
        config_.empty() ? std::string("the default CFD configuration") : config_.string();
    // Converged samples of earlier runs, for warm starts.
    std::error_code ec;
    if (std::filesystem::is_directory(options_.work_dir, ec)) {
        for (const auto& e : std::filesystem::directory_iterator(options_.work_dir, ec)) {
            const nlohmann::json s = read_summary(e.path());
            if (s.is_null() || !s.value("converged", false) || !s.contains("flow")) continue;
            const auto& fl = s["flow"];
            Done d{fl.value("mach", 0.0),
                   fl.value("alpha_deg", 0.0) / rad_to_deg,
                   fl.value("beta_deg", 0.0) / rad_to_deg,
                   {},
                   {},
                   e.path()};
            for (std::size_t k = 0; k < 3; ++k) {
                d.rates[k] = summary_value(s, "rates", rate_names[k]);
                d.deflection[k] =
                    summary_value(s, "deflections_deg", deflection_modes[k]) / rad_to_deg;
            }
            done_.push_back(std::move(d));
        }
    }
}

bool LaunchedEulerSource::has_control(const std::string& mode) const {
    return std::any_of(surfaces_.begin(), surfaces_.end(),
                       [&](const meshmotion::ControlSurfaceSpec& s) { return s.mode == mode; });
}

std::filesystem::path LaunchedEulerSource::sample_folder(const aero::AeroQuery<double>& q) const {
    std::string name =
        fmt::format("M{:.6f}_a{:+.6f}_b{:+.6f}", q.mach, q.alpha * rad_to_deg, q.beta * rad_to_deg);
    if (rotates(query_rates(q)))
        name += fmt::format("_p{:+.6f}_q{:+.6f}_r{:+.6f}", q.p_hat, q.q_hat, q.r_hat);
    if (deflects(query_deflections(q)))
        name += fmt::format("_de{:+.6f}_da{:+.6f}_dr{:+.6f}", q.elevator * rad_to_deg,
                            q.aileron * rad_to_deg, q.rudder * rad_to_deg);
    return options_.work_dir / name;
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
                       fmt::format("{}", q.beta * rad_to_deg)});
    // Rates and deflections only where they are not 0: a static sample's job as before them.
    const BodyRates rates = query_rates(q);
    const std::array<const char*, 3> rate_options{"--p-hat", "--q-hat", "--r-hat"};
    for (std::size_t k = 0; k < 3; ++k)
        if (rates[k] != 0.0) w.insert(w.end(), {rate_options[k], fmt::format("{}", rates[k])});
    const ModeDeflections d = query_deflections(q);
    for (std::size_t k = 0; k < 3; ++k)
        if (d[k] != 0.0)
            w.insert(w.end(), {fmt::format("--{}-deg", deflection_modes[k]),
                               fmt::format("{}", d[k] * rad_to_deg)});
    w.insert(w.end(), {"--out", sample_folder(q).string()});
    if (!initial.empty()) w.insert(w.end(), {"--initial", initial.string()});
    return w;
}

std::filesystem::path LaunchedEulerSource::nearest_done(const aero::AeroQuery<double>& q) const {
    std::lock_guard lock(mutex_);
    const BodyRates rates = query_rates(q);
    const ModeDeflections deflection = query_deflections(q);
    const Done* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    for (const Done& c : done_) {
        // The distance of EulerSource's warm start: degrees, Mach over 0.05, rates over 0.01
        // and deflections in degrees (squared, summed in its order).
        double d2 = std::pow((c.alpha - q.alpha) * rad_to_deg, 2) +
                    std::pow((c.beta - q.beta) * rad_to_deg, 2) +
                    std::pow((c.mach - q.mach) / 0.05, 2);
        for (std::size_t k = 0; k < 3; ++k)
            d2 += std::pow((c.rates[k] - rates[k]) / 0.01, 2) +
                  std::pow((c.deflection[k] - deflection[k]) * rad_to_deg, 2);
        if (d2 < best_d) {
            best_d = d2;
            best = &c;
        }
    }
    return best ? best->folder / "restart.bin" : std::filesystem::path{};
}

aero::SourceResult LaunchedEulerSource::evaluate(const aero::AeroQuery<double>& q,
                                                 const aero::FlowConditions& /*conditions*/) const {
    if (q.alpha_dot_hat != 0.0 || q.beta_dot_hat != 0.0)
        throw InputError(fmt::format(
            "euler source with a launcher: alpha_dot_hat {:g}, beta_dot_hat {:g}: a steady "
            "manta cfd job gives the rotation rates p_hat, q_hat, r_hat only; expected 0 (the "
            "alpha_dot and beta_dot derivatives need a time-accurate solution)",
            q.alpha_dot_hat, q.beta_dot_hat));
    const BodyRates rates = query_rates(q);
    const ModeDeflections deflection = query_deflections(q);
    // A deflection of a mode no surface has: refused before a job, as EulerSource refuses it.
    DeflectionNaming naming;
    naming.names = {"elevator deflection", "aileron deflection", "rudder deflection"};
    naming.config = config_label_;
    (void)surface_deflections(surfaces_, deflection, naming);

    const std::filesystem::path folder = sample_folder(q);
    const std::string where = fmt::format(
        "euler sample at M {:g}, alpha {:.4g} deg, beta {:.4g} deg{}{}", q.mach,
        q.alpha * rad_to_deg, q.beta * rad_to_deg,
        rotates(rates)
            ? fmt::format(", p_hat {:g}, q_hat {:g}, r_hat {:g}", q.p_hat, q.q_hat, q.r_hat)
            : std::string(),
        deflects(deflection)
            ? fmt::format(", elevator {:.4g} deg, aileron {:.4g} deg, rudder {:.4g} deg",
                          q.elevator * rad_to_deg, q.aileron * rad_to_deg, q.rudder * rad_to_deg)
            : std::string());
    nlohmann::json s = read_summary(folder);
    if (s.is_null() || !s.value("converged", false)) {
        // The folder's own restart file, when a killed job left one, wins over --initial
        // (manta cfd resumes from it).
        const std::filesystem::path initial = nearest_done(q);
        std::vector<std::string> cmd = command(q, initial);
        std::error_code ec;
        std::filesystem::create_directories(folder, ec);
        const std::filesystem::path log = folder / "job.log";
        core::ProcessResult r = core::run_process(cmd, log, options_.environment);
        if ((r.exit_code != 0 || !read_summary(folder).value("converged", false)) &&
            !initial.empty()) {
            // A start from another sample's solution can fail where the free stream does not
            // (EulerSource does the same): the job again from the free stream (--restart: not
            // from the failed run's restart file), the warm job's log kept as job_warm.log.
            std::filesystem::rename(log, folder / "job_warm.log", ec);
            cmd = command(q, {});
            cmd.push_back("--restart");
            r = core::run_process(cmd, log, options_.environment);
        }
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
    {
        // The folder's name rounds to 6 decimals: its summary must be of this very query.
        const auto& fl = s.at("flow");
        bool same = std::abs(fl.value("mach", -1.0) - q.mach) <= 1e-12 &&
                    std::abs(fl.value("alpha_deg", 1e9) - q.alpha * rad_to_deg) <= 1e-9 &&
                    std::abs(fl.value("beta_deg", 1e9) - q.beta * rad_to_deg) <= 1e-9;
        for (std::size_t k = 0; k < 3; ++k)
            same = same && std::abs(summary_value(s, "rates", rate_names[k]) - rates[k]) <= 1e-12 &&
                   std::abs(summary_value(s, "deflections_deg", deflection_modes[k]) -
                            deflection[k] * rad_to_deg) <= 1e-9;
        if (!same)
            throw InputError(fmt::format(
                "{}: {} holds the solution of another flow condition (Mach {}, alpha {} deg, "
                "beta {} deg, rates {}, deflections {}); expected this sample's, or remove the "
                "folder",
                where, (folder / "summary.json").string(), fl.value("mach", 0.0),
                fl.value("alpha_deg", 0.0), fl.value("beta_deg", 0.0),
                s.contains("rates") ? s["rates"].dump() : std::string("none"),
                s.contains("deflections_deg") ? s["deflections_deg"].dump() : std::string("none")));
    }
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
        done_.push_back({q.mach, q.alpha, q.beta, rates, deflection, folder});
    }
    return source_result(f);
}

}  // namespace manta::euler
