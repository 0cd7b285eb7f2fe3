/// `manta demo`: the main job on the Ranger 2000 with the embedded default aircraft.
/// Issue 2 scope: trim, dynamic modes and a simulated response to control doublets, with the
/// results (resolved aircraft file, trajectory CSV, summary JSON, SVG plot) in one folder.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "commands.hpp"
#include "embedded_ranger.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"
#include "manta/core/version.hpp"
#include "manta/flightdyn/modes.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "manta/flightdyn/trim.hpp"
#include "svg_plot.hpp"

namespace manta::cli {

namespace {

using core::rad_to_deg;

// Doublets on each axis: elevator at 2 s, aileron at 20 s, rudder at 40 s (radians about trim).
std::string demo_inputs_csv(const flightdyn::Controls<double>& trim) {
    std::string s =
        "# MANTA demo inputs: 2-degree elevator doublet, 5-degree aileron doublet, 4-degree rudder "
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
    row(40.2, 0, 0, 4);
    row(41.2, 0, 0, 4);
    row(41.4, 0, 0, -4);
    row(42.4, 0, 0, -4);
    row(42.6, 0, 0, 0);
    return s;
}

}  // namespace

void add_demo(CLI::App& app, Action& action) {
    auto* cmd =
        app.add_subcommand("demo",
                           "Run the main job on the Ranger 2000 (embedded default aircraft): "
                           "trim, dynamic modes, simulated response to control doublets");
    struct Opts {
        std::string out = "out/demo";
        std::string aircraft;
        double speed = 150.0;
        double altitude = 3000.0;
        double duration = 60.0;
        bool json = false;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
    cmd->add_option("--aircraft", o->aircraft, "Aircraft file instead of the embedded Ranger 2000");
    cmd->add_option("--speed", o->speed, "Trim airspeed [m/s]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--altitude", o->altitude, "Trim altitude [m]")->capture_default_str();
    cmd->add_option("--duration", o->duration, "Simulated time [s]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--json", o->json, "Print the summary as one JSON object");
    cmd->callback([o, &action] {
        action = [o]() -> int {
            namespace fs = std::filesystem;
            const auto wall0 = std::chrono::steady_clock::now();
            const fs::path out = o->out;
            const bool quiet = o->json;
            auto say = [&](const std::string& s) {
                if (!quiet) {
                    fmt::print("{}\n", s);
                    std::fflush(stdout);
                }
            };

            // 1. Aircraft: the embedded Ranger 2000, written out so the user has the file.
            aircraft::AircraftDefinition ac;
            if (o->aircraft.empty()) {
                core::write_file_atomic(out / "aircraft.yaml", embedded_ranger_yaml);
                ac = aircraft::parse_aircraft(embedded_ranger_yaml,
                                              (out / "aircraft.yaml").string(), out);
            } else {
                ac = aircraft::load_aircraft(o->aircraft);
            }
            const auto model = ac.flight_model();
            say(fmt::format("[1/4] aircraft  {} — mass case '{}', {:.0f} kg; aero: {}", ac.name,
                            model.mass.name, model.mass.mass, ac.aero_label));

            // 2. Trim.
            flightdyn::TrimTarget target;
            target.airspeed = o->speed;
            target.altitude = o->altitude;
            const auto tr = flightdyn::trim(model, target);
            say(fmt::format(
                "[2/4] trim      V = {} m/s, h = {} m: alpha {:.3f} deg, elevator {:.3f} deg, "
                "throttle {:.4f} (residual {:.1e})",
                o->speed, o->altitude, tr.state[flightdyn::euler::alpha] * rad_to_deg,
                tr.controls.elevator * rad_to_deg, tr.controls.throttle, tr.residual_norm));

            // 3. Modes.
            const auto modes =
                flightdyn::analyse_modes(flightdyn::linearise(model, tr.state, tr.controls));
            say("[3/4] modes");
            nlohmann::json jmodes = nlohmann::json::array();
            for (const auto* group : {&modes.longitudinal, &modes.lateral}) {
                for (const auto& m : *group) {
                    say(
                        fmt::format("        {:<22} lambda = {:9.4f} {:+9.4f}i  omega_n {:7.4f} "
                                    "rad/s  zeta {:7.4f}",
                                    m.name, m.eigenvalue.real(), m.eigenvalue.imag(),
                                    m.natural_frequency, m.damping_ratio));
                    jmodes.push_back({{"name", m.name},
                                      {"eigenvalue_real", m.eigenvalue.real()},
                                      {"eigenvalue_imag", m.eigenvalue.imag()},
                                      {"natural_frequency", m.natural_frequency},
                                      {"damping_ratio", m.damping_ratio}});
                }
            }

            // 4. Simulation of control doublets.
            const std::string inputs_text = demo_inputs_csv(tr.controls);
            core::write_file_atomic(out / "inputs.csv", inputs_text);
            const auto inputs = flightdyn::InputHistory::parse(
                inputs_text, (out / "inputs.csv").string(), tr.controls);
            flightdyn::SimulationOptions so;
            so.duration = o->duration;
            so.dt = 0.01;
            so.output_interval = 0.05;
            so.aircraft_name = ac.name;
            so.mass_case = model.mass.name;
            if (!quiet) {
                so.progress = [](const flightdyn::SimulationProgress& p) {
                    fmt::print(stderr,
                               "\r        simulating {:5.1f} / {:.0f} s ({:3.0f} %), about {:.1f} "
                               "s left   ",
                               p.t, p.duration, 100.0 * p.fraction(), p.wall_remaining);
                };
            }
            const auto sim = flightdyn::simulate(model, tr.state, inputs, so);
            if (!quiet) fmt::print(stderr, "\n");
            flightdyn::write_trajectory(out / "trajectory.csv", sim);
            say(fmt::format("[4/4] simulate  {:.1f} s with RK4 at 100 Hz in {:.2f} s wall ({}); {}",
                            sim.final_time, sim.wall_seconds, to_string(sim.end_reason),
                            sim.out_of_range.total() ? sim.out_of_range.summary()
                                                     : "all table look-ups in range"));

            // Plot.
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
            const std::string svg = svg_time_histories(
                fmt::format("{}: response to control doublets from trim at {} m/s, {} m", ac.name,
                            o->speed, o->altitude),
                "time [s]", t, panels);
            core::write_file_atomic(out / "response.svg", svg);

            const double wall =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
            nlohmann::json summary = {{"aircraft", ac.name},
                                      {"mass_case", model.mass.name},
                                      {"aero_model", ac.aero_label},
                                      {"trim",
                                       {{"airspeed", o->speed},
                                        {"altitude", o->altitude},
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
                                        {"saturated", sim.saturation.total()}}},
                                      {"files",
                                       {{"aircraft", (out / "aircraft.yaml").string()},
                                        {"inputs", (out / "inputs.csv").string()},
                                        {"trajectory", (out / "trajectory.csv").string()},
                                        {"plot", (out / "response.svg").string()}}},
                                      {"wall_seconds", wall},
                                      {"version", core::version()}};
            core::write_file_atomic(out / "summary.json", summary.dump(2) + "\n");
            if (o->json) {
                print_json(summary);
            } else {
                say(
                    fmt::format("done in {:.1f} s. Results in {}/: trajectory.csv, response.svg "
                                "(plot), summary.json",
                                wall, out.string()));
            }
            return 0;
        };
    });
}

}  // namespace manta::cli
