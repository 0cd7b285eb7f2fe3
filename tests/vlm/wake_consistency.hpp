#pragma once
// Shared by test_wake_consistency_validation.cpp and test_wake_consistency_slow.cpp: the Ranger
// 2000 lattice, the steady solution and an unsteady run held at a constant state.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/model.hpp"
#include "manta/vlm/steady.hpp"
#include "manta/vlm/unsteady.hpp"

namespace manta::vlm::testing {

/// 150 m/s at 3000 m (speed of sound 328.58 m/s, US 1976): the Mach number.
inline constexpr double v0 = 150.0;
inline constexpr double mach = 0.4565;

inline Model ranger_model(int n_chord, double strip_width) {
    const auto def = aircraft::load_aircraft(std::filesystem::path(MANTA_SOURCE_DIR) / "examples" /
                                             "ranger2000" / "aircraft.yaml");
    const Reference ref{def.reference.area, def.reference.span, def.reference.chord,
                        def.moment_reference_geom};
    LatticeDensity d;
    d.n_chord = n_chord;
    d.strip_width = strip_width;
    return from_geometry(def.geometry, ref, d, def.name);
}

struct Coefficients {
    double CL = 0, CY = 0, Cl = 0, Cm = 0, Cn = 0;
};

/// A constant attitude (pitch theta = alpha, heading psi = -beta) held for `steps` time steps of
/// c_ref / v0 (the replay's), the unsteady solver started steady, its last step.
inline Coefficients unsteady_at(const Model& m, double alpha, double beta, double wake_length,
                                WakeModel wake = WakeModel::prescribed, int steps = 4) {
    UnsteadyOptions o;
    o.mach = mach;
    o.dt = m.reference.chord / v0;
    o.wake_length = wake_length;
    o.wake = wake;
    o.span_loading = false;
    o.threads = 2;
    aero::Motion mo;
    const double t_end = steps * o.dt;
    mo.t = {0.0, t_end};
    for (auto& c : mo.position) c.assign(2, 0.0);
    for (auto& c : mo.angles) c.assign(2, 0.0);
    mo.angles[1] = {alpha, alpha};
    mo.angles[2] = {-beta, -beta};
    for (const char* n : {"elevator", "aileron", "rudder"}) mo.add_mode(n, {0.0, 0.0});
    mo.metadata.v0 = v0;
    UnsteadySolver u(m, build_lattice(m), o);
    const UnsteadyHistory h = u.run(mo);
    const UnsteadyStep& st = h.steps.back();
    return {st.CL, st.CY, st.body.Cl, st.body.Cm, st.body.Cn};
}

struct Sweep {
    std::vector<Coefficients> steady, unsteady;
};

/// Steady (trailing legs along the free stream) and unsteady coefficients at every
/// alpha [deg], printed with their differences.
inline Sweep sweep(const Model& m, const std::vector<double>& alphas_deg, double beta,
                   double wake_length) {
    constexpr double deg = std::numbers::pi / 180.0;
    SteadyOptions so;
    so.trailing_legs = TrailingLegs::freestream;
    const SteadySolver steady(m, build_lattice(m), mach, so);
    Sweep sw;
    for (const double a : alphas_deg) {
        FlowState s;
        s.alpha = a * deg;
        s.beta = beta;
        const SteadyResult r = steady.solve(s);
        sw.steady.push_back({r.CL, r.CY, r.body.Cl, r.body.Cm, r.body.Cn});
        sw.unsteady.push_back(unsteady_at(m, a * deg, beta, wake_length));
        const Coefficients& q = sw.steady.back();
        const Coefficients& u = sw.unsteady.back();
        std::printf(
            "alpha %5.1f beta %4.1f: steady CL %.5f Cm %.5f | unsteady CL %.5f Cm %.5f | "
            "dCL %+.3f %% dCm %+.5f dCY %+.5f dCl %+.5f dCn %+.5f\n",
            a, beta / deg, q.CL, q.Cm, u.CL, u.Cm, 100.0 * (u.CL - q.CL) / q.CL, u.Cm - q.Cm,
            u.CY - q.CY, u.Cl - q.Cl, u.Cn - q.Cn);
    }
    return sw;
}

}  // namespace manta::vlm::testing
