/// `manta`: command-line entry point. Exit codes: 0 success, 2 bad input (configuration, input
/// files, command-line values), 1 failed computation (no convergence, numerical breakdown).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/error.hpp"
#include "manta/core/memory.hpp"
#include "manta/core/text.hpp"
#include "manta/core/version.hpp"

namespace manta::cli {

void print_json(const nlohmann::json& j) {
    std::cout << j.dump(2) << '\n';
}

void add_aircraft_options(CLI::App* cmd, AircraftOptions& o) {
    cmd->add_option("--aircraft", o.aircraft, "Aircraft file (YAML)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--mass-case", o.mass_case,
                    "Mass case of the aircraft file (default: its default case)");
    cmd->add_option("--tables", o.tables,
                    "Aero database replacing the aircraft file's (a database.yaml or a `manta "
                    "tables --out` folder)")
        ->check(CLI::ExistingPath);
}

std::shared_ptr<const aero::AeroDatabase> load_tables(const std::string& tables,
                                                      const aircraft::AircraftDefinition& def) {
    if (tables.empty()) return def.aero;
    std::filesystem::path p(tables);
    if (std::filesystem::is_directory(p)) {
        p /= "database.yaml";
        if (!std::filesystem::exists(p))
            throw InputError(fmt::format(
                "--tables {}: a folder without database.yaml; expected a database file or a "
                "`manta tables --out` folder",
                tables));
    }
    return std::make_shared<const aero::AeroDatabase>(aero::AeroDatabase::read(p));
}

flightdyn::FlightModel flight_model_of(const aircraft::AircraftDefinition& def,
                                       const AircraftOptions& o) {
    flightdyn::FlightModel model = def.flight_model(o.mass_case);
    if (!o.tables.empty()) model.aero = load_tables(o.tables, def);
    return model;
}

void add_required_flight_condition(CLI::App* cmd, FlightCondition& c) {
    cmd->add_option("--speed", c.speed, "True airspeed [m/s]")
        ->required()
        ->check(real_positive(range::max_speed, "m/s"));
    cmd->add_option("--altitude", c.altitude,
                    "Altitude [m] (geometric, US Standard Atmosphere 1976)")
        ->required()
        ->check(altitude());
}

}  // namespace manta::cli

int main(int argc, char** argv) {
    using namespace manta;
    core::keep_large_allocations();
    CLI::App app{
        "MANTA: aircraft manoeuvres with aerodynamics from flow solutions.\n"
        "Run 'manta <command> --help' for the options of a command.",
        "manta"};
    // Parse errors quote the command line: its control bytes are escaped (set before the
    // subcommands are added, which copy it).
    app.failure_message([](const CLI::App* a, const CLI::Error& e) {
        const std::string what = e.what();
        std::string text = CLI::FailureMessage::simple(a, e);
        if (text.compare(0, what.size(), what) == 0)
            text = core::printable(what) + text.substr(what.size());
        return text;
    });
    app.set_version_flag("--version", "manta " + core::version());
    app.require_subcommand(1);
    bool debug = false;
    app.add_flag("--debug", debug, "Show debug-level log messages");
    app.fallthrough();

    cli::Action action;
    cli::add_atmosphere(app, action);
    cli::add_config(app, action);
    cli::add_trim(app, action);
    cli::add_modes(app, action);
    cli::add_simulate(app, action);
    cli::add_demo(app, action);
    cli::add_vlm(app, action);
    cli::add_vlm_unsteady(app, action);
    cli::add_oscillation(app, action);
    cli::add_optimise(app, action);
    cli::add_tables(app, action);
    cli::add_replay(app, action);
    cli::add_report(app, action);
    cli::add_cfd(app, action);
    cli::add_mesh(app, action);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    spdlog::set_level(debug ? spdlog::level::debug : spdlog::level::info);
    spdlog::set_pattern("%^[%l]%$ %v");
    try {
        return action ? action() : 0;
    } catch (const manta::Error& e) {
        std::fprintf(stderr, "manta: error: %s\n", e.what());
        return e.exit_code();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "manta: internal error: %s\n", core::printable(e.what()).c_str());
        return 1;
    }
}
