/// `manta trim`: steady flight (level, climbing or turning) of an aircraft file.

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/trim.hpp"

namespace manta::cli {

namespace {

struct TrimArgs {
    AircraftOptions ac;
    FlightCondition fc;
    std::optional<double> climb_angle_deg;
    std::optional<double> turn_rate_deg_s;
    double heading_deg = 0.0;
    bool ignore_limits = false;
    bool json = false;
};

}  // namespace

/// JSON object of a trim result (SI and radians under plain keys, degrees under *_deg keys).
nlohmann::json trim_json(const flightdyn::TrimResult& r);

nlohmann::json trim_json(const flightdyn::TrimResult& r) {
    using flightdyn::euler::Index;
    const auto& s = r.state;
    const double rtd = core::rad_to_deg;
    nlohmann::json j;
    auto angle = [&](const char* key, double rad) {
        j[key] = rad;
        j[std::string(key) + "_deg"] = rad * rtd;
    };
    angle("alpha", s[Index::alpha]);
    angle("beta", s[Index::beta]);
    angle("theta", s[Index::theta]);
    angle("phi", s[Index::phi]);
    angle("psi", s[Index::psi]);
    angle("elevator", r.controls.elevator);
    angle("aileron", r.controls.aileron);
    angle("rudder", r.controls.rudder);
    j["throttle"] = r.controls.throttle;
    j["p"] = s[Index::p];
    j["q"] = s[Index::q];
    j["r"] = s[Index::r];
    j["airspeed"] = s[Index::V];
    j["altitude"] = -s[Index::z];
    j["residual"] = r.residual_norm;
    j["iterations"] = r.iterations;
    j["violations"] = r.violations;
    return j;
}

void add_trim(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "trim",
        "Trim an aircraft: steady wings-level flight, steady climb or descent, or a coordinated\n"
        "steady turn (Stevens, Lewis & Johnson 2015 sec. 3.6). Prints angles, controls, body "
        "rates\n"
        "and the residual. Exit 1 if no trim exists (the message says why), 2 on bad input.");
    auto a = std::make_shared<TrimArgs>();
    add_aircraft_options(cmd, a->ac);
    add_required_flight_condition(cmd, a->fc);
    auto* climb = cmd->add_option("--climb-angle-deg", a->climb_angle_deg,
                                  "Flight-path angle [deg], + climbing (default 0)")
                      ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    auto* turn = cmd->add_option("--turn-rate-deg-s", a->turn_rate_deg_s,
                                 "Turn rate [deg/s], + turning right (coordinated turn; default 0)")
                     ->check(real_in(-360.0, 360.0, "deg/s"));
    climb->excludes(turn);
    turn->excludes(climb);
    cmd->add_option("--heading-deg", a->heading_deg, "Heading psi [deg] (default 0)")
        ->check(real_in(-360.0, 360.0, "deg"));
    cmd->add_flag("--ignore-limits", a->ignore_limits,
                  "Report control-limit and table-range violations instead of failing");
    cmd->add_flag("--json", a->json,
                  "Print one JSON object (SI units and radians; *_deg keys in degrees)");
    cmd->callback([a, &action] {
        action = [a]() -> int {
            const auto def = aircraft::load_aircraft(a->ac.aircraft);
            const flightdyn::FlightModel model = flight_model_of(def, a->ac);
            flightdyn::TrimTarget target;
            target.airspeed = a->fc.speed;
            target.altitude = a->fc.altitude;
            target.climb_angle = core::deg(a->climb_angle_deg.value_or(0.0));
            target.turn_rate = core::deg(a->turn_rate_deg_s.value_or(0.0));
            target.heading = core::deg(a->heading_deg);
            flightdyn::TrimOptions options;
            options.enforce_limits = !a->ignore_limits;
            const flightdyn::TrimResult r = flightdyn::trim(model, target, options);
            const std::string mass_case = model.mass.name;
            if (a->json) {
                nlohmann::json j = trim_json(r);
                j["aircraft"] = def.name;
                j["mass_case"] = mass_case;
                j["climb_angle"] = target.climb_angle;
                j["climb_angle_deg"] = target.climb_angle * core::rad_to_deg;
                j["turn_rate"] = target.turn_rate;
                print_json(j);
                return 0;
            }
            using flightdyn::euler::Index;
            const auto& s = r.state;
            // Degrees for display; values at rounding level print as 0 rather than -0.00000.
            auto rtd_of = [](double rad) {
                return std::abs(rad) < 1e-12 ? 0.0 : rad * core::rad_to_deg;
            };
            const double rtd = core::rad_to_deg;
            std::string kind = "level flight";
            if (target.turn_rate != 0.0) {
                kind = fmt::format("coordinated turn at {:g} deg/s", target.turn_rate * rtd);
            } else if (target.climb_angle != 0.0) {
                kind = fmt::format("{} at {:g} deg", target.climb_angle > 0 ? "climb" : "descent",
                                   std::abs(target.climb_angle) * rtd);
            }
            fmt::print("Trim of {} (mass case '{}'): {}, V = {:g} m/s, h = {:g} m\n", def.name,
                       mass_case, kind, target.airspeed, target.altitude);
            fmt::print("  alpha      {:11.5f} deg\n", rtd_of(s[Index::alpha]));
            fmt::print("  beta       {:11.5f} deg\n", rtd_of(s[Index::beta]));
            fmt::print("  theta      {:11.5f} deg\n", rtd_of(s[Index::theta]));
            fmt::print("  phi        {:11.5f} deg\n", rtd_of(s[Index::phi]));
            fmt::print("  elevator   {:11.5f} deg\n", rtd_of(r.controls.elevator));
            fmt::print("  aileron    {:11.5f} deg\n", rtd_of(r.controls.aileron));
            fmt::print("  rudder     {:11.5f} deg\n", rtd_of(r.controls.rudder));
            fmt::print("  throttle   {:11.5f}\n", r.controls.throttle);
            fmt::print("  p          {:11.5f} deg/s\n", rtd_of(s[Index::p]));
            fmt::print("  q          {:11.5f} deg/s\n", rtd_of(s[Index::q]));
            fmt::print("  r          {:11.5f} deg/s\n", rtd_of(s[Index::r]));
            fmt::print(
                "  residual   {:11.3e} (max |d/dt| of V, alpha, beta, p, q, r; SI) after {} Newton "
                "steps\n",
                r.residual_norm, r.iterations);
            if (!r.violations.empty()) fmt::print("  warning: {}\n", r.violations);
            return 0;
        };
    });
}

}  // namespace manta::cli
