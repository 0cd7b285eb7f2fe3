/// @file test_frames.cpp
/// The frame conversions of core/frames.hpp against independent constructions: Eigen's
/// axis-angle rotations (the 3-2-1 sequence as R_z(psi) R_y(theta) R_x(phi) from body to earth,
/// Stevens, Lewis & Johnson 2015 sec. 1.3), Eigen's quaternions, finite differences of the
/// matrix for the angle rates (dC/dt = -[omega]x C), and docs/conventions.md for the geometry
/// axes ((x, y, z)_body = (-x, y, -z)_geometry, a rotation by 180 deg about y).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "manta/core/autodiff.hpp"
#include "manta/core/frames.hpp"

namespace core = manta::core;
using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

constexpr double pi = std::numbers::pi;

/// C_earth_from_body by Eigen's axis-angle rotations: yaw about z, then pitch about the new y,
/// then roll about the new x.
Matrix3d eigen_earth_from_body(double phi, double theta, double psi) {
    return (AngleAxisd(psi, Vector3d::UnitZ()) * AngleAxisd(theta, Vector3d::UnitY()) *
            AngleAxisd(phi, Vector3d::UnitX()))
        .toRotationMatrix();
}

/// Random angle triples with theta away from +-90 deg.
std::vector<std::array<double, 3>> random_angles(int n) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> a(-pi, pi), t(-0.49 * pi, 0.49 * pi);
    std::vector<std::array<double, 3>> out;
    for (int i = 0; i < n; ++i) out.push_back({a(rng), t(rng), a(rng)});
    return out;
}

}  // namespace

TEST(Frames, GeometryToBodyFlipIsTheConventionsRotation) {
    // docs/conventions.md: (x, y, z)_body = (-x, y, -z)_geometry.
    const Vector3d g(1.5, -2.0, 0.25);
    EXPECT_EQ(core::body_from_geometry(g), Vector3d(-1.5, -2.0, -0.25));
    EXPECT_EQ(core::geometry_from_body(g), Vector3d(-1.5, -2.0, -0.25));
    // An involution, and the rotation by pi about y (a proper rotation: det +1).
    EXPECT_EQ(core::geometry_from_body(core::body_from_geometry(g)), g);
    const Matrix3d Ry = AngleAxisd(pi, Vector3d::UnitY()).toRotationMatrix();
    EXPECT_LT((core::dcm_body_from_geometry() - Ry).cwiseAbs().maxCoeff(), 4e-15);
    EXPECT_EQ(core::dcm_body_from_geometry() * g, core::body_from_geometry(g));
    EXPECT_DOUBLE_EQ(core::dcm_body_from_geometry().determinant(), 1.0);
    // Forces and moments alike: r x F in geometry axes maps to r x F in body axes.
    const Vector3d r(0.3, 1.2, -0.4), F(-2.0, 0.5, 7.0);
    EXPECT_LT((core::body_from_geometry(r.cross(F)) -
               core::body_from_geometry(r).cross(core::body_from_geometry(F)))
                  .norm(),
              1e-14);
    // Aft in geometry is backwards in body axes; up is minus z (down).
    EXPECT_EQ(core::body_from_geometry(Vector3d::UnitX()), -Vector3d::UnitX());
    EXPECT_EQ(core::body_from_geometry(Vector3d::UnitZ()), -Vector3d::UnitZ());
}

TEST(Frames, DcmIsOrthonormalAndMatchesAxisAngleComposition) {
    for (const auto& e : random_angles(200)) {
        const Matrix3d C = core::dcm_body_from_earth(e[0], e[1], e[2]);
        EXPECT_LT((C * C.transpose() - Matrix3d::Identity()).cwiseAbs().maxCoeff(), 4e-15);
        EXPECT_NEAR(C.determinant(), 1.0, 4e-15);
        EXPECT_LT(
            (core::dcm_earth_from_body(e[0], e[1], e[2]) - eigen_earth_from_body(e[0], e[1], e[2]))
                .cwiseAbs()
                .maxCoeff(),
            4e-15);
        EXPECT_EQ(core::dcm_body_from_earth(e), C);
        EXPECT_EQ(core::dcm_earth_from_body(e[0], e[1], e[2]), C.transpose());
    }
}

TEST(Frames, DcmKnownRotations) {
    const Vector3d north = Vector3d::UnitX(), down = Vector3d::UnitZ();
    const double h = 0.5 * pi;
    // Heading east (psi = 90 deg): north is off the left wing.
    EXPECT_LT((core::dcm_body_from_earth(0, 0, h) * north - Vector3d(0, -1, 0)).norm(), 4e-15);
    // Nose up 90 deg: down points aft along body x.
    EXPECT_LT((core::dcm_body_from_earth(0, h, 0) * down - Vector3d(-1, 0, 0)).norm(), 4e-15);
    // Right wing down 90 deg: down points along the right wing.
    EXPECT_LT((core::dcm_body_from_earth(h, 0, 0) * down - Vector3d(0, 1, 0)).norm(), 4e-15);
    // Level flight heading north: identity.
    EXPECT_EQ(core::dcm_body_from_earth(0, 0, 0), Matrix3d::Identity());
    // 30 deg bank: gravity in body axes g (0, sin(phi), cos(phi)) (Stevens, Lewis & Johnson
    // 2015 eq. 2.5-10 at theta = 0).
    const double phi = pi / 6;
    EXPECT_LT(
        (core::dcm_body_from_earth(phi, 0, 0) * down - Vector3d(0, std::sin(phi), std::cos(phi)))
            .norm(),
        4e-15);
}

TEST(Frames, EulerFromDcmRoundTrip) {
    for (const auto& e : random_angles(200)) {
        const auto back = core::euler_from_dcm(core::dcm_body_from_earth(e));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], e[k], 1e-12) << k;
    }
    // Past theta = 90 deg the principal triple (phi + pi, pi - theta, psi + pi) is returned,
    // the same attitude.
    const std::array<double, 3> e{0.2, 0.6 * pi, -0.4};
    const auto p = core::euler_from_dcm(core::dcm_body_from_earth(e));
    EXPECT_LE(std::abs(p[1]), 0.5 * pi);
    EXPECT_LT((core::dcm_body_from_earth(p) - core::dcm_body_from_earth(e)).cwiseAbs().maxCoeff(),
              4e-15);
}

TEST(Frames, QuaternionDcmMatchesEulerDcm) {
    for (const auto& e : random_angles(100)) {
        const Eigen::Quaterniond q(eigen_earth_from_body(e[0], e[1], e[2]));
        const Eigen::Vector4d qv(q.w(), q.x(), q.y(), q.z());
        const Matrix3d C = core::dcm_earth_from_body(e[0], e[1], e[2]);
        EXPECT_LT((core::dcm_earth_from_unit_quaternion(qv) - C).cwiseAbs().maxCoeff(), 4e-15);
        // Any norm: normalised first; the sign of q does not matter.
        EXPECT_LT((core::dcm_earth_from_quaternion(-3.0 * qv) - C).cwiseAbs().maxCoeff(), 4e-15);
        // The scalar form of the flight kernels: q of any norm with 1 / |q|^2.
        const Eigen::Vector4d qs = 2.5 * qv;
        const auto c = core::dcm_earth_from_quaternion_sc(qs[0], qs[1], qs[2], qs[3],
                                                          1.0 / qs.squaredNorm());
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) EXPECT_NEAR(c[i][j], C(i, j), 4e-15);
    }
}

TEST(Frames, AngleRatesAgainstFiniteDifferencesAndEachOther) {
    // Body rates from -dC/dt C^T = [omega]x, C = C_body_from_earth, by central differences.
    const std::array<double, 3> e0{0.4, -0.3, 1.1}, rates{0.7, -0.2, 0.5};
    const double h = 1e-6;
    auto at = [&](double t) {
        return core::dcm_body_from_earth(e0[0] + rates[0] * t, e0[1] + rates[1] * t,
                                         e0[2] + rates[2] * t);
    };
    const Matrix3d W = -(at(h) - at(-h)) / (2 * h) * at(0).transpose();
    const auto pqr = core::body_rates_from_euler_rates(e0, rates);
    EXPECT_NEAR(pqr[0], W(2, 1), 1e-9);
    EXPECT_NEAR(pqr[1], W(0, 2), 1e-9);
    EXPECT_NEAR(pqr[2], W(1, 0), 1e-9);
    // The two relations are each other's inverse.
    for (const auto& e : random_angles(100)) {
        const auto w = core::body_rates_from_euler_rates(e, rates);
        const auto back = core::euler_rates_from_body_rates(e, w);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], rates[k], 1e-12);
    }
    // Steady turn at psi_dot: omega = psi_dot (earth z in body axes), the third column of C.
    const std::array<double, 3> e{0.5, 0.1, 2.0};
    const auto turn = core::body_rates_from_euler_rates(e, {0.0, 0.0, 0.3});
    const Matrix3d C = core::dcm_body_from_earth(e);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(turn[k], 0.3 * C(k, 2), 4e-15);
}

TEST(Frames, ScalarFormsWorkForAutomaticDifferentiation) {
    // d/dphi of C_body_from_earth through the AD scalar against the analytic derivative
    // R1'(phi) R2 R3.
    const double phi = 0.3, theta = -0.2, psi = 0.9;
    const core::Dual f = core::make_dual(phi, 1, 0);
    const core::Dual t = core::make_constant(theta, 1), p = core::make_constant(psi, 1);
    const core::Dual sf = sin(f), cf = cos(f), st = sin(t), ct = cos(t), sp = sin(p), cp = cos(p);
    const auto C = core::dcm_body_from_earth_sc(sf, cf, st, ct, sp, cp);
    const double h = 1e-6;
    const Matrix3d dC = (core::dcm_body_from_earth(phi + h, theta, psi) -
                         core::dcm_body_from_earth(phi - h, theta, psi)) /
                        (2 * h);
    const Matrix3d C0 = core::dcm_body_from_earth(phi, theta, psi);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            EXPECT_DOUBLE_EQ(C[i][j].value(), C0(i, j));
            EXPECT_NEAR(C[i][j].derivatives()[0], dC(i, j), 1e-9);
        }
    // earth_from_body is C^T v.
    const auto v = core::earth_from_body(C, core::Dual(1.0), core::Dual(2.0), core::Dual(-0.5));
    const Vector3d ref = C0.transpose() * Vector3d(1.0, 2.0, -0.5);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(v[k].value(), ref[k], 4e-15);
}

TEST(Frames, AirVelocityAndFreeStream) {
    const double V = 42.0, a = 0.12, b = -0.07;
    const Vector3d uvw = core::air_velocity_body(V, a, b);
    EXPECT_NEAR(uvw.norm(), V, 1e-13);
    EXPECT_NEAR(std::atan2(uvw.z(), uvw.x()), a, 4e-15);
    EXPECT_NEAR(std::asin(uvw.y() / V), b, 4e-15);
    // The free stream in geometry axes is the air's velocity (minus the aircraft's) turned into
    // geometry axes: exactly, as both are sign changes.
    EXPECT_EQ(core::free_stream_geometry(a, b),
              core::geometry_from_body(-core::air_velocity_body(1.0, a, b)));
    // Positive sideslip is wind from the right: the stream moves toward -y.
    EXPECT_LT(core::free_stream_geometry(0.0, 0.1).y(), 0.0);
    // Positive alpha: the stream comes from below, moving up (+z geometry) and aft (+x).
    EXPECT_GT(core::free_stream_geometry(0.1, 0.0).z(), 0.0);
    EXPECT_GT(core::free_stream_geometry(0.1, 0.0).x(), 0.0);
}
