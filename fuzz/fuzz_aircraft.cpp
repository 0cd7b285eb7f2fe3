/// @file fuzz_aircraft.cpp
/// libFuzzer target for the aircraft YAML reader (`aircraft::parse_aircraft`) (issue 16;
/// docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. An aircraft read must hold what
/// docs/aircraft-format.md promises (else `abort`, a finding): positive finite reference values,
/// at least one mass case with a positive mass, a finite centre of gravity and a symmetric
/// positive-definite inertia tensor, the default case among them, control limits ordered within
/// 90 deg and throttle within [0, 1], positive gravity, an aero model, a flight model for every
/// mass case, and finite coefficients at zero incidence.

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string_view>

#include <Eigen/Eigenvalues>

#include "fuzz_check.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"

namespace {

using manta::fuzz::check;
using manta::fuzz::finite;

void check_range(const std::array<double, 2>& r, double lo, double hi, const char* what) {
    check(finite(r[0]) && finite(r[1]) && r[0] < r[1] && r[0] >= lo && r[1] <= hi, what);
}

void check_aircraft(const manta::aircraft::AircraftDefinition& a) {
    const auto& ref = a.reference;
    check(finite(ref.area) && ref.area > 0.0, "aircraft: reference area finite, > 0");
    check(finite(ref.span) && ref.span > 0.0, "aircraft: reference span finite, > 0");
    check(finite(ref.chord) && ref.chord > 0.0, "aircraft: reference chord finite, > 0");
    check(a.moment_reference_geom.allFinite(), "aircraft: moment reference finite");
    check(!a.mass_cases.empty(), "aircraft: at least one mass case");
    bool default_found = false;
    for (const auto& m : a.mass_cases) {
        default_found = default_found || m.name == a.default_mass_case;
        check(finite(m.mass) && m.mass > 0.0, "aircraft: mass finite, > 0");
        check(m.cg_geom.allFinite(), "aircraft: centre of gravity finite");
        check(m.inertia.allFinite(), "aircraft: inertia finite");
        check((m.inertia.array() == m.inertia.transpose().array()).all(),
              "aircraft: inertia symmetric");
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.inertia);
        check(eig.eigenvalues().minCoeff() > 0.0, "aircraft: inertia positive definite");
    }
    check(default_found, "aircraft: the default mass case is one of the cases");
    constexpr double half_pi = std::numbers::pi / 2;
    check_range(a.limits.elevator, -half_pi, half_pi, "aircraft: elevator limits");
    check_range(a.limits.aileron, -half_pi, half_pi, "aircraft: aileron limits");
    check_range(a.limits.rudder, -half_pi, half_pi, "aircraft: rudder limits");
    check_range(a.limits.throttle, 0.0, 1.0, "aircraft: throttle limits");
    check(finite(a.environment.gravity) && a.environment.gravity > 0.0,
          "aircraft: gravity finite, > 0");
    check(a.engine_angular_momentum.allFinite(), "aircraft: engine angular momentum finite");
    check(finite(a.envelope.max_mach) && finite(a.envelope.dive_mach) && finite(a.envelope.ceiling),
          "aircraft: envelope finite");
    check(a.aero != nullptr, "aircraft: an aero model");
    for (const auto& m : a.mass_cases) (void)a.flight_model(m.name);
    const manta::aero::AeroQuery<double> q{};
    const auto c = a.aero->evaluate(q, manta::aero::Interpolation::multilinear);
    check(finite(c.CX) && finite(c.CY) && finite(c.CZ) && finite(c.Cl) && finite(c.Cm) &&
              finite(c.Cn),
          "aircraft: coefficients finite at zero incidence");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        // Relative file names (airfoils) resolve in a folder that does not exist.
        const auto a = manta::aircraft::parse_aircraft(text, "fuzz.yaml", "/nonexistent-fuzz-dir");
        try {
            check_aircraft(a);
        } catch (const manta::Error& e) {
            // A flight model of a validated aircraft must be made: an error here is a finding.
            std::fprintf(stderr, "fuzz invariant violated: %s\n", e.what());
            std::abort();
        }
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
