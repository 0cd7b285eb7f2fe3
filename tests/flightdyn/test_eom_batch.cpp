// The batched right-hand sides (euler_rhs_batch, quaternion_rhs_batch; the four-lane AVX2
// kernels of src/flightdyn/fast_rhs_batch_impl.inc) against the reference templates, the lanes
// they hand back to the scalar path, and the evaluation count.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "eom_models.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/eom.hpp"
#include "random_states.hpp"
#include "test_sim_models.hpp"

namespace fd = manta::flightdyn;
using manta::core::deg;
using manta::test::max_rel;
using manta::test::RandomCase;

namespace {

struct Batch {
    std::vector<fd::EulerState<double>> s;
    std::vector<fd::Controls<double>> u;
};

Batch batch_of(const std::vector<RandomCase>& cases) {
    Batch b;
    for (const auto& c : cases) {
        b.s.push_back(c.state);
        b.u.push_back(c.controls);
    }
    return b;
}

/// Largest relative difference of the batch results (both state forms) from the reference
/// templates, state by state.
double worst_against_reference(const fd::FlightModel& m, const Batch& b) {
    std::vector<fd::EulerState<double>> d(b.s.size());
    fd::euler_rhs_batch(m, b.s, b.u, d);
    double worst = 0.0;
    for (std::size_t i = 0; i < b.s.size(); ++i)
        worst = std::max(worst, max_rel(d[i], fd::detail::euler_rhs_reference(m, b.s[i], b.u[i])));
    std::vector<fd::QuatState<double>> q, dq(b.s.size());
    for (const auto& x : b.s) q.push_back(fd::to_quaternion_state(x));
    fd::quaternion_rhs_batch(m, q, b.u, dq);
    for (std::size_t i = 0; i < q.size(); ++i)
        worst =
            std::max(worst, max_rel(dq[i], fd::detail::quaternion_rhs_reference(m, q[i], b.u[i])));
    return worst;
}

}  // namespace

// Every comparison model (eom_models.hpp), states over all attitudes, headings up to 7 rad,
// altitudes 200 m to 12 km (two atmosphere layers), some beyond the tables; 401 states, so the last
// one is not in a group of four. Agreement to rounding with the templates.
TEST(BatchedRhs, MatchesTheReferenceTemplates) {
    const Batch b = batch_of(manta::test::random_cases(401, 8, {60, 230, -8, 22, 11}));
    for (const fd::FlightModel& m : manta::test::eom_comparison_models()) {
        SCOPED_TRACE(m.name);
        EXPECT_LT(worst_against_reference(m, b), 1e-13);
    }
}

// The vector atmosphere over every layer from the bottom of the model to 70 km, with speeds
// kept inside the Mach grid, and the vector exponential, logarithm, sine and cosine over the
// angles' whole reduced range (headings to 1e4 rad).
TEST(BatchedRhs, AllAtmosphereLayersAndLargeAngles) {
    const fd::FlightModel m = manta::test::ranger_like();
    std::vector<RandomCase> cases = manta::test::random_cases(400, 12, {60, 200, -4, 14, 8});
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const double h = -4000.0 + 74000.0 * static_cast<double>(i) / 399.0;
        cases[i].state[fd::euler::z] = -h;
        const double sound = std::sqrt(1.4 * 287.05 * fd::us1976(h).temperature);
        cases[i].state[fd::euler::V] = std::min(cases[i].state[fd::euler::V], 0.65 * sound);
        cases[i].state[fd::euler::psi] *= std::pow(10.0, static_cast<double>(i % 4));
    }
    EXPECT_LT(worst_against_reference(m, batch_of(cases)), 1e-13);
}

// States the four-lane pass does not take (above the alpha grid, alpha beyond -pi, a heading
// beyond the vector reduction's range, a non-principal sideslip) sit in groups with
// states it takes: each comes out as euler_rhs gives it, and every evaluation is counted once.
TEST(BatchedRhs, RefusedLanesTakeTheScalarPathAndAreCounted) {
    const fd::FlightModel m = manta::test::ranger_like();
    RandomCase inside;
    inside.state << 0.0, 0.0, -3000.0, 0.1, 0.05, 0.3, 150.0, deg(3.0), deg(1.0), 0.1, 0.05, 0.02;
    inside.controls.throttle = 0.5;
    std::vector<RandomCase> cases(16, inside);
    cases[1].state[fd::euler::alpha] = deg(40.0);
    cases[4].state[fd::euler::alpha] = -3.5;  // beyond -pi: not principal air data
    cases[6].state[fd::euler::psi] = 3e5;
    cases[11].state[fd::euler::beta] = deg(120.0);
    for (std::size_t i = 0; i < cases.size(); ++i)
        cases[i].state[fd::euler::V] += static_cast<double>(i);
    const Batch b = batch_of(cases);
    m.aero->reset_out_of_range();
    std::vector<fd::EulerState<double>> d(b.s.size());
    fd::euler_rhs_batch(m, b.s, b.u, d);
    EXPECT_EQ(m.aero->out_of_range().evaluations, b.s.size());
    EXPECT_GT(m.aero->out_of_range().total(), 0u);  // the alpha = 40 deg query
    for (std::size_t i = 0; i < b.s.size(); ++i) {
        SCOPED_TRACE(i);
        const fd::EulerState<double> one = fd::euler_rhs(m, b.s[i], b.u[i]);
        if (one.allFinite()) {
            EXPECT_LT(max_rel(d[i], one), 1e-13);
        } else {
            EXPECT_FALSE(d[i].allFinite());
        }
    }
    // Where the processor has the four-lane kernel, the groups were taken by it: all 16 written
    // by the batched pass, the refused lanes by euler_rhs within it.
    if (fd::detail::has_avx2_rhs_kernels()) {
        std::size_t next = 99;
        fd::detail::batched_euler_rhs(m, b.s.data(), b.u.data(), d.data(), b.s.size(),
                                      fd::detail::FastKernelSet::avx2, next);
        EXPECT_EQ(next, 16u);
        std::vector<fd::QuatState<double>> q, dq(b.s.size());
        for (const auto& x : b.s) q.push_back(fd::to_quaternion_state(x));
        fd::detail::batched_quaternion_rhs(m, q.data(), b.u.data(), dq.data(), q.size(),
                                           fd::detail::FastKernelSet::avx2, next);
        EXPECT_EQ(next, 16u);
        for (std::size_t i = 0; i < q.size(); ++i) {
            const fd::QuatState<double> one = fd::quaternion_rhs(m, q[i], b.u[i]);
            if (one.allFinite()) {
                EXPECT_LT(max_rel(dq[i], one), 1e-13) << i;
            }
        }
    }
}

// Quaternion states with the air angles in every quadrant (alpha to +-180 deg, sideslip to
// +-89 deg, through the vector atan2's octants), on a model without aero tables (no grid to
// leave) and on the Ranger-like model (where most are beyond its tables and go the scalar way).
TEST(BatchedRhs, QuaternionAirAnglesInEveryQuadrant) {
    auto rigid = manta::test::rigid_body(5000.0, 8000.0, 25000.0, 30000.0, 1000.0);
    rigid.engine.static_thrust_sl = 14000.0;
    std::vector<RandomCase> cases = manta::test::random_cases(400, 31, {30, 230, -8, 22, 11});
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const double a = -179.0 + 358.0 * static_cast<double>(i) / 399.0;
        cases[i].state[fd::euler::alpha] = deg(a);
        cases[i].state[fd::euler::beta] = deg(89.0 * std::sin(0.37 * static_cast<double>(i)));
    }
    const Batch b = batch_of(cases);
    EXPECT_LT(worst_against_reference(rigid, b), 1e-13);
    EXPECT_LT(worst_against_reference(manta::test::ranger_like(), b), 1e-13);
}

// Spans of different lengths are refused in one line naming the counts.
TEST(BatchedRhs, MismatchedSpansAreRefused) {
    const fd::FlightModel m = manta::test::ranger_like();
    const Batch b = batch_of(manta::test::random_cases(5, 1, {60, 230, -8, 22, 11}));
    std::vector<fd::EulerState<double>> d(4);
    try {
        fd::euler_rhs_batch(m, b.s, b.u, d);
        FAIL() << "no error";
    } catch (const manta::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("5 states, 5 controls and 4 outputs"),
                  std::string::npos)
            << e.what();
    }
    std::vector<fd::QuatState<double>> q(5), dq(4);
    EXPECT_THROW(fd::quaternion_rhs_batch(m, q, b.u, dq), manta::InputError);
}
