/// Validation of scenario 1 with the vortex-lattice source on the Ranger 2000
/// (examples/ranger2000/aircraft.yaml, coarse lattice): the static table (alpha -4..12
/// deg x M 0.1..0.6 x beta -8..8 deg, 9 x 6 x 9 = 486 entries) rebuilt from 65 adaptively chosen
/// samples (maximum-MSE infill, as in Ghoreyshi et al. 2010, sec. II.B: "a 500 entry table ... for
/// 65 calculations") against the brute-force table of all 486 entries: the largest error of each
/// coefficient must stay below 2 % of its range, and the same budget spent on one Latin
/// hypercube must do worse. Scenario 2 on the same source: the elevator, aileron and rudder
/// increment tables (alpha x M x delta, 9 x 6 x 9 entries, deflections within the aircraft's limits
/// of examples/ranger2000/aircraft.yaml) from 12 deflected samples each, against the brute-force
/// increments of every entry. The numbers are printed (and quoted in docs/tables.md).

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/tables/generator.hpp"
#include "manta/vlm/source.hpp"

using namespace manta;
using namespace manta::tables;

namespace {

std::array<double, 6> max_relative_error(const TableWithSigma& t, const TableWithSigma& ref) {
    std::array<double, 6> err{}, lo, hi;
    lo.fill(1e300);
    hi.fill(-1e300);
    for (std::size_t e = 0; e < ref.table.values.size() / 6; ++e)
        for (std::size_t j = 0; j < 6; ++j) {
            const double r = ref.table.values[e * 6 + j];
            lo[j] = std::min(lo[j], r);
            hi[j] = std::max(hi[j], r);
            err[j] = std::max(err[j], std::abs(t.table.values[e * 6 + j] - r));
        }
    for (std::size_t j = 0; j < 6; ++j) err[j] /= hi[j] - lo[j];
    return err;
}

/// The coarse vortex lattice of the Ranger 2000 and the flow conditions at 3000 m.
struct RangerVlm {
    aircraft::AircraftDefinition def;
    std::unique_ptr<vlm::VlmSource> src;
    RunOptions options;
};

RangerVlm ranger_vlm() {
    RangerVlm r;
    r.def = aircraft::load_aircraft(std::filesystem::path(MANTA_SOURCE_DIR) /
                                    "examples/ranger2000/aircraft.yaml");
    const auto& def = r.def;
    vlm::Reference ref;
    ref.area = def.reference.area;
    ref.span = def.reference.span;
    ref.chord = def.reference.chord;
    ref.point = def.moment_reference_geom;
    vlm::LatticeDensity density;
    density.n_chord = 4;
    density.strip_width = 0.05;
    r.src = std::make_unique<vlm::VlmSource>(
        vlm::from_geometry(def.geometry, ref, density, def.name), def.geometry);
    const auto atm = flightdyn::us1976(3000.0);
    r.options.jobs = 2;
    r.options.conditions = [atm](double mach) {
        aero::FlowConditions c;
        c.reynolds_per_metre =
            vlm::reynolds_per_metre(atm.density, mach * atm.speed_of_sound, atm.dynamic_viscosity);
        return c;
    };
    return r;
}

double coef(const aero::SourceResult& r, std::size_t j) {
    const double v[6] = {r.wind.CL, r.wind.CD, r.wind.CY, r.body.Cl, r.body.Cm, r.body.Cn};
    return v[j];
}

/// Brute-force increments C(alpha, M, delta) - C(alpha, M, 0) at every entry of a control table
/// (entry-major, six coefficients per entry), evaluated with `jobs` threads.
std::vector<double> brute_force_increments(const aero::Table& t, const aero::AeroSource& src,
                                           const RunOptions& o) {
    const auto& A = t.axes;
    const std::size_t na = A[0].breakpoints.size(), nm = A[1].breakpoints.size(),
                      nd = A[2].breakpoints.size();
    std::vector<double> out(na * nm * nd * 6, 0.0);
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (;;) {
            const std::size_t g = next.fetch_add(1);
            if (g >= na * nm) return;
            aero::AeroQuery<double> q0;
            q0.alpha = A[0].breakpoints[g / nm];
            q0.mach = A[1].breakpoints[g % nm];
            const aero::FlowConditions fc = o.conditions(q0.mach);
            const aero::SourceResult r0 = src.evaluate(q0, fc);
            for (std::size_t k = 0; k < nd; ++k) {
                aero::AeroQuery<double> q = q0;
                const double d = A[2].breakpoints[k];
                (A[2].axis == aero::Axis::elevator  ? q.elevator
                 : A[2].axis == aero::Axis::aileron ? q.aileron
                                                    : q.rudder) = d;
                const aero::SourceResult r1 = d == 0.0 ? r0 : src.evaluate(q, fc);
                for (std::size_t j = 0; j < 6; ++j)
                    out[(g * nd + k) * 6 + j] = coef(r1, j) - coef(r0, j);
            }
        }
    };
    std::vector<std::thread> threads;
    for (int k = 1; k < o.jobs; ++k) threads.emplace_back(work);
    work();
    for (auto& th : threads) th.join();
    return out;
}

}  // namespace

TEST(TablesVlmValidation, AdaptiveSixtyFiveSamplesWithinTwoPercentAndBetterThanLhs) {
    using clock = std::chrono::steady_clock;
    const auto def = aircraft::load_aircraft(std::filesystem::path(MANTA_SOURCE_DIR) /
                                             "examples/ranger2000/aircraft.yaml");
    vlm::Reference ref;
    ref.area = def.reference.area;
    ref.span = def.reference.span;
    ref.chord = def.reference.chord;
    ref.point = def.moment_reference_geom;
    vlm::LatticeDensity density;
    density.n_chord = 4;
    density.strip_width = 0.05;
    const vlm::VlmSource src(vlm::from_geometry(def.geometry, ref, density, def.name),
                             def.geometry);
    const auto atm = flightdyn::us1976(3000.0);
    RunOptions o;
    o.jobs = 2;
    o.conditions = [atm](double mach) {
        aero::FlowConditions c;
        c.reynolds_per_metre =
            vlm::reynolds_per_metre(atm.density, mach * atm.speed_of_sound, atm.dynamic_viscosity);
        return c;
    };
    Campaign c = parse_campaign(
        "schema_version: 1\nname: ranger vlm\nsource: {type: analytic}\n"
        "static: {budget: 65, batch: 1, initial_design: {size: 20, seed: 1}}\n",
        "validation.yaml");

    auto t0 = clock::now();
    const TableWithSigma brute = brute_force_static(c.static_table, src, o);
    const double t_brute = std::chrono::duration<double>(clock::now() - t0).count();

    const auto dir = std::filesystem::temp_directory_path() / "manta_tables_vlm_validation";
    std::filesystem::remove_all(dir);
    auto run = [&](InfillCriterion criterion, const char* name) {
        Campaign k = c;
        k.static_table.criterion = criterion;
        auto store =
            SampleStore::open(dir / (std::string(name) + ".sqlite"), src.name(), src.fingerprint());
        const auto t = clock::now();
        const CampaignResult r = run_campaign(k, src, *store, o);
        const double dt = std::chrono::duration<double>(clock::now() - t).count();
        EXPECT_EQ(r.reports[0].samples_done, 65);
        const auto err = max_relative_error(r.tables[0], brute);
        std::printf("%-8s (65 samples, %.1f s):", name, dt);
        for (std::size_t j = 0; j < 6; ++j)
            std::printf(" %s %.2f %%", coefficient_names[j], 100 * err[j]);
        std::printf("\n");
        return err;
    };
    std::printf("brute force: 486 entries in %.1f s (%d jobs)\n", t_brute, o.jobs);
    const auto adaptive = run(InfillCriterion::max_mse, "adaptive");
    const auto random = run(InfillCriterion::random, "lhs");
    double worst_adaptive = 0.0, worst_random = 0.0;
    for (std::size_t j = 0; j < 6; ++j) {
        EXPECT_LT(adaptive[j], 0.02) << coefficient_names[j];
        worst_adaptive = std::max(worst_adaptive, adaptive[j]);
        worst_random = std::max(worst_random, random[j]);
    }
    // The adaptive design beats the Latin hypercube on the worst coefficient.
    EXPECT_LT(worst_adaptive, worst_random);
}

TEST(TablesVlmValidation, ControlIncrementsFromTwelveSamplesAgainstBruteForce) {
    // Scenario 2: the campaign of examples/ranger2000/campaign.yaml on the coarse lattice (static
    // table from 65 adaptive samples, then 12 deflected samples per control).
    const RangerVlm v = ranger_vlm();
    const Campaign c = parse_campaign(
        "schema_version: 1\nname: ranger vlm controls\nsource: {type: analytic}\n"
        "static: {budget: 65, batch: 1, initial_design: {size: 20, seed: 1}}\n"
        "controls:\n"
        "  elevator: {deflection_deg: {min: -25, max: 15, count: 9}, samples: 12}\n"
        "  aileron: {deflection_deg: {min: -25, max: 15, count: 9}, samples: 12}\n"
        "  rudder: {deflection_deg: {min: -17.5, max: 17.5, count: 9}, samples: 12}\n",
        "validation.yaml");
    // Within the aircraft's limits (controls: in aircraft.yaml).
    for (const ControlPlan& p : c.controls) {
        const auto& lim = p.control == aero::Axis::elevator  ? v.def.limits.elevator
                          : p.control == aero::Axis::aileron ? v.def.limits.aileron
                                                             : v.def.limits.rudder;
        check_control_limits(p, lim[0], lim[1]);
    }
    const auto dir = std::filesystem::temp_directory_path() / "manta_tables_vlm_controls";
    std::filesystem::remove_all(dir);
    auto store = SampleStore::open(dir / "controls.sqlite", v.src->name(), v.src->fingerprint());
    const CampaignResult r = run_campaign(c, *v.src, *store, v.options);
    ASSERT_EQ(r.tables.size(), 4u);
    struct Check {
        aero::Axis control;
        std::vector<std::size_t> coefficients;
        std::vector<double> bounds;  // of the max error over the largest |increment|
    };
    // The coefficients each control drives (aileron: roll, adverse yaw, side force). Measured
    // (docs/tables.md): elevator dCL 0.40 %, dCD 4.5 %, dCm 0.38 %; aileron dCl 1.7 %, dCn 2.4 %,
    // dCY 1.2 %; rudder dCY 0.40 %, dCl 1.5 %, dCn 0.13 % (the previous Co-Kriging of the full
    // coefficient: 6.0, 26.5, 5.2; 4.8, 9.2, 8.6; 6.8, 10.6, 7.7 %). The bounds leave a margin.
    // With the source's trailing legs along the free stream (MANTA issue 16, docs/vlm.md) the
    // increments depend more on alpha (the wing's wake moves relative to the T-tail): elevator
    // dCL 0.79 %, dCD 3.6 %, dCm 1.02 %; aileron 1.04, 2.07, 0.95 %; rudder 0.61, 0.87, 1.63 %.
    const std::vector<Check> checks = {{aero::Axis::elevator, {0, 1, 4}, {0.01, 0.06, 0.015}},
                                       {aero::Axis::aileron, {3, 5, 2}, {0.02, 0.035, 0.02}},
                                       {aero::Axis::rudder, {2, 3, 5}, {0.01, 0.02, 0.025}}};
    for (std::size_t k = 0; k < 3; ++k) {
        const TableWithSigma& t = r.tables[k + 1];
        ASSERT_EQ(t.table.axes[2].axis, checks[k].control);
        const std::vector<double> truth = brute_force_increments(t.table, *v.src, v.options);
        for (std::size_t i = 0; i < checks[k].coefficients.size(); ++i) {
            const std::size_t j = checks[k].coefficients[i];
            double err = 0.0, range = 0.0;
            for (std::size_t e = 0; e < truth.size() / 6; ++e) {
                err = std::max(err, std::abs(t.table.values[e * 6 + j] - truth[e * 6 + j]));
                range = std::max(range, std::abs(truth[e * 6 + j]));
            }
            std::printf("vlm %s d%s: max error %.2f %% of max |increment| %.5f\n",
                        std::string(aero::to_string(checks[k].control)).c_str(),
                        coefficient_names[j], 100 * err / range, range);
            EXPECT_LT(err, checks[k].bounds[i] * range)
                << aero::to_string(checks[k].control) << " " << coefficient_names[j];
            // Zero deflection: exactly zero by construction.
            for (std::size_t e = 0; e < truth.size() / 6; ++e)
                if (t.table.axes[2].breakpoints[e % t.table.axes[2].breakpoints.size()] == 0.0) {
                    EXPECT_EQ(t.table.values[e * 6 + j], 0.0);
                }
        }
    }
}
