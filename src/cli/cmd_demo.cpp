/// `manta demo`: the whole pipeline on the Ranger 2000 with the inputs compiled into the program
/// (docs/demo.md): aerodynamic tables from the vortex lattice by sampling and Kriging (`manta
/// tables`), the tables flown (trim, modes, response to control doublets), the paper's three
/// time-optimal manoeuvres on the tables (`manta optimise`), each replayed through the unsteady
/// vortex lattice and compared with the tables (`manta replay`), and the HTML report (`manta
/// report`). With `--fidelity euler` the campaign meshes the aircraft and fills the tables from
/// Euler solutions, and the replays are time-accurate Euler on that mesh. Stages run as child
/// processes of this program, several at once, each with its log; a run folder that exists is
/// resumed (finished stages are kept).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
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
#include "manta/manoeuvres/manoeuvre.hpp"
#include "manta/replay/trajectory.hpp"
#include "manta/tables/campaign.hpp"
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

// --fidelity euler: what the Euler pipeline costs, measured on the 2-core development sandbox
// (docs/demo.md, "Timings"), for the estimate the demo prints before it starts.
struct EulerCosts {
    double mesh_s;      ///< meshing the aircraft
    double solution_s;  ///< one steady Euler solution (warm-started from its neighbour) per job
    double first_s;     ///< the extra of the first, cold solution
    double step_s;      ///< one physical step of the Euler replay
    double optimise_s;  ///< one manoeuvre optimisation on the tables
};
// The coarse full model (138 951 nodes, docs/meshgen.md): 65-127 s of meshing; a cold solution
// 12 min, warm ones about a third (docs/tables.md); a replay step 61 s of CPU (the first 10 steps
// of 0.01 s of the level turn from the free stream with the default unsteady settings, load 4-5:
// an upper bound, the start transient takes more inner iterations than later steps).
constexpr EulerCosts euler_costs_full{130.0, 240.0, 480.0, 60.0, 150.0};
// The quick mesh (size factor 8, 17 056 nodes), first order to 3 orders: 19 s of meshing, 26
// solutions in 100 s with two jobs at load 4-5, 0.85 s per replay step of at most 10 inner
// iterations.
constexpr EulerCosts euler_costs_quick{20.0, 7.7, 0.0, 0.85, 10.0};
// The quick demo flies the level turn on tables whose drag is mostly numerical (first order on
// the size-factor-8 mesh: CD 0.18 at alpha 0 against 0.027 on the coarse mesh at second order):
// with the Ranger's engine it cannot even trim (throttle 2.78 at 150 m/s, 3000 m), so its thrust
// is scaled by the smallest whole factor that trims it (throttle 0.93 at the level turn's mass,
// 0.96 at the maximum take-off mass).
constexpr double euler_quick_thrust_factor = 3.0;
// The quick demo replays the first seconds of the level turn at a fixed time step.
constexpr double euler_quick_replay_s = 2.0;
constexpr double euler_quick_replay_dt = 0.05;

std::string duration_words(double s) {
    if (s < 120.0) return fmt::format("{:.0f} s", s);
    if (s < 2.0 * 3600.0) return fmt::format("{:.0f} min", s / 60.0);
    if (s < 48.0 * 3600.0) return fmt::format("{:.1f} h", s / 3600.0);
    return fmt::format("{:.1f} days ({:.0f} h)", s / 86400.0, s / 3600.0);
}

// Euler solutions of a campaign: the static budget, every control's deflected samples and six
// rotating-frame solutions per dynamic point.
int campaign_solutions(const tables::Campaign& c) {
    int n = c.static_table.budget;
    for (const auto& cp : c.controls) n += cp.samples;
    if (c.dynamic) {
        const auto na =
            c.dynamic->alpha.empty() ? c.static_table.alpha.size() : c.dynamic->alpha.size();
        const auto nm =
            c.dynamic->mach.empty() ? c.static_table.mach.size() : c.dynamic->mach.size();
        n += static_cast<int>(6 * na * nm);
    }
    return n;
}

// A child's last line without the program's "manta: error: " prefix.
std::string strip_error_prefix(const std::string& line) {
    const std::string prefix = "manta: error: ";
    return line.starts_with(prefix) ? line.substr(prefix.size()) : line;
}

// Wall time of `total` seconds of work split over `parallel` equal children.
double over(double total, int parallel) {
    return total / std::max(1, parallel);
}

// The aircraft text with its engine's `static_thrust:` multiplied by `factor` (the quick Euler
// demo); unchanged, and `scaled` false, when it has none.
std::string scale_thrust(const std::string& text, double factor, bool& scaled) {
    static const std::regex line(R"(^(\s*static_thrust:\s*)([-+0-9.eE]+)(.*)$)");
    std::istringstream in(text);
    std::string out, l;
    scaled = false;
    while (std::getline(in, l)) {
        std::smatch m;
        if (!scaled && std::regex_match(l, m, line)) {
            l = fmt::format("{}{}  # x {} for the quick Euler demo (docs/demo.md); was {}{}",
                            m[1].str(), std::stod(m[2].str()) * factor, factor, m[2].str(),
                            m[3].str());
            scaled = true;
        }
        out += l + "\n";
    }
    return out;
}

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
        "Run the whole pipeline on the Ranger 2000 (inputs compiled in): tables by sampling and "
        "Kriging (vortex lattice, or Euler CFD on a generated mesh with --fidelity euler), the "
        "tables flown, the paper's three time-optimal manoeuvres, their replay through the same "
        "source against the tables, and the HTML report (docs/demo.md)");
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
                    "Aerodynamic source of the tables and the replay: vlm (vortex lattice, "
                    "minutes) or euler (Euler CFD on the coarse full-model mesh the campaign "
                    "generates; days on 2 cores, the estimate is printed at the start)")
        ->capture_default_str();
    cmd->add_option("--manoeuvres", o->manoeuvres,
                    "Manoeuvres: immelmann, lazy_eight, barrel_roll, level_turn (compiled in) or "
                    "manoeuvre files (default: the paper's three)")
        ->delimiter(',');
    cmd->add_option("--jobs", o->jobs, "Stages run at once (default: one per hardware thread)")
        ->check(integer_in(0, 1024));
    cmd->add_flag("--quick", o->quick,
                  "Smoke run: the level turn instead of the paper's manoeuvres (vlm: about a "
                  "minute; euler: a tiny mesh, 26 Euler solutions, 2 s of the turn replayed, "
                  "about 3 minutes on 2 cores)");
    cmd->add_flag("--restart", o->restart, "Discard the run folder's results and start again");
    cmd->add_option("--replay-dt", o->replay_dt,
                    "Time step of the replays [s] (default: chosen by manta replay from the "
                    "manoeuvre; 0.05 with --fidelity euler --quick)")
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
            const bool euler = o->fidelity == "euler";
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
                for (const char* d :
                     {"tables", "fly", "manoeuvres", "replay", "replay-vlm", "figures"}) {
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
            std::string campaign(!euler     ? embedded::ranger_campaign
                                 : o->quick ? embedded::ranger_campaign_euler_quick
                                            : embedded::ranger_campaign_euler);
            // The aircraft file the campaign reads (an Euler campaign meshes it: the mesh is
            // named after it).
            fs::path campaign_aircraft = inputs / "aircraft.yaml";
            // The quick Euler demo's aircraft: the engine's thrust scaled
            // (euler_quick_thrust_factor).
            const bool scaled_engine = euler && o->quick;
            bool thrust_scaled = false;
            // A given aircraft file is read as it is first, so that its errors name it.
            if (!o->aircraft.empty()) ac = aircraft::load_aircraft(o->aircraft);
            const std::string aircraft_text = o->aircraft.empty()
                                                  ? std::string(embedded::ranger_aircraft)
                                                  : core::read_file(o->aircraft);
            core::write_file_atomic(
                inputs / "aircraft.yaml",
                scaled_engine
                    ? scale_thrust(aircraft_text, euler_quick_thrust_factor, thrust_scaled)
                    : aircraft_text);
            if (o->aircraft.empty() || scaled_engine)
                ac = aircraft::load_aircraft(inputs / "aircraft.yaml");
            if (!o->aircraft.empty() && !scaled_engine) {
                const std::string key = "  aircraft: aircraft.yaml";
                const auto at = campaign.find(key);
                if (at != std::string::npos) {
                    campaign_aircraft = fs::absolute(o->aircraft);
                    campaign.replace(at, key.size(),
                                     "  aircraft: \"" + campaign_aircraft.string() + "\"");
                }
            }
            core::write_file_atomic(out / "aircraft.yaml",
                                    core::read_file(inputs / "aircraft.yaml"));
            core::write_file_atomic(inputs / "campaign.yaml", campaign);
            // The Euler numerics beside the campaign (its `config:` names them), and the one the
            // replays use.
            fs::path cfd_config;
            if (euler) {
                if (!embedded::ranger_cfd_euler.empty())
                    core::write_file_atomic(inputs / "cfd-euler.yaml", embedded::ranger_cfd_euler);
                core::write_file_atomic(inputs / "cfd-euler-quick.yaml",
                                        embedded::ranger_cfd_euler_quick);
                if (o->quick) {
                    cfd_config = inputs / "cfd-euler-quick.yaml";
                } else if (!embedded::ranger_cfd_euler.empty()) {
                    cfd_config = inputs / "cfd-euler.yaml";
                }
            }
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

            // --fidelity euler: the campaign, the mesh it makes, and what it all costs.
            const fs::path mesh_file =
                out / "tables" / "mesh" /
                fmt::format("{}_full_coarse.su2", campaign_aircraft.stem().string());
            const double replay_until = euler && o->quick ? euler_quick_replay_s : 0.0;
            const double replay_dt = o->replay_dt > 0.0  ? o->replay_dt
                                     : euler && o->quick ? euler_quick_replay_dt
                                                         : 0.0;
            nlohmann::json euler_json = nullptr;
            if (euler) {
                const EulerCosts& k = o->quick ? euler_costs_quick : euler_costs_full;
                const tables::Campaign c = tables::read_campaign(inputs / "campaign.yaml");
                const int n_solutions = campaign_solutions(c);
                long steps = 0;
                for (const auto& [name, file] : manoeuvre_files) {
                    const auto spec = manoeuvres::load_manoeuvre(file);
                    // One reference chord per step at the entry speed (the automatic step).
                    const double dt =
                        replay_dt > 0.0 ? replay_dt : ac.reference.chord / spec.entry_speed;
                    const double flight = replay_until > 0.0 ? replay_until : spec.duration_guess;
                    steps += static_cast<long>(std::ceil(flight / dt));
                }
                const int n_man = static_cast<int>(manoeuvre_files.size());
                const double tables_s =
                    k.mesh_s + k.first_s + over(n_solutions * k.solution_s, jobs);
                const double optimise_s = over(n_man * k.optimise_s, jobs);
                const double replay_s =
                    over(static_cast<double>(steps) * k.step_s, std::min(jobs, n_man));
                const double total_s = tables_s + optimise_s + replay_s;
                say(fmt::format(
                    "      estimate: about {} with {} job(s) ({}: {} Euler solutions ~{}, {} "
                    "optimisation(s) ~{}, {} serial Euler replay steps ~{}; costs measured on a "
                    "2-core machine, docs/demo.md)",
                    duration_words(total_s), jobs,
                    o->quick ? "a tiny full-model mesh, size factor 8"
                             : "the coarse full-model mesh, 138 951 nodes for the Ranger",
                    n_solutions, duration_words(tables_s), n_man, duration_words(optimise_s), steps,
                    duration_words(replay_s)));
                if (scaled_engine) {
                    say(fmt::format(
                        "      quick: the engine's thrust x {} in {} ({}): the tiny mesh's "
                        "first-order drag (CD 0.18 at alpha 0) is mostly numerical; the replay "
                        "covers the first {} s",
                        euler_quick_thrust_factor, (inputs / "aircraft.yaml").string(),
                        thrust_scaled ? "scaled" : "no static_thrust found, unchanged",
                        replay_until));
                }
                euler_json = {{"mesh", mesh_file.string()},
                              {"cfd_config", cfd_config.string()},
                              {"solutions", n_solutions},
                              {"replay_steps_estimated", steps},
                              {"estimate_s", total_s},
                              {"thrust_factor", thrust_scaled ? euler_quick_thrust_factor : 1.0},
                              {"replay_until", replay_until > 0.0 ? nlohmann::json(replay_until)
                                                                  : nlohmann::json(nullptr)}};
            }

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
                if (euler) {
                    say(fmt::format(
                        "[2/6] tables     the aircraft meshed (full model, coarse level{}; kept "
                        "on a rerun) and Euler tables: adaptive sampling, Kriging, co-Kriged "
                        "control increments, rotating-frame rate derivatives (manta tables)",
                        o->quick ? ", sizes x 8" : ""));
                } else {
                    say("[2/6] tables     aerodynamic tables from the vortex lattice: adaptive "
                        "sampling, Kriging, co-Kriged control increments (manta tables)");
                }
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
                if (r[0].exit_code == 2) {
                    // Bad input (an aircraft that cannot be meshed, a campaign key): the stage's
                    // own one-line error.
                    throw InputError(fmt::format("demo: the table campaign: {}; log: {}",
                                                 strip_error_prefix(r[0].last_line),
                                                 (out / "logs" / "tables.log").string()));
                }
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
            if (euler) {
                // The steps now that the manoeuvres' durations are known.
                long steps = 0;
                for (const auto& name : optimised) {
                    const auto tr =
                        replay::read_trajectory(out / "manoeuvres" / name / "trajectory_dense.csv");
                    double flight = tr.t.back() - tr.t.front();
                    if (replay_until > 0.0) flight = std::min(flight, replay_until);
                    double vmax = 0.0;
                    for (const double v : tr.V) vmax = std::max(vmax, v);
                    const double dt = replay_dt > 0.0 ? replay_dt : ac.reference.chord / vmax;
                    steps += static_cast<long>(std::ceil(flight / dt));
                }
                const double replay_s =
                    over(static_cast<double>(steps) *
                             (o->quick ? euler_costs_quick : euler_costs_full).step_s,
                         std::min(jobs, std::max(1, static_cast<int>(optimised.size()))));
                say(fmt::format(
                    "[5/6] replay     {} manoeuvre(s){} through time-accurate Euler "
                    "CFD on {} (moving mesh and control surfaces), compared with "
                    "the tables: about {} steps, {} (resumable)",
                    optimised.size(),
                    replay_until > 0.0 ? fmt::format(", the first {} s of each,", replay_until)
                                       : "",
                    mesh_file.filename().string(), steps, duration_words(replay_s)));
            } else {
                say(fmt::format(
                    "[5/6] replay     {} manoeuvre(s) through the unsteady vortex lattice, "
                    "compared with the tables (resumable)",
                    optimised.size()));
            }
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
                    dir.string()};
                if (euler) {
                    // Serial Euler on the campaign's mesh (its companion beside it gives the
                    // markers and control surfaces), with the campaign's numerics.
                    args.insert(args.end(), {"--mesh", mesh_file.string()});
                    if (!cfd_config.empty())
                        args.insert(args.end(), {"--cfd-config", cfd_config.string()});
                    if (replay_until > 0.0)
                        args.insert(args.end(), {"--until", fmt::format("{}", replay_until)});
                } else {
                    // The replays run side by side, one thread each.
                    args.insert(args.end(), {"--threads", "1"});
                }
                if (replay_dt > 0.0) {
                    args.push_back("--dt");
                    args.push_back(fmt::format("{}", replay_dt));
                }
                if (markers.done("replay_" + name, args, dir / "summary.json")) {
                    say(fmt::format("      replay {}: already done (kept)", name));
                } else {
                    rep_jobs.push_back(
                        {"replay " + name, args, out / "logs" / ("replay_" + name + ".log")});
                    rep_names.push_back(name);
                }
                if (!euler) continue;
                // The Euler demo also replays each manoeuvre through the unsteady vortex lattice
                // (seconds), into replay-vlm/<name>/: the report draws the Euler replay, the
                // tables and the lattice replay on the same axes (docs/report.md).
                const fs::path vdir = out / "replay-vlm" / name;
                std::vector<std::string> vargs{
                    "replay",
                    "--trajectory",
                    (out / "manoeuvres" / name / "trajectory_dense.csv").string(),
                    "--source",
                    "vlm",
                    "--aircraft",
                    (inputs / "aircraft.yaml").string(),
                    "--tables",
                    database.string(),
                    "--out",
                    vdir.string(),
                    "--threads",
                    "1"};
                if (replay_until > 0.0)
                    vargs.insert(vargs.end(), {"--until", fmt::format("{}", replay_until)});
                if (markers.done("replay_vlm_" + name, vargs, vdir / "summary.json")) {
                    say(fmt::format("      lattice replay {}: already done (kept)", name));
                    continue;
                }
                rep_jobs.push_back({"lattice replay " + name, vargs,
                                    out / "logs" / ("replay_vlm_" + name + ".log")});
                rep_names.push_back("vlm_" + name);
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
                  {"replay_dt", replay_dt},
                  {"aircraft",
                   o->aircraft.empty() ? std::string("compiled-in Ranger 2000") : o->aircraft},
                  {"hardware_threads", hw}}},
                {"euler", euler_json},
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
