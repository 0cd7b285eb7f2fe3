/// Campaign files: a full campaign read back, the Ranger defaults, and the one-line errors
/// (file, line, key, value, expectation) of the validation layer.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/tables/campaign.hpp"

using namespace manta;
using namespace manta::tables;

namespace {

/// The error message of parsing `text`, or "" if it parses.
std::string error_of(const std::string& text) {
    try {
        (void)parse_campaign(text, "c.yaml");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return {};
}

const std::string minimal = "schema_version: 1\nname: t\nsource: {type: analytic}\n";

}  // namespace

TEST(Campaign, FullFileIsReadInSiUnits) {
    const Campaign c = parse_campaign(R"(schema_version: 1
name: Ranger tables
source:
  type: vlm
  aircraft: ../ranger2000/aircraft.yaml
  lattice: {n_chord: 4, strip_width: 0.05}
  viscous: false
flight_condition: {altitude: 3000}
static:
  alpha_deg: {min: -4, max: 12, count: 9}
  mach: [0.1, 0.3, 0.6]
  beta: [-0.1, 0, 0.1]
  initial_design: {size: 10, seed: 7}
  budget: 40
  criterion: ei
  ei: {coefficient: Cm, sense: max}
  batch: 3
  cv_threshold: 0.01
  kriging: {correlation: matern52, trend: linear, nugget: estimate, restarts: 3}
controls:
  elevator: {deflection_deg: {min: -25, max: 15, count: 5}, samples: 10, seed: 4}
  rudder: {deflection_deg: [-10, 10], mach: [0.2, 0.4]}
dynamic: {alpha_deg: [0, 10], rate_step: 0.02}
output: {extrapolation: linear, plot_mach: [0.3], plot_beta_deg: [0, 5]}
)",
                                      "c.yaml", "/campaigns");
    EXPECT_EQ(c.name, "Ranger tables");
    EXPECT_EQ(c.source.type, SourceType::vlm);
    EXPECT_EQ(c.source.aircraft, std::filesystem::path("/campaigns/../ranger2000/aircraft.yaml"));
    EXPECT_EQ(c.source.n_chord, 4);
    EXPECT_FALSE(c.source.viscous);
    EXPECT_EQ(c.altitude, 3000.0);
    ASSERT_EQ(c.static_table.alpha.size(), 9u);
    EXPECT_NEAR(c.static_table.alpha.front(), core::deg(-4.0), 1e-15);
    EXPECT_NEAR(c.static_table.alpha[2], 0.0, 0.0);  // exact zero breakpoint
    EXPECT_EQ(c.static_table.mach.size(), 3u);
    EXPECT_EQ(c.static_table.beta[0], -0.1);
    EXPECT_EQ(c.static_table.initial_size, 10);
    EXPECT_EQ(c.static_table.seed, 7u);
    EXPECT_EQ(c.static_table.budget, 40);
    EXPECT_EQ(c.static_table.criterion, InfillCriterion::ei);
    EXPECT_EQ(c.static_table.ei_coefficient, "Cm");
    EXPECT_TRUE(c.static_table.ei_maximise);
    EXPECT_EQ(c.static_table.batch, 3);
    EXPECT_EQ(c.static_table.cv_threshold, 0.01);
    EXPECT_EQ(c.static_table.kriging.correlation, surrogate::Correlation::matern52);
    EXPECT_EQ(c.static_table.kriging.trend, surrogate::Trend::linear);
    EXPECT_TRUE(c.static_table.kriging.estimate_nugget);
    EXPECT_EQ(c.static_table.kriging.restarts, 3);
    ASSERT_EQ(c.controls.size(), 2u);
    EXPECT_EQ(c.controls[0].control, aero::Axis::elevator);
    EXPECT_EQ(c.controls[0].deflection.size(), 6u);  // -25 -15 -5 5 15 and 0 inserted
    EXPECT_EQ(c.controls[1].control, aero::Axis::rudder);
    // 0 is inserted into an axis that lacks it: the increment is zero there.
    EXPECT_EQ(c.controls[1].deflection.size(), 3u);
    EXPECT_EQ(c.controls[1].deflection[1], 0.0);
    EXPECT_EQ(c.controls[1].samples, 12);
    EXPECT_EQ(c.controls[1].mach, (std::vector<double>{0.2, 0.4}));
    EXPECT_EQ(c.controls[1].alpha, c.static_table.alpha);  // default: the static axis
    ASSERT_TRUE(c.dynamic);
    EXPECT_EQ(c.dynamic->alpha.size(), 2u);
    EXPECT_EQ(c.dynamic->mach, c.static_table.mach);
    EXPECT_EQ(c.dynamic->rate_step, 0.02);
    EXPECT_EQ(c.output.extrapolation, aero::Extrapolation::linear);
    EXPECT_EQ(c.output.plot_beta.size(), 2u);
}

TEST(Campaign, DefaultsAreTheRangerTableOfTheIssue) {
    const Campaign c = parse_campaign(minimal, "c.yaml");
    EXPECT_EQ(c.static_table.alpha.size() * c.static_table.mach.size() * c.static_table.beta.size(),
              486u);
    EXPECT_NEAR(c.static_table.alpha.back(), core::deg(12.0), 1e-15);
    EXPECT_EQ(c.static_table.mach.front(), 0.1);
    EXPECT_EQ(c.static_table.mach.back(), 0.6);
    EXPECT_NEAR(c.static_table.beta.front(), core::deg(-8.0), 1e-15);
    EXPECT_EQ(c.static_table.budget, 65);
    EXPECT_EQ(c.static_table.criterion, InfillCriterion::max_mse);
    EXPECT_TRUE(c.controls.empty());
    EXPECT_FALSE(c.dynamic);
}

TEST(Campaign, UnknownKeyIsNamedWithLineAndSuggestion) {
    const std::string m = error_of(minimal + "static:\n  budjet: 40\n");
    EXPECT_NE(m.find("c.yaml:5"), std::string::npos) << m;
    EXPECT_NE(m.find("budjet"), std::string::npos) << m;
    EXPECT_NE(m.find("did you mean 'budget'"), std::string::npos) << m;
}

TEST(Campaign, EulerSourceNeedsAMeshAndFillsEverySection) {
    // The mesh is required and resolved against the campaign's folder, like an aircraft file.
    EXPECT_NE(error_of("schema_version: 1\nname: t\nsource: {type: euler}\n").find("'source.mesh'"),
              std::string::npos);
    const Campaign c = parse_campaign(
        "schema_version: 1\nname: t\nsource: {type: euler, mesh: m.su2, config: cfd.yaml}\n",
        "c.yaml", "/cases");
    EXPECT_EQ(c.source.type, SourceType::euler);
    EXPECT_EQ(c.source.mesh, std::filesystem::path("/cases/m.su2"));
    EXPECT_EQ(c.source.cfd_config, std::filesystem::path("/cases/cfd.yaml"));
    // Control deflections (deformed mesh) and rotation rates (rotating frame) are accepted.
    const std::string head = "schema_version: 1\nname: t\nsource: {type: euler, mesh: m.su2}\n";
    const Campaign cd = parse_campaign(
        head + "controls:\n  elevator: {deflection_deg: [-5, 0, 5]}\ndynamic: {rate_step: 0.01}\n",
        "c.yaml", "/cases");
    ASSERT_EQ(cd.controls.size(), 1U);
    EXPECT_EQ(cd.controls[0].control, aero::Axis::elevator);
    ASSERT_TRUE(cd.dynamic);
    EXPECT_DOUBLE_EQ(cd.dynamic->rate_step, 0.01);
    // Also with a launcher (each sample a steady manta cfd job with its deflections and rates).
    const Campaign cl = parse_campaign(
        "schema_version: 1\nname: t\nsource: {type: euler, mesh: m.su2, launcher: mpirun}\n"
        "controls:\n  elevator: {deflection_deg: [-5, 0, 5]}\ndynamic: {rate_step: 0.01}\n",
        "c.yaml", "/cases");
    EXPECT_TRUE(cl.source.launched);
    EXPECT_EQ(cl.source.launcher, "mpirun");
    ASSERT_EQ(cl.controls.size(), 1U);
    ASSERT_TRUE(cl.dynamic);
}

TEST(Campaign, BadValuesAreReportedWithTheirExpectation) {
    EXPECT_NE(error_of(minimal + "static: {criterion: maxmse}\n").find("did you mean 'max_mse'"),
              std::string::npos);
    EXPECT_NE(error_of(minimal + "static: {mach: [0.1, 1.2]}\n").find("1.2"), std::string::npos);
    EXPECT_NE(error_of(minimal + "static: {alpha_deg: [0, 4, 2]}\n").find("strictly increasing"),
              std::string::npos);
    EXPECT_NE(error_of(minimal + "static: {budget: 600}\n").find("486 entries"), std::string::npos);
    EXPECT_NE(error_of(minimal + "static: {budget: 10, initial_design: {size: 20}}\n")
                  .find("exceeds the budget"),
              std::string::npos);
    EXPECT_NE(error_of(minimal + "controls: {elevator: {samples: 4}}\n").find("deflection_deg"),
              std::string::npos);
    EXPECT_NE(error_of(minimal + "controls: {flap: {deflection_deg: [0, 10]}}\n").find("flap"),
              std::string::npos);
    EXPECT_NE(
        error_of("schema_version: 2\nname: t\nsource: {type: analytic}\n").find("schema_version"),
        std::string::npos);
    EXPECT_NE(error_of(minimal + "static: {kriging: {nugget: lots}}\n").find("estimate"),
              std::string::npos);
}

TEST(Campaign, DeflectionsBeyondTheAircraftLimitsAreRefused) {
    const Campaign c =
        parse_campaign(minimal + "controls:\n  rudder: {deflection_deg: [-20, 0, 20]}\n", "c.yaml");
    try {
        check_control_limits(c.controls[0], core::deg(-17.5), core::deg(17.5));
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("c.yaml:5"), std::string::npos) << m;
        EXPECT_NE(m.find("controls.rudder.deflection_deg"), std::string::npos) << m;
        EXPECT_NE(m.find("17.5"), std::string::npos) << m;
    }
    EXPECT_NO_THROW(check_control_limits(c.controls[0], core::deg(-25), core::deg(25)));
}

TEST(Campaign, LinspaceHitsBothEndsAndZero) {
    const auto v = linspace(core::deg(-8.0), core::deg(8.0), 9);
    EXPECT_EQ(v.front(), core::deg(-8.0));
    EXPECT_EQ(v.back(), core::deg(8.0));
    EXPECT_EQ(v[4], 0.0);
    EXPECT_FALSE(std::signbit(v[4]));
}

// The Ranger's Euler campaigns of examples/ranger2000: the half model's longitudinal tables and
// the full model's static (alpha, Mach, sideslip), control and dynamic tables of the paper's
// sec. III-IV.A (65 static solutions, 12 deflected solutions per control); every deflection
// within the aircraft file's control limits.
TEST(Campaign, TheRangerEulerCampaignsAreValid) {
    const std::filesystem::path dir =
        std::filesystem::path(MANTA_SOURCE_DIR) / "examples/ranger2000";
    const auto def = aircraft::load_aircraft(dir / "aircraft.yaml");
    const auto check_limits = [&](const Campaign& c) {
        for (const auto& plan : c.controls) {
            const auto& lim = plan.control == aero::Axis::elevator  ? def.limits.elevator
                              : plan.control == aero::Axis::aileron ? def.limits.aileron
                                                                    : def.limits.rudder;
            EXPECT_NO_THROW(check_control_limits(plan, lim[0], lim[1])) << plan.where;
        }
    };

    const Campaign half = read_campaign(dir / "campaign-euler-half.yaml");
    EXPECT_EQ(half.source.type, SourceType::euler);
    EXPECT_EQ(half.source.mesh_model, "half");
    EXPECT_EQ(half.source.mesh_level, "coarse");
    EXPECT_EQ(half.source.aircraft, dir / "aircraft.yaml");
    ASSERT_EQ(half.static_table.beta.size(), 1U);  // a half model: beta 0 only
    EXPECT_EQ(half.static_table.beta[0], 0.0);
    ASSERT_EQ(half.controls.size(), 1U);
    EXPECT_EQ(half.controls[0].control, aero::Axis::elevator);
    EXPECT_FALSE(half.dynamic.has_value());  // rates need the whole aircraft
    check_limits(half);

    const Campaign full = read_campaign(dir / "campaign-euler.yaml");
    EXPECT_EQ(full.source.type, SourceType::euler);
    EXPECT_EQ(full.source.mesh_model, "full");
    EXPECT_EQ(full.static_table.budget, 65);
    EXPECT_DOUBLE_EQ(full.static_table.alpha.front(), core::deg(-6.0));
    EXPECT_DOUBLE_EQ(full.static_table.alpha.back(), core::deg(14.0));
    EXPECT_EQ(full.static_table.mach.back(), 0.6);
    EXPECT_EQ(full.static_table.beta.size(), 5U);
    ASSERT_EQ(full.controls.size(), 3U);
    for (const auto& plan : full.controls) EXPECT_EQ(plan.samples, 12) << plan.where;
    ASSERT_TRUE(full.dynamic.has_value());
    EXPECT_EQ(full.dynamic->alpha.size() * full.dynamic->mach.size(), 6U);
    check_limits(full);
}
