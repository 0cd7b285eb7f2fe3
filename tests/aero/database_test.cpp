// AeroDatabase: interpolation properties, extrapolation and its counters, validation messages,
// axis conversions and the linear-derivative builder.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <thread>

#include "aero_test_util.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/autodiff.hpp"
#include "manta/core/error.hpp"
#include "manta/core/fastmath.hpp"

namespace manta::aero {
namespace {

using test::deg;
using test::linspace;
using test::make_table;

const std::vector<std::string> body_columns = {"CX", "CY", "CZ", "Cl", "Cm", "Cn"};
const std::vector<std::string> wind_columns = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};

/// Random multilinear function of d variables: sum over subsets S of c_S prod_{k in S} x_k.
struct Multilinear {
    std::vector<double> c;
    int d = 0;
    Multilinear(int dims, std::mt19937& rng) : d(dims) {
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        c.resize(std::size_t{1} << dims);
        for (auto& v : c) v = u(rng);
    }
    double operator()(const std::vector<double>& x) const {
        double s = 0.0;
        for (std::size_t m = 0; m < c.size(); ++m) {
            double p = c[m];
            for (int k = 0; k < d; ++k)
                if (m & (std::size_t{1} << k)) p *= x[static_cast<std::size_t>(k)];
            s += p;
        }
        return s;
    }
};

/// Body-axis database with one static table over `axes`, every column a function of the point.
AeroDatabase body_database(std::vector<GridAxis> axes,
                           const std::function<std::vector<double>(const std::vector<double>&)>& f,
                           Extrapolation e = Extrapolation::clamp) {
    std::vector<Table> tables;
    tables.push_back(
        make_table("static", TableKind::static_table, std::move(axes), body_columns, f));
    return AeroDatabase({"test", "", ""}, ForceAxes::body, e, std::move(tables));
}

/// Random point inside the table's box.
std::vector<double> random_point(const std::vector<GridAxis>& axes, std::mt19937& rng) {
    std::vector<double> p;
    for (const auto& a : axes) {
        std::uniform_real_distribution<double> u(a.breakpoints.front(), a.breakpoints.back());
        p.push_back(u(rng));
    }
    return p;
}

AeroQuery<double> query_at(const std::vector<GridAxis>& axes, const std::vector<double>& p) {
    AeroQuery<double> q;
    for (std::size_t k = 0; k < axes.size(); ++k) test::set_axis(q, axes[k].axis, p[k]);
    return q;
}

void expect_multilinear_exact(std::vector<GridAxis> axes, unsigned seed) {
    std::mt19937 rng(seed);
    const int d = static_cast<int>(axes.size());
    std::vector<Multilinear> f;
    for (int c = 0; c < 6; ++c) f.emplace_back(d, rng);
    const AeroDatabase db = body_database(axes, [&](const std::vector<double>& p) {
        std::vector<double> row;
        for (const auto& fc : f) row.push_back(fc(p));
        return row;
    });
    for (int n = 0; n < 2000; ++n) {
        const auto p = random_point(axes, rng);
        const auto r = test::as_array(db.evaluate(query_at(axes, p), Interpolation::multilinear));
        for (int c = 0; c < 6; ++c)
            EXPECT_NEAR(r[static_cast<std::size_t>(c)], f[static_cast<std::size_t>(c)](p), 1e-13);
        if (n % 10 == 0) {  // C1 reproduces multilinear data as well (it is exact on quadratics)
            const auto r1 = test::as_array(db.evaluate(query_at(axes, p), Interpolation::c1));
            for (int c = 0; c < 6; ++c)
                EXPECT_NEAR(r1[static_cast<std::size_t>(c)], f[static_cast<std::size_t>(c)](p),
                            1e-13);
        }
    }
    EXPECT_EQ(db.out_of_range().total(), 0u);
    EXPECT_EQ(db.out_of_range().evaluations, 2200u);
}

// ---------------------------------------------------------------- multilinear

TEST(AeroDatabaseMultilinear, ExactOnMultilinearData3D) {
    // Non-uniform alpha, uniform mach, uneven beta.
    expect_multilinear_exact({{Axis::alpha, {-0.2, -0.1, 0.0, 0.05, 0.1, 0.2, 0.35}},
                              {Axis::mach, linspace(0.1, 0.6, 6)},
                              {Axis::beta, {-0.1, 0.0, 0.03, 0.1}}},
                             1);
}

TEST(AeroDatabaseMultilinear, ExactOnMultilinearData4D) {
    expect_multilinear_exact({{Axis::alpha, linspace(-0.2, 0.4, 7)},
                              {Axis::mach, {0.1, 0.3, 0.35, 0.6}},
                              {Axis::beta, linspace(-0.1, 0.1, 5)},
                              {Axis::elevator, {-0.3, -0.1, 0.0, 0.2, 0.3}}},
                             2);
}

TEST(AeroDatabaseMultilinear, ExactOnMultilinearData5DAnd6D) {
    // More than four active axes: the run-time (not specialised) kernels.
    expect_multilinear_exact({{Axis::alpha, linspace(-0.2, 0.4, 4)},
                              {Axis::mach, {0.1, 0.3, 0.6}},
                              {Axis::beta, linspace(-0.1, 0.1, 3)},
                              {Axis::elevator, {-0.3, 0.0, 0.3}},
                              {Axis::aileron, {-0.2, 0.1, 0.2}}},
                             14);
    expect_multilinear_exact({{Axis::alpha, linspace(-0.2, 0.4, 3)},
                              {Axis::mach, {0.1, 0.6}},
                              {Axis::beta, linspace(-0.1, 0.1, 3)},
                              {Axis::elevator, {-0.3, 0.3}},
                              {Axis::aileron, {-0.2, 0.1, 0.2}},
                              {Axis::rudder, {-0.3, 0.3}}},
                             15);
}

TEST(AeroDatabaseMultilinear, WideDynamicTable) {
    // Fourteen rate columns: beyond the specialised kernels.
    const GridAxis alpha{Axis::alpha, {-0.1, 0.0, 0.1, 0.2}};
    const GridAxis mach{Axis::mach, {0.2, 0.4}};
    std::vector<std::string> columns;
    for (const char* c : {"CX", "CY", "CZ", "Cl", "Cm", "Cn", "CX"}) {
        for (const char* r : {"p", "q"}) columns.push_back(std::string(c) + "_" + r);
    }
    columns[12] = "Cm_alphadot";
    columns[13] = "Cn_betadot";
    std::vector<Table> tables;
    tables.push_back(
        make_table("static", TableKind::static_table, {alpha}, {"CX"},
                   [](const std::vector<double>& p) { return std::vector<double>{p[0]}; }));
    tables.push_back(make_table("dynamic", TableKind::dynamic, {alpha, mach}, columns,
                                [](const std::vector<double>& p) {
                                    std::vector<double> row;
                                    for (int c = 0; c < 14; ++c)
                                        row.push_back((c + 1) * (1 + p[0] + 2 * p[1]));
                                    return row;
                                }));
    const AeroDatabase db({"wide", "", ""}, ForceAxes::body, Extrapolation::clamp, tables);
    AeroQuery<double> q;
    q.alpha = 0.05;
    q.mach = 0.3;
    q.p_hat = 0.1;
    q.q_hat = 0.2;
    q.alpha_dot_hat = 0.3;
    q.beta_dot_hat = 0.4;
    const double k = 1 + 0.05 + 0.6;
    for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
        const auto r = db.evaluate(q, method);
        EXPECT_NEAR(r.CX, 0.05 + k * (1 * 0.1 + 2 * 0.2), 1e-14);
        EXPECT_NEAR(r.CY, k * (3 * 0.1 + 4 * 0.2), 1e-14);
        EXPECT_NEAR(r.Cm, k * (9 * 0.1 + 10 * 0.2 + 13 * 0.3), 1e-14);
        EXPECT_NEAR(r.Cn, k * (11 * 0.1 + 12 * 0.2 + 14 * 0.4), 1e-14);
        AeroQuery<core::Dual> qd;
        qd.alpha = core::make_dual(q.alpha, 2, 0);
        qd.mach = q.mach;
        qd.p_hat = q.p_hat;
        qd.q_hat = q.q_hat;
        qd.alpha_dot_hat = q.alpha_dot_hat;
        qd.beta_dot_hat = core::make_dual(q.beta_dot_hat, 2, 1);
        const auto d = db.evaluate(qd, method);
        EXPECT_NEAR(d.Cn.value(), r.Cn, 1e-14);
        EXPECT_NEAR(d.Cn.derivatives()(0), 11 * 0.1 + 12 * 0.2 + 14 * 0.4, 1e-12);  // d/d alpha
        EXPECT_NEAR(d.Cn.derivatives()(1), 14 * k, 1e-12);                          // d/d betadot
    }
}

TEST(AeroDatabaseMultilinear, OneBreakpointAxisIsConstantAndNotCounted) {
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.1, 0.0, 0.2}}, {Axis::beta, {0.0}}};
    const AeroDatabase db = body_database(axes, [](const std::vector<double>& p) {
        return std::vector<double>{p[0], 2 * p[0], 0, 0, 0, 1.0};
    });
    AeroQuery<double> q;
    q.alpha = 0.1;
    q.beta = 0.3;  // far from the single beta breakpoint: constant, not extrapolation
    const auto r = db.evaluate(q, Interpolation::multilinear);
    EXPECT_NEAR(r.CX, 0.1, 1e-15);
    EXPECT_NEAR(r.CY, 0.2, 1e-15);
    EXPECT_DOUBLE_EQ(r.Cn, 1.0);
    EXPECT_EQ(db.out_of_range().total(), 0u);
}

TEST(AeroDatabaseMultilinear, TableWithoutAxesIsConstant) {
    const AeroDatabase db = body_database(
        {}, [](const std::vector<double>&) { return std::vector<double>{1, 2, 3, 4, 5, 6}; });
    const auto r = test::as_array(db.evaluate(AeroQuery<double>{}, Interpolation::multilinear));
    const auto r1 = test::as_array(db.evaluate(AeroQuery<double>{}, Interpolation::c1));
    for (int c = 0; c < 6; ++c) {
        EXPECT_EQ(r[static_cast<std::size_t>(c)], c + 1.0);
        EXPECT_EQ(r1[static_cast<std::size_t>(c)], c + 1.0);
    }
}

/// A scalar type that is neither double nor first-order AD: evaluate takes the generic path.
struct Plain {
    double v = 0.0;
    Plain() = default;
    Plain(double x) : v(x) {}  // NOLINT(google-explicit-constructor)
    [[nodiscard]] double value() const { return v; }
    Plain operator+(const Plain& o) const { return v + o.v; }
    Plain operator-(const Plain& o) const { return v - o.v; }
    Plain operator*(const Plain& o) const { return v * o.v; }
    Plain operator-() const { return -v; }
    friend Plain cos(const Plain& x) { return std::cos(x.v); }
    friend Plain sin(const Plain& x) { return std::sin(x.v); }
};

TEST(AeroDatabaseMultilinear, FastPathMatchesGenericKernel) {
    // evaluate<double> multilinear runs a specialised kernel; the generic template must agree.
    const AeroDatabase db = test::ranger_like();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    for (int n = 0; n < 500; ++n) {
        AeroQuery<double> q;
        for (double* f : test::fields(q)) *f = u(rng);
        q.mach = 0.1 + 0.5 * (u(rng) + 0.5);
        // A scalar type that is not double and not first-order AD takes the generic path.
        AeroQuery<Plain> qp;
        qp.alpha = q.alpha, qp.beta = q.beta, qp.mach = q.mach, qp.elevator = q.elevator;
        qp.aileron = q.aileron, qp.rudder = q.rudder, qp.p_hat = q.p_hat, qp.q_hat = q.q_hat;
        qp.r_hat = q.r_hat, qp.alpha_dot_hat = q.alpha_dot_hat, qp.beta_dot_hat = q.beta_dot_hat;
        for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
            const auto a = test::as_array(db.evaluate(q, method));
            const auto b = db.evaluate(qp, method);
            const std::array<double, 6> bv = {b.CX.v, b.CY.v, b.CZ.v, b.Cl.v, b.Cm.v, b.Cn.v};
            for (std::size_t c = 0; c < 6; ++c)
                EXPECT_NEAR(a[c], bv[c], 1e-13 * (1 + std::abs(a[c])));
        }
    }
}

// ---------------------------------------------------------------- C1

/// Database over `axes` with values from a seeded random generator (rough data).
AeroDatabase random_database(const std::vector<GridAxis>& axes, unsigned seed,
                             Extrapolation e = Extrapolation::clamp) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    return body_database(
        axes,
        [&](const std::vector<double>&) {
            std::vector<double> row;
            for (int c = 0; c < 6; ++c) row.push_back(u(rng));
            return row;
        },
        e);
}

TEST(AeroDatabaseC1, ExactAtNodes) {
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.2, -0.1, 0.0, 0.05, 0.1, 0.2, 0.35}},
                                        {Axis::mach, {0.1, 0.3, 0.6}},
                                        {Axis::beta, {-0.1, 0.1}},
                                        {Axis::rudder, {-0.3, -0.1, 0.0, 0.2}}};
    const AeroDatabase db = random_database(axes, 4);
    const Table& t = db.tables()[0];
    std::vector<std::size_t> idx(axes.size(), 0);
    for (std::size_t n = 0; n < t.n_points(); ++n) {
        std::vector<double> p;
        for (std::size_t k = 0; k < axes.size(); ++k) p.push_back(axes[k].breakpoints[idx[k]]);
        for (const auto method : {Interpolation::c1, Interpolation::multilinear}) {
            const auto r = test::as_array(db.evaluate(query_at(axes, p), method));
            for (std::size_t c = 0; c < 6; ++c)
                EXPECT_NEAR(r[c], t.values[n * 6 + c], 4e-16) << n << " " << c;
        }
        for (std::size_t k = idx.size(); k-- > 0;) {
            if (++idx[k] < axes[k].breakpoints.size()) break;
            idx[k] = 0;
        }
    }
}

TEST(AeroDatabaseC1, ReproducesProductsOfQuadratics) {
    // The 3-point slopes are exact for quadratics, so the Hermite interpolant is too.
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.2, -0.1, 0.0, 0.05, 0.1, 0.2, 0.35}},
                                        {Axis::mach, {0.1, 0.25, 0.3, 0.6}},
                                        {Axis::beta, {-0.1, 0.02, 0.1}}};
    auto f = [](const std::vector<double>& p) {
        return (1 + 2 * p[0] - 3 * p[0] * p[0]) * (0.5 - p[1] + 0.7 * p[1] * p[1]) *
               (2 + p[2] - 4 * p[2] * p[2]);
    };
    const AeroDatabase db = body_database(axes, [&](const std::vector<double>& p) {
        return std::vector<double>{f(p), -f(p), 0, 0, 0, 0};
    });
    std::mt19937 rng(5);
    double worst_linear = 0.0;
    for (int n = 0; n < 1000; ++n) {
        const auto p = random_point(axes, rng);
        EXPECT_NEAR(db.evaluate(query_at(axes, p), Interpolation::c1).CX, f(p), 1e-13);
        worst_linear = std::max(
            worst_linear,
            std::abs(db.evaluate(query_at(axes, p), Interpolation::multilinear).CX - f(p)));
    }
    EXPECT_GT(worst_linear, 1e-4);  // multilinear is not exact here: the test has teeth
}

/// Value and partial derivative along `axis` at `p` (AD, so one-sided at the cell chosen).
std::pair<double, double> value_and_slope(const AeroDatabase& db, const std::vector<GridAxis>& axes,
                                          const std::vector<double>& p, std::size_t axis,
                                          std::size_t column, Interpolation method) {
    AeroQuery<core::Dual> q;
    for (std::size_t k = 0; k < axes.size(); ++k) {
        test::set_axis(q, axes[k].axis,
                       k == axis ? core::make_dual(p[k], 1, 0) : core::make_constant(p[k], 1));
    }
    const auto r = test::as_array(db.evaluate(q, method));
    const auto& v = r[column];
    return {v.value(), v.derivatives().size() ? v.derivatives()(0) : 0.0};
}

TEST(AeroDatabaseC1, ValueAndFirstDerivativesContinuousAcrossInteriorFaces) {
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.2, -0.1, 0.0, 0.05, 0.1, 0.2, 0.35}},
                                        {Axis::mach, {0.1, 0.2, 0.45, 0.6}},
                                        {Axis::beta, {-0.1, 0.0, 0.1}}};
    const AeroDatabase db = random_database(axes, 6);
    std::mt19937 rng(7);
    double worst_value = 0.0, worst_slope = 0.0, worst_linear_slope = 0.0;
    for (std::size_t k = 0; k < axes.size(); ++k) {
        const auto& x = axes[k].breakpoints;
        for (std::size_t j = 1; j + 1 < x.size(); ++j) {
            for (int trial = 0; trial < 20; ++trial) {
                auto p = random_point(axes, rng);
                const double eps = 1e-9 * (x[j + 1] - x[j - 1]);
                for (std::size_t c = 0; c < 6; ++c) {
                    p[k] = x[j] - eps;  // left cell
                    const auto left = value_and_slope(db, axes, p, k, c, Interpolation::c1);
                    p[k] = x[j] + eps;  // right cell
                    const auto right = value_and_slope(db, axes, p, k, c, Interpolation::c1);
                    worst_value = std::max(worst_value, std::abs(left.first - right.first));
                    worst_slope = std::max(worst_slope, std::abs(left.second - right.second));
                    // The partial derivatives along the other axes must match as well.
                    for (std::size_t other = 0; other < axes.size(); ++other) {
                        if (other == k) continue;
                        p[k] = x[j] - eps;
                        const double dl =
                            value_and_slope(db, axes, p, other, c, Interpolation::c1).second;
                        p[k] = x[j] + eps;
                        const double dr =
                            value_and_slope(db, axes, p, other, c, Interpolation::c1).second;
                        worst_slope = std::max(worst_slope, std::abs(dl - dr));
                    }
                    p[k] = x[j] - eps;
                    const double ml =
                        value_and_slope(db, axes, p, k, c, Interpolation::multilinear).second;
                    p[k] = x[j] + eps;
                    const double mr =
                        value_and_slope(db, axes, p, k, c, Interpolation::multilinear).second;
                    worst_linear_slope = std::max(worst_linear_slope, std::abs(ml - mr));
                }
            }
        }
    }
    // Slopes are O(100) on this rough data; second derivatives O(1e4): jumps of O(eps * f'').
    EXPECT_LT(worst_value, 1e-7);
    EXPECT_LT(worst_slope, 1e-4);
    EXPECT_GT(worst_linear_slope, 1.0);  // multilinear slopes do jump: the comparison has teeth
}

TEST(AeroDatabaseC1, TwoPointAxisIsLinear) {
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.1, 0.3}}};
    const AeroDatabase db = body_database(axes, [](const std::vector<double>& p) {
        return std::vector<double>{1 + 2 * p[0], 0, 0, 0, 0, 0};
    });
    for (const double a : {-0.1, 0.0, 0.123, 0.3}) {
        AeroQuery<double> q;
        q.alpha = a;
        EXPECT_NEAR(db.evaluate(q, Interpolation::c1).CX, 1 + 2 * a, 1e-15);
    }
}

// ---------------------------------------------------------------- extrapolation

TEST(AeroDatabaseExtrapolation, ClampHoldsEdgeValueAndCounts) {
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.1, 0.0, 0.1, 0.2}},
                                        {Axis::mach, {0.2, 0.4}}};
    auto f = [](const std::vector<double>& p) {
        return std::vector<double>{1 + p[0] + p[0] * p[1], p[1], 0, 0, 0, 0};
    };
    const AeroDatabase db = body_database(axes, f, Extrapolation::clamp);
    for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
        db.reset_out_of_range();
        AeroQuery<double> q;
        q.mach = 0.3;
        q.alpha = 0.5;
        EXPECT_NEAR(db.evaluate(q, method).CX, f({0.2, 0.3})[0], 1e-15);
        q.alpha = 0.25;
        EXPECT_NEAR(db.evaluate(q, method).CX, f({0.2, 0.3})[0], 1e-15);
        q.alpha = -0.4;
        q.mach = 0.9;
        EXPECT_NEAR(db.evaluate(q, method).CX, f({-0.1, 0.4})[0], 1e-15);
        EXPECT_NEAR(db.evaluate(q, method).CY, 0.4, 1e-15);
        // Derivative zero outside.
        AeroQuery<core::Dual> qd;
        qd.alpha = core::make_dual(0.3, 2, 0);
        qd.mach = core::make_dual(0.1, 2, 1);
        const auto r = db.evaluate(qd, method);
        EXPECT_EQ(r.CX.derivatives()(0), 0.0);
        EXPECT_EQ(r.CX.derivatives()(1), 0.0);

        const OutOfRangeReport rep = db.out_of_range();
        EXPECT_EQ(rep.evaluations, 5u);
        ASSERT_EQ(rep.entries.size(), 2u);
        EXPECT_EQ(rep.entries[0].table, "static");
        EXPECT_EQ(rep.entries[0].axis, Axis::alpha);
        EXPECT_EQ(rep.entries[0].above, 3u);
        EXPECT_EQ(rep.entries[0].below, 2u);
        EXPECT_EQ(rep.entries[0].highest, 0.5);
        EXPECT_EQ(rep.entries[0].lowest, -0.4);
        EXPECT_EQ(rep.entries[0].table_min, -0.1);
        EXPECT_EQ(rep.entries[0].table_max, 0.2);
        EXPECT_EQ(rep.entries[1].axis, Axis::mach);
        EXPECT_EQ(rep.entries[1].above, 2u);
        EXPECT_EQ(rep.entries[1].below, 1u);
        EXPECT_EQ(rep.entries[1].highest, 0.9);
        EXPECT_EQ(rep.entries[1].lowest, 0.1);
        EXPECT_EQ(rep.total(), 8u);
        EXPECT_EQ(rep.summary(),
                  "static/alpha: 2 below -0.1 (min -0.4), 3 above 0.2 (max 0.5)\n"
                  "static/mach: 1 below 0.2 (min 0.1), 2 above 0.4 (max 0.9)");
    }
    db.reset_out_of_range();
    EXPECT_EQ(db.out_of_range().total(), 0u);
    EXPECT_EQ(db.out_of_range().evaluations, 0u);
    EXPECT_TRUE(db.out_of_range().entries.empty());
    EXPECT_EQ(db.out_of_range().summary(), "");
}

TEST(AeroDatabaseExtrapolation, LinearContinuesEdgeCell) {
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.1, 0.0, 0.1, 0.2}},
                                        {Axis::mach, {0.2, 0.4}}};
    // Multilinear data: linear extrapolation of it is exact everywhere.
    auto f = [](const std::vector<double>& p) {
        return std::vector<double>{1 + p[0] + 3 * p[0] * p[1], p[1] - p[0], 0, 0, 0, 0};
    };
    const AeroDatabase db = body_database(axes, f, Extrapolation::linear);
    for (const std::vector<double>& p :
         {std::vector<double>{0.5, 0.3}, {-0.4, 0.9}, {0.3, 0.0}, {-1.0, -0.2}}) {
        const auto r = db.evaluate(query_at(axes, p), Interpolation::multilinear);
        EXPECT_NEAR(r.CX, f(p)[0], 1e-14);
        EXPECT_NEAR(r.CY, f(p)[1], 1e-14);
    }
    const auto rep = db.out_of_range();
    EXPECT_EQ(rep.evaluations, 4u);
    EXPECT_EQ(rep.entries[0].above, 2u);
    EXPECT_EQ(rep.entries[0].below, 2u);
    EXPECT_EQ(rep.entries[0].lowest, -1.0);
    EXPECT_EQ(rep.entries[1].lowest, -0.2);
}

TEST(AeroDatabaseExtrapolation, LinearC1ContinuesWithEdgeSlopeAndStaysC1) {
    const std::vector<GridAxis> axes = {{Axis::alpha, {-0.1, 0.0, 0.05, 0.1, 0.2}}};
    const AeroDatabase db = random_database(axes, 8, Extrapolation::linear);
    for (const double edge : {-0.1, 0.2}) {
        const double sign = edge < 0 ? -1.0 : 1.0;
        for (std::size_t c = 0; c < 6; ++c) {
            const auto at_edge =
                value_and_slope(db, axes, {edge - sign * 1e-12}, 0, c, Interpolation::c1);
            const auto outside =
                value_and_slope(db, axes, {edge + sign * 1e-12}, 0, c, Interpolation::c1);
            EXPECT_NEAR(at_edge.first, outside.first, 1e-9);
            EXPECT_NEAR(at_edge.second, outside.second, 1e-7);
            const auto far =
                value_and_slope(db, axes, {edge + sign * 0.3}, 0, c, Interpolation::c1);
            EXPECT_NEAR(far.first, at_edge.first + sign * 0.3 * at_edge.second, 1e-9);
            EXPECT_NEAR(far.second, at_edge.second, 1e-7);
        }
    }
}

TEST(AeroDatabaseExtrapolation, SharedGridCountsEveryTableAxis) {
    const std::vector<GridAxis> ax = {{Axis::alpha, {-0.1, 0.1}},
                                      {Axis::elevator, {-0.2, 0.0, 0.2}}};
    std::vector<Table> tables;
    tables.push_back(
        make_table("static", TableKind::static_table, {ax[0]}, {"CL"},
                   [](const std::vector<double>& p) { return std::vector<double>{p[0]}; }));
    tables.push_back(
        make_table("elevator", TableKind::control, ax, {"Cm"},
                   [](const std::vector<double>& p) { return std::vector<double>{-p[1]}; }));
    const AeroDatabase db({"t", "", ""}, ForceAxes::wind, Extrapolation::clamp, tables);
    AeroQuery<double> q;
    q.alpha = 0.2;
    q.elevator = -0.3;
    (void)db.evaluate(q, Interpolation::multilinear);
    const auto rep = db.out_of_range();
    ASSERT_EQ(rep.entries.size(), 3u);
    EXPECT_EQ(rep.entries[0].table, "static");
    EXPECT_EQ(rep.entries[1].table, "elevator");
    EXPECT_EQ(rep.entries[1].axis, Axis::alpha);
    EXPECT_EQ(rep.entries[2].axis, Axis::elevator);
    EXPECT_EQ(rep.entries[2].below, 1u);
    EXPECT_EQ(rep.summary(),
              "static/alpha: 1 above 0.1 (max 0.2)\nelevator/alpha: 1 above 0.1 (max 0.2)\n"
              "elevator/elevator: 1 below -0.2 (min -0.3)");
}

TEST(AeroDatabaseExtrapolation, CountersAreThreadSafe) {
    const AeroDatabase db = test::ranger_like();
    constexpr int n_threads = 4, per_thread = 20000;
    std::vector<std::thread> threads;
    for (int t = 0; t < n_threads; ++t) {
        threads.emplace_back([&db, t] {
            AeroQuery<double> q;
            q.mach = 0.3;
            for (int n = 0; n < per_thread; ++n) {
                q.alpha =
                    (n % 2 == 0) ? 0.6 + 0.001 * t : 0.0;  // every other query above alpha range
                (void)db.evaluate(q, n % 3 ? Interpolation::multilinear : Interpolation::c1);
            }
        });
    }
    for (auto& th : threads) th.join();
    const auto rep = db.out_of_range();
    EXPECT_EQ(rep.evaluations, std::uint64_t{n_threads} * per_thread);
    for (const auto& e : rep.entries) {
        EXPECT_EQ(e.axis, Axis::alpha);
        EXPECT_EQ(e.above, std::uint64_t{n_threads} * per_thread / 2);
        EXPECT_EQ(e.below, 0u);
        EXPECT_DOUBLE_EQ(e.highest, 0.6 + 0.001 * (n_threads - 1));
    }
    EXPECT_EQ(rep.entries.size(), 5u);  // alpha of static, three controls, dynamic
}

TEST(AeroDatabaseExtrapolation, NanPropagatesWithoutCounting) {
    const AeroDatabase db = test::ranger_like();
    AeroQuery<double> q;
    q.mach = 0.3;
    q.alpha = std::numeric_limits<double>::quiet_NaN();
    for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
        const auto r = db.evaluate(q, method);
        EXPECT_TRUE(std::isnan(r.CX));
        EXPECT_TRUE(std::isnan(r.Cm));
    }
    EXPECT_EQ(db.out_of_range().total(), 0u);
}

// ---------------------------------------------------------------- sums, rates, axes

TEST(AeroDatabaseEvaluate, SumsStaticControlsAndRates) {
    const GridAxis alpha{Axis::alpha, {-0.1, 0.0, 0.1, 0.2}};
    const GridAxis mach{Axis::mach, {0.2, 0.4}};
    std::vector<Table> tables;
    tables.push_back(make_table("dyn", TableKind::dynamic, {alpha, mach},
                                {"CX_q", "Cm_q", "Cl_p", "Cn_r", "CZ_alphadot", "CY_betadot"},
                                [](const std::vector<double>& p) {
                                    return std::vector<double>{1 + p[0], -10 + p[1], -0.4,
                                                               -0.1,     -2,         0.3};
                                }));
    tables.push_back(make_table(
        "base", TableKind::static_table, {alpha}, body_columns,
        [](const std::vector<double>& p) { return std::vector<double>{p[0], 1, 2, 3, 4, 5}; }));
    tables.push_back(make_table("ail", TableKind::control, {{Axis::aileron, {-0.3, 0.3}}},
                                {"Cl", "Cn"}, [](const std::vector<double>& p) {
                                    return std::vector<double>{0.2 * p[0], -0.01 * p[0]};
                                }));
    const AeroDatabase db({"t", "", ""}, ForceAxes::body, Extrapolation::clamp, tables);
    AeroQuery<double> q;
    q.alpha = 0.05;
    q.mach = 0.3;
    q.aileron = 0.1;
    q.p_hat = 0.01;
    q.q_hat = 0.02;
    q.r_hat = 0.03;
    q.alpha_dot_hat = 0.04;
    q.beta_dot_hat = 0.05;
    for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
        const auto r = db.evaluate(q, method);
        EXPECT_NEAR(r.CX, 0.05 + (1 + 0.05) * 0.02, 1e-15);
        EXPECT_NEAR(r.CY, 1 + 0.3 * 0.05, 1e-15);
        EXPECT_NEAR(r.CZ, 2 - 2 * 0.04, 1e-15);
        EXPECT_NEAR(r.Cl, 3 + 0.2 * 0.1 - 0.4 * 0.01, 1e-15);
        EXPECT_NEAR(r.Cm, 4 + (-10 + 0.3) * 0.02, 1e-14);
        EXPECT_NEAR(r.Cn, 5 - 0.01 * 0.1 - 0.1 * 0.03, 1e-15);
    }
}

// evaluate_with_angle_rates: the value is evaluate()'s bit for bit, the partial derivatives are
// the alphadot and betadot columns (rotated to body axes with the forces), and the pass counts
// once, out-of-range queries included.
TEST(AeroDatabaseEvaluate, AngleRatePartialsFromOnePass) {
    const GridAxis alpha{Axis::alpha, linspace(-0.1, 0.3, 5)};
    const GridAxis beta{Axis::beta, linspace(-0.2, 0.2, 3)};
    const GridAxis mach{Axis::mach, {0.2, 0.4, 0.6}};
    auto wavy = [](const std::vector<double>& p, int c) {
        double v = 0.1 * (c + 1);
        for (std::size_t k = 0; k < p.size(); ++k) v += std::sin(3.0 * p[k] + c + k) * 0.2;
        return v;
    };
    auto rows = [&](int n) {
        return [n, &wavy](const std::vector<double>& p) {
            std::vector<double> r;
            for (int c = 0; c < n; ++c) r.push_back(wavy(p, c));
            return r;
        };
    };
    std::vector<AeroDatabase> dbs;
    for (const ForceAxes axes : {ForceAxes::body, ForceAxes::wind}) {
        const auto& cols = axes == ForceAxes::body ? body_columns : wind_columns;
        const std::string f1 = cols[0], f3 = cols[2];
        std::vector<Table> tables;
        tables.push_back(
            make_table("static", TableKind::static_table, {alpha, mach, beta}, cols, rows(6)));
        tables.push_back(make_table("elev", TableKind::control,
                                    {alpha, {Axis::elevator, {-0.3, 0.0, 0.3}}}, {f1, f3, "Cm"},
                                    rows(3)));
        // Every rate, the angle rates on several coefficients (the specialised rated kernel).
        tables.push_back(
            make_table("dyn", TableKind::dynamic, {alpha, mach},
                       {f1 + "_q", "Cm_q", "Cl_p", "Cn_r", f3 + "_alphadot", "Cm_alphadot",
                        f1 + "_alphadot", "CY_betadot", "Cn_betadot", "Cl_betadot"},
                       rows(10)));
        dbs.emplace_back(DatabaseInfo{"t", "", ""}, axes, Extrapolation::linear, tables);
        // Fourteen rate columns: the run-time kernel.
        std::vector<std::string> wide;
        for (const auto& c : cols) {
            for (const char* r : {"p", "alphadot"}) wide.push_back(c + "_" + r);
        }
        wide.push_back("CY_betadot");
        wide.push_back("Cn_betadot");
        tables.back() = make_table("dyn", TableKind::dynamic, {alpha, mach}, wide, rows(14));
        dbs.emplace_back(DatabaseInfo{"t", "", ""}, axes, Extrapolation::clamp, tables);
    }
    dbs.push_back(test::ranger_like());  // wind axes, alphadot columns only
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int outside = 0;  // queries that were counted out of range
    for (std::size_t k = 0; k < dbs.size(); ++k) {
        const AeroDatabase& db = dbs[k];
        const bool has_beta_dot = k + 1 < dbs.size();
        for (const auto method : {Interpolation::multilinear, Interpolation::c1}) {
            SCOPED_TRACE("database " + std::to_string(k) + ", " + std::string(to_string(method)));
            for (int n = 0; n < 200; ++n) {
                AeroQuery<double> q;
                q.alpha = 0.1 + 0.25 * u(rng);  // partly beyond the tables
                q.beta = 0.25 * u(rng);
                q.mach = 0.4 + 0.25 * u(rng);
                q.elevator = 0.35 * u(rng);
                q.p_hat = 0.05 * u(rng);
                q.q_hat = 0.05 * u(rng);
                q.r_hat = 0.05 * u(rng);
                q.alpha_dot_hat = 0.02 * u(rng);
                q.beta_dot_hat = 0.02 * u(rng);
                db.reset_out_of_range();
                const AngleRateExpansion e = db.evaluate_with_angle_rates(q, method);
                const OutOfRangeReport once = db.out_of_range();
                EXPECT_EQ(once.evaluations, 1u);
                const auto c = test::as_array(db.evaluate(q, method));
                EXPECT_EQ(db.out_of_range().total(), 2 * once.total());
                outside += once.total() > 0 ? 1 : 0;
                EXPECT_EQ(test::as_array(e.value), c);
                // Affine in the angle rates: a finite step is the partial derivative exactly.
                AeroQuery<double> qa = q, qb = q;
                qa.alpha_dot_hat += 0.5;
                qb.beta_dot_hat += 0.5;
                const auto ca = test::as_array(db.evaluate(qa, method));
                const auto cb = test::as_array(db.evaluate(qb, method));
                const auto da = test::as_array(e.d_alpha_dot_hat);
                const auto db_ = test::as_array(e.d_beta_dot_hat);
                for (std::size_t i = 0; i < 6; ++i) {
                    EXPECT_NEAR(ca[i] - c[i], 0.5 * da[i], 1e-14 * (1.0 + std::abs(c[i])));
                    EXPECT_NEAR(cb[i] - c[i], 0.5 * db_[i], 1e-14 * (1.0 + std::abs(c[i])));
                    if (!has_beta_dot) {
                        EXPECT_EQ(db_[i], 0.0);
                    }
                }
                EXPECT_NE(da[2], 0.0);  // CZ: the alphadot columns are there
                if (has_beta_dot) {
                    EXPECT_NE(db_[5], 0.0);  // Cn_betadot
                }
            }
        }
    }
    EXPECT_GT(outside, 100);
}

TEST(AeroDatabaseEvaluate, WindForcesAreConvertedToBodyAxes) {
    const GridAxis alpha{Axis::alpha, linspace(-0.3, 0.5, 9)};
    const GridAxis beta{Axis::beta, linspace(-0.2, 0.2, 5)};
    auto f = [](const std::vector<double>& p) {
        return std::vector<double>{0.3 + 5 * p[0], 0.02 + p[0] * p[1], -0.5 * p[1], 0.1, 0.2, 0.3};
    };
    std::vector<Table> wind_tables;
    wind_tables.push_back(
        make_table("static", TableKind::static_table, {alpha, beta}, wind_columns, f));
    const AeroDatabase wind({"w", "", ""}, ForceAxes::wind, Extrapolation::clamp, wind_tables);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> ua(-0.3, 0.5), ub(-0.2, 0.2);
    for (int n = 0; n < 200; ++n) {
        AeroQuery<double> q;
        q.alpha = ua(rng);
        q.beta = ub(rng);
        const auto r = wind.evaluate(q, Interpolation::multilinear);
        const auto w = f({q.alpha, q.beta});
        const auto b = body_from_wind(w[0], w[1], w[2], q.alpha, q.beta);
        EXPECT_NEAR(r.CX, b[0], 1e-14);
        EXPECT_NEAR(r.CY, b[1], 1e-14);
        EXPECT_NEAR(r.CZ, b[2], 1e-14);
        EXPECT_NEAR(r.Cl, w[3], 1e-15);
        EXPECT_NEAR(r.Cm, w[4], 1e-15);
        EXPECT_NEAR(r.Cn, w[5], 1e-15);
        // And back.
        const auto back = wind_from_body(r.CX, r.CY, r.CZ, q.alpha, q.beta);
        EXPECT_NEAR(back.CL, w[0], 1e-14);
        EXPECT_NEAR(back.CD, w[1], 1e-14);
        EXPECT_NEAR(back.CY, w[2], 1e-14);
    }
    // At zero incidence: drag along -x, lift along -z, side force along +y.
    AeroQuery<double> q0;
    const auto r0 = wind.evaluate(q0, Interpolation::multilinear);
    const auto w0 = f({0.0, 0.0});
    EXPECT_NEAR(r0.CX, -w0[1], 1e-15);
    EXPECT_NEAR(r0.CY, w0[2], 1e-15);
    EXPECT_NEAR(r0.CZ, -w0[0], 1e-15);
}

TEST(AeroDatabaseEvaluate, WindBodyRoundTrip) {
    std::mt19937 rng(10);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int n = 0; n < 1000; ++n) {
        const double CL = u(rng), CD = u(rng), CY = u(rng), a = 1.5 * u(rng), b = 1.5 * u(rng);
        const auto body = body_from_wind(CL, CD, CY, a, b);
        const auto w = wind_from_body(body[0], body[1], body[2], a, b);
        EXPECT_NEAR(w.CL, CL, 1e-14);
        EXPECT_NEAR(w.CD, CD, 1e-14);
        EXPECT_NEAR(w.CY, CY, 1e-14);
        // The conversion is a rotation: it keeps the norm.
        EXPECT_NEAR(std::hypot(body[0], body[1], body[2]), std::hypot(CL, CD, CY), 1e-14);
    }
}

TEST(AeroDatabaseEvaluate, FastSineAndCosineWithinOneUlp) {
    // The double path rotates wind forces with core::sin_cos (fdlibm kernels on |x| <= pi/4;
    // the reduction beyond is tested in tests/core/test_fastmath.cpp).
    auto ordered = [](double a) {  // doubles mapped to integers in the same order, -0 = +0
        const auto i = std::bit_cast<std::int64_t>(a);
        return i < 0 ? std::numeric_limits<std::int64_t>::min() - i : i;
    };
    auto ulps = [&](double a, double b) { return std::abs(ordered(a) - ordered(b)); };
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> u(-std::numbers::pi / 4, std::numbers::pi / 4);
    std::int64_t worst = 0;
    for (int n = 0; n < 200000; ++n) {
        double x = u(rng);
        if (n % 3 == 0) x *= 1e-4;
        double s = 0.0, c = 0.0;
        core::sin_cos(x, s, c);
        worst = std::max({worst, ulps(s, std::sin(x)), ulps(c, std::cos(x))});
    }
    EXPECT_LE(worst, 1);
    for (const double x : {0.0, -0.0, 1e-300, -1e-9, 1.0, -2.5, 100.0}) {
        double s = 0.0, c = 0.0;
        core::sin_cos(x, s, c);
        EXPECT_LE(ulps(s, std::sin(x)), 1) << x;
        EXPECT_LE(ulps(c, std::cos(x)), 1) << x;
        EXPECT_EQ(std::signbit(s), std::signbit(std::sin(x))) << x;
    }
    double s = 0.0, c = 0.0;
    core::sin_cos(std::numeric_limits<double>::quiet_NaN(), s, c);
    EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

TEST(AeroDatabaseEvaluate, CopyAndMoveKeepTablesAndCounters) {
    AeroDatabase db = test::ranger_like();
    AeroQuery<double> q;
    q.alpha = 1.0;
    q.mach = 0.3;
    const auto r = db.evaluate(q, Interpolation::multilinear);
    const AeroDatabase copy(db);
    EXPECT_EQ(copy.out_of_range().evaluations, 1u);
    EXPECT_EQ(copy.out_of_range().total(), db.out_of_range().total());
    EXPECT_EQ(copy.evaluate(q, Interpolation::multilinear).Cm, r.Cm);
    AeroDatabase moved(std::move(db));
    EXPECT_EQ(moved.evaluate(q, Interpolation::multilinear).Cm, r.Cm);
    AeroDatabase assigned = test::ranger_like(Extrapolation::linear);
    assigned = copy;
    EXPECT_EQ(assigned.extrapolation(), Extrapolation::clamp);
    EXPECT_EQ(assigned.evaluate(q, Interpolation::multilinear).Cm, r.Cm);
    EXPECT_EQ(assigned.info().name, "Ranger-like");
}

TEST(AeroDatabaseNames, ToStringAndAngles) {
    EXPECT_EQ(to_string(ForceAxes::wind), "wind");
    EXPECT_EQ(to_string(ForceAxes::body), "body");
    EXPECT_EQ(to_string(Interpolation::multilinear), "multilinear");
    EXPECT_EQ(to_string(Interpolation::c1), "c1");
    EXPECT_EQ(to_string(Extrapolation::clamp), "clamp");
    EXPECT_EQ(to_string(Extrapolation::linear), "linear");
    EXPECT_EQ(to_string(TableKind::static_table), "static");
    EXPECT_EQ(to_string(TableKind::control), "control");
    EXPECT_EQ(to_string(TableKind::dynamic), "dynamic");
    EXPECT_EQ(to_string(Axis::elevator), "elevator");
    EXPECT_TRUE(is_angle(Axis::rudder));
    EXPECT_FALSE(is_angle(Axis::mach));
    Table t;
    t.axes = {{Axis::alpha, {1, 2, 3}}, {Axis::mach, {1, 2}}};
    EXPECT_EQ(t.n_points(), 6u);
}

// ---------------------------------------------------------------- validation messages

/// Message of the InputError the constructor throws for `tables`.
std::string construct_error(std::vector<Table> tables, ForceAxes axes = ForceAxes::wind) {
    try {
        const AeroDatabase db({"t", "", ""}, axes, Extrapolation::clamp, std::move(tables));
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

Table simple(std::string name, TableKind kind, std::vector<GridAxis> axes,
             std::vector<std::string> columns) {
    return make_table(
        std::move(name), kind, std::move(axes), columns,
        [&](const std::vector<double>&) { return std::vector<double>(columns.size(), 0.0); });
}

const GridAxis a3{Axis::alpha, {-0.1, 0.0, 0.1}};

TEST(AeroDatabaseValidation, ExactlyOneStaticTable) {
    EXPECT_EQ(construct_error({}),
              "aero database: no static table; exactly one table of kind 'static' is required "
              "(tables: none)");
    const auto e = construct_error({simple("dyn", TableKind::dynamic, {a3}, {"CL_q"})});
    EXPECT_NE(e.find("no static table"), std::string::npos) << e;
    EXPECT_NE(e.find("table 'dyn' (dynamic)"), std::string::npos) << e;
    const auto e2 = construct_error({simple("s1", TableKind::static_table, {a3}, {"CL"}),
                                     simple("s2", TableKind::static_table, {a3}, {"CD"})});
    EXPECT_EQ(e2,
              "aero database: table 's2' is a second static table (the first is 's1'); exactly one "
              "static table is allowed");
}

TEST(AeroDatabaseValidation, ControlAndDynamicTables) {
    const Table s = simple("static", TableKind::static_table, {a3}, {"CL"});
    const GridAxis de{Axis::elevator, {-0.2, 0.2}};
    const GridAxis da{Axis::aileron, {-0.2, 0.2}};
    auto e = construct_error({s, simple("elev", TableKind::control, {a3}, {"Cm"})});
    EXPECT_EQ(e,
              "aero database: control table 'elev' has 0 control axes (axes: alpha); a control "
              "table needs exactly one of elevator, aileron, rudder");
    e = construct_error({s, simple("mix", TableKind::control, {de, da}, {"Cm"})});
    EXPECT_NE(e.find("control table 'mix' has 2 control axes (axes: elevator, aileron)"),
              std::string::npos)
        << e;
    e = construct_error({s, simple("e1", TableKind::control, {a3, de}, {"Cm"}),
                         simple("e2", TableKind::control, {de}, {"CL"})});
    EXPECT_EQ(e,
              "aero database: control table 'e2' is a second table for control 'elevator' (the "
              "first is 'e1'); at most one per control");
    e = construct_error({s, simple("d1", TableKind::dynamic, {a3}, {"Cm_q"}),
                         simple("d2", TableKind::dynamic, {a3}, {"Cl_p"})});
    EXPECT_EQ(e,
              "aero database: table 'd2' is a second dynamic table (the first is 'd1'); at most "
              "one dynamic table is allowed");
    // One control table per control is fine.
    EXPECT_EQ(construct_error({s, simple("e", TableKind::control, {a3, de}, {"Cm"}),
                               simple("a", TableKind::control, {da}, {"Cl"})}),
              "<no error>");
}

TEST(AeroDatabaseValidation, NamesAndColumns) {
    const Table s = simple("static", TableKind::static_table, {a3}, {"CL"});
    auto e = construct_error({simple("", TableKind::static_table, {a3}, {"CL"})});
    EXPECT_EQ(e, "aero database: table [0] has an empty name; expected a unique name");
    e = construct_error({s, simple("static", TableKind::dynamic, {a3}, {"CL_q"})});
    EXPECT_EQ(
        e, "aero database: table [1] name 'static' repeats table [0]; table names must be unique");
    e = construct_error({simple("static", TableKind::static_table, {a3}, {"CL", "Cmm"})});
    EXPECT_EQ(e,
              "aero database: table 'static' (static): unknown column 'Cmm' (did you mean 'Cm'?); "
              "expected one of CL, CD, CY, Cl, Cm, Cn (wind force axes)");
    e = construct_error({simple("static", TableKind::static_table, {a3}, {"CX"})});
    EXPECT_NE(e.find("unknown column 'CX' ('CX' is a body-axis force but force_axes is wind)"),
              std::string::npos)
        << e;
    e = construct_error({simple("static", TableKind::static_table, {a3}, {"CL"})}, ForceAxes::body);
    EXPECT_NE(e.find("unknown column 'CL' ('CL' is a wind-axis force but force_axes is body); "
                     "expected one of CX, CY, CZ, Cl, Cm, Cn (body force axes)"),
              std::string::npos)
        << e;
    e = construct_error({simple("static", TableKind::static_table, {a3}, {"CL", "CD", "CL"})});
    EXPECT_EQ(
        e,
        "aero database: table 'static' (static): column 'CL' appears twice (columns [0] and [2])");
    e = construct_error({simple("static", TableKind::static_table, {a3}, {})});
    EXPECT_EQ(e, "aero database: table 'static' (static) has no columns; expected at least one");
    e = construct_error({s, simple("dyn", TableKind::dynamic, {a3}, {"Cm_qq"})});
    EXPECT_NE(e.find("table 'dyn' (dynamic): unknown column 'Cm_qq' (did you mean 'Cm_q'?); "
                     "dynamic columns are <coef>_<rate> with coef in CL, CD, CY, Cl, Cm, Cn (wind "
                     "force axes) and rate in p, q, r, alphadot, betadot"),
              std::string::npos)
        << e;
    e = construct_error({s, simple("dyn", TableKind::dynamic, {a3}, {"CX_q"})});
    EXPECT_NE(e.find("unknown column 'CX_q'"), std::string::npos) << e;
    e = construct_error({s, simple("dyn", TableKind::dynamic, {a3}, {"Cm"})});
    EXPECT_NE(e.find("unknown column 'Cm'"), std::string::npos) << e;
}

TEST(AeroDatabaseValidation, Axes) {
    auto e = construct_error(
        {simple("static", TableKind::static_table, {{Axis::alpha, {0.0, 0.1, 0.1}}}, {"CL"})});
    EXPECT_EQ(e,
              "aero database: table 'static' (static): axis 'alpha' breakpoint [2] = 0.1 is not "
              "greater than breakpoint [1] = 0.1; breakpoints must be strictly increasing");
    e = construct_error(
        {simple("static", TableKind::static_table, {{Axis::mach, {0.3, 0.2}}}, {"CL"})});
    EXPECT_NE(e.find("axis 'mach' breakpoint [1] = 0.2 is not greater than breakpoint [0] = 0.3"),
              std::string::npos)
        << e;
    e = construct_error(
        {simple("static", TableKind::static_table, {a3, {Axis::beta, {0.0}}, a3}, {"CL"})});
    EXPECT_EQ(e,
              "aero database: table 'static' (static): axis 'alpha' appears twice (axes [0] and "
              "[2]); each axis at most once per table");
    Table t = simple("static", TableKind::static_table, {a3}, {"CL"});
    t.axes.push_back({Axis::beta, {}});
    e = construct_error({t});
    EXPECT_EQ(e,
              "aero database: table 'static' (static): axis 'beta' has no breakpoints; expected at "
              "least one");
    e = construct_error(
        {simple("static", TableKind::static_table, {{Axis::alpha, {0.0, std::nan("")}}}, {"CL"})});
    EXPECT_NE(e.find("axis 'alpha' breakpoint [1] = nan is not finite"), std::string::npos) << e;
    e = construct_error(
        {simple("static", TableKind::static_table, {{Axis::alpha, {-10, 0, 10}}}, {"CL"})});
    EXPECT_NE(e.find("axis 'alpha' breakpoint [0] = -10 rad exceeds 2 pi in magnitude and looks "
                     "like degrees"),
              std::string::npos)
        << e;
    e = construct_error(
        {simple("static", TableKind::static_table, {{Axis::mach, {-0.1, 0.3}}}, {"CL"})});
    EXPECT_NE(e.find("axis 'mach' breakpoint [0] = -0.1 is negative"), std::string::npos) << e;
}

TEST(AeroDatabaseValidation, Values) {
    Table t =
        simple("static", TableKind::static_table, {a3, {Axis::mach, {0.1, 0.2}}}, {"CL", "CD"});
    t.values.pop_back();
    auto e = construct_error({t});
    EXPECT_EQ(e,
              "aero database: table 'static' (static) has 11 values; expected 12 = 6 grid points x "
              "2 columns");
    t.values.push_back(0.0);
    t.values[7] = std::numeric_limits<double>::infinity();
    e = construct_error({t});
    EXPECT_EQ(e,
              "aero database: table 'static' (static): value [7] (grid point 3, column 'CD') = inf "
              "is not finite");
}

// ---------------------------------------------------------------- from_derivatives

LinearDerivatives random_derivatives(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    LinearDerivatives d;
    for (double* v :
         {&d.CL_0,    &d.CL_alpha,    &d.CL_q,     &d.CL_alphadot, &d.CL_de,       &d.CD_0,
          &d.CD_k,    &d.CL_min_drag, &d.CD_de,    &d.CY_beta,     &d.CY_p,        &d.CY_r,
          &d.CY_da,   &d.CY_dr,       &d.Cl_beta,  &d.Cl_p,        &d.Cl_r,        &d.Cl_da,
          &d.Cl_dr,   &d.Cm_0,        &d.Cm_alpha, &d.Cm_q,        &d.Cm_alphadot, &d.Cm_de,
          &d.Cn_beta, &d.Cn_p,        &d.Cn_r,     &d.Cn_da,       &d.Cn_dr}) {
        *v = u(rng);
    }
    return d;
}

DerivativeGrids small_grids() {
    DerivativeGrids g;
    g.alpha = {-0.1, 0.0, 0.05, 0.1, 0.3};
    g.mach = {0.1, 0.4, 0.6};
    g.beta = {-0.1, 0.0, 0.1};
    g.elevator = {-0.3, 0.0, 0.2};
    g.aileron = {-0.2, 0.2};
    g.rudder = {-0.3, -0.1, 0.3};
    return g;
}

/// Wind-axis coefficients of a query (back from the body axes evaluate returns).
std::array<double, 6> wind_of(const AeroDatabase& db, const AeroQuery<double>& q, Interpolation m) {
    const auto b = db.evaluate(q, m);
    const auto w = wind_from_body(b.CX, b.CY, b.CZ, q.alpha, q.beta);
    return {w.CL, w.CD, w.CY, b.Cl, b.Cm, b.Cn};
}

TEST(AeroDatabaseFromDerivatives, ReproducesLinearTermsExactly) {
    std::mt19937 rng(11);
    for (const bool pg : {false, true}) {
        LinearDerivatives d = random_derivatives(rng);
        d.prandtl_glauert = pg;
        d.mach_ref = 0.3;
        const DerivativeGrids g = small_grids();
        const AeroDatabase db = AeroDatabase::from_derivatives(d, g, {"lin", "", ""});
        EXPECT_EQ(db.force_axes(), ForceAxes::wind);
        EXPECT_EQ(db.info().source, "linear-derivatives");
        ASSERT_EQ(db.tables().size(), 5u);
        EXPECT_EQ(db.tables()[4].columns.size(), 10u);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int n = 0; n < 500; ++n) {
            AeroQuery<double> q;
            q.alpha = -0.1 + 0.4 * u(rng);
            q.beta = -0.1 + 0.2 * u(rng);
            // With Prandtl-Glauert the slopes vary with Mach; check at the Mach breakpoints.
            q.mach = pg ? g.mach[static_cast<std::size_t>(n % 3)] : 0.1 + 0.5 * u(rng);
            q.elevator = g.elevator[static_cast<std::size_t>(n % 3)];  // CD_de de^2 exact at nodes
            q.aileron = -0.2 + 0.4 * u(rng);
            q.rudder = -0.3 + 0.6 * u(rng);
            q.p_hat = u(rng) - 0.5;
            q.q_hat = u(rng) - 0.5;
            q.r_hat = u(rng) - 0.5;
            q.alpha_dot_hat = u(rng) - 0.5;
            q.beta_dot_hat = u(rng) - 0.5;
            const double k = pg ? std::sqrt(1 - 0.09) / std::sqrt(1 - q.mach * q.mach) : 1.0;
            const auto w = wind_of(db, q, Interpolation::multilinear);
            const double CL = d.CL_0 + k * d.CL_alpha * q.alpha + k * d.CL_de * q.elevator +
                              d.CL_q * q.q_hat + d.CL_alphadot * q.alpha_dot_hat;
            EXPECT_NEAR(w[0], CL, 1e-13);
            EXPECT_NEAR(w[2],
                        k * (d.CY_beta * q.beta + d.CY_da * q.aileron + d.CY_dr * q.rudder) +
                            d.CY_p * q.p_hat + d.CY_r * q.r_hat,
                        1e-13);
            EXPECT_NEAR(w[3],
                        k * (d.Cl_beta * q.beta + d.Cl_da * q.aileron + d.Cl_dr * q.rudder) +
                            d.Cl_p * q.p_hat + d.Cl_r * q.r_hat,
                        1e-13);
            EXPECT_NEAR(w[4],
                        d.Cm_0 + k * (d.Cm_alpha * q.alpha + d.Cm_de * q.elevator) +
                            d.Cm_q * q.q_hat + d.Cm_alphadot * q.alpha_dot_hat,
                        1e-13);
            EXPECT_NEAR(w[5],
                        k * (d.Cn_beta * q.beta + d.Cn_da * q.aileron + d.Cn_dr * q.rudder) +
                            d.Cn_p * q.p_hat + d.Cn_r * q.r_hat,
                        1e-13);
        }
        // The drag polar at the alpha nodes: CD_0 + CD_k (CL_static - CL_min_drag)^2 + CD_de de^2.
        for (const double a : g.alpha) {
            for (const double de : g.elevator) {
                AeroQuery<double> q;
                q.alpha = a;
                q.mach = 0.4;
                q.elevator = de;
                const double k = pg ? std::sqrt(1 - 0.09) / std::sqrt(1 - 0.16) : 1.0;
                const double CLs = d.CL_0 + k * d.CL_alpha * a;
                const auto w = wind_of(db, q, Interpolation::multilinear);
                EXPECT_NEAR(w[1],
                            d.CD_0 + d.CD_k * (CLs - d.CL_min_drag) * (CLs - d.CL_min_drag) +
                                k * d.CD_de * de * de,
                            1e-13);
            }
        }
    }
}

TEST(AeroDatabaseFromDerivatives, LinearExtrapolationKeepsLinearTermsOutside) {
    std::mt19937 rng(12);
    const LinearDerivatives d = random_derivatives(rng);
    const AeroDatabase db = AeroDatabase::from_derivatives(d, small_grids(), {});
    EXPECT_EQ(db.extrapolation(), Extrapolation::linear);
    AeroQuery<double> q;
    q.alpha = 0.5;  // above the alpha grid
    q.beta = -0.3;  // below the beta grid
    q.mach = 0.3;
    q.aileron = 0.4;
    const auto w = wind_of(db, q, Interpolation::multilinear);
    EXPECT_NEAR(w[0], d.CL_0 + d.CL_alpha * 0.5, 1e-13);
    EXPECT_NEAR(w[4], d.Cm_0 + d.Cm_alpha * 0.5, 1e-13);
    EXPECT_NEAR(w[3], d.Cl_beta * -0.3 + d.Cl_da * 0.4, 1e-13);
    EXPECT_GT(db.out_of_range().total(), 0u);
}

TEST(AeroDatabaseFromDerivatives, OmitsEmptyControlsAndZeroColumns) {
    LinearDerivatives d;
    d.CL_alpha = 5.0;
    d.Cm_de = -1.0;
    d.Cm_q = -10.0;
    DerivativeGrids g;
    g.alpha = {-0.1, 0.1};
    g.mach = {0.2};
    g.beta = {0.0};
    g.elevator = {-0.2, 0.2};
    g.rudder = {-0.2, 0.2};  // all rudder derivatives zero: table dropped
    const AeroDatabase db = AeroDatabase::from_derivatives(d, g, {"x", "y", "z"});
    EXPECT_EQ(db.info().source, "z");
    ASSERT_EQ(db.tables().size(), 3u);
    EXPECT_EQ(db.tables()[0].columns.size(), 6u);
    EXPECT_EQ(db.tables()[1].name, "elevator");
    EXPECT_EQ(db.tables()[1].columns, std::vector<std::string>{"Cm"});
    EXPECT_EQ(db.tables()[2].kind, TableKind::dynamic);
    EXPECT_EQ(db.tables()[2].columns, std::vector<std::string>{"Cm_q"});
}

TEST(AeroDatabaseFromDerivatives, Errors) {
    LinearDerivatives d;
    d.Cn_beta = 0.1;
    DerivativeGrids g = small_grids();
    g.beta = {0.0};
    auto message = [&](const LinearDerivatives& dd, const DerivativeGrids& gg) {
        try {
            (void)AeroDatabase::from_derivatives(dd, gg, {});
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("<no error>");
    };
    EXPECT_EQ(message(d, g),
              "aero database from derivatives: the beta grid has one breakpoint but CY_beta, "
              "Cl_beta or Cn_beta is "
              "nonzero; a linear term needs at least two breakpoints");
    g = small_grids();
    g.alpha.clear();
    EXPECT_NE(message(d, g).find("the alpha grid is empty"), std::string::npos);
    g = small_grids();
    g.mach = {0.5, 1.2};
    d.prandtl_glauert = true;
    EXPECT_EQ(message(d, g),
              "aero database from derivatives: Mach breakpoint 1.2 with prandtl_glauert; the "
              "Prandtl-Glauert rule "
              "needs M < 1");
    g = small_grids();
    g.alpha = {0.0, 20.0};  // degrees by mistake
    EXPECT_NE(message(d, g).find("looks like degrees"), std::string::npos);
}

}  // namespace
}  // namespace manta::aero
