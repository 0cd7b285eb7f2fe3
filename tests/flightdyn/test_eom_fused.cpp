// The fused double-precision right-hand side (src/flightdyn/fast_rhs*.cpp) against the templates
// it replaces (detail::euler_rhs_reference, detail::quaternion_rhs_reference), for the baseline
// and, where the processor has it, the AVX2 kernel set; and the cases it hands back to the
// templates (out-of-table queries, which must still be counted, thrust tables, C1 tables).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "eom_models.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/eom.hpp"
#include "random_states.hpp"
#include "test_sim_models.hpp"

namespace fd = manta::flightdyn;
using fd::detail::FastKernelSet;
using manta::core::deg;

namespace {

using Case = manta::test::RandomCase;
using manta::test::max_rel;

/// States mostly inside the tables, some beyond them; all attitudes and headings.
std::vector<Case> random_cases(int n, unsigned seed) {
    return manta::test::random_cases(n, seed, {60, 230, -8, 22, 11});
}

std::vector<FastKernelSet> kernel_sets() {
    std::vector<FastKernelSet> sets = {FastKernelSet::baseline};
    if (fd::detail::has_avx2_rhs_kernels()) sets.push_back(FastKernelSet::avx2);
    return sets;
}

const char* name_of(FastKernelSet k) {
    return k == FastKernelSet::avx2 ? "avx2" : "baseline";
}

}  // namespace

// Both state forms, both kernel sets, every model: the fused result equals the templates' to
// rounding (FMA contraction and the uniform-grid cell formula change the last bits), and the
// fused path takes most states (the rest are out-of-table queries).
TEST(FusedRhs, MatchesTheReferenceTemplates) {
    const auto cases = random_cases(400, 21);
    for (const fd::FlightModel& m : manta::test::eom_comparison_models()) {
        for (const FastKernelSet k : kernel_sets()) {
            SCOPED_TRACE(m.name + ", " + name_of(k));
            double worst_e = 0.0, worst_q = 0.0;
            int taken_e = 0, taken_q = 0;
            for (const Case& c : cases) {
                fd::EulerState<double> de;
                if (fd::detail::fast_euler_rhs(m, c.state, c.controls, de, k)) {
                    ++taken_e;
                    const auto ref = fd::detail::euler_rhs_reference(m, c.state, c.controls);
                    worst_e = std::max(worst_e, max_rel(de, ref));
                }
                const fd::QuatState<double> x = fd::to_quaternion_state(c.state);
                fd::QuatState<double> dq;
                if (fd::detail::fast_quaternion_rhs(m, x, c.controls, dq, k)) {
                    ++taken_q;
                    const auto ref = fd::detail::quaternion_rhs_reference(m, x, c.controls);
                    worst_q = std::max(worst_q, max_rel(dq, ref));
                }
            }
            EXPECT_LT(worst_e, 1e-13);
            EXPECT_LT(worst_q, 1e-13);
            EXPECT_GT(taken_e, 200);
            EXPECT_EQ(taken_q, taken_e);
            if (!m.aero) {
                EXPECT_EQ(taken_e, static_cast<int>(cases.size()));
            }
        }
    }
}

// Grids that are not exactly uniform take the other two cell searches (a uniform guess corrected
// by one cell for nodes within h/4 of uniform, a binary search otherwise): the same agreement.
TEST(FusedRhs, NonUniformGridsMatchTheReference) {
    fd::FlightModel m = manta::test::ranger_like();
    std::vector<manta::aero::Table> tables = m.aero->tables();
    for (auto& t : tables) {
        for (auto& a : t.axes) {
            if (a.axis == manta::aero::Axis::mach) a.breakpoints[3] += 0.013;  // within h/4
            if (a.axis == manta::aero::Axis::alpha && a.breakpoints.size() > 4)
                a.breakpoints[4] += 0.4 * (a.breakpoints[5] - a.breakpoints[4]);  // beyond h/4
        }
    }
    m.aero = std::make_shared<const manta::aero::AeroDatabase>(
        m.aero->info(), m.aero->force_axes(), m.aero->extrapolation(), std::move(tables));
    fd::finalize(m);
    for (const FastKernelSet k : kernel_sets()) {
        SCOPED_TRACE(name_of(k));
        int taken = 0;
        double worst = 0.0;
        for (const Case& c : random_cases(300, 5)) {
            fd::EulerState<double> d;
            if (!fd::detail::fast_euler_rhs(m, c.state, c.controls, d, k)) continue;
            ++taken;
            worst = std::max(worst,
                             max_rel(d, fd::detail::euler_rhs_reference(m, c.state, c.controls)));
        }
        EXPECT_GT(taken, 150);
        EXPECT_LT(worst, 1e-13);
    }
}

// An out-of-table query goes to the templates, which count it; every evaluation is counted once
// whichever path takes it.
TEST(FusedRhs, OutOfTableQueriesAreHandedBackAndCounted) {
    const fd::FlightModel m = manta::test::ranger_like();
    m.aero->reset_out_of_range();
    Case inside;
    inside.state << 0.0, 0.0, -3000.0, 0.1, 0.05, 0.3, 150.0, deg(3.0), deg(1.0), 0.1, 0.05, 0.02;
    inside.controls.throttle = 0.5;
    Case beyond = inside;
    beyond.state[fd::euler::alpha] = deg(40.0);  // above the alpha grid
    fd::EulerState<double> d;
    EXPECT_TRUE(
        fd::detail::fast_euler_rhs(m, inside.state, inside.controls, d, FastKernelSet::baseline));
    EXPECT_FALSE(
        fd::detail::fast_euler_rhs(m, beyond.state, beyond.controls, d, FastKernelSet::baseline));
    auto r = m.aero->out_of_range();
    EXPECT_EQ(r.evaluations, 1u);  // the fused evaluation; the refused one counts nothing
    EXPECT_EQ(r.total(), 0u);
    (void)fd::euler_rhs(m, inside.state, inside.controls);
    (void)fd::euler_rhs(m, beyond.state, beyond.controls);
    r = m.aero->out_of_range();
    EXPECT_EQ(r.evaluations, 3u);
    EXPECT_GT(r.total(), 0u);
    const auto all = r.entries;
    ASSERT_FALSE(all.empty());
    for (const auto& e : all) EXPECT_EQ(e.axis, manta::aero::Axis::alpha);
}

// Models the fused path does not cover take the templates; euler_rhs gives their result.
TEST(FusedRhs, UncoveredModelsTakeTheTemplates) {
    const Case c = random_cases(1, 3).front();
    fd::FlightModel c1 = manta::test::ranger_like();
    c1.interpolation = manta::aero::Interpolation::c1;
    fd::FlightModel table = manta::test::ranger_like();
    table.engine.type = fd::EngineModel::Type::table;
    table.engine.altitude = {0.0, 10000.0};
    table.engine.mach = {0.0, 1.0};
    table.engine.throttle = {0.0, 1.0};
    table.engine.thrust = {0.0, 14000.0, 0.0, 13000.0, 0.0, 6000.0, 0.0, 5500.0};
    fd::finalize(table);
    for (const fd::FlightModel* m : {&c1, &table}) {
        fd::EulerState<double> d;
        EXPECT_FALSE(fd::detail::fast_euler_rhs(*m, c.state, c.controls, d));
        EXPECT_EQ(fd::euler_rhs(*m, c.state, c.controls),
                  fd::detail::euler_rhs_reference(*m, c.state, c.controls));
    }
    // Loads wanted: the templates, which fill them.
    const fd::FlightModel m = manta::test::ranger_like();
    fd::Loads<double> L;
    EXPECT_EQ(fd::euler_rhs(m, c.state, c.controls, &L),
              fd::detail::euler_rhs_reference(m, c.state, c.controls));
    EXPECT_GT(L.dynamic_pressure, 0.0);
}

// The automatic choice names its set; a processor with AVX2 and FMA uses them unless the
// environment says otherwise.
TEST(FusedRhs, KernelChoice) {
    const std::string name = fd::detail::fast_rhs_kernel_name();
    EXPECT_TRUE(name == "avx2" || name == "baseline" || name == "reference") << name;
    if (name == "avx2") {
        EXPECT_TRUE(fd::detail::has_avx2_rhs_kernels());
    }
}
