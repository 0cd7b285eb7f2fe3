#pragma once
// Flight models built in code for the flight-dynamics tests (no aircraft file needed).

#include <cmath>
#include <memory>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/model.hpp"

namespace manta::test {

/// Uniform grid lo, lo + step, ..., hi.
inline std::vector<double> grid(double lo, double hi, double step) {
    std::vector<double> g;
    const int n = static_cast<int>(std::lround((hi - lo) / step));
    for (int i = 0; i <= n; ++i) g.push_back(lo + step * i);
    return g;
}

/// A rigid body with no aerodynamics and no thrust: mass [kg], principal inertia [kg m^2], Ixz.
inline flightdyn::FlightModel rigid_body(double mass, double ixx, double iyy, double izz,
                                         double ixz = 0.0) {
    flightdyn::FlightModel m;
    m.name = "rigid body";
    m.mass.name = "test";
    m.mass.mass = mass;
    m.mass.inertia << ixx, 0.0, -ixz, 0.0, iyy, 0.0, -ixz, 0.0, izz;
    m.engine.static_thrust_sl = 0.0;
    flightdyn::finalize(m);
    return m;
}

/// Derivative grids like the Ranger's tables: alpha -6..20 deg step 2, Mach 0.1..0.7 step 0.1,
/// beta -10..10 deg step 2.5, controls over their travel.
inline aero::DerivativeGrids ranger_grids() {
    aero::DerivativeGrids g;
    g.alpha = grid(core::deg(-6.0), core::deg(20.0), core::deg(2.0));
    g.mach = grid(0.1, 0.7, 0.1);
    g.beta = grid(core::deg(-10.0), core::deg(10.0), core::deg(2.5));
    g.elevator = grid(core::deg(-25.0), core::deg(15.0), core::deg(5.0));
    g.aileron = grid(core::deg(-25.0), core::deg(15.0), core::deg(5.0));
    g.rudder = grid(core::deg(-17.5), core::deg(17.5), core::deg(5.0));
    return g;
}

/// The linear derivatives of examples/ranger2000/aircraft.yaml (typical of a jet trainer), per rad.
inline aero::LinearDerivatives ranger_derivatives() {
    aero::LinearDerivatives d;
    d.CL_0 = 0.15;
    d.CL_alpha = 5.0;
    d.CL_q = 4.5;
    d.CL_alphadot = 1.5;
    d.CL_de = 0.40;
    d.CD_0 = 0.022;
    d.CD_k = 0.0564;
    d.CL_min_drag = 0.10;
    d.CY_beta = -0.60;
    d.CY_r = 0.30;
    d.CY_dr = 0.15;
    d.Cl_beta = -0.08;
    d.Cl_p = -0.45;
    d.Cl_r = 0.10;
    d.Cl_da = 0.10;
    d.Cl_dr = 0.012;
    d.Cm_0 = 0.02;
    d.Cm_alpha = -0.80;
    d.Cm_q = -14.0;
    d.Cm_alphadot = -3.7;
    d.Cm_de = -1.20;
    d.Cn_beta = 0.10;
    d.Cn_p = -0.03;
    d.Cn_r = -0.18;
    d.Cn_da = -0.008;
    d.Cn_dr = -0.07;
    d.mach_ref = 0.3;
    d.prandtl_glauert = true;
    return d;
}

/// Mass (MTOW case), inertia, reference geometry and engine of the Ranger 2000 as in
/// examples/ranger2000/aircraft.yaml, with the CG at the moment reference point.
inline flightdyn::FlightModel ranger_like(const aero::LinearDerivatives& d,
                                          const aero::DerivativeGrids& g) {
    flightdyn::FlightModel m;
    m.name = "ranger-like (test)";
    m.reference.area = 15.5;
    m.reference.span = 10.46;
    m.reference.chord = 1.545;
    m.mass.name = "mtow";
    m.mass.mass = 3765.0;
    m.mass.inertia << 9287.1, 0.0, 0.0, 0.0, 13584.1, 0.0, 0.0, 0.0, 21237.6;
    m.engine.type = flightdyn::EngineModel::Type::lapse;
    m.engine.static_thrust_sl = 14190.0;
    aero::DatabaseInfo info;
    info.name = "ranger-like";
    info.source = "linear-derivatives";
    info.description = "test model";
    m.aero = std::make_shared<const aero::AeroDatabase>(
        aero::AeroDatabase::from_derivatives(d, g, info));
    flightdyn::finalize(m);
    return m;
}

inline flightdyn::FlightModel ranger_like() {
    return ranger_like(ranger_derivatives(), ranger_grids());
}

}  // namespace manta::test
