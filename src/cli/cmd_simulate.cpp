/// @file cmd_simulate.cpp
/// `manta simulate`: time simulation of an aircraft file from a trimmed state, driven by a
/// control-input CSV (docs/flight-dynamics.md#the-simulate-command), or an ensemble of cases from
/// a cases CSV flown in lock-step (`--cases`, docs/flight-dynamics.md#ensembles---cases).

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/cases.hpp"
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
    std::string cases;    ///< --cases FILE: an ensemble
    std::string out_dir;  ///< --out-dir DIR of an ensemble
    bool json = false;
    // Options a run of --cases rejects (given or not).
    CLI::Option* inputs_opt = nullptr;
    CLI::Option* out_opt = nullptr;
    CLI::Option* speed_opt = nullptr;
    CLI::Option* altitude_opt = nullptr;
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

/// The simulation options of the command line (validated before anything is read).
flightdyn::SimulationOptions make_options(const SimulateArgs& a) {
    flightdyn::SimulationOptions opt;
    opt.duration = a.duration;
    opt.dt = a.dt;
    opt.output_interval = a.output_interval;
    opt.integrator = flightdyn::parse_integrator(a.integrator);
    opt.form = flightdyn::parse_state_form(a.form);
    opt.rtol = a.rtol;
    opt.atol = a.atol;
    opt.validate();
    return opt;
}

/// Status line on stderr: rewritten in place on a terminal, a line every 5 s otherwise; nothing
/// for runs shorter than half a second. `printed` tells whether a line was written.
void install_progress(flightdyn::SimulationOptions& opt, bool& printed) {
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    opt.progress_interval = tty ? 0.25 : 5.0;
    opt.progress = [tty, &printed](const flightdyn::SimulationProgress& p) {
        if (p.wall_elapsed < 0.5) return;  // short runs print nothing
        const std::string where =
            p.n_cases > 1 ? fmt::format("{} of {} cases ended", p.cases_ended, p.n_cases)
                          : fmt::format("t = {:.1f} of {:.1f} s", p.t, p.duration);
        std::fprintf(stderr, "%ssimulate: %3.0f%%  %s, about %s left%s", tty ? "\r" : "",
                     100.0 * p.fraction(), where.c_str(), format_duration(p.wall_remaining).c_str(),
                     tty ? "   " : "\n");
        std::fflush(stderr);
        printed = true;
    };
}

/// A single run: --inputs (optional), --speed, --altitude, --out.
int run_single(const SimulateArgs& a) {
    flightdyn::SimulationOptions opt = make_options(a);  // bad options fail before any reading
    core::prepare_output_file(a.out, "--out");           // and an unwritable --out too

    const auto def = aircraft::load_aircraft(a.ac.aircraft);
    const flightdyn::FlightModel model = flight_model_of(def, a.ac);
    flightdyn::TrimTarget target;
    target.airspeed = a.speed;
    target.altitude = a.altitude;
    const flightdyn::TrimResult trim = flightdyn::trim(model, target);
    const flightdyn::InputHistory inputs =
        a.inputs.empty() ? flightdyn::InputHistory(trim.controls)
                         : flightdyn::InputHistory::read(a.inputs, trim.controls);
    opt.aircraft_name = def.name;
    opt.mass_case = model.mass.name;

    bool printed = false;
    if (!a.json) install_progress(opt, printed);
    // Rows go to the file as they are computed (no trajectory is kept in memory).
    flightdyn::TrajectoryWriter writer(a.out);
    opt.row_sink = writer.sink();
    const std::string out = a.out;
    opt.on_abort = [out, &writer](const flightdyn::SimulationResult& partial) {
        writer.finish(partial);
        std::fprintf(stderr, "manta: partial trajectory up to t = %g s saved to %s\n",
                     partial.final_time, out.c_str());
    };

    const flightdyn::SimulationResult res = flightdyn::simulate(model, trim.state, inputs, opt);
    if (printed && ::isatty(STDERR_FILENO) != 0) std::fprintf(stderr, "\n");
    writer.finish(res);

    if (a.json) {
        nlohmann::json j;
        j["aircraft"] = def.name;
        j["mass_case"] = model.mass.name;
        j["integrator"] = std::string(flightdyn::to_string(opt.integrator));
        j["form"] = std::string(flightdyn::to_string(opt.form));
        j["dt"] = opt.dt;
        j["inputs"] = a.inputs;
        j["duration_requested"] = opt.duration;
        j["duration"] = res.final_time;
        j["end_reason"] = std::string(flightdyn::to_string(res.end_reason));
        j["end_message"] = res.end_message;
        j["steps"] = res.steps;
        j["rhs_evaluations"] = res.rhs_evaluations;
        j["wall_time"] = res.wall_seconds;
        j["initial_state"] = {{"airspeed", a.speed},
                              {"altitude", a.altitude},
                              {"alpha", trim.state[flightdyn::euler::alpha]},
                              {"theta", trim.state[flightdyn::euler::theta]},
                              {"elevator", trim.controls.elevator},
                              {"aileron", trim.controls.aileron},
                              {"rudder", trim.controls.rudder},
                              {"throttle", trim.controls.throttle}};
        j["final_state"] = state_json(res);
        j["saturation"] = saturation_json(res.saturation);
        j["out_of_table"] = out_of_range_json(res.out_of_range);
        j["output_file"] = a.out;
        j["rows"] = res.n_rows;
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
        a.speed, a.altitude, trim.state[alpha] * rtd, trim.controls.elevator * rtd,
        trim.controls.throttle);
    fmt::print("  inputs  {}\n",
               a.inputs.empty() ? std::string("none (trim controls held)") : a.inputs);
    fmt::print("  end     {}: {}\n", flightdyn::to_string(res.end_reason), res.end_message);
    fmt::print("  cost    {} steps, {} rhs evaluations, wall time {:.3f} s ({:.0f}x real time)\n",
               res.steps, res.rhs_evaluations, res.wall_seconds,
               res.wall_seconds > 0 ? res.final_time / res.wall_seconds : 0.0);
    fmt::print(
        "  final   t {:.3f} s: x {:.1f} y {:.1f} m, altitude {:.1f} m, V {:.2f} m/s, alpha "
        "{:.2f} "
        "beta {:.2f} deg\n",
        res.final_time, s[x], s[y], -s[z], s[V], s[alpha] * rtd, s[beta] * rtd);
    fmt::print(
        "          phi {:.2f} theta {:.2f} psi {:.2f} deg, p {:.4f} q {:.4f} r {:.4f} rad/s\n",
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
    fmt::print("  output  {} ({} rows)\n", a.out, res.n_rows);
    return 0;
}

// ------------------------------------------------------------------------------- ensembles

using flightdyn::CaseRow;

/// Run `fn`; a MANTA error it throws is thrown again, of the same kind (so the same exit code),
/// with `where` in front.
template <class Fn>
auto with_context(const std::string& where, Fn&& fn) {
    try {
        return fn();
    } catch (const ConvergenceError& e) {
        throw ConvergenceError(where + e.what());
    } catch (const NumericalError& e) {
        throw NumericalError(where + e.what());
    } catch (const InputError& e) {
        throw InputError(where + e.what());
    } catch (const IoError& e) {
        throw IoError(where + e.what());
    } catch (const ConfigError& e) {
        throw ConfigError(where + e.what());
    }
}

/// Largest and smallest value of trajectory column `name` over the rows.
std::pair<double, double> column_range(const flightdyn::SimulationResult& r,
                                       const std::string& name) {
    const auto& cols = r.columns;
    const auto c =
        static_cast<std::size_t>(std::find(cols.begin(), cols.end(), name) - cols.begin());
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& row : r.rows) {
        if (c >= row.size()) continue;
        lo = std::min(lo, row[c]);
        hi = std::max(hi, row[c]);
    }
    return {lo, hi};
}

/// An ensemble: --cases FILE --out-dir DIR.
int run_ensemble(const SimulateArgs& a) {
    const auto clash = [](const CLI::Option* o, const char* why) {
        if (o != nullptr && o->count() > 0)
            throw InputError(fmt::format("{} cannot be used with --cases: {}", o->get_name(), why));
    };
    clash(a.inputs_opt, "give each case's inputs in the cases file's column 'inputs'");
    clash(a.out_opt, "an ensemble writes DIR/<name>.csv per case into --out-dir DIR");
    clash(a.speed_opt, "each case's speed is the cases file's column 'speed'");
    clash(a.altitude_opt, "each case's altitude is the cases file's column 'altitude'");
    if (a.out_dir.empty())
        throw InputError(
            "--cases needs --out-dir DIR (where DIR/<name>.csv per case and DIR/summary.json go)");
    flightdyn::SimulationOptions opt = make_options(a);
    const std::vector<CaseRow> rows =
        flightdyn::read_cases(a.cases);  // errors before the aircraft is read

    const auto def = aircraft::load_aircraft(a.ac.aircraft);
    const flightdyn::FlightModel model = flight_model_of(def, a.ac);
    opt.aircraft_name = def.name;
    opt.mass_case = model.mass.name;
    std::vector<flightdyn::TrimResult> trims;
    std::vector<flightdyn::EnsembleCase> cases;
    for (const CaseRow& c : rows) {
        const std::string where = fmt::format("{}:{}: case '{}': ", a.cases, c.line, c.name);
        flightdyn::TrimTarget target;
        target.airspeed = c.speed;
        target.altitude = c.altitude;
        target.climb_angle = c.climb_angle_deg * core::deg_to_rad;
        trims.push_back(
            with_context(where + "no trim: ", [&] { return flightdyn::trim(model, target); }));
        const flightdyn::Controls<double>& u0 = trims.back().controls;
        flightdyn::InputHistory inputs =
            c.inputs.empty() ? flightdyn::InputHistory(u0) : with_context(where, [&] {
                return flightdyn::InputHistory::parse(c.inputs_text, c.inputs_path.string(), u0);
            });
        cases.push_back({c.name, trims.back().state, std::move(inputs)});
    }

    // Every case trimmed: the output folder is checked and locked before anything is flown.
    const core::RunFolderLock lock(a.out_dir, "simulate", "--out-dir");
    bool printed = false;
    if (!a.json) install_progress(opt, printed);
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<flightdyn::SimulationResult> results =
        flightdyn::simulate_ensemble(model, cases, opt);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (printed && ::isatty(STDERR_FILENO) != 0) std::fprintf(stderr, "\n");

    const std::filesystem::path dir(a.out_dir);
    nlohmann::json list = nlohmann::json::array();
    std::map<std::string, int> ended;
    for (const char* r : {"completed", "ground", "left_atmosphere", "numerical_error"})
        ended[r] = 0;
    double case_seconds = 0.0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const CaseRow& c = rows[i];
        flightdyn::SimulationResult& res = results[i];
        res.metadata.push_back(fmt::format(
            "case: {} ({} line {}): trimmed at V {:g} m/s, altitude {:g} m, climb angle {:g} deg",
            c.name, a.cases, c.line, c.speed, c.altitude, c.climb_angle_deg));
        const std::filesystem::path out = dir / (c.name + ".csv");
        flightdyn::write_trajectory(out, res);
        const auto [nz_min, nz_max] = column_range(res, "nz");
        const double h_min = column_range(res, "altitude").first;
        const std::string reason(flightdyn::to_string(res.end_reason));
        ++ended[reason];
        case_seconds += res.final_time;
        const flightdyn::TrimResult& trim = trims[i];
        list.push_back({{"name", c.name},
                        {"line", c.line},
                        {"speed", c.speed},
                        {"altitude", c.altitude},
                        {"climb_angle_deg", c.climb_angle_deg},
                        {"inputs", c.inputs},
                        {"output_file", out.string()},
                        {"end_reason", reason},
                        {"end_message", res.end_message},
                        {"end_time", res.final_time},
                        {"steps", res.steps},
                        {"rhs_evaluations", res.rhs_evaluations},
                        {"rows", res.rows.size()},
                        {"max_nz", nz_max},
                        {"min_nz", nz_min},
                        {"min_altitude", h_min},
                        {"initial_state",
                         {{"alpha", trim.state[flightdyn::euler::alpha]},
                          {"theta", trim.state[flightdyn::euler::theta]},
                          {"elevator", trim.controls.elevator},
                          {"aileron", trim.controls.aileron},
                          {"rudder", trim.controls.rudder},
                          {"throttle", trim.controls.throttle}}},
                        {"final_state", state_json(res)},
                        {"saturation", saturation_json(res.saturation)},
                        {"out_of_table", out_of_range_json(res.out_of_range)}});
    }
    nlohmann::json j;
    j["aircraft"] = def.name;
    j["mass_case"] = model.mass.name;
    j["cases_file"] = a.cases;
    j["out_dir"] = a.out_dir;
    j["integrator"] = std::string(flightdyn::to_string(opt.integrator));
    j["form"] = std::string(flightdyn::to_string(opt.form));
    j["dt"] = opt.dt;
    j["output_interval"] = opt.output_interval > 0 ? opt.output_interval : opt.dt;
    j["duration_requested"] = opt.duration;
    j["n_cases"] = rows.size();
    j["ended"] = ended;
    j["wall_time"] = wall;
    j["case_seconds"] = case_seconds;
    j["case_seconds_per_wall_second"] = wall > 0 ? case_seconds / wall : 0.0;
    j["cases"] = list;
    core::write_file_atomic(dir / "summary.json", j.dump(2) + "\n");

    if (a.json) {
        print_json(j);
    } else {
        fmt::print("simulate: {} cases of {} (mass case {}), {} {}, {} form, {:g} s each\n",
                   rows.size(), def.name, model.mass.name, flightdyn::to_string(opt.integrator),
                   opt.integrator == flightdyn::Integrator::rk4
                       ? fmt::format("dt {:g} s", opt.dt)
                       : fmt::format("rtol {:g} atol {:g}", opt.rtol, opt.atol),
                   flightdyn::to_string(opt.form), opt.duration);
        std::size_t w = 4;
        for (const CaseRow& c : rows) w = std::max(w, c.name.size());
        fmt::print("  {:<{}}  {:<15}  {:>9}  {:>7}  {:>16}\n", "name", w, "end", "t [s]", "max nz",
                   "min altitude [m]");
        int saturated = 0, outside = 0;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const auto& c = list[i];
            fmt::print("  {:<{}}  {:<15}  {:>9.3f}  {:>7.3f}  {:>16.1f}\n", rows[i].name, w,
                       c["end_reason"].get<std::string>(), c["end_time"].get<double>(),
                       c["max_nz"].get<double>(), c["min_altitude"].get<double>());
            saturated += results[i].saturation.total() > 0 ? 1 : 0;
            outside += results[i].out_of_range.total() > 0 ? 1 : 0;
        }
        if (saturated + outside > 0)
            fmt::print(
                "  {} case(s) saturated a control, {} queried outside the aero tables "
                "(per case in summary.json)\n",
                saturated, outside);
        fmt::print("  cost    wall time {:.3g} s, {:.0f} case-seconds per wall second\n", wall,
                   wall > 0 ? case_seconds / wall : 0.0);
        fmt::print("  output  {}/<name>.csv and {}\n", a.out_dir, (dir / "summary.json").string());
    }
    int failed = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        if (results[i].end_reason != flightdyn::EndReason::numerical_error) continue;
        ++failed;
        std::fprintf(stderr, "manta: error: %s:%d: case '%s': %s (partial trajectory saved)\n",
                     a.cases.c_str(), rows[i].line, rows[i].name.c_str(),
                     results[i].end_message.c_str());
    }
    return failed > 0 ? 1 : 0;
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
        "Ensemble: --cases FILE --out-dir DIR flies every row of the cases CSV (columns name,\n"
        "speed, altitude; optional inputs, climb_angle_deg), each trimmed at its own condition,\n"
        "in lock-step; writes DIR/<name>.csv per case and DIR/summary.json and prints a table.\n"
        "Exit 1 if no trim exists or the state becomes NaN/Inf (the partial trajectory is saved),\n"
        "2 on bad input. Formats: docs/flight-dynamics.md, docs/formats.md.");
    auto a = std::make_shared<SimulateArgs>();
    add_aircraft_options(cmd, a->ac);
    a->inputs_opt = cmd->add_option("--inputs", a->inputs,
                                    "Control-input CSV (default: hold the trim controls)")
                        ->check(CLI::ExistingFile);
    cmd->add_option("--duration", a->duration, "Simulated time [s]")
        ->required()
        ->check(real_positive(range::max_duration, "s"));
    a->speed_opt =
        cmd->add_option("--speed", a->speed, "Initial true airspeed [m/s] (trimmed level flight)")
            ->capture_default_str()
            ->check(real_positive(range::max_speed, "m/s"));
    a->altitude_opt = cmd->add_option("--altitude", a->altitude, "Initial altitude [m] (geometric)")
                          ->capture_default_str()
                          ->check(altitude());
    cmd->add_option("--dt", a->dt, "Time step [s] (rk4 step; dopri5 initial step)")
        ->capture_default_str()
        ->check(real_positive(range::max_time_step, "s"));
    cmd->add_option("--output-interval", a->output_interval,
                    "Interval between trajectory rows [s] (default: every step, dt)")
        ->check(real_in(0.0, range::max_duration, "s"));
    cmd->add_option(
           "--integrator", a->integrator,
           "rk4 (fixed step, classical Runge-Kutta) or dopri5 (adaptive Dormand-Prince 5(4))")
        ->capture_default_str();
    cmd->add_option("--form", a->form,
                    "State form: quaternion (no attitude singularity) or euler (the paper's state; "
                    "singular at "
                    "theta = +-90 deg)")
        ->capture_default_str();
    cmd->add_option("--rtol", a->rtol, "dopri5 relative tolerance")
        ->capture_default_str()
        ->check(real_positive(1.0));
    cmd->add_option("--atol", a->atol, "dopri5 absolute tolerance (SI units, radians)")
        ->capture_default_str()
        ->check(real_positive(1e3));
    a->out_opt = cmd->add_option("--out", a->out, "Trajectory CSV to write")
                     ->capture_default_str()
                     ->check(output_path());
    cmd->add_option("--cases", a->cases,
                    "Ensemble: cases CSV (name,speed,altitude[,inputs][,climb_angle_deg]); "
                    "excludes --inputs, --out, --speed, --altitude")
        ->check(CLI::ExistingFile);
    cmd->add_option("--out-dir", a->out_dir,
                    "Ensemble output folder: <name>.csv per case and summary.json")
        ->check(output_path());
    cmd->add_flag("--json", a->json,
                  "Print one JSON object (SI units and radians; *_deg keys in degrees)");
    cmd->callback([a, &action] {
        action = [a]() -> int {
            if (!a->cases.empty()) return run_ensemble(*a);
            if (!a->out_dir.empty())
                throw InputError(
                    "--out-dir is for ensembles: give --cases FILE too (a single run writes "
                    "--out FILE)");
            return run_single(*a);
        };
    });
}

}  // namespace manta::cli
