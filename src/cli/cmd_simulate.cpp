/// `manta simulate`: time simulation of an aircraft file from a trimmed state, driven by a
/// control-input CSV (docs/flight-dynamics.md#the-simulate-command).

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/simulate.hpp"
#include "manta/flightdyn/trim.hpp"

namespace manta::cli {

namespace {

struct SimulateArgs {
    AircraftOptions ac;
    std::string inputs;
    double duration = 0.0;
    double speed = 150.0;
    double altitude = 3000.0;
    double dt = 0.01;
    double output_interval = 0.0;
    std::string integrator = "rk4";
    std::string form = "quaternion";
    double rtol = 1e-8;
    double atol = 1e-8;
    std::string out = "trajectory.csv";
    bool json = false;
};

nlohmann::json state_json(const flightdyn::SimulationResult& res) {
    using namespace flightdyn::euler;
    const auto& s = res.final_state;
    const double rtd = core::rad_to_deg;
    nlohmann::json j;
    j["t"] = res.final_time;
    j["x"] = s[x];
    j["y"] = s[y];
    j["z"] = s[z];
    j["altitude"] = -s[z];
    auto angle = [&](const char* key, double rad) {
        j[key] = rad;
        j[std::string(key) + "_deg"] = rad * rtd;
    };
    angle("phi", s[phi]);
    angle("theta", s[theta]);
    angle("psi", s[psi]);
    j["V"] = s[V];
    angle("alpha", s[alpha]);
    angle("beta", s[beta]);
    j["p"] = s[p];
    j["q"] = s[q];
    j["r"] = s[r];
    angle("elevator", res.final_controls.elevator);
    angle("aileron", res.final_controls.aileron);
    angle("rudder", res.final_controls.rudder);
    j["throttle"] = res.final_controls.throttle;
    return j;
}

nlohmann::json saturation_json(const flightdyn::SaturationReport& s) {
    nlohmann::json j;
    j["total"] = s.total();
    for (int c = 0; c < flightdyn::n_channels; ++c) {
        nlohmann::json e = {{"input_rows", s.input_rows[c]},
                            {"output_samples", s.output_samples[c]}};
        if (s.input_rows[c] > 0) {
            e["first_time"] = s.first_time[c];
            e["first_value"] = s.first_value[c];
        }
        j[std::string(flightdyn::to_string(static_cast<flightdyn::Channel>(c)))] = e;
    }
    return j;
}

nlohmann::json out_of_range_json(const aero::OutOfRangeReport& r) {
    nlohmann::json entries = nlohmann::json::array();
    for (const auto& e : r.entries) {
        nlohmann::json x = {{"table", e.table},
                            {"axis", std::string(aero::to_string(e.axis))},
                            {"below", e.below},
                            {"above", e.above}};
        if (e.below > 0) x["lowest"] = e.lowest;
        if (e.above > 0) x["highest"] = e.highest;
        entries.push_back(x);
    }
    return {{"total", r.total()}, {"evaluations", r.evaluations}, {"entries", entries}};
}

/// "1 min 05 s", "12 s", "0.4 s".
std::string format_duration(double s) {
    if (s < 10) return fmt::format("{:.1f} s", s);
    if (s < 60) return fmt::format("{:.0f} s", s);
    const auto total = static_cast<long>(std::lround(s));
    if (total < 3600) return fmt::format("{} min {:02d} s", total / 60, total % 60);
    return fmt::format("{} h {:02d} min", total / 3600, (total % 3600) / 60);
}

}  // namespace

void add_simulate(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "simulate",
        "Simulate an aircraft in time from a trimmed level-flight state, driven by a "
        "control-input\n"
        "CSV (columns t, elevator|elevator_deg, aileron|aileron_deg, rudder|rudder_deg, throttle;\n"
        "absent columns hold the trim value). Writes the trajectory CSV atomically and prints a\n"
        "summary. Stops early on the ground or on leaving the atmosphere model (said in the "
        "summary).\n"
        "Exit 1 if no trim exists or the state becomes NaN/Inf (the partial trajectory is saved),\n"
        "2 on bad input. Formats: docs/flight-dynamics.md.");
    auto a = std::make_shared<SimulateArgs>();
    add_aircraft_options(cmd, a->ac);
    cmd->add_option("--inputs", a->inputs, "Control-input CSV (default: hold the trim controls)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--duration", a->duration, "Simulated time [s]")->required();
    cmd->add_option("--speed", a->speed, "Initial true airspeed [m/s] (trimmed level flight)")
        ->capture_default_str();
    cmd->add_option("--altitude", a->altitude, "Initial altitude [m] (geometric)")
        ->capture_default_str();
    cmd->add_option("--dt", a->dt, "Time step [s] (rk4 step; dopri5 initial step)")
        ->capture_default_str();
    cmd->add_option("--output-interval", a->output_interval,
                    "Interval between trajectory rows [s] (default: every step, dt)");
    cmd->add_option(
           "--integrator", a->integrator,
           "rk4 (fixed step, classical Runge-Kutta) or dopri5 (adaptive Dormand-Prince 5(4))")
        ->capture_default_str();
    cmd->add_option("--form", a->form,
                    "State form: quaternion (no attitude singularity) or euler (the paper's state; "
                    "singular at "
                    "theta = +-90 deg)")
        ->capture_default_str();
    cmd->add_option("--rtol", a->rtol, "dopri5 relative tolerance")->capture_default_str();
    cmd->add_option("--atol", a->atol, "dopri5 absolute tolerance (SI units, radians)")
        ->capture_default_str();
    cmd->add_option("--out", a->out, "Trajectory CSV to write")->capture_default_str();
    cmd->add_flag("--json", a->json,
                  "Print one JSON object (SI units and radians; *_deg keys in degrees)");
    cmd->callback([a, &action] {
        action = [a]() -> int {
            flightdyn::SimulationOptions opt;
            opt.duration = a->duration;
            opt.dt = a->dt;
            opt.output_interval = a->output_interval;
            opt.integrator = flightdyn::parse_integrator(a->integrator);
            opt.form = flightdyn::parse_state_form(a->form);
            opt.rtol = a->rtol;
            opt.atol = a->atol;
            opt.validate();  // bad options fail before the aircraft is read and trimmed

            const auto def = aircraft::load_aircraft(a->ac.aircraft);
            const flightdyn::FlightModel model = def.flight_model(a->ac.mass_case);
            flightdyn::TrimTarget target;
            target.airspeed = a->speed;
            target.altitude = a->altitude;
            const flightdyn::TrimResult trim = flightdyn::trim(model, target);
            const flightdyn::InputHistory inputs =
                a->inputs.empty() ? flightdyn::InputHistory(trim.controls)
                                  : flightdyn::InputHistory::read(a->inputs, trim.controls);
            opt.aircraft_name = def.name;
            opt.mass_case = model.mass.name;

            // Status line on stderr: rewritten in place on a terminal, a line every 5 s otherwise.
            const bool tty = ::isatty(STDERR_FILENO) != 0;
            bool printed = false;
            if (!a->json) {
                opt.progress_interval = tty ? 0.25 : 5.0;
                opt.progress = [tty, &printed](const flightdyn::SimulationProgress& p) {
                    if (p.wall_elapsed < 0.5) return;  // short runs print nothing
                    std::fprintf(stderr, "%ssimulate: %3.0f%%  t = %.1f of %.1f s, about %s left%s",
                                 tty ? "\r" : "", 100.0 * p.fraction(), p.t, p.duration,
                                 format_duration(p.wall_remaining).c_str(), tty ? "   " : "\n");
                    std::fflush(stderr);
                    printed = true;
                };
            }
            const std::string out = a->out;
            opt.on_abort = [out](const flightdyn::SimulationResult& partial) {
                flightdyn::write_trajectory(out, partial);
                std::fprintf(stderr, "manta: partial trajectory up to t = %g s saved to %s\n",
                             partial.final_time, out.c_str());
            };

            const flightdyn::SimulationResult res =
                flightdyn::simulate(model, trim.state, inputs, opt);
            if (printed && tty) std::fprintf(stderr, "\n");
            flightdyn::write_trajectory(a->out, res);

            if (a->json) {
                nlohmann::json j;
                j["aircraft"] = def.name;
                j["mass_case"] = model.mass.name;
                j["integrator"] = std::string(flightdyn::to_string(opt.integrator));
                j["form"] = std::string(flightdyn::to_string(opt.form));
                j["dt"] = opt.dt;
                j["inputs"] = a->inputs;
                j["duration_requested"] = opt.duration;
                j["duration"] = res.final_time;
                j["end_reason"] = std::string(flightdyn::to_string(res.end_reason));
                j["end_message"] = res.end_message;
                j["steps"] = res.steps;
                j["rhs_evaluations"] = res.rhs_evaluations;
                j["wall_time"] = res.wall_seconds;
                j["initial_state"] = {{"airspeed", a->speed},
                                      {"altitude", a->altitude},
                                      {"alpha", trim.state[flightdyn::euler::alpha]},
                                      {"theta", trim.state[flightdyn::euler::theta]},
                                      {"elevator", trim.controls.elevator},
                                      {"aileron", trim.controls.aileron},
                                      {"rudder", trim.controls.rudder},
                                      {"throttle", trim.controls.throttle}};
                j["final_state"] = state_json(res);
                j["saturation"] = saturation_json(res.saturation);
                j["out_of_table"] = out_of_range_json(res.out_of_range);
                j["output_file"] = a->out;
                j["rows"] = res.rows.size();
                print_json(j);
                return 0;
            }

            using namespace flightdyn::euler;
            const double rtd = core::rad_to_deg;
            const auto& s = res.final_state;
            fmt::print("simulate: {} (mass case {}), {} {}, {} form\n", def.name, model.mass.name,
                       flightdyn::to_string(opt.integrator),
                       opt.integrator == flightdyn::Integrator::rk4
                           ? fmt::format("dt {:g} s", opt.dt)
                           : fmt::format("rtol {:g} atol {:g}", opt.rtol, opt.atol),
                       flightdyn::to_string(opt.form));
            fmt::print(
                "  start   trimmed level flight: V {:g} m/s, altitude {:g} m, alpha {:.3f} deg, "
                "elevator "
                "{:.3f} deg, throttle {:.4f}\n",
                a->speed, a->altitude, trim.state[alpha] * rtd, trim.controls.elevator * rtd,
                trim.controls.throttle);
            fmt::print("  inputs  {}\n",
                       a->inputs.empty() ? std::string("none (trim controls held)") : a->inputs);
            fmt::print("  end     {}: {}\n", flightdyn::to_string(res.end_reason), res.end_message);
            fmt::print(
                "  cost    {} steps, {} rhs evaluations, wall time {:.3f} s ({:.0f}x real time)\n",
                res.steps, res.rhs_evaluations, res.wall_seconds,
                res.wall_seconds > 0 ? res.final_time / res.wall_seconds : 0.0);
            fmt::print(
                "  final   t {:.3f} s: x {:.1f} y {:.1f} m, altitude {:.1f} m, V {:.2f} m/s, alpha "
                "{:.2f} "
                "beta {:.2f} deg\n",
                res.final_time, s[x], s[y], -s[z], s[V], s[alpha] * rtd, s[beta] * rtd);
            fmt::print(
                "          phi {:.2f} theta {:.2f} psi {:.2f} deg, p {:.4f} q {:.4f} r {:.4f} "
                "rad/s\n",
                s[phi] * rtd, s[theta] * rtd, s[psi] * rtd, s[p], s[q], s[r]);
            const std::string sat = res.saturation.summary(model.limits);
            fmt::print("  limits  {}\n", sat.empty() ? std::string("no control saturated") : sat);
            const std::string oor = res.out_of_range.summary();
            if (oor.empty()) {
                fmt::print("  tables  no query outside the aero tables ({} evaluations)\n",
                           res.out_of_range.evaluations);
            } else {
                fmt::print("  tables  {} of {} evaluations outside the aero tables:\n",
                           res.out_of_range.total(), res.out_of_range.evaluations);
                std::size_t start = 0;
                while (start < oor.size()) {
                    const std::size_t nl = oor.find('\n', start);
                    fmt::print("          {}\n",
                               oor.substr(start, nl == std::string::npos ? nl : nl - start));
                    if (nl == std::string::npos) break;
                    start = nl + 1;
                }
            }
            fmt::print("  output  {} ({} rows)\n", a->out, res.rows.size());
            return 0;
        };
    });
}

}  // namespace manta::cli
