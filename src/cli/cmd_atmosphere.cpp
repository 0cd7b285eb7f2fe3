#include <fmt/format.h>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/core/error.hpp"
#include "manta/flightdyn/atmosphere.hpp"

namespace manta::cli {

void add_atmosphere(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("atmosphere", "US Standard Atmosphere 1976 at an altitude");
    auto altitude = std::make_shared<double>(0.0);
    auto geopotential = std::make_shared<bool>(false);
    auto json = std::make_shared<bool>(false);
    cmd->add_option("--altitude", *altitude, "Altitude [m] (geometric unless --geopotential)")
        ->required()
        ->check(cli::altitude());
    cmd->add_flag("--geopotential", *geopotential, "Read --altitude as geopotential altitude [m']");
    cmd->add_flag("--json", *json, "Print one JSON object (SI units)");
    cmd->callback([=, &action] {
        action = [=]() -> int {
            const double h = *altitude;
            const auto a = *geopotential ? flightdyn::us1976_geopotential(h) : flightdyn::us1976(h);
            const double z = *geopotential ? flightdyn::geometric_from_geopotential(h) : h;
            if (*json) {
                print_json({{"geometric_altitude", z},
                            {"geopotential_altitude", a.geopotential_altitude},
                            {"temperature", a.temperature},
                            {"pressure", a.pressure},
                            {"density", a.density},
                            {"speed_of_sound", a.speed_of_sound},
                            {"dynamic_viscosity", a.dynamic_viscosity},
                            {"model", "US Standard Atmosphere 1976"}});
            } else {
                fmt::print("US Standard Atmosphere 1976\n");
                fmt::print("  geometric altitude     {:12.3f} m\n", z);
                fmt::print("  geopotential altitude  {:12.3f} m'\n", a.geopotential_altitude);
                fmt::print("  temperature            {:12.4f} K\n", a.temperature);
                fmt::print("  pressure               {:12.6g} Pa\n", a.pressure);
                fmt::print("  density                {:12.6g} kg/m^3\n", a.density);
                fmt::print("  speed of sound         {:12.4f} m/s\n", a.speed_of_sound);
                fmt::print("  dynamic viscosity      {:12.6g} Pa s\n", a.dynamic_viscosity);
            }
            return 0;
        };
    });
}

}  // namespace manta::cli
