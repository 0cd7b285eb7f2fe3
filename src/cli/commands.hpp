#pragma once
/// @file commands.hpp
/// Registration of the `manta` subcommands. Each subcommand lives in its own cmd_<name>.cpp and
/// adds itself to the app; its callback stores the action to run in `Action`, so errors are
/// handled in one place (main.cpp): manta::Error -> one line on stderr and its exit code.

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "manta/aircraft/aircraft.hpp"
#include "manta/geometry/aircraft_geometry.hpp"
#include "manta/vlm/model.hpp"

namespace manta::cli {

/// What a parsed subcommand runs; returns the process exit code.
using Action = std::function<int()>;

void add_atmosphere(CLI::App& app, Action& action);
void add_config(CLI::App& app, Action& action);
void add_trim(CLI::App& app, Action& action);
void add_modes(CLI::App& app, Action& action);
void add_simulate(CLI::App& app, Action& action);
void add_demo(CLI::App& app, Action& action);
void add_vlm(CLI::App& app, Action& action);
void add_vlm_unsteady(CLI::App& app, Action& action);
/// `oscillation` and its alias `vlm-oscillation` (cmd_oscillation.cpp).
void add_oscillation(CLI::App& app, Action& action);
void add_optimise(CLI::App& app, Action& action);
void add_tables(CLI::App& app, Action& action);
void add_replay(CLI::App& app, Action& action);
void add_report(CLI::App& app, Action& action);
void add_cfd(CLI::App& app, Action& action);
void add_mesh(CLI::App& app, Action& action);

/// Options every aircraft command shares: the aircraft file and its loading case.
struct AircraftOptions {
    std::string aircraft;   ///< --aircraft FILE (required, must exist)
    std::string mass_case;  ///< --mass-case NAME ("" = the file's default case)
    std::string tables;     ///< --tables FILE|DIR ("" = the aircraft file's aero model)
};
/// Add --aircraft, --mass-case and --tables to `cmd`.
void add_aircraft_options(CLI::App* cmd, AircraftOptions& o);

/// The aero database of `--tables`: a database file, or a `manta tables --out` folder (its
/// database.yaml); the aircraft file's own model when `tables` is empty. InputError naming the
/// option for a folder without a database.
[[nodiscard]] std::shared_ptr<const aero::AeroDatabase> load_tables(
    const std::string& tables, const aircraft::AircraftDefinition& def);
/// The flight model of `def` in the mass case of `o`, with the database of `o.tables` in place of
/// the aircraft file's aero model where given.
[[nodiscard]] flightdyn::FlightModel flight_model_of(const aircraft::AircraftDefinition& def,
                                                     const AircraftOptions& o);

/// A level-flight condition given on the command line.
struct FlightCondition {
    double speed = 0.0;     ///< --speed [m/s], true airspeed
    double altitude = 0.0;  ///< --altitude [m], geometric
};
/// Add --speed and --altitude to `cmd`, both required.
void add_required_flight_condition(CLI::App* cmd, FlightCondition& c);

/// A vortex-lattice model read from a MANTA aircraft file (YAML, with its shape for the viscous
/// drag) or an AVL geometry file (`.avl`, by extension).
struct VlmInput {
    vlm::Model model;
    std::optional<geometry::AircraftGeometry> geometry;  ///< MANTA files only
    std::string label;                                   ///< which kind of file
    double default_mach = 0.0;                           ///< the AVL header's Mach, else 0
};
[[nodiscard]] VlmInput load_vlm_input(const std::string& file, const vlm::LatticeDensity& density);

/// Print a JSON object on stdout (one object, 2-space indented).
void print_json(const nlohmann::json& j);

}  // namespace manta::cli
