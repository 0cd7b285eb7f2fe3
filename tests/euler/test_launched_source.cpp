/// @file test_launched_source.cpp
/// The Euler source whose samples run as `manta cfd` jobs (launched_source.hpp), serial jobs
/// without a launcher, and `manta cfd --p-hat --q-hat --r-hat` (the case driver's rotating
/// frame), on the coarse half wing with a flap of the meshmotion tests, `test::flap_wing(2)` (the
/// aft 25 % of the chord between y = 1 and 2 m, the marker `flap` driven by the elevator; the
/// symmetry plane y = 0, so q_hat is the rate a half model takes):
/// - a static, a deflected (elevator 5 deg), a rotating (q_hat 0.02) and a deflected rotating
///   sample through jobs equal EulerSource::evaluate on the same files in the same order (the
///   same warm starts from the nearest converged sample: the same iterations), coefficients to
///   1e-9; the folders and the jobs' words carry the rates and deflections, the summaries name
///   them (`rates`, `deflections_deg`);
/// - a new source on the same work folder takes the converged samples (no job), and its nearest
///   done sample is measured in (alpha, beta, Mach, rates, deflections);
/// - one-line errors before any job for alpha_dot_hat and a deflection of a mode no surface has;
///   a rotation through the symmetry plane fails in the job (exit 2) and the error names the
///   plane (the log's last line);
/// - `manta cfd`: a restart file of another rate is refused naming both, a warm start from one is
///   taken, a rate with --motion is refused, and the rates are in the restart fingerprint.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <unistd.h>

#include "flap_meshes.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/launched_source.hpp"
#include "manta/euler/source.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
namespace fs = std::filesystem;
constexpr double deg = M_PI / 180.0;

constexpr const char* config_text =
    "markers: {wing: wall, flap: wall, symmetry: symmetry, farfield: farfield}\n"
    "reference: {area: 3, chord: 1, span: 3, moment_point: [0.25, 0, 0]}\n"
    "numerics: {order: 1}\n"
    "solver: {residual_drop: 4}\n"
    "output: {checkpoint_interval_s: 0, volume: false}\n"
    "control_surfaces:\n"
    "  - {mode: elevator, marker: flap, hinge: [[0.75, 1, 0], [0.75, 2, 0]]}\n";

/// The folder with flap.su2 and cfd.yaml (made once per process: CTest runs each test in its own
/// process, several at once).
const fs::path& folder() {
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() /
                           ("manta-euler-launched-source-" + std::to_string(::getpid()));
        fs::remove_all(d);
        fs::create_directories(d);
        const mesh::Mesh m = test::flap_wing(2.0);
        std::printf("flap_wing(2): %d nodes\n", static_cast<int>(m.n_nodes()));
        test::write_su2(m, d / "flap.su2");
        std::ofstream(d / "cfd.yaml") << config_text;
        return d;
    }();
    return dir;
}

euler::LaunchOptions options(const std::string& work) {
    euler::LaunchOptions o;
    o.executable = MANTA_EXE;
    o.work_dir = folder() / work;
    return o;
}

aero::AeroQuery<double> query(double elevator_deg = 0.0, double q_hat = 0.0) {
    aero::AeroQuery<double> q;
    q.mach = 0.3;
    q.alpha = 2.0 * deg;
    q.elevator = elevator_deg * deg;
    q.q_hat = q_hat;
    return q;
}

double max_difference(const aero::SourceResult& a, const aero::SourceResult& b) {
    const double d[] = {a.wind.CL - b.wind.CL, a.wind.CD - b.wind.CD, a.wind.CY - b.wind.CY,
                        a.body.CX - b.body.CX, a.body.CY - b.body.CY, a.body.CZ - b.body.CZ,
                        a.body.Cl - b.body.Cl, a.body.Cm - b.body.Cm, a.body.Cn - b.body.Cn};
    double m = 0.0;
    for (const double x : d) m = std::max(m, std::abs(x));
    return m;
}

nlohmann::json summary(const fs::path& run) {
    std::ifstream in(run / "summary.json");
    return nlohmann::json::parse(in);
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

double seconds(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The four samples, in this order: static, deflected, rotating, deflected and rotating.
const std::vector<aero::AeroQuery<double>>& queries() {
    static const std::vector<aero::AeroQuery<double>> q{query(), query(5.0), query(0.0, 0.02),
                                                        query(5.0, 0.02)};
    return q;
}

TEST(LaunchedEulerSource, JobsWithRatesAndDeflectionsEqualTheInProcessSource) {
    const fs::path mesh = folder() / "flap.su2", config = folder() / "cfd.yaml";
    const euler::LaunchedEulerSource jobs(mesh, config, options("jobs"));
    const auto in_process = euler::EulerSource::from_files(mesh, config);
    EXPECT_EQ(jobs.fingerprint(), in_process->fingerprint());
    EXPECT_TRUE(jobs.has_control("elevator"));
    EXPECT_FALSE(jobs.has_control("aileron"));

    const char* names[] = {"static", "elevator 5 deg", "q_hat 0.02", "elevator 5 deg, q_hat 0.02"};
    int job_iterations = 0;
    for (std::size_t k = 0; k < queries().size(); ++k) {
        const aero::AeroQuery<double>& q = queries()[k];
        aero::SourceResult a, b;
        const double t_job = seconds([&] { a = jobs.evaluate(q, {}); });
        const double t_in = seconds([&] { b = in_process->evaluate(q, {}); });
        const double diff = max_difference(a, b);
        const nlohmann::json s = summary(jobs.sample_folder(q));
        job_iterations += s["iterations"].get<int>();
        std::printf(
            "%-28s job %.2f s, in process %.2f s; CL %.10f Cm %.10f; max |difference| %.3g; %d "
            "iterations\n",
            names[k], t_job, t_in, a.wind.CL, a.body.Cm, diff, s["iterations"].get<int>());
        EXPECT_LT(diff, 1e-9) << names[k];
        EXPECT_NEAR(s["rates"]["q_hat"].get<double>(), q.q_hat, 1e-15) << names[k];
        EXPECT_EQ(s["rates"]["p_hat"].get<double>(), 0.0);
        EXPECT_NEAR(s["deflections_deg"]["elevator"].get<double>(), q.elevator / deg, 1e-12);
    }
    // The same warm starts: the same iterations in all.
    EXPECT_EQ(job_iterations, in_process->stats().iterations);
    EXPECT_EQ(in_process->stats().warm_starts, 3);
    // Rates and deflections move the coefficients (pitch damping, the flap's lift).
    const auto r0 = in_process->evaluate(queries()[0], {});
    const auto rq = in_process->evaluate(queries()[2], {});
    EXPECT_GT(rq.wind.CL, r0.wind.CL);
    EXPECT_LT(rq.body.Cm, r0.body.Cm);

    // The folders and the jobs' words carry the rates and deflections, a static one neither.
    EXPECT_EQ(jobs.sample_folder(queries()[0]).filename().string(),
              "M0.300000_a+2.000000_b+0.000000");
    EXPECT_EQ(jobs.sample_folder(queries()[3]).filename().string(),
              "M0.300000_a+2.000000_b+0.000000_p+0.000000_q+0.020000_r+0.000000_de+5.000000_"
              "da+0.000000_dr+0.000000");
    const std::vector<std::string> w = jobs.command(queries()[3], "init/restart.bin");
    auto after = [&](const std::string& word) {
        const auto it = std::find(w.begin(), w.end(), word);
        return it != w.end() && it + 1 != w.end() ? *(it + 1) : std::string("(none)");
    };
    EXPECT_EQ(after("--q-hat"), "0.02");
    EXPECT_EQ(after("--elevator-deg"), "5");
    EXPECT_EQ(after("--initial"), "init/restart.bin");
    EXPECT_EQ(after("--p-hat"), "(none)");
    EXPECT_EQ(after("--aileron-deg"), "(none)");
    const std::vector<std::string> w0 = jobs.command(queries()[0], {});
    EXPECT_EQ(std::find(w0.begin(), w0.end(), "--q-hat"), w0.end());
    EXPECT_EQ(std::find(w0.begin(), w0.end(), "--elevator-deg"), w0.end());
}

TEST(LaunchedEulerSource, ANewSourceTakesTheConvergedSamplesAndTheirNearest) {
    const fs::path mesh = folder() / "flap.su2", config = folder() / "cfd.yaml";
    {
        const euler::LaunchedEulerSource first(mesh, config, options("again"));
        for (const auto& q : queries()) (void)first.evaluate(q, {});
    }
    const euler::LaunchedEulerSource again(mesh, config, options("again"));
    // Converged: read back, no job (the log is not written again).
    const fs::path log = again.sample_folder(queries()[3]) / "job.log";
    const auto stamp = fs::last_write_time(log);
    const auto size = fs::file_size(log);
    const aero::SourceResult r = again.evaluate(queries()[3], {});
    EXPECT_EQ(fs::last_write_time(log), stamp);
    EXPECT_EQ(fs::file_size(log), size);
    EXPECT_NE(r.wind.CL, 0.0);
    // The nearest in (alpha, beta, Mach, rates, deflections), from the summaries.
    EXPECT_EQ(again.nearest_done(query(0.0, 0.018)),
              again.sample_folder(queries()[2]) / "restart.bin");
    EXPECT_EQ(again.nearest_done(query(4.5)), again.sample_folder(queries()[1]) / "restart.bin");
    EXPECT_EQ(again.nearest_done(query(4.5, 0.018)),
              again.sample_folder(queries()[3]) / "restart.bin");
    EXPECT_EQ(again.nearest_done(query(0.5)), again.sample_folder(queries()[0]) / "restart.bin");
}

// A job warm-started from another sample that fails is run again from the free stream (as
// EulerSource does): the nearest sample's restart file is cut short after it converged, so the
// next sample's job, started with --initial from it, fails; the second job (--restart, no
// --initial) converges and equals the in-process solution from the free stream, and the failed
// job's log is kept as job_warm.log.
TEST(LaunchedEulerSource, AFailedWarmJobRunsAgainFromTheFreeStream) {
    const fs::path mesh = folder() / "flap.su2", config = folder() / "cfd.yaml";
    const euler::LaunchedEulerSource jobs(mesh, config, options("cold_retry"));
    aero::AeroQuery<double> first = query(), second = query();
    second.alpha = 3.0 * deg;
    (void)jobs.evaluate(first, {});
    const fs::path restart = jobs.sample_folder(first) / "restart.bin";
    ASSERT_TRUE(fs::exists(restart));
    fs::resize_file(restart, fs::file_size(restart) / 2);
    const aero::SourceResult a = jobs.evaluate(second, {});
    const auto cold = euler::EulerSource::from_files(mesh, config);
    const aero::SourceResult b = cold->evaluate(second, {});
    EXPECT_LT(max_difference(a, b), 1e-9);
    const fs::path f = jobs.sample_folder(second);
    ASSERT_TRUE(fs::exists(f / "job_warm.log"));
    const std::string warm_log = manta::core::read_file(f / "job_warm.log");
    EXPECT_NE(warm_log.find("the restart file is truncated"), std::string::npos)
        << warm_log.substr(0, 400);
    const nlohmann::json s = summary(f);
    EXPECT_TRUE(s["converged"].get<bool>());
    EXPECT_EQ(s["iterations"].get<int>(), cold->stats().iterations);
}

TEST(LaunchedEulerSource, RefusesBeforeAJobOrNamesTheJobsError) {
    const euler::LaunchedEulerSource jobs(folder() / "flap.su2", folder() / "cfd.yaml",
                                          options("errors"));
    aero::AeroQuery<double> q = query();
    q.alpha_dot_hat = 0.01;
    std::string e = error_of([&] { (void)jobs.evaluate(q, {}); });
    EXPECT_NE(e.find("alpha_dot_hat"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    q = query();
    q.aileron = 2.0 * deg;
    e = error_of([&] { (void)jobs.evaluate(q, {}); });
    EXPECT_NE(e.find("aileron"), std::string::npos) << e;
    EXPECT_NE(e.find("cfd.yaml"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_FALSE(fs::exists(jobs.sample_folder(q)));
    // A roll rate turns the half model through its symmetry plane: the job fails (exit 2).
    q = query();
    q.p_hat = 0.02;
    e = error_of([&] { (void)jobs.evaluate(q, {}); });
    std::printf("p_hat on the half model: %s\n", e.c_str());
    EXPECT_NE(e.find("exited with status 2"), std::string::npos) << e;
    EXPECT_NE(e.find("symmetry plane 'symmetry'"), std::string::npos) << e;
    EXPECT_NE(e.find("--p-hat 0.02"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

euler::CaseInputs inputs(const std::string& run, double q_hat) {
    euler::CaseInputs in;
    in.mesh = folder() / "flap.su2";
    in.config = folder() / "cfd.yaml";
    in.out = folder() / run;
    in.mach = 0.3;
    in.alpha = 2.0 * deg;
    in.q_hat = q_hat;
    return in;
}

TEST(CfdRates, RestartsOfAnotherRateAreRefusedWarmStartsTaken) {
    parallel::SerialCommunicator comm;
    euler::SolveOutcome cold;
    {
        euler::CfdCase c(inputs("rate", 0.02), comm);
        EXPECT_EQ(c.rates()[1], 0.02);
        cold = c.run().outcome;
    }
    ASSERT_TRUE(cold.converged) << cold.reason;
    // The same rate resumes (converged: no iteration); another, or none, is refused.
    {
        euler::CfdCase again(inputs("rate", 0.02), comm);
        EXPECT_EQ(again.resumed_from(), cold.iterations);
    }
    std::string e = error_of([&] { euler::CfdCase(inputs("rate", 0.01), comm); });
    EXPECT_NE(e.find("another rotation rate (no deflection, p_hat 0, q_hat 0.02"),
              std::string::npos)
        << e;
    EXPECT_NE(e.find("q_hat 0.02"), std::string::npos) << e;
    EXPECT_NE(e.find("q_hat 0.01"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    e = error_of([&] { euler::CfdCase(inputs("rate", 0.0), comm); });
    EXPECT_NE(e.find("no rotation"), std::string::npos) << e;
    // A warm start from the solution at another rate converges to a cold run's lift.
    euler::CaseInputs warm = inputs("rate_warm", 0.025);
    warm.initial = folder() / "rate" / "restart.bin";
    euler::CfdCase w(warm, comm);
    const euler::SolveOutcome ow = w.run().outcome;
    euler::CaseInputs cold_in = inputs("rate_cold", 0.025);
    euler::CfdCase cc(cold_in, comm);
    const euler::SolveOutcome oc = cc.run().outcome;
    std::printf("q_hat 0.025: warm %d iterations, cold %d; CL %.8f, %.8f\n", ow.iterations,
                oc.iterations, ow.forces.CL, oc.forces.CL);
    ASSERT_TRUE(ow.converged && oc.converged);
    EXPECT_LT(ow.iterations, oc.iterations);
    EXPECT_NEAR(ow.forces.CL, oc.forces.CL, 1e-4);
    // The configuration's flow.q_hat is the rate when no option gives one.
    std::ofstream(folder() / "cfd_rate.yaml") << config_text << "flow: {q_hat: 0.02}\n";
    euler::CaseInputs from_config = inputs("rate_config", 0.0);
    from_config.q_hat.reset();
    from_config.config = folder() / "cfd_rate.yaml";
    euler::CfdCase fc(from_config, comm);
    EXPECT_EQ(fc.rates()[1], 0.02);
    EXPECT_EQ(fc.solver().rotating_frame().omega.norm(),
              euler::body_rate_frame({0, 0.02, 0}, 0.3, 3.0, 1.0, {0.25, 0, 0}).omega.norm());
    // A roll rate through the symmetry plane, and a rate with a motion: one-line errors.
    euler::CaseInputs roll = inputs("roll", 0.0);
    roll.p_hat = 0.01;
    e = error_of([&] { euler::CfdCase(roll, comm); });
    EXPECT_NE(e.find("--p-hat 0.01"), std::string::npos) << e;
    EXPECT_NE(e.find("symmetry plane 'symmetry'"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    std::ofstream(folder() / "motion.csv")
        << "# v0: 100\n# mach: 0.3\n"
        << "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder\n"
        << "0,0,0,0,0,0,0,0,0,0\n0.01,0,0,0,0,0,0,0,0,0\n";
    euler::CaseInputs moving = inputs("moving", 0.02);
    moving.alpha.reset();
    moving.motion = folder() / "motion.csv";
    e = error_of([&] { euler::CfdCase(moving, comm); });
    EXPECT_NE(e.find("--motion"), std::string::npos) << e;
    EXPECT_NE(e.find("--q-hat 0.02"), std::string::npos) << e;
}

}  // namespace
