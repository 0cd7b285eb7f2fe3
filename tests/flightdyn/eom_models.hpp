#pragma once
/// @file eom_models.hpp
/// The models on which the fused and batched right-hand sides are compared with the reference
/// templates (test_eom_fused.cpp, test_eom_batch.cpp).

#include <filesystem>
#include <utility>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/model.hpp"
#include "random_states.hpp"
#include "test_sim_models.hpp"

namespace manta::test {

/// with_beta_dot's model with an engine's angular momentum as well: every term of the loads in
/// play.
inline flightdyn::FlightModel every_term(flightdyn::FlightModel m) {
    m = with_beta_dot(std::move(m));
    m.name += ", offsets";
    m.engine_angular_momentum = Eigen::Vector3d(30.0, 0.0, 0.0);
    flightdyn::finalize(m);
    return m;
}

/// No aero (a tilted thrust line), the Ranger-like derivative tables, every term, and the Ranger
/// of examples/ (the benchmark's model) when the file is there.
inline std::vector<flightdyn::FlightModel> eom_comparison_models() {
    std::vector<flightdyn::FlightModel> out;
    auto rigid = rigid_body(5000.0, 8000.0, 25000.0, 30000.0, 1000.0);
    rigid.engine.static_thrust_sl = 14000.0;
    rigid.engine.thrust_angle = core::deg(2.0);
    rigid.name = "rigid body";
    out.push_back(rigid);
    out.push_back(ranger_like());
    out.back().name = "Ranger-like";
    out.push_back(every_term(ranger_like()));
    const std::filesystem::path file =
        std::filesystem::path(MANTA_SOURCE_DIR) / "examples" / "ranger2000" / "aircraft.yaml";
    if (std::filesystem::exists(file)) {
        flightdyn::FlightModel m = aircraft::load_aircraft(file).flight_model();
        flightdyn::finalize(m);
        m.name = "Ranger 2000 (examples)";
        out.push_back(std::move(m));
    }
    return out;
}

}  // namespace manta::test
