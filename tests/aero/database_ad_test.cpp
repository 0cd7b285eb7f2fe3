// AeroDatabase::evaluate with automatic-differentiation scalars: derivatives against central
// finite differences, for both interpolants, inside and outside the tables.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "aero_test_util.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/autodiff.hpp"

namespace manta::aero {
namespace {

constexpr int n_in = 11;

/// Random query whose table coordinates sit well inside cells (at least 5% of a cell from any
/// breakpoint), so a central difference never straddles a cell face.
AeroQuery<double> interior_query(std::mt19937& rng) {
    std::uniform_real_distribution<double> t(0.05, 0.95), u(-0.5, 0.5);
    std::uniform_int_distribution<int> cell16(0, 15), cell5(0, 4), cell8(0, 7);
    const double deg = test::deg;
    AeroQuery<double> q;
    q.alpha = (-8 + 2 * (cell16(rng) + t(rng))) * deg;
    q.mach = 0.1 + 0.1 * (cell5(rng) + t(rng));
    q.beta = (-8 + 2 * (cell8(rng) + t(rng))) * deg;
    q.elevator = (-20 + 5 * (cell8(rng) + t(rng))) * deg;
    q.aileron = (-20 + 5 * (cell8(rng) + t(rng))) * deg;
    q.rudder = (-20 + 5 * (cell8(rng) + t(rng))) * deg;
    q.p_hat = 0.2 * u(rng);
    q.q_hat = 0.2 * u(rng);
    q.r_hat = 0.2 * u(rng);
    q.alpha_dot_hat = 0.2 * u(rng);
    q.beta_dot_hat = 0.2 * u(rng);
    return q;
}

/// Query with every input an independent variable.
AeroQuery<core::Dual> seeded(AeroQuery<double> q) {
    AeroQuery<core::Dual> d;
    const auto in = test::fields(q);
    const auto out = test::fields(d);
    for (std::size_t k = 0; k < in.size(); ++k)
        *out[k] = core::make_dual(*in[k], n_in, static_cast<Eigen::Index>(k));
    return d;
}

/// Central-difference Jacobian d(coefficient)/d(input), 6 x 11.
std::array<std::array<double, n_in>, 6> finite_difference(const AeroDatabase& db,
                                                          const AeroQuery<double>& q,
                                                          Interpolation m, double h = 1e-6) {
    std::array<std::array<double, n_in>, 6> J{};
    for (std::size_t k = 0; k < n_in; ++k) {
        AeroQuery<double> qp = q, qm = q;
        *test::fields(qp)[k] += h;
        *test::fields(qm)[k] -= h;
        const auto fp = test::as_array(db.evaluate(qp, m));
        const auto fm = test::as_array(db.evaluate(qm, m));
        for (std::size_t c = 0; c < 6; ++c) J[c][k] = (fp[c] - fm[c]) / (2 * h);
    }
    return J;
}

void expect_ad_matches_fd(const AeroDatabase& db, const AeroQuery<double>& q, Interpolation m) {
    const auto ad = test::as_array(db.evaluate(seeded(q), m));
    const auto value = test::as_array(db.evaluate(q, m));
    const auto fd = finite_difference(db, q, m);
    for (std::size_t c = 0; c < 6; ++c) {
        EXPECT_NEAR(ad[c].value(), value[c], 1e-14 * (1 + std::abs(value[c])));
        ASSERT_EQ(ad[c].derivatives().size(), n_in);
        for (std::size_t k = 0; k < n_in; ++k) {
            const double d = ad[c].derivatives()(static_cast<Eigen::Index>(k));
            EXPECT_NEAR(d, fd[c][k], 2e-7 * (1 + std::abs(d)))
                << "coefficient " << c << " input " << k;
        }
    }
}

TEST(AeroDatabaseAutodiff, MatchesFiniteDifferencesInside) {
    for (const bool uniform : {true, false}) {
        const AeroDatabase db = test::ranger_like(Extrapolation::clamp, uniform);
        std::mt19937 rng(21);
        for (int n = 0; n < 40; ++n) {
            const auto q = interior_query(rng);
            expect_ad_matches_fd(db, q, Interpolation::multilinear);
            expect_ad_matches_fd(db, q, Interpolation::c1);
        }
    }
}

TEST(AeroDatabaseAutodiff, MatchesFiniteDifferencesOnRoughData) {
    // Random (non-smooth) data on a non-uniform grid: the C1 slopes then differ from the secants.
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const GridAxis alpha{Axis::alpha, {-0.2, -0.1, 0.0, 0.05, 0.1, 0.2, 0.35}};
    const GridAxis mach{Axis::mach, {0.1, 0.2, 0.45, 0.6}};
    const GridAxis beta{Axis::beta, {-0.1, 0.0, 0.1}};
    auto rand_row = [&](std::size_t n) {
        std::vector<double> r;
        for (std::size_t k = 0; k < n; ++k) r.push_back(u(rng));
        return r;
    };
    std::vector<Table> tables;
    tables.push_back(test::make_table("static", TableKind::static_table, {alpha, mach, beta},
                                      {"CL", "CD", "CY", "Cl", "Cm", "Cn"},
                                      [&](const std::vector<double>&) { return rand_row(6); }));
    tables.push_back(test::make_table(
        "rudder", TableKind::control, {alpha, {Axis::rudder, {-0.3, -0.1, 0.0, 0.2, 0.3}}},
        {"CY", "Cn"}, [&](const std::vector<double>&) { return rand_row(2); }));
    tables.push_back(test::make_table("dynamic", TableKind::dynamic, {alpha, mach},
                                      {"Cm_q", "CL_alphadot", "Cn_r", "Cl_betadot"},
                                      [&](const std::vector<double>&) { return rand_row(4); }));
    const AeroDatabase db({"rough", "", ""}, ForceAxes::wind, Extrapolation::linear, tables);
    for (int n = 0; n < 60; ++n) {
        AeroQuery<double> q;
        // Avoid breakpoints by a margin larger than the difference step.
        auto pick = [&](const std::vector<double>& x) {
            std::uniform_int_distribution<std::size_t> cell(0, x.size() - 2);
            std::uniform_real_distribution<double> t(0.05, 0.95);
            const std::size_t i = cell(rng);
            return x[i] + t(rng) * (x[i + 1] - x[i]);
        };
        q.alpha = pick(alpha.breakpoints);
        q.mach = pick(mach.breakpoints);
        q.beta = pick(beta.breakpoints);
        q.rudder = pick({-0.3, -0.1, 0.0, 0.2, 0.3});
        q.q_hat = 0.1 * u(rng);
        q.r_hat = 0.1 * u(rng);
        q.alpha_dot_hat = 0.1 * u(rng);
        q.beta_dot_hat = 0.1 * u(rng);
        expect_ad_matches_fd(db, q, Interpolation::multilinear);
        expect_ad_matches_fd(db, q, Interpolation::c1);
    }
}

TEST(AeroDatabaseAutodiff, OutsideTheTables) {
    std::mt19937 rng(23);
    AeroQuery<double> q = interior_query(rng);
    q.alpha = 30 * test::deg;    // above the alpha grid
    q.rudder = -25 * test::deg;  // below the rudder grid
    for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
        // Linear extrapolation: smooth outside, derivatives match differences.
        expect_ad_matches_fd(test::ranger_like(Extrapolation::linear), q, method);
        // Clamp: constant along the clamped axes.
        const AeroDatabase clamp = test::ranger_like(Extrapolation::clamp);
        const auto ad = test::as_array(clamp.evaluate(seeded(q), method));
        for (std::size_t c = 0; c < 6; ++c) {
            if (c < 3) continue;  // forces turn with alpha through the wind-to-body rotation
            EXPECT_EQ(ad[c].derivatives()(0), 0.0) << c;  // d/d alpha
            EXPECT_EQ(ad[c].derivatives()(5), 0.0) << c;  // d/d rudder
        }
        expect_ad_matches_fd(clamp, q, method);
    }
}

TEST(AeroDatabaseAutodiff, PartiallySeededAndFixedSizeScalars) {
    const AeroDatabase db = test::ranger_like();
    std::mt19937 rng(24);
    const auto q = interior_query(rng);
    // Only alpha and elevator are variables; the other fields keep empty derivative vectors.
    AeroQuery<core::Dual> d;
    d.alpha = core::make_dual(q.alpha, 2, 0);
    d.elevator = core::make_dual(q.elevator, 2, 1);
    d.mach = q.mach;
    d.q_hat = q.q_hat;
    AeroQuery<double> qd;
    qd.alpha = q.alpha;
    qd.elevator = q.elevator;
    qd.mach = q.mach;
    qd.q_hat = q.q_hat;
    const auto full = test::as_array(db.evaluate(seeded(qd), Interpolation::c1));
    const auto part = test::as_array(db.evaluate(d, Interpolation::c1));
    // A fixed-size derivative vector takes the same path.
    using Fixed = Eigen::AutoDiffScalar<Eigen::Vector2d>;
    AeroQuery<Fixed> f;
    f.alpha = Fixed(q.alpha, Eigen::Vector2d(1, 0));
    f.elevator = Fixed(q.elevator, Eigen::Vector2d(0, 1));
    f.mach = Fixed(q.mach, Eigen::Vector2d::Zero());
    f.q_hat = Fixed(q.q_hat, Eigen::Vector2d::Zero());
    const auto fixed = test::as_array(db.evaluate(f, Interpolation::c1));
    for (std::size_t c = 0; c < 6; ++c) {
        ASSERT_EQ(part[c].derivatives().size(), 2);
        EXPECT_EQ(part[c].value(), full[c].value());
        EXPECT_NEAR(part[c].derivatives()(0), full[c].derivatives()(0), 1e-14);
        EXPECT_NEAR(part[c].derivatives()(1), full[c].derivatives()(3), 1e-14);
        EXPECT_NEAR(fixed[c].derivatives()(0), full[c].derivatives()(0), 1e-14);
        EXPECT_NEAR(fixed[c].derivatives()(1), full[c].derivatives()(3), 1e-14);
    }
}

/// Minimal forward-mode dual number with one derivative: not an Eigen type, so evaluate runs
/// the generic path with every weight in this type.
struct Fwd {
    double v = 0.0;
    double d = 0.0;
    Fwd() = default;
    Fwd(double value, double derivative = 0.0) : v(value), d(derivative) {}  // NOLINT
    [[nodiscard]] double value() const { return v; }
    Fwd operator+(const Fwd& o) const { return {v + o.v, d + o.d}; }
    Fwd operator-(const Fwd& o) const { return {v - o.v, d - o.d}; }
    Fwd operator*(const Fwd& o) const { return {v * o.v, d * o.v + v * o.d}; }
    Fwd operator-() const { return {-v, -d}; }
    friend Fwd cos(const Fwd& x) { return {std::cos(x.v), -std::sin(x.v) * x.d}; }
    friend Fwd sin(const Fwd& x) { return {std::sin(x.v), std::cos(x.v) * x.d}; }
};

TEST(AeroDatabaseAutodiff, GenericScalarPathAgreesWithDual) {
    for (const auto extrapolation : {Extrapolation::clamp, Extrapolation::linear}) {
        const AeroDatabase db = test::ranger_like(extrapolation);
        std::mt19937 rng(25);
        for (int n = 0; n < 20; ++n) {
            auto q = interior_query(rng);
            if (n % 4 == 0) q.alpha = 0.6;  // out of range too
            const auto dual = test::as_array(db.evaluate(seeded(q), Interpolation::c1));
            for (std::size_t k = 0; k < n_in; ++k) {
                AeroQuery<Fwd> f;
                auto qd = q;
                const auto in = test::fields(qd);
                const auto out = test::fields(f);
                for (std::size_t j = 0; j < n_in; ++j) *out[j] = Fwd(*in[j], j == k ? 1.0 : 0.0);
                for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
                    const auto g = db.evaluate(f, method);
                    const std::array<Fwd, 6> ga = {g.CX, g.CY, g.CZ, g.Cl, g.Cm, g.Cn};
                    const auto ref = test::as_array(db.evaluate(seeded(q), method));
                    for (std::size_t c = 0; c < 6; ++c) {
                        EXPECT_NEAR(ga[c].v, ref[c].value(), 1e-14);
                        EXPECT_NEAR(ga[c].d, ref[c].derivatives()(static_cast<Eigen::Index>(k)),
                                    1e-12);
                    }
                }
            }
            (void)dual;
        }
    }
}

TEST(AeroDatabaseAutodiff, CountsOneEvaluationPerCall) {
    const AeroDatabase db = test::ranger_like();
    std::mt19937 rng(26);
    (void)db.evaluate(seeded(interior_query(rng)), Interpolation::multilinear);
    (void)db.evaluate(seeded(interior_query(rng)), Interpolation::c1);
    AeroQuery<Fwd> f;
    f.mach = 0.3;
    (void)db.evaluate(f, Interpolation::c1);
    EXPECT_EQ(db.out_of_range().evaluations, 3u);
    EXPECT_EQ(db.out_of_range().total(), 0u);
}

}  // namespace
}  // namespace manta::aero
