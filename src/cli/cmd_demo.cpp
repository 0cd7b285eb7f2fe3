/// `manta demo`: the whole pipeline on the Ranger 2000 with the inputs compiled into the program
/// (docs/demo.md): aerodynamic tables from the vortex lattice by sampling and Kriging (`manta
/// tables`), the tables flown (trim, modes, response to control doublets), the paper's three
/// time-optimal manoeuvres on the tables (`manta optimise`), each replayed through the unsteady
/// vortex lattice and compared with the tables (`manta replay`), and the HTML report (`manta
/// report`). Stages run as child processes of this program, several at once, each with its log;
/// a run folder that exists is resumed (finished stages are kept).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include "checks.hpp"
#include "commands.hpp"
#include "embedded_inputs.hpp"
#include "manta/aero/database.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"
#include "manta/core/version.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/modes.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "manta/flightdyn/trim.hpp"
#include "subprocess.hpp"
#include "svg_plot.hpp"

namespace manta::cli {

namespace {

using core::rad_to_deg;

// Doublets on each axis: elevator at 2 s, aileron at 20 s, rudder at 40 s (radians about trim).
std::string demo_inputs_csv(const flightdyn::Controls<double>& trim) {
    std::string s =
        "# MANTA demo inputs: 2-degree elevator doublet, 5-degree aileron doublet, 2-degree rudder "
        "doublet\n";
    s += "t,elevator,aileron,rudder,throttle\n";
    auto row = [&](double t, double de, double da, double dr) {
        s += fmt::format("{},{},{},{},{}\n", t, trim.elevator + core::deg(de),
                         trim.aileron + core::deg(da), trim.rudder + core::deg(dr), trim.throttle);
    };
    row(0, 0, 0, 0);
    row(2.0, 0, 0, 0);
    row(2.2, -2, 0, 0);
    row(3.2, -2, 0, 0);
    row(3.4, 2, 0, 0);
    row(4.4, 2, 0, 0);
    row(4.6, 0, 0, 0);
    row(20.0, 0, 0, 0);
    row(20.2, 0, 5, 0);
    row(21.2, 0, 5, 0);
    row(21.4, 0, -5, 0);
    row(22.4, 0, -5, 0);
    row(22.6, 0, 0, 0);
    row(40.0, 0, 0, 0);
    row(40.2, 0, 0, 2);
    row(41.2, 0, 0, 2);
    row(41.4, 0, 0, -2);
    row(42.4, 0, 0, -2);
    row(42.6, 0, 0, 0);
    return s;
}

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The manoeuvres compiled into the program, by name.
std::string_view embedded_manoeuvre(const std::string& name) {
    if (name == "immelmann") return embedded::immelmann;
    if (name == "lazy_eight") return embedded::lazy_eight;
    if (name == "barrel_roll") return embedded::barrel_roll;
    if (name == "level_turn") return embedded::level_turn;
    return {};
}

// A stage marker: the arguments a finished stage ran with, so a second `manta demo` into the same
// folder keeps what is done and reruns what changed.
struct Markers {
    fs::path dir;
    [[nodiscard]] fs::path file(const std::string& key) const { return dir / (key + ".done"); }
    [[nodiscard]] static std::string signature(const std::vector<std::string>& args) {
        std::string s = core::version() + "\n";
        for (const auto& a : args) s += a + "\n";
        return s;
    }
    [[nodiscard]] bool done(const std::string& key, const std::vector<std::string>& args,
                            const fs::path& output) const {
        std::error_code ec;
        if (!fs::exists(file(key), ec) || !fs::exists(output, ec)) return false;
        return core::read_file(file(key)) == signature(args);
    }
    void mark(const std::string& key, const std::vector<std::string>& args) const {
        core::write_file_atomic(file(key), signature(args));
    }
    void clear() const {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

// Stage 3: the generated tables flown: trim, modes, response to control doublets (in process).
nlohmann::json fly_tables(const aircraft::AircraftDefinition& ac, const fs::path& database,
                          const fs::path& out, double speed, double altitude, double duration,
                          bool quiet) {
    auto say = [&](const std::string& s) {
        if (!quiet) {
            fmt::print("{}\n", s);
            std::fflush(stdout);
        }
    };
    auto model = ac.flight_model();
    model.aero = std::make_shared<const aero::AeroDatabase>(aero::AeroDatabase::read(database));
    flightdyn::finalize(model);

    flightdyn::TrimTarget target;
    target.airspeed = speed;
    target.altitude = altitude;
    const auto tr = flightdyn::trim(model, target);
    say(fmt::format(
        "      trim at {} m/s, {} m: alpha {:.3f} deg, elevator {:.3f} deg, throttle {:.4f} "
        "(residual {:.1e})",
        speed, altitude, tr.state[flightdyn::euler::alpha] * rad_to_deg,
        tr.controls.elevator * rad_to_deg, tr.controls.throttle, tr.residual_norm));

    const auto modes = flightdyn::analyse_modes(flightdyn::linearise(model, tr.state, tr.controls));
    nlohmann::json jmodes = nlohmann::json::array();
    for (const auto* group : {&modes.longitudinal, &modes.lateral}) {
        for (const auto& m : *group) {
            say(
                fmt::format("      {:<22} lambda = {:9.4f} {:+9.4f}i  omega_n {:7.4f} rad/s  zeta "
                            "{:7.4f}",
                            m.name, m.eigenvalue.real(), m.eigenvalue.imag(), m.natural_frequency,
                            m.damping_ratio));
            jmodes.push_back({{"name", m.name},
                              {"eigenvalue_real", m.eigenvalue.real()},
                              {"eigenvalue_imag", m.eigenvalue.imag()},
                              {"natural_frequency", m.natural_frequency},
                              {"damping_ratio", m.damping_ratio}});
        }
    }

    const std::string inputs_text = demo_inputs_csv(tr.controls);
    core::write_file_atomic(out / "inputs.csv", inputs_text);
    const auto inputs =
        flightdyn::InputHistory::parse(inputs_text, (out / "inputs.csv").string(), tr.controls);
    flightdyn::SimulationOptions so;
    so.duration = duration;
    so.dt = 0.01;
    so.output_interval = 0.05;
    so.aircraft_name = ac.name;
    so.mass_case = model.mass.name;
    const auto sim = flightdyn::simulate(model, tr.state, inputs, so);
    flightdyn::write_trajectory(out / "trajectory.csv", sim);
    say(fmt::format(
        "      doublets: {:.1f} s simulated with RK4 at 100 Hz in {:.2f} s ({}); {}",
        sim.final_time, sim.wall_seconds, to_string(sim.end_reason),
        sim.out_of_range.total() ? sim.out_of_range.summary() : "all table look-ups in range"));

    const auto& cols = sim.columns;
    auto col = [&](const std::string& name, double scale) {
        const auto it = std::find(cols.begin(), cols.end(), name);
        const auto k = static_cast<std::size_t>(it - cols.begin());
        std::vector<double> v;
        for (const auto& r : sim.rows) v.push_back(r[k] * scale);
        return v;
    };
    const auto t = col("t", 1.0);
    std::vector<Panel> panels = {
        {"alpha [deg]", col("alpha", rad_to_deg), "#1f77b4"},
        {"q [deg/s]", col("q", rad_to_deg), "#1f77b4"},
        {"phi [deg]", col("phi", rad_to_deg), "#d62728"},
        {"p [deg/s]", col("p", rad_to_deg), "#d62728"},
        {"beta [deg]", col("beta", rad_to_deg), "#2ca02c"},
        {"r [deg/s]", col("r", rad_to_deg), "#2ca02c"},
        {"altitude [m]", col("altitude", 1.0), "#9467bd"},
        {"V [m/s]", col("V", 1.0), "#9467bd"},
        {"nz [-]", col("nz", 1.0), "#8c564b"},
        {"elevator [deg]", col("elevator", rad_to_deg), "#444"},
        {"aileron [deg]", col("aileron", rad_to_deg), "#444"},
        {"rudder [deg]", col("rudder", rad_to_deg), "#444"},
    };
    core::write_file_atomic(
        out / "response.svg",
        svg_time_histories(fmt::format("{} on the generated tables: response to control doublets "
                                       "from trim at {} m/s, {} m",
                                       ac.name, speed, altitude),
                           "time [s]", t, panels));
    nlohmann::json summary = {{"aircraft", ac.name},
                              {"mass_case", model.mass.name},
                              {"tables", database.string()},
                              {"trim",
                               {{"airspeed", speed},
                                {"altitude", altitude},
                                {"alpha", tr.state[flightdyn::euler::alpha]},
                                {"theta", tr.state[flightdyn::euler::theta]},
                                {"elevator", tr.controls.elevator},
                                {"aileron", tr.controls.aileron},
                                {"rudder", tr.controls.rudder},
                                {"throttle", tr.controls.throttle},
                                {"residual", tr.residual_norm}}},
                              {"modes", jmodes},
                              {"simulation",
                               {{"duration", sim.final_time},
                                {"end_reason", std::string(to_string(sim.end_reason))},
                                {"steps", sim.steps},
                                {"wall_seconds", sim.wall_seconds},
                                {"out_of_table", sim.out_of_range.total()},
                                {"saturated", sim.saturation.total()}}}};
    core::write_file_atomic(out / "summary.json", summary.dump(2) + "\n");
    return summary;
}

}  // namespace

void add_demo(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "demo",
        "Run the whole pipeline on the Ranger 2000 (inputs compiled in): VLM tables by sampling "
        "and Kriging, the tables flown, the paper's three time-optimal manoeuvres, their UVLM "
        "replay against the tables, and the HTML report (docs/demo.md)");
    struct Opts {
        std::string out = "out/demo";
        std::string aircraft;
        std::string fidelity = "vlm";
        std::vector<std::string> manoeuvres;
        int jobs = 0;
        bool quick = false;
        bool restart = false;
        double replay_dt = 0.0;
        bool json = false;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("--out", o->out, "Run folder (resumed when it exists)")
        ->capture_default_str()
        ->check(output_path());
    cmd->add_option("--aircraft", o->aircraft,
                    "Aircraft file instead of the embedded Ranger 2000 (its campaign and "
                    "manoeuvres are the Ranger's)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--fidelity", o->fidelity,
                    "Aerodynamic source of the tables and the replay: vlm (vortex lattice) or "
                    "euler (Euler CFD on a coarse mesh)")
        ->capture_default_str();
    cmd->add_option("--manoeuvres", o->manoeuvres,
                    "Manoeuvres: immelmann, lazy_eight, barrel_roll, level_turn (compiled in) or "
                    "manoeuvre files (default: the paper's three)")
        ->delimiter(',');
    cmd->add_option("--jobs", o->jobs, "Stages run at once (default: one per hardware thread)")
        ->check(integer_in(0, 1024));
    cmd->add_flag("--quick", o->quick,
                  "Smoke run: the level turn instead of the paper's manoeuvres (under a minute)");
    cmd->add_flag("--restart", o->restart, "Discard the run folder's results and start again");
    cmd->add_option("--replay-dt", o->replay_dt,
                    "Time step of the replays [s] (default: chosen "
                    "by manta replay from the manoeuvre)")
        ->check(real_in(0.0, 1.0, "s"));
    cmd->add_flag("--json", o->json, "Print the run summary (run.json) as one JSON object");
    cmd->callback([o, &action] {
        action = [o]() -> int {
            const auto wall0 = Clock::now();
            const fs::path out = fs::absolute(o->out);
            const bool quiet = o->json;
            auto say = [&](const std::string& s) {
                if (!quiet) {
                    fmt::print("{}\n", s);
                    std::fflush(stdout);
                }
            };
            if (o->fidelity != "vlm" && o->fidelity != "euler") {
                throw InputError(fmt::format(
                    "--fidelity: '{}' is not a fidelity; expected vlm or euler", o->fidelity));
            }
            if (o->fidelity == "euler") {
                throw InputError(
                    "--fidelity euler: this version of MANTA has no Euler CFD source that can "
                    "generate tables and replay manoeuvres yet; use --fidelity vlm");
            }
            std::vector<std::string> names = o->manoeuvres;
            if (names.empty()) {
                names = o->quick
                            ? std::vector<std::string>{"level_turn"}
                            : std::vector<std::string>{"immelmann", "lazy_eight", "barrel_roll"};
            }
            const int hw = static_cast<int>(std::thread::hardware_concurrency());
            const int jobs = o->jobs > 0 ? o->jobs : std::max(1, hw);

            // The demo's own folder, locked while it runs (its stages lock their sub-folders).
            const core::RunFolderLock lock(out, "demo");
            const Markers markers{out / ".demo"};
            if (o->restart) {
                markers.clear();
                for (const char* d : {"tables", "fly", "manoeuvres", "replay", "figures"}) {
                    std::error_code ec;
                    fs::remove_all(out / d, ec);
                }
            }
            fs::create_directories(markers.dir);
            const fs::path inputs = out / "inputs";

            // 1. Inputs: the aircraft, the campaign and the manoeuvres, written out so the user
            // has the files (and can rerun any stage by hand with the commands in the logs).
            const auto t_inputs = Clock::now();
            aircraft::AircraftDefinition ac;
            std::string campaign(embedded::ranger_campaign);
            if (o->aircraft.empty()) {
                core::write_file_atomic(inputs / "aircraft.yaml", embedded::ranger_aircraft);
                ac = aircraft::load_aircraft(inputs / "aircraft.yaml");
            } else {
                ac = aircraft::load_aircraft(o->aircraft);
                core::write_file_atomic(inputs / "aircraft.yaml", core::read_file(o->aircraft));
                const std::string key = "  aircraft: aircraft.yaml";
                const auto at = campaign.find(key);
                if (at != std::string::npos) {
                    campaign.replace(at, key.size(),
                                     "  aircraft: \"" + fs::absolute(o->aircraft).string() + "\"");
                }
            }
            core::write_file_atomic(out / "aircraft.yaml",
                                    core::read_file(inputs / "aircraft.yaml"));
            core::write_file_atomic(inputs / "campaign.yaml", campaign);
            std::vector<std::pair<std::string, fs::path>> manoeuvre_files;
            for (const auto& n : names) {
                const auto text = embedded_manoeuvre(n);
                if (!text.empty()) {
                    const fs::path f = inputs / "manoeuvres" / (n + ".yaml");
                    core::write_file_atomic(f, text);
                    manoeuvre_files.emplace_back(n, f);
                    continue;
                }
                std::error_code ec;
                if (!fs::is_regular_file(n, ec)) {
                    throw InputError(fmt::format(
                        "--manoeuvres: '{}' is neither a compiled-in manoeuvre (immelmann, "
                        "lazy_eight, barrel_roll, level_turn) nor a manoeuvre file",
                        n));
                }
                const std::string stem = fs::path(n).stem().string();
                const fs::path f = inputs / "manoeuvres" / (stem + ".yaml");
                core::write_file_atomic(f, core::read_file(n));
                manoeuvre_files.emplace_back(stem, f);
            }
            say(
                fmt::format("[1/6] inputs     {} ({}); campaign, {} manoeuvre(s) in {}/ "
                            "({} stage(s) at once)",
                            ac.name, o->aircraft.empty() ? "compiled in" : o->aircraft,
                            manoeuvre_files.size(), inputs.string(), jobs));

            nlohmann::json timings = nlohmann::json::object();
            timings["inputs"] = seconds_since(t_inputs);
            const fs::path program = self_executable();
            RunChildrenOptions rco;
            rco.quiet = quiet;
            rco.jobs = jobs;
            // Each child is single-threaded: the parallelism is across children.
            rco.environment = {"OMP_NUM_THREADS=1", "OPENBLAS_NUM_THREADS=1"};
            bool failed = false;

            // 2. Tables (the campaign resumes from its sample store by itself).
            const auto t_tables = Clock::now();
            const fs::path database = out / "tables" / "database.yaml";
            {
                say("[2/6] tables     aerodynamic tables from the vortex lattice: adaptive "
                    "sampling, Kriging, co-Kriged control increments (manta tables)");
                std::vector<ChildJob> tj{
                    {"tables",
                     {"tables", "--campaign", (inputs / "campaign.yaml").string(), "--out",
                      (out / "tables").string(), "--jobs", std::to_string(jobs),
                      "--progress-interval", "2"},
                     out / "logs" / "tables.log"}};
                RunChildrenOptions one = rco;
                one.jobs = 1;
                one.environment.clear();
                const auto r = run_children(program, tj, one);
                if (r[0].exit_code != 0) {
                    throw ConvergenceError(fmt::format(
                        "demo: the table campaign failed (exit {}): {}; log: {}", r[0].exit_code,
                        r[0].last_line, (out / "logs" / "tables.log").string()));
                }
            }
            timings["tables"] = seconds_since(t_tables);

            // 3. The tables flown.
            const auto t_fly = Clock::now();
            say("[3/6] fly        the tables in the 6-DoF equations: trim, modes, doublets");
            fs::create_directories(out / "fly");
            (void)fly_tables(ac, database, out / "fly", 150.0, 3000.0, 60.0, quiet);
            timings["fly"] = seconds_since(t_fly);

            // 4. Time-optimal manoeuvres on the tables.
            const auto t_opt = Clock::now();
            say(
                fmt::format("[4/6] optimise   {} time-optimal manoeuvre(s) on the tables (LGL "
                            "pseudo-spectral, IPOPT)",
                            manoeuvre_files.size()));
            std::vector<ChildJob> opt_jobs;
            std::vector<std::string> opt_names;
            nlohmann::json opt_times = nlohmann::json::object();
            for (const auto& [name, file] : manoeuvre_files) {
                const fs::path dir = out / "manoeuvres" / name;
                std::vector<std::string> args{
                    "optimise",        "--aircraft",  (inputs / "aircraft.yaml").string(),
                    "--manoeuvre",     file.string(), "--tables",
                    database.string(), "--out",       dir.string(),
                    "--progress"};
                const auto sig = args;
                if (markers.done("optimise_" + name, sig, dir / "summary.json")) {
                    say(fmt::format("      optimise {}: already done (kept)", name));
                    continue;
                }
                opt_jobs.push_back(
                    {"optimise " + name, args, out / "logs" / ("optimise_" + name + ".log")});
                opt_names.push_back(name);
            }
            std::vector<std::string> optimised;
            {
                const auto res = run_children(program, opt_jobs, rco);
                for (std::size_t k = 0; k < res.size(); ++k) {
                    opt_times[opt_names[k]] = res[k].wall_seconds;
                    if (res[k].exit_code == 0) {
                        markers.mark("optimise_" + opt_names[k], opt_jobs[k].args);
                    } else {
                        failed = true;
                    }
                }
            }
            for (const auto& [name, file] : manoeuvre_files) {
                std::error_code ec;
                if (fs::exists(out / "manoeuvres" / name / "trajectory_dense.csv", ec) &&
                    fs::exists(markers.file("optimise_" + name), ec)) {
                    optimised.push_back(name);
                }
            }
            timings["optimise"] = opt_times;
            timings["optimise_total"] = seconds_since(t_opt);

            // 5. Replays through the unsteady vortex lattice, compared with the tables.
            const auto t_rep = Clock::now();
            say(
                fmt::format("[5/6] replay     {} manoeuvre(s) through the unsteady vortex lattice, "
                            "compared with the tables (resumable)",
                            optimised.size()));
            std::vector<ChildJob> rep_jobs;
            std::vector<std::string> rep_names;
            nlohmann::json rep_times = nlohmann::json::object();
            for (const auto& name : optimised) {
                const fs::path dir = out / "replay" / name;
                std::vector<std::string> args{
                    "replay",
                    "--trajectory",
                    (out / "manoeuvres" / name / "trajectory_dense.csv").string(),
                    "--source",
                    o->fidelity,
                    "--aircraft",
                    (inputs / "aircraft.yaml").string(),
                    "--tables",
                    database.string(),
                    "--out",
                    dir.string(),
                    "--threads",
                    "1"};  // the replays run side by side, one thread each
                if (o->replay_dt > 0.0) {
                    args.push_back("--dt");
                    args.push_back(fmt::format("{}", o->replay_dt));
                }
                if (markers.done("replay_" + name, args, dir / "summary.json")) {
                    say(fmt::format("      replay {}: already done (kept)", name));
                    continue;
                }
                rep_jobs.push_back(
                    {"replay " + name, args, out / "logs" / ("replay_" + name + ".log")});
                rep_names.push_back(name);
            }
            {
                const auto res = run_children(program, rep_jobs, rco);
                for (std::size_t k = 0; k < res.size(); ++k) {
                    rep_times[rep_names[k]] = res[k].wall_seconds;
                    if (res[k].exit_code == 0) {
                        markers.mark("replay_" + rep_names[k], rep_jobs[k].args);
                    } else {
                        failed = true;
                    }
                }
            }
            timings["replay"] = rep_times;
            timings["replay_total"] = seconds_since(t_rep);

            // 6. Report (run.json first: the report shows it as provenance).
            nlohmann::json run = {
                {"manta_version", core::version()},
                {"command", "manta demo"},
                {"settings",
                 {{"out", out.string()},
                  {"fidelity", o->fidelity},
                  {"manoeuvres", names},
                  {"jobs", jobs},
                  {"quick", o->quick},
                  {"replay_dt", o->replay_dt},
                  {"aircraft",
                   o->aircraft.empty() ? std::string("compiled-in Ranger 2000") : o->aircraft},
                  {"hardware_threads", hw}}},
                {"aircraft", "aircraft.yaml"},
                {"timings_s", timings}};
            core::write_file_atomic(out / "run.json", run.dump(2) + "\n");
            const auto t_rep2 = Clock::now();
            say("[6/6] report     the self-contained HTML report (manta report)");
            const fs::path html = out / "report.html";
            {
                std::vector<ChildJob> rj{{"report",
                                          {"report", out.string(), "--html", html.string(),
                                           "--figures", (out / "figures").string()},
                                          out / "logs" / "report.log"}};
                RunChildrenOptions one = rco;
                one.jobs = 1;
                const auto r = run_children(program, rj, one);
                if (r[0].exit_code != 0) failed = true;
            }
            timings["report"] = seconds_since(t_rep2);
            timings["total"] = seconds_since(wall0);
            run["timings_s"] = timings;
            run["status"] = failed ? "some stages failed (see logs/)" : "complete";
            core::write_file_atomic(out / "run.json", run.dump(2) + "\n");
            if (o->json) {
                print_json(run);
            } else {
                say(fmt::format(
                    "done in {:.1f} s{}. Report: {}", seconds_since(wall0),
                    failed ? " WITH FAILED STAGES (see " + (out / "logs").string() + ")" : "",
                    html.string()));
            }
            return failed ? 1 : 0;
        };
    });
}

}  // namespace manta::cli
