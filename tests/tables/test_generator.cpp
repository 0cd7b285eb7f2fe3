/// Campaigns on the analytic source: scenario 1 (static table) reaches a stated accuracy against
/// the closed form, scenario 2 (control increments fused with the static model from 12 samples)
/// is exactly zero at zero deflection and accurate elsewhere, dynamic derivatives match the closed
/// form, and a campaign interrupted (twice, with samples in flight) and resumed gives bit-identical
/// tables.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/tables/analytic_source.hpp"
#include "manta/tables/generator.hpp"

using namespace manta;
using namespace manta::tables;

namespace {

std::filesystem::path fresh(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "manta_tables_generator" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir / "samples.sqlite";
}

double coef(const aero::SourceResult& r, std::size_t j) {
    const double v[6] = {r.wind.CL, r.wind.CD, r.wind.CY, r.body.Cl, r.body.Cm, r.body.Cn};
    return v[j];
}

/// A campaign on the analytic source: the default static grid (9 x 6 x 9).
Campaign analytic_campaign(int budget, int batch) {
    Campaign c = parse_campaign(
        "schema_version: 1\nname: analytic\nsource: {type: analytic}\n"
        "static: {budget: " +
            std::to_string(budget) + ", batch: " + std::to_string(batch) +
            ", initial_design: {size: 20, seed: 3}}\n"
            "controls:\n  elevator: {deflection_deg: {min: -25, max: 15, count: 9}, samples: 12}\n"
            "  rudder: {deflection_deg: [-17.5, -8.75, 0, 8.75, 17.5], samples: 12}\n"
            "dynamic: {alpha_deg: [-4, 4, 12], mach: [0.1, 0.6]}\n",
        "analytic.yaml");
    return c;
}

/// Largest error of each coefficient of a static table against the source, over the range of
/// the coefficient on the grid.
std::array<double, 6> relative_errors(const TableWithSigma& t, const aero::AeroSource& src) {
    std::array<double, 6> err{}, lo, hi;
    lo.fill(1e300);
    hi.fill(-1e300);
    const auto& A = t.table.axes;
    std::size_t e = 0;
    for (const double a : A[0].breakpoints)
        for (const double m : A[1].breakpoints)
            for (const double b : A[2].breakpoints) {
                aero::AeroQuery<double> q;
                q.alpha = a;
                q.mach = m;
                q.beta = b;
                const auto r = src.evaluate(q, {});
                for (std::size_t j = 0; j < 6; ++j) {
                    const double truth = coef(r, j);
                    lo[j] = std::min(lo[j], truth);
                    hi[j] = std::max(hi[j], truth);
                    err[j] = std::max(err[j], std::abs(t.table.values[e * 6 + j] - truth));
                }
                ++e;
            }
    for (std::size_t j = 0; j < 6; ++j) err[j] /= hi[j] - lo[j];
    return err;
}

/// Throws a non-std exception after `limit` evaluations: the campaign stops like a killed
/// process (the sample in flight stays pending in the store, nothing is recorded for it).
struct Killed {};
class KillingSource : public aero::AeroSource {
public:
    KillingSource(const aero::AeroSource& inner, int limit) : inner_(inner), limit_(limit) {}
    std::string name() const override { return inner_.name(); }
    std::string fingerprint() const override { return inner_.fingerprint(); }
    aero::SourceResult evaluate(const aero::AeroQuery<double>& q,
                                const aero::FlowConditions& c) const override {
        if (count_.fetch_add(1) >= limit_) throw Killed{};
        return inner_.evaluate(q, c);
    }

private:
    const aero::AeroSource& inner_;
    int limit_;
    mutable std::atomic<int> count_{0};
};

/// The 65-sample campaign with two control tables, run once for the tests that inspect it.
const CampaignResult& full_campaign() {
    static const CampaignResult result = [] {
        const AnalyticSource src;
        auto store = SampleStore::open(fresh("full"), src.name(), src.fingerprint());
        RunOptions o;
        o.jobs = 2;
        return run_campaign(analytic_campaign(65, 4), src, *store, o);
    }();
    return result;
}

}  // namespace

TEST(Campaign, StaticTableReachesStatedAccuracy) {
    // Scenario 1 on the 486-entry grid with the paper's 65 samples: every coefficient within
    // 2 % of its range at every entry (the figures are printed for docs/tables.md).
    const AnalyticSource src;
    const CampaignResult& r = full_campaign();
    EXPECT_EQ(r.reports[0].samples_done, 65);
    const auto err = relative_errors(r.tables[0], src);
    for (std::size_t j = 0; j < 6; ++j) {
        std::printf("static %s: max error %.3f %% of range, LOO/range %.2e\n", coefficient_names[j],
                    100 * err[j], r.reports[0].loo[j].relative);
        EXPECT_LT(err[j], 0.02) << coefficient_names[j];
    }
    // Sampled entries hold the sampled values with zero sigma; others a positive sigma.
    const auto& sig = r.tables[0].sigma;
    const auto n_zero = std::count(sig.begin(), sig.end(), 0.0);
    EXPECT_EQ(n_zero, 65 * 6);
}

TEST(Campaign, ControlIncrementsAreZeroAtZeroDeflectionAndAccurate) {
    const AnalyticSource src;
    const CampaignResult& r = full_campaign();
    ASSERT_EQ(r.tables.size(), 4u);
    for (std::size_t k = 1; k <= 2; ++k) {
        const TableWithSigma& t = r.tables[k];
        const aero::Axis control = t.table.axes[2].axis;
        const auto& A = t.table.axes;
        std::array<double, 6> err{}, range{};
        std::size_t e = 0;
        for (const double a : A[0].breakpoints)
            for (const double m : A[1].breakpoints)
                for (const double d : A[2].breakpoints) {
                    aero::AeroQuery<double> q0;
                    q0.alpha = a;
                    q0.mach = m;
                    aero::AeroQuery<double> q = q0;
                    (control == aero::Axis::elevator ? q.elevator : q.rudder) = d;
                    const auto r0 = src.evaluate(q0, {}), r1 = src.evaluate(q, {});
                    for (std::size_t j = 0; j < 6; ++j) {
                        const double v = t.table.values[e * 6 + j];
                        if (d == 0.0) {
                            EXPECT_EQ(v, 0.0);  // exactly, by construction
                            EXPECT_EQ(t.sigma[e * 6 + j], 0.0);
                        }
                        const double truth = coef(r1, j) - coef(r0, j);
                        err[j] = std::max(err[j], std::abs(v - truth));
                        range[j] = std::max(range[j], std::abs(truth));
                    }
                    ++e;
                }
        // The increments the control drives: elevator CL Cm (CD), rudder CY Cl Cn.
        const std::vector<std::size_t> main = control == aero::Axis::elevator
                                                  ? std::vector<std::size_t>{0, 1, 4}
                                                  : std::vector<std::size_t>{2, 3, 5};
        for (const std::size_t j : main) {
            std::printf("%s d%s: max error %.2f %% of max |increment| %.4f, slope gain %.3f\n",
                        std::string(aero::to_string(control)).c_str(), coefficient_names[j],
                        100 * err[j] / range[j], range[j], r.reports[k].rho[j]);
            // Measured (docs/tables.md), 12 samples over 9 x 6 x 9 entries: elevator dCL 5.0 %,
            // dCD 10.6 %, dCm 5.3 %; rudder dCY 0.11 %, dCl 2.4 %, dCn 0.11 % of the largest
            // increment (the previous Co-Kriging of the full coefficient: 19 %, 45 %, 19 %; 3.7 %).
            // The bounds leave a margin for platform differences.
            const double bound = control == aero::Axis::elevator ? (j == 1 ? 0.13 : 0.065)
                                 : j == 3                        ? 0.035
                                                                 : 0.005;
            EXPECT_LT(err[j], bound * range[j])
                << aero::to_string(control) << " " << coefficient_names[j];
        }
    }
}

TEST(Campaign, DynamicDerivativesMatchTheClosedForm) {
    const AnalyticSource src;
    const Campaign c = analytic_campaign(30, 4);
    auto store = SampleStore::open(fresh("dynamic"), src.name(), src.fingerprint());
    const CampaignResult r = run_campaign(c, src, *store, {});
    const TableWithSigma& t = r.tables.back();
    ASSERT_EQ(t.table.kind, aero::TableKind::dynamic);
    const auto& cols = t.table.columns;
    const auto col = [&](const std::string& n) {
        return static_cast<std::size_t>(std::find(cols.begin(), cols.end(), n) - cols.begin());
    };
    const auto& p = src.parameters();
    // Affine in q_hat and p_hat: central differences are exact to rounding.
    for (std::size_t g = 0; g < t.table.n_points(); ++g) {
        EXPECT_NEAR(t.table.values[g * cols.size() + col("Cm_q")], p.Cm_q, 1e-9);
        EXPECT_NEAR(t.table.values[g * cols.size() + col("Cl_p")], p.Cl_p, 1e-9);
        EXPECT_NEAR(t.table.values[g * cols.size() + col("CY_r")], p.CY_r, 1e-9);
    }
    EXPECT_EQ(r.reports.back().samples_done, 3 * 2 * 6);
}

TEST(Campaign, InterruptedAndResumedEqualsUninterrupted) {
    const AnalyticSource src;
    const Campaign c = analytic_campaign(40, 3);
    RunOptions o;
    o.jobs = 1;
    auto ref_store = SampleStore::open(fresh("reference"), src.name(), src.fingerprint());
    const CampaignResult ref = run_campaign(c, src, *ref_store, o);
    const std::string ref_text = make_database(c, ref, src.name()).to_text();

    const auto file = fresh("interrupted");
    // Killed during the initial design, then during an infill round (a batch of 3 with samples
    // still pending), then in the control scenario; the fourth run completes.
    int total_evaluated = 0;
    for (const int limit : {7, 25, 10}) {
        auto store = SampleStore::open(file, src.name(), src.fingerprint());
        const KillingSource killer(src, limit);
        EXPECT_THROW((void)run_campaign(c, killer, *store, o), Killed);
        total_evaluated += limit;
    }
    {
        auto store = SampleStore::open(file, src.name(), src.fingerprint());
        int pending = 0;
        for (const auto& s : store->samples()) pending += s.status == SampleStatus::pending;
        EXPECT_GE(pending, 1);  // samples were in flight when the run was "killed"
    }
    auto store = SampleStore::open(file, src.name(), src.fingerprint());
    const CampaignResult res = run_campaign(c, src, *store, o);
    EXPECT_EQ(res.reused, total_evaluated);
    EXPECT_EQ(res.reused + res.evaluated, ref.evaluated);  // nothing computed twice
    EXPECT_EQ(make_database(c, res, src.name()).to_text(), ref_text);
    for (std::size_t k = 0; k < ref.tables.size(); ++k)
        EXPECT_EQ(res.tables[k].sigma, ref.tables[k].sigma);
}

TEST(Campaign, FailedSamplesAreRecordedAndNotRetriedUnlessAsked) {
    AnalyticParameters p;
    p.fail_above_alpha = core::deg(10.5);  // the alpha = 12 deg entries fail
    const AnalyticSource src(p);
    Campaign c = analytic_campaign(30, 4);
    c.controls.clear();
    c.dynamic.reset();
    const auto file = fresh("failures");
    int failed = 0;
    {
        auto store = SampleStore::open(file, src.name(), src.fingerprint());
        const CampaignResult r = run_campaign(c, src, *store, {});
        failed = r.failed;
        EXPECT_GT(failed, 0);
        EXPECT_EQ(r.reports[0].samples_done + r.reports[0].samples_failed, 30);
        for (const auto& s : store->samples()) {
            if (s.status == SampleStatus::failed) {
                EXPECT_NE(s.error.find("fail_above_alpha"), std::string::npos);
            }
        }
    }
    {
        auto store = SampleStore::open(file, src.name(), src.fingerprint());
        const CampaignResult r = run_campaign(c, src, *store, {});
        EXPECT_EQ(r.evaluated, 0);  // failures are not retried
        EXPECT_EQ(r.failed, failed);
    }
    {
        auto store = SampleStore::open(file, src.name(), src.fingerprint());
        RunOptions o;
        o.retry_failed = true;
        const CampaignResult r = run_campaign(c, src, *store, o);
        EXPECT_EQ(r.evaluated, failed);  // each failed sample evaluated once more (and fails)
    }
}

TEST(Campaign, RandomDesignSpendsTheBudgetAtOnce) {
    const AnalyticSource src;
    Campaign c = analytic_campaign(40, 4);
    c.static_table.criterion = InfillCriterion::random;
    c.controls.clear();
    c.dynamic.reset();
    auto store = SampleStore::open(fresh("random"), src.name(), src.fingerprint());
    const CampaignResult r = run_campaign(c, src, *store, {});
    EXPECT_EQ(r.reports[0].samples_done, 40);
    EXPECT_EQ(r.reports[0].stop_reason, "design");
}

TEST(Campaign, CrossValidationThresholdStopsEarly) {
    const AnalyticSource src;
    Campaign c = analytic_campaign(65, 2);
    c.static_table.cv_threshold = 0.05;
    c.controls.clear();
    c.dynamic.reset();
    auto store = SampleStore::open(fresh("cv"), src.name(), src.fingerprint());
    const CampaignResult r = run_campaign(c, src, *store, {});
    EXPECT_EQ(r.reports[0].stop_reason, "cv_threshold");
    EXPECT_LT(r.reports[0].samples_done, 65);
    for (const auto& e : r.reports[0].loo) EXPECT_LT(e.relative, 0.05);
}
