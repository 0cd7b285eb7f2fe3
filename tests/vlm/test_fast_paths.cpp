// The solvers' fast paths give the numbers of the plain ones: the steady solver's two half
// systems of a mirror-symmetric lattice against the whole system (docs/vlm.md, Performance), the
// AVX2 and AVX-512 kernels against the baseline ones (detail/kernels.hpp), NOWAKE strips in both
// halves, and the single-precision path (kernels, factorisation with iterative refinement)
// against the double-precision one.

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

#include "manta/vlm/detail/dense_lu.hpp"
#include "manta/vlm/detail/kernels.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/steady.hpp"

namespace {

using namespace manta::vlm;
using Eigen::Vector3d;

Section section(const Vector3d& le, double chord, double incidence = 0.0) {
    Section s;
    s.leading_edge = le;
    s.chord = chord;
    s.incidence = incidence;
    return s;
}

SectionControl control(const char* name, double hinge, double duplicate_sign) {
    SectionControl c;
    c.name = name;
    c.hinge_chord_fraction = hinge;
    c.duplicate_sign = duplicate_sign;
    return c;
}

/// A small aircraft, mirror-symmetric about y = 0: a tapered, twisted, dihedral wing with
/// ailerons (antisymmetric), a tail with an elevator (symmetric), both mirrored, and a fin with a
/// rudder in the plane y = 0 (its own mirror image); `fin_offset` moves the fin off the plane.
Model aircraft(double fin_offset, bool nowake_tail = false) {
    Model m;
    m.name = "mirror";
    m.reference = {8.0, 8.0, 1.0, Vector3d(0.3, 0.0, 0.0)};
    Surface wing;
    wing.name = "wing";
    wing.n_chord = 5;
    wing.n_span = 12;
    wing.y_duplicate = 0.0;
    Section root = section(Vector3d(0, 0, 0), 1.2, 0.03);
    Section mid = section(Vector3d(0.1, 2.5, 0.15), 1.0, 0.01);
    Section tip = section(Vector3d(0.25, 4.0, 0.3), 0.6, -0.02);
    mid.controls.push_back(control("aileron", 0.7, -1.0));
    tip.controls.push_back(control("aileron", 0.7, -1.0));
    wing.sections = {root, mid, tip};
    Surface tail;
    tail.name = "tail";
    tail.n_chord = 4;
    tail.n_span = 6;
    tail.y_duplicate = 0.0;
    tail.component = 1;
    tail.sheds_wake = !nowake_tail;
    Section troot = section(Vector3d(4.0, 0, 0.2), 0.7);
    Section ttip = section(Vector3d(4.2, 1.5, 0.2), 0.4);
    troot.controls.push_back(control("elevator", 0.6, 1.0));
    ttip.controls.push_back(control("elevator", 0.6, 1.0));
    tail.sections = {troot, ttip};
    Surface fin;
    fin.name = "fin";
    fin.n_chord = 4;
    fin.n_span = 5;
    fin.component = 1;
    Section froot = section(Vector3d(3.9, fin_offset, 0.25), 0.9);
    Section ftip = section(Vector3d(4.3, fin_offset, 1.4), 0.5);
    froot.controls.push_back(control("rudder", 0.65, 1.0));
    ftip.controls.push_back(control("rudder", 0.65, 1.0));
    fin.sections = {froot, ftip};
    m.surfaces = {wing, tail, fin};
    return m;
}

void expect_same(const Derivatives& a, const Derivatives& b, double tol) {
    EXPECT_LT((a.body - b.body).cwiseAbs().maxCoeff(), tol * a.body.cwiseAbs().maxCoeff());
    EXPECT_LT((a.stability - b.stability).cwiseAbs().maxCoeff(),
              tol * a.stability.cwiseAbs().maxCoeff());
    ASSERT_EQ(a.control.cols(), b.control.cols());
    EXPECT_LT((a.control - b.control).cwiseAbs().maxCoeff(), tol * a.control.cwiseAbs().maxCoeff());
    EXPECT_NEAR(a.x_neutral_point, b.x_neutral_point, tol);
    EXPECT_NEAR(a.state.CL, b.state.CL, tol);
    EXPECT_NEAR(a.state.CY, b.state.CY, tol);
    EXPECT_NEAR(a.state.CD_induced, b.state.CD_induced, tol);
    EXPECT_NEAR(a.state.body.Cl, b.state.body.Cl, tol);
    EXPECT_NEAR(a.state.body.Cn, b.state.body.Cn, tol);
    EXPECT_LT((a.state.gamma - b.state.gamma).cwiseAbs().maxCoeff(),
              tol * a.state.gamma.cwiseAbs().maxCoeff());
}

// The symmetric lattice is solved as two half systems; moving the fin 1e-12 off the plane of
// symmetry breaks the exact symmetry, so that lattice is solved as one whole system. Both give
// the same solution at an asymmetric state with every control deflected.
TEST(VlmFastPaths, MirrorHalfSystemsMatchTheWholeSystem) {
    for (const bool nowake : {false, true}) {
        SCOPED_TRACE(nowake);
        const Model sym = aircraft(0.0, nowake);
        const Model whole = aircraft(1e-12, nowake);
        FlowState s;
        s.alpha = 0.08;
        s.beta = -0.05;
        s.p_hat = 0.02;
        s.q_hat = -0.01;
        s.r_hat = 0.03;
        s.deflection = Eigen::Vector3d(0.05, -0.03, 0.02);  // aileron, elevator, rudder
        SteadyOptions dbl;
        dbl.single_precision = false;
        const SteadySolver a(sym, build_lattice(sym), 0.3, dbl);
        const SteadySolver b(whole, build_lattice(whole), 0.3, dbl);
        expect_same(a.derivatives(s), b.derivatives(s), 1e-9);
        // Single precision: the two paths round different matrices.
        const SteadySolver af(sym, build_lattice(sym), 0.3);
        const SteadySolver bf(whole, build_lattice(whole), 0.3);
        expect_same(af.derivatives(s), bf.derivatives(s), 1e-5);
        EXPECT_LT((a.unit_circulations(s.deflection) - b.unit_circulations(s.deflection))
                      .cwiseAbs()
                      .maxCoeff(),
                  1e-9);
        // The rolling moment of a symmetric state is zero by symmetry on the split path.
        FlowState z;
        z.alpha = 0.05;
        EXPECT_NEAR(a.solve(z).body.Cl, 0.0, 1e-14);
        EXPECT_NEAR(a.solve(z).CY, 0.0, 1e-14);
        EXPECT_NEAR(af.solve(z).body.Cl, 0.0, 1e-14);
        EXPECT_NEAR(af.solve(z).CY, 0.0, 1e-14);
    }
}

// The single-precision path (the default) against the double-precision one, whole and half
// systems, at an asymmetric state with every control deflected: every derivative within 1e-6 of
// the largest (docs/vlm.md, Performance: 4e-8 on the Ranger and b737 lattices).
TEST(VlmFastPaths, SinglePrecisionMatchesDoublePrecision) {
    for (const double fin_offset : {0.0, 1e-12}) {
        SCOPED_TRACE(fin_offset);
        const Model m = aircraft(fin_offset, true);
        FlowState s;
        s.alpha = 0.08;
        s.beta = -0.05;
        s.p_hat = 0.02;
        s.q_hat = -0.01;
        s.r_hat = 0.03;
        s.deflection = Eigen::Vector3d(0.05, -0.03, 0.02);
        SteadyOptions dbl;
        dbl.single_precision = false;
        const SteadySolver d(m, build_lattice(m), 0.5, dbl);
        const SteadySolver f(m, build_lattice(m), 0.5);
        const Derivatives dd = d.derivatives(s), df = f.derivatives(s);
        expect_same(dd, df, 1e-6);
        EXPECT_LT((dd.body - df.body).cwiseAbs().maxCoeff(), 1e-6 * dd.body.cwiseAbs().maxCoeff());
        // And a tolerance that the single-precision path without refinement (errors of order
        // cond(A) x 6e-8) would not meet for the circulations.
        EXPECT_LT((dd.state.gamma - df.state.gamma).cwiseAbs().maxCoeff(),
                  1e-5 * dd.state.gamma.cwiseAbs().maxCoeff());
    }
}

// The single-precision factorisation with iterative refinement solves its matrix to double
// precision; an ill-conditioned matrix falls back to the double-precision factorisation.
TEST(VlmFastPaths, SinglePrecisionLuRefinesToDoublePrecision) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Eigen::Index n = 300, k = 4;
    Eigen::MatrixXf A(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i) A(i, j) = static_cast<float>(u(rng));
    A.diagonal().array() += 20.0f;
    Eigen::MatrixXd B(n, k);
    for (Eigen::Index j = 0; j < k; ++j)
        for (Eigen::Index i = 0; i < n; ++i) B(i, j) = u(rng);
    const Eigen::MatrixXd Ad = A.cast<double>();
    const Eigen::MatrixXd X = Ad.partialPivLu().solve(B);
    detail::DenseLU lu;
    lu.compute_single(A);
    EXPECT_TRUE(lu.single_precision());
    const Eigen::MatrixXd Y = lu.solve(B);
    EXPECT_LT((X - Y).cwiseAbs().maxCoeff(), 1e-12 * X.cwiseAbs().maxCoeff());
    // A single-precision solve alone is ~1e-7 off: the refinement is what gets there.
    Eigen::MatrixXf Yf = A.partialPivLu().solve(B.cast<float>());
    EXPECT_GT((X - Yf.cast<double>()).cwiseAbs().maxCoeff(), 1e-10 * X.cwiseAbs().maxCoeff());
    // Columns scaled by 1e-6 and a zero column converge too.
    Eigen::MatrixXd B2 = B;
    B2.col(1) *= 1e-6;
    B2.col(2).setZero();
    const Eigen::MatrixXd Y2 = lu.solve(B2);
    EXPECT_LT((Y2.col(1) - 1e-6 * X.col(1)).cwiseAbs().maxCoeff(),
              1e-12 * 1e-6 * X.col(1).cwiseAbs().maxCoeff());
    EXPECT_EQ(Y2.col(2).cwiseAbs().maxCoeff(), 0.0);
    // Nearly singular (two rows equal to 1e-6): single-precision factors cannot refine it.
    Eigen::MatrixXf S = A;
    S.row(1) = S.row(0);
    S(1, 0) += 1e-6f * std::abs(S(1, 0)) + 1e-6f;
    detail::DenseLU ls;
    ls.compute_single(S);
    EXPECT_FALSE(ls.single_precision());
    const Eigen::MatrixXd Sd = S.cast<double>();
    const Eigen::MatrixXd Z = ls.solve(B);
    // A backward-stable double-precision solve: residual of the order of rounding of A Z.
    EXPECT_LT((Sd * Z - B).cwiseAbs().maxCoeff(),
              1e-13 * static_cast<double>(n) * Sd.cwiseAbs().maxCoeff() * Z.cwiseAbs().maxCoeff());
}

// Every kernel of the AVX2 and AVX-512 sets gives the baseline set's numbers to rounding.
void expect_kernels_match_baseline(const detail::Kernels* fast) {
    const detail::Kernels& base = detail::baseline_kernels();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    // Horseshoes: random ends, two sets (an image with factor -1), mixed components and cores.
    const long n = 64;
    std::vector<double> e(6 * n), cin(n), cx(n);
    std::vector<int> comp(n);
    for (double& v : e) v = u(rng);
    for (long j = 0; j < n; ++j) {
        cin[static_cast<std::size_t>(j)] = 1e-8;
        cx[static_cast<std::size_t>(j)] = 0.01;
        comp[static_cast<std::size_t>(j)] = static_cast<int>(j % 2);
    }
    std::vector<double> r0x(n), r0y(n), r0z(n), l2(n);
    for (long j = 0; j < n; ++j) {
        const auto k = static_cast<std::size_t>(j);
        r0x[k] = e[static_cast<std::size_t>(3 * n + j)] - e[k];
        r0y[k] = e[static_cast<std::size_t>(4 * n + j)] - e[static_cast<std::size_t>(n + j)];
        r0z[k] = e[static_cast<std::size_t>(5 * n + j)] - e[static_cast<std::size_t>(2 * n + j)];
        l2[k] = r0x[k] * r0x[k] + r0y[k] * r0y[k] + r0z[k] * r0z[k];
    }
    auto to_float = [](const std::vector<double>& v) {
        return std::vector<float>(v.begin(), v.end());
    };
    const std::vector<float> r0x_f = to_float(r0x), r0y_f = to_float(r0y), r0z_f = to_float(r0z),
                             l2_f = to_float(l2), cin_f = to_float(cin), cx_f = to_float(cx);
    const double* p0 = e.data();
    detail::HorseshoeSet set{1.0,        p0,           p0 + n,       p0 + 2 * n,   p0 + 3 * n,
                             p0 + 4 * n, p0 + 5 * n,   r0x.data(),   r0y.data(),   r0z.data(),
                             l2.data(),  r0x_f.data(), r0y_f.data(), r0z_f.data(), l2_f.data()};
    detail::HorseshoeSet image = set;
    image.factor = -1.0;
    const detail::HorseshoeSet sets[2] = {set, image};
    const detail::HorseshoeRows rows{sets, 2,   cin.data(),   cx.data(),  comp.data(),
                                     n,    0.8, cin_f.data(), cx_f.data()};
    for (int t = 0; t < 5; ++t) {
        const double p[3] = {u(rng), u(rng), u(rng)};
        std::vector<double> a(3 * n), b(3 * n);
        base.horseshoe_row(rows, p, t % 2, a.data(), a.data() + n, a.data() + 2 * n);
        fast->horseshoe_row(rows, p, t % 2, b.data(), b.data() + n, b.data() + 2 * n);
        for (std::size_t k = 0; k < a.size(); ++k)
            EXPECT_NEAR(a[k], b[k], 1e-12 * (1.0 + std::abs(a[k])));
        // Single precision: the two sets agree to single-precision rounding, and both with the
        // double-precision rows to single-precision accuracy.
        std::vector<float> af(3 * n), bf(3 * n);
        base.horseshoe_row_f(rows, p, t % 2, af.data(), af.data() + n, af.data() + 2 * n);
        fast->horseshoe_row_f(rows, p, t % 2, bf.data(), bf.data() + n, bf.data() + 2 * n);
        double vmax = 0.0;
        for (const double v : a) vmax = std::max(vmax, std::abs(v));
        for (std::size_t k = 0; k < a.size(); ++k) {
            EXPECT_NEAR(af[k], bf[k], 1e-6 * vmax);
            EXPECT_NEAR(af[k], a[k], 1e-5 * vmax);
        }
    }
    // LU, solve and product on a diagonally weighted random matrix.
    const long m = 37, k = 3;
    std::vector<double> A(m * m), B(m * k);
    for (double& v : A) v = u(rng);
    for (long i = 0; i < m; ++i) A[static_cast<std::size_t>(i * m + i)] += 4.0;
    for (double& v : B) v = u(rng);
    std::vector<double> la = A, lb = A, xa = B, xb = B;
    std::vector<int> pa(m), pb(m);
    base.lu_factor(la.data(), m, pa.data());
    fast->lu_factor(lb.data(), m, pb.data());
    base.lu_solve(la.data(), m, pa.data(), xa.data(), k);
    fast->lu_solve(lb.data(), m, pb.data(), xb.data(), k);
    for (std::size_t q = 0; q < xa.size(); ++q) EXPECT_NEAR(xa[q], xb[q], 1e-12);
    std::vector<double> ca(m * k), cb(m * k);
    base.gemm_tn(A.data(), m, m, B.data(), k, ca.data());
    fast->gemm_tn(A.data(), m, m, B.data(), k, cb.data());
    for (std::size_t q = 0; q < ca.size(); ++q) EXPECT_NEAR(ca[q], cb[q], 1e-12);
    // Single precision: factorisation, solve, product; the mixed product against double.
    const std::vector<float> Af = to_float(A), Bf = to_float(B);
    std::vector<float> lfa = Af, lfb = Af, xfa = Bf, xfb = Bf, cfa(m * k), cfb(m * k);
    base.lu_factor_f(lfa.data(), m, pa.data());
    fast->lu_factor_f(lfb.data(), m, pb.data());
    base.lu_solve_f(lfa.data(), m, pa.data(), xfa.data(), k);
    fast->lu_solve_f(lfb.data(), m, pb.data(), xfb.data(), k);
    for (std::size_t q = 0; q < xa.size(); ++q) {
        EXPECT_NEAR(xfa[q], xfb[q], 1e-5);
        EXPECT_NEAR(xfa[q], xa[q], 1e-5);
    }
    base.gemm_tn_f(Af.data(), m, m, Bf.data(), k, cfa.data());
    fast->gemm_tn_f(Af.data(), m, m, Bf.data(), k, cfb.data());
    for (std::size_t q = 0; q < ca.size(); ++q) {
        EXPECT_NEAR(cfa[q], cfb[q], 1e-5);
        EXPECT_NEAR(cfa[q], ca[q], 1e-5);
    }
    // gemm_fd: C = A B with the single-precision A, everything else double (exact products of
    // the rounded A); four columns at a time and the remainder (m = 37).
    std::vector<double> da(m * k), db(m * k);
    base.gemm_fd(Af.data(), m, m, B.data(), k, da.data());
    fast->gemm_fd(Af.data(), m, m, B.data(), k, db.data());
    for (long i = 0; i < m; ++i)
        for (long c = 0; c < k; ++c) {
            double ref = 0.0;
            for (long j = 0; j < m; ++j)
                ref += static_cast<double>(Af[static_cast<std::size_t>(j * m + i)]) *
                       B[static_cast<std::size_t>(c * m + j)];
            const auto q = static_cast<std::size_t>(c * m + i);
            EXPECT_NEAR(da[q], ref, 1e-13);
            EXPECT_NEAR(db[q], ref, 1e-13);
        }
    // Unsteady grid kernel: 3 rows of 9 points, spanwise and chordwise families.
    const long np = 27;
    std::vector<double> gx(np), gy(np), gz(np), S(np), K(np);
    for (long j = 0; j < np; ++j) {
        const auto q = static_cast<std::size_t>(j);
        gx[q] = 0.3 * static_cast<double>(j / 9);
        gy[q] = 0.2 * static_cast<double>(j % 9);
        gz[q] = 0.01 * u(rng);
        S[q] = u(rng);
        K[q] = 1e-6;
    }
    const double p[3] = {0.35, 0.7, 0.05};
    std::vector<double> sa(5 * np), sb(5 * np);
    double acc_a[12] = {}, acc_b[12] = {};
    for (auto [s, kern, acc] : {std::tuple{&sa, &base, acc_a}, std::tuple{&sb, fast, acc_b}}) {
        double* r = s->data();
        kern->grid_points(gx.data(), gy.data(), gz.data(), np, p, 1e-20, r, r + np, r + 2 * np,
                          r + 3 * np, r + 4 * np);
        kern->segment_family(r, r + np, r + 2 * np, r + 3 * np, r + 4 * np, np - 1, 1, S.data(),
                             K.data(), 1e-40, acc);
        kern->segment_family(r, r + np, r + 2 * np, r + 3 * np, r + 4 * np, np - 9, 9, S.data(),
                             K.data(), 1e-40, acc);
    }
    for (int d = 0; d < 3; ++d) {
        double a = 0.0, b = 0.0;
        for (int l = 0; l < 4; ++l) {
            a += acc_a[4 * d + l];
            b += acc_b[4 * d + l];
        }
        EXPECT_NEAR(a, b, 1e-12 * (1.0 + std::abs(a)));
    }
}

TEST(VlmFastPaths, Avx2KernelsMatchTheBaseline) {
    const detail::Kernels* fast = detail::avx2_kernels();
    if (fast == nullptr) GTEST_SKIP() << "no AVX2 kernels on this processor or build";
    expect_kernels_match_baseline(fast);
}

TEST(VlmFastPaths, Avx512KernelsMatchTheBaseline) {
    const detail::Kernels* fast = detail::avx512_kernels();
    if (fast == nullptr) GTEST_SKIP() << "no AVX-512 kernels on this processor or build";
    expect_kernels_match_baseline(fast);
}

}  // namespace
