/// `manta modes`: trim in level flight, linearise, and report the dynamic modes.

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <string>

#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/modes.hpp"
#include "manta/flightdyn/trim.hpp"

namespace manta::cli {

/// Defined in cmd_trim.cpp.
nlohmann::json trim_json(const flightdyn::TrimResult& r);

namespace {

struct ModesArgs {
    AircraftOptions ac;
    FlightCondition fc;
    bool json = false;
};

/// A number for JSON; infinity (no period, no halving time) becomes null.
nlohmann::json finite_or_null(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json mode_json(const flightdyn::Mode& m) {
    return {{"name", m.name},
            {"eigenvalue", {m.eigenvalue.real(), m.eigenvalue.imag()}},
            {"oscillatory", m.oscillatory},
            {"stable", m.is_stable()},
            {"natural_frequency", m.natural_frequency},
            {"damping_ratio", m.damping_ratio},
            {"period", finite_or_null(m.period)},
            {"time_to_half", finite_or_null(m.time_to_half)},
            {"time_to_double", finite_or_null(m.time_to_double)}};
}

nlohmann::json matrix_json(const Eigen::Matrix4d& A) {
    nlohmann::json rows = nlohmann::json::array();
    for (int i = 0; i < 4; ++i) rows.push_back({A(i, 0), A(i, 1), A(i, 2), A(i, 3)});
    return rows;
}

std::string time_text(double t) {
    return std::isfinite(t) ? fmt::format("{:9.3f} s", t) : std::string("        -  ");
}

void print_modes(const char* title, const std::vector<flightdyn::Mode>& modes) {
    fmt::print("{}\n", title);
    fmt::print("  {:<22} {:>24} {:>11} {:>8} {:>11} {:>11} {:>11}\n", "mode", "eigenvalue [1/s]",
               "wn [rad/s]", "zeta", "period", "t_half", "t_double");
    for (const auto& m : modes) {
        const std::string ev = m.oscillatory ? fmt::format("{:.5f} +/- {:.5f}i",
                                                           m.eigenvalue.real(), m.eigenvalue.imag())
                                             : fmt::format("{:.5f}", m.eigenvalue.real());
        fmt::print("  {:<22} {:>24} {:>11.5f} {:>8.4f} {:>11} {:>11} {:>11}\n", m.name, ev,
                   m.natural_frequency, m.damping_ratio, time_text(m.period),
                   time_text(m.time_to_half), time_text(m.time_to_double));
    }
}

}  // namespace

void add_modes(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "modes",
        "Dynamic modes about a level-flight trim: linearise the 6-DoF equations exactly "
        "(automatic\n"
        "differentiation), split longitudinal (V, alpha, q, theta) and lateral-directional (beta, "
        "p,\n"
        "r, phi) subsystems and report short period, phugoid, Dutch roll, roll and spiral with\n"
        "eigenvalue, natural frequency, damping ratio, period and time to half or double "
        "amplitude.");
    auto a = std::make_shared<ModesArgs>();
    add_aircraft_options(cmd, a->ac);
    add_required_flight_condition(cmd, a->fc);
    cmd->add_flag("--json", a->json, "Print one JSON object (SI units and radians)");
    cmd->callback([a, &action] {
        action = [a]() -> int {
            const auto def = aircraft::load_aircraft(a->ac.aircraft);
            const flightdyn::FlightModel model = flight_model_of(def, a->ac);
            flightdyn::TrimTarget target;
            target.airspeed = a->fc.speed;
            target.altitude = a->fc.altitude;
            const flightdyn::TrimResult tr = flightdyn::trim(model, target);
            const flightdyn::LinearModel lin = flightdyn::linearise(model, tr.state, tr.controls);
            const flightdyn::ModesResult modes = flightdyn::analyse_modes(lin);
            if (a->json) {
                nlohmann::json j;
                j["aircraft"] = def.name;
                j["mass_case"] = model.mass.name;
                j["trim"] = trim_json(tr);
                j["longitudinal"] = nlohmann::json::array();
                for (const auto& m : modes.longitudinal) j["longitudinal"].push_back(mode_json(m));
                j["lateral"] = nlohmann::json::array();
                for (const auto& m : modes.lateral) j["lateral"].push_back(mode_json(m));
                j["longitudinal_states"] = {"V", "alpha", "q", "theta"};
                j["lateral_states"] = {"beta", "p", "r", "phi"};
                j["A_longitudinal"] = matrix_json(modes.A_longitudinal);
                j["A_lateral"] = matrix_json(modes.A_lateral);
                nlohmann::json ev = nlohmann::json::array();
                for (int i = 0; i < 12; ++i)
                    ev.push_back(
                        {modes.eigenvalues_full[i].real(), modes.eigenvalues_full[i].imag()});
                j["eigenvalues_full"] = ev;
                print_json(j);
                return 0;
            }
            const double rtd = core::rad_to_deg;
            fmt::print(
                "Modes of {} (mass case '{}') about level flight at V = {:g} m/s, h = {:g} m\n",
                def.name, model.mass.name, target.airspeed, target.altitude);
            fmt::print(
                "  trim: alpha {:.4f} deg, elevator {:.4f} deg, throttle {:.4f}, residual "
                "{:.2e}\n\n",
                tr.state[flightdyn::euler::alpha] * rtd, tr.controls.elevator * rtd,
                tr.controls.throttle, tr.residual_norm);
            print_modes("Longitudinal (V, alpha, q, theta)", modes.longitudinal);
            fmt::print("\n");
            print_modes("Lateral-directional (beta, p, r, phi)", modes.lateral);
            fmt::print(
                "\nAll 12 eigenvalues of the full state (x, y, z, phi, theta, psi, V, alpha, beta, "
                "p, q, r):\n");
            for (int i = 0; i < 12; ++i) {
                const auto l = modes.eigenvalues_full[i];
                fmt::print("  {:12.6f} {:+12.6f}i\n", l.real(), l.imag());
            }
            return 0;
        };
    });
}

}  // namespace manta::cli
