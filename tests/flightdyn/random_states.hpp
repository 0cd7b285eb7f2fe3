#pragma once
/// @file random_states.hpp
/// Random flight states and controls for the tests that compare two evaluations of the equations
/// of motion (test_eom_fast.cpp, test_eom_fused.cpp), and their relative difference.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/model.hpp"

namespace manta::test {

/// The Ranger-like model with beta-dot columns added to its dynamic table (CY, Cl, Cn), so
/// both angle rates enter the solve; the CG moved off the moment reference point and the thrust
/// line tilted and offset, so every term of the loads is exercised.
inline flightdyn::FlightModel with_beta_dot(flightdyn::FlightModel m) {
    std::vector<aero::Table> tables = m.aero->tables();
    for (auto& t : tables) {
        if (t.kind != aero::TableKind::dynamic) continue;
        const std::size_t nc = t.columns.size(), np = t.n_points();
        std::vector<double> values;
        for (std::size_t p = 0; p < np; ++p) {
            for (std::size_t c = 0; c < nc; ++c) values.push_back(t.values[p * nc + c]);
            values.push_back(0.3 + 0.01 * static_cast<double>(p % 5));     // CY_betadot
            values.push_back(-0.05 + 0.002 * static_cast<double>(p % 3));  // Cl_betadot
            values.push_back(0.08 - 0.003 * static_cast<double>(p % 7));   // Cn_betadot
        }
        t.columns.insert(t.columns.end(), {"CY_betadot", "Cl_betadot", "Cn_betadot"});
        t.values = std::move(values);
    }
    m.aero = std::make_shared<const aero::AeroDatabase>(m.aero->info(), m.aero->force_axes(),
                                                        m.aero->extrapolation(), std::move(tables));
    m.name += ", beta-dot columns";
    m.mass.cg_geom = Eigen::Vector3d(0.12, 0.01, -0.05);
    m.engine.thrust_angle = core::deg(2.5);
    m.engine.has_position = true;
    m.engine.position = {1.0, 0.0, -0.3};
    flightdyn::finalize(m);
    return m;
}

/// One state with its controls.
struct RandomCase {
    flightdyn::EulerState<double> state;
    flightdyn::Controls<double> controls;
};

/// The ranges of airspeed [m/s], angle of attack and sideslip [deg] the states are drawn from;
/// position, attitude, rates and controls have fixed ranges (all attitudes and headings, rates up
/// to 1 rad/s, deflections over the Ranger's travel, any throttle).
struct CaseRanges {
    double speed_lo, speed_hi;
    double alpha_deg_lo, alpha_deg_hi;
    double beta_deg;  ///< sideslip in [-beta_deg, beta_deg]
};

/// `n` cases from the seed `seed`.
inline std::vector<RandomCase> random_cases(int n, unsigned seed, const CaseRanges& r) {
    using core::deg;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto in = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
    std::vector<RandomCase> out(static_cast<std::size_t>(n));
    for (auto& c : out) {
        c.state << in(-1e4, 1e4), in(-1e4, 1e4), -in(200, 12000), in(-3.0, 3.0), in(-1.4, 1.4),
            in(-7.0, 7.0), in(r.speed_lo, r.speed_hi), deg(in(r.alpha_deg_lo, r.alpha_deg_hi)),
            deg(in(-r.beta_deg, r.beta_deg)), in(-1.0, 1.0), in(-0.5, 0.5), in(-0.5, 0.5);
        c.controls.elevator = deg(in(-25, 15));
        c.controls.aileron = deg(in(-25, 15));
        c.controls.rudder = deg(in(-17, 17));
        c.controls.throttle = in(0.0, 1.0);
    }
    return out;
}

/// Largest |a - b| relative to 1 + |b| over the entries.
template <class A, class B>
double max_rel(const A& a, const B& b) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < a.size(); ++i)
        worst = std::max(worst, std::abs(a[i] - b[i]) / (1.0 + std::abs(b[i])));
    return worst;
}

}  // namespace manta::test
