// Motion histories: file round trip, located errors, interpolation and body rates, harmonic
// motions.

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"

namespace manta::aero {
namespace {

constexpr double pi = std::numbers::pi;

std::filesystem::path temp_dir() {
    // One folder per process: the same test may run at once from several build trees.
    const auto dir = std::filesystem::temp_directory_path() /
                     ("manta_motion_test_" + std::to_string(static_cast<long>(::getpid())));
    std::filesystem::create_directories(dir);
    return dir;
}

void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b,
                      const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i]), std::bit_cast<std::uint64_t>(b[i]))
            << what << "[" << i << "]: " << a[i] << " vs " << b[i];
    }
}

void expect_same_motion(const Motion& a, const Motion& b) {
    expect_same_bits(a.t, b.t, "t");
    for (std::size_t k = 0; k < 3; ++k) {
        expect_same_bits(a.position[k], b.position[k], "position");
        expect_same_bits(a.angles[k], b.angles[k], "angles");
    }
    ASSERT_EQ(a.mode_names, b.mode_names);
    for (std::size_t k = 0; k < a.modes.size(); ++k)
        expect_same_bits(a.modes[k], b.modes[k], "mode_" + a.mode_names[k]);
    ASSERT_EQ(a.metadata.v0.has_value(), b.metadata.v0.has_value());
    ASSERT_EQ(a.metadata.mach.has_value(), b.metadata.mach.has_value());
    ASSERT_EQ(a.metadata.altitude.has_value(), b.metadata.altitude.has_value());
    if (a.metadata.v0) {
        EXPECT_EQ(*a.metadata.v0, *b.metadata.v0);
    }
    if (a.metadata.mach) {
        EXPECT_EQ(*a.metadata.mach, *b.metadata.mach);
    }
    if (a.metadata.altitude) {
        EXPECT_EQ(*a.metadata.altitude, *b.metadata.altitude);
    }
    EXPECT_EQ(a.metadata.comments, b.metadata.comments);
}

/// A motion whose columns are the given functions of time sampled at `times`.
template <class F>
Motion sampled(const std::vector<double>& times, F f) {
    Motion m;
    m.t = times;
    for (auto& c : m.position) c.clear();
    for (auto& c : m.angles) c.clear();
    std::vector<std::vector<double>> modes(4);
    for (const double t : times) {
        const std::array<double, 10> v = f(t);
        for (std::size_t k = 0; k < 3; ++k) {
            m.position[k].push_back(v[k]);
            m.angles[k].push_back(v[3 + k]);
        }
        for (std::size_t k = 0; k < 4; ++k) modes[k].push_back(v[6 + k]);
    }
    m.add_mode("elevator", modes[0]);
    m.add_mode("aileron", modes[1]);
    m.add_mode("rudder", modes[2]);
    m.add_mode("flap", modes[3]);
    return m;
}

TEST(MotionFile, RoundTripIsExact) {
    const std::vector<double> awkward{
        0.1,     1.0 / 3.0, -0.0, 1e-300, std::numeric_limits<double>::denorm_min(),
        pi / 2,  // the largest deflection (issue 16)
        -pi / 2, 2.5e-7};
    std::vector<double> times;
    for (int i = 0; i < 8; ++i) times.push_back(0.1 * i + 1e-17 * i * i);
    std::size_t n = 0;
    Motion m = sampled(times, [&](double t) {
        std::array<double, 10> v{};
        for (std::size_t k = 0; k < v.size(); ++k) v[k] = awkward[(n + k) % awkward.size()] * t;
        v[4] = awkward[n % awkward.size()];
        ++n;
        return v;
    });
    m.metadata.v0 = 150.0;
    m.metadata.mach = 0.45;
    m.metadata.altitude = 3000.0 + 1.0 / 3.0;
    m.metadata.comments = {"source: test trajectory", "entry: level flight"};

    const auto file = temp_dir() / "roundtrip.motion.csv";
    write_motion(file, m);
    const Motion back = read_motion(file);
    expect_same_motion(m, back);
    EXPECT_EQ(motion_to_text(back), core::read_file(file));
    std::filesystem::remove_all(file.parent_path());
}

TEST(MotionFile, ReadsTheDocumentedLayout) {
    const std::string text =
        "# v0: 150.0\n"
        "# mach: 0.45\n"
        "# altitude: 3000\n"
        "# made by hand\n"
        "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_rudder,mode_elevator,mode_aileron,mode_flap\n"
        "0, 0, 0, 0, 0, 0,    0, 0, 0,    0, 0\n"
        "0.5, 1, 2, 3, 0.1, 0.2, 0.3, 0.01, 0.02, 0.03, 0.04\n"
        "\n"
        "1.0, 2, 4, 6, 0.2, 0.4, 0.6, 0.02, 0.04, 0.06, 0.08\n";
    const Motion m = parse_motion(text, "hand.csv");
    ASSERT_EQ(m.n_samples(), 3u);
    EXPECT_EQ(*m.metadata.v0, 150.0);
    EXPECT_EQ(*m.metadata.mach, 0.45);
    EXPECT_EQ(*m.metadata.altitude, 3000.0);
    EXPECT_EQ(m.metadata.comments, std::vector<std::string>{"made by hand"});
    EXPECT_EQ(m.mode_names, (std::vector<std::string>{"rudder", "elevator", "aileron", "flap"}));
    EXPECT_EQ(m.find_mode("elevator"), 1);
    EXPECT_EQ(m.find_mode("spoiler"), -1);
    EXPECT_EQ(m.position[2][1], 3.0);
    EXPECT_EQ(m.angles[2][2], 0.6);
    EXPECT_EQ(m.modes[static_cast<std::size_t>(m.find_mode("flap"))][2], 0.08);
    // Without metadata it is still a motion.
    const Motion bare = parse_motion(
        "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder\n"
        "0,0,0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0,0,0\n",
        "bare.csv");
    EXPECT_FALSE(bare.metadata.v0.has_value());
    EXPECT_TRUE(bare.metadata.comments.empty());
}

struct BadCase {
    std::string name;
    std::string text;
    std::vector<std::string> expected;  // substrings of the message
};

TEST(MotionFile, ErrorsAreOneLineWithFileLineAndColumn) {
    const std::string header =
        "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder\n";
    const std::string row0 = "0,0,0,0,0,0,0,0,0,0\n";
    const std::string row1 = "0.1,0,0,0,0,0,0,0,0,0\n";
    const std::vector<BadCase> cases{
        {"decreasing time",
         "# v0: 100\n" + header + row0 + row1 + "0.05,0,0,0,0,0,0,0,0,0\n",
         {"m.csv:5:", "'t'", "0.05", "increase strictly"}},
        {"repeated time", header + row0 + row1 + row1, {"m.csv:4:", "'t'", "0.1"}},
        {"missing columns",
         "t,x_ref,y_ref,z_ref,phi,psi,mode_elevator,mode_aileron\n0,0,0,0,0,0,0,0\n",
         {"m.csv:1:", "missing columns", "'theta'", "'mode_rudder'"}},
        {"non-numeric",
         header + row0 + "0.1,0,0,0,0,abc,0,0,0,0\n",
         {"m.csv:3:", "'theta'", "'abc'", "not a number"}},
        {"nan", header + row0 + "0.1,0,0,nan,0,0,0,0,0,0\n", {"m.csv:3:", "'z_ref'", "finite"}},
        {"one row", "# one sample\n" + header + row0, {"m.csv:2:", "'t'", "at least 2"}},
        {"no rows", header, {"m.csv:1:", "'t'", "at least 2"}},
        {"unknown column",
         "t,x_ref,y_ref,z_ref,phi,theta,psi,alpha,mode_elevator,mode_aileron,mode_rudder\n",
         {"m.csv:1:", "'alpha'", "not a motion column"}},
        {"empty mode name", "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_\n", {"m.csv:1:", "'mode_'"}},
        {"bad mode name",
         "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder,mode_f-1\n",
         {"m.csv:1:", "'mode_f-1'"}},
        {"metadata not a number",
         "# v0: fast\n" + header + row0 + row1,
         {"m.csv:1:", "'v0'", "'fast'"}},
        {"metadata out of range",
         "\n# mach: -0.5\n" + header + row0 + row1,
         {"m.csv:2:", "'mach'", "negative"}},
        {"zero speed", "# v0: 0\n" + header + row0 + row1, {"m.csv:1:", "'v0'", "positive"}},
        {"metadata twice",
         "# v0: 100\n# altitude: 1\n# v0: 120\n" + header + row0 + row1,
         {"m.csv:3:", "'v0'", "twice", "line 1"}},
        {"short row", header + row0 + "0.1,0,0\n", {"m.csv:3:", "3 fields"}},
        // Found by fuzz_motion (issue 16): the comment was kept and the motion could not be
        // written back (a line break once written).
        {"carriage return inside a comment",
         "# made\rby hand\n" + header + row0 + row1,
         {"m.csv:1:", "carriage return"}},
    };
    for (const auto& c : cases) {
        try {
            (void)parse_motion(c.text, "m.csv");
            ADD_FAILURE() << c.name << ": no error";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.find('\n'), std::string::npos) << c.name << ": " << msg;
            for (const auto& s : c.expected)
                EXPECT_NE(msg.find(s), std::string::npos)
                    << c.name << ": '" << s << "' not in " << msg;
        }
    }
}

TEST(MotionFile, MissingFileIsAnIoError) {
    const auto dir = temp_dir();
    EXPECT_THROW((void)read_motion(dir / "no-such-motion.csv"), IoError);
    EXPECT_THROW((void)read_motion(dir), IoError);  // a folder, not a file
    std::filesystem::remove_all(dir);
}

TEST(MotionFile, WriteRejectsInvalidMotions) {
    Motion m = harmonic_motion(OscillationAxis::pitch, 0.1, 2.0, 1, 8);
    const auto file = temp_dir() / "bad.motion.csv";
    const auto expect_rejected = [&](const Motion& bad, const std::string& part) {
        try {
            write_motion(file, bad);
            ADD_FAILURE() << "no error for " << part;
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(part), std::string::npos) << msg;
            EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
        EXPECT_FALSE(std::filesystem::exists(file));
    };
    {
        Motion bad = m;
        bad.angles[1].pop_back();
        expect_rejected(bad, "'theta'");
    }
    {
        Motion bad = m;
        bad.position[0][3] = std::nan("");
        expect_rejected(bad, "row 4");
    }
    {
        Motion bad = m;
        bad.t[5] = bad.t[4];
        expect_rejected(bad, "row 6");
    }
    {
        Motion bad = m;
        bad.mode_names.erase(bad.mode_names.begin() + 1);
        bad.modes.erase(bad.modes.begin() + 1);
        expect_rejected(bad, "'mode_aileron'");
    }
    {
        Motion bad = m;
        bad.add_mode("elevator", bad.modes[0]);
        expect_rejected(bad, "twice");
    }
    {
        Motion bad = m;
        bad.metadata.comments = {"v0: 12"};
        expect_rejected(bad, "metadata");
    }
    {
        Motion bad = m;
        bad.metadata.comments = {"two\nlines"};
        expect_rejected(bad, "line break");
    }
    {
        Motion bad = m;
        bad.metadata.v0 = -1.0;
        expect_rejected(bad, "'v0'");
    }
    std::filesystem::remove_all(file.parent_path());
}

TEST(MotionInterpolation, ReproducesCubicsExactly) {
    // Cubics in every column, on non-uniform times; values and rates must be exact to rounding.
    const auto cubic = [](double a, double b, double c, double d) {
        return [=](double t) { return a + t * (b + t * (c + t * d)); };
    };
    const auto dcubic = [](double b, double c, double d) {
        return [=](double t) { return b + t * (2 * c + 3 * t * d); };
    };
    const std::array<std::array<double, 4>, 10> coef{{{0.1, -2, 0.5, 0.3},
                                                      {1, 0.2, -0.1, 0.05},
                                                      {-3, 1, 1, -0.2},
                                                      {0.01, 0.2, 0.03, -0.004},
                                                      {0, -0.1, 0.05, 0.01},
                                                      {0.3, 0, 0, 0.02},
                                                      {0, 0.01, 0, 0},
                                                      {0.02, 0, -0.01, 0.001},
                                                      {0, 0, 0.1, 0},
                                                      {-0.05, 0.1, -0.02, 0.003}}};
    for (const std::vector<double>& times :
         {std::vector<double>{0.0, 0.4, 1.1, 1.5},
          std::vector<double>{-1.0, -0.7, 0.0, 0.2, 0.9, 1.0, 1.8, 2.5, 2.6}}) {
        const Motion m = sampled(times, [&](double t) {
            std::array<double, 10> v{};
            for (std::size_t k = 0; k < 10; ++k)
                v[k] = cubic(coef[k][0], coef[k][1], coef[k][2], coef[k][3])(t);
            return v;
        });
        m.validate();
        const int n_probe = 101;
        for (int j = 0; j < n_probe; ++j) {
            const double t = times.front() + (times.back() - times.front()) * j / (n_probe - 1);
            const MotionState s = m.at(t);
            for (std::size_t k = 0; k < 10; ++k) {
                const double f = cubic(coef[k][0], coef[k][1], coef[k][2], coef[k][3])(t);
                const double df = dcubic(coef[k][1], coef[k][2], coef[k][3])(t);
                const double value = k < 3   ? s.position[k]
                                     : k < 6 ? s.euler[k - 3]
                                             : s.modes[k - 6];
                const double rate = k < 3   ? s.velocity[k]
                                    : k < 6 ? s.euler_rates[k - 3]
                                            : s.mode_rates[k - 6];
                EXPECT_NEAR(value, f, 1e-12) << "column " << k << " at t = " << t;
                EXPECT_NEAR(rate, df, 1e-11) << "column " << k << " rate at t = " << t;
            }
            EXPECT_FALSE(s.clamped);
        }
    }
}

TEST(MotionInterpolation, TwoSamplesAreLinear) {
    const Motion m = sampled({1.0, 3.0}, [](double t) {
        std::array<double, 10> v{};
        v.fill(2.0 * t - 1.0);
        return v;
    });
    const MotionState s = m.at(2.5);
    EXPECT_DOUBLE_EQ(s.euler[1], 4.0);
    EXPECT_DOUBLE_EQ(s.euler_rates[1], 2.0);
    EXPECT_DOUBLE_EQ(s.modes[3], 4.0);
}

TEST(MotionInterpolation, SineToInterpolationAccuracy) {
    const double amplitude = 0.05, omega = 3.0;
    for (const int per_period : {16, 32, 64}) {
        const Motion m = harmonic_motion(OscillationAxis::pitch, amplitude, omega, 3, per_period);
        double err_value = 0.0, err_rate = 0.0;
        for (int j = 0; j <= 997; ++j) {
            const double t = m.t.back() * j / 997.0;
            const MotionState s = m.at(t);
            err_value = std::max(err_value, std::abs(s.euler[1] - amplitude * std::sin(omega * t)));
            err_rate = std::max(
                err_rate, std::abs(s.euler_rates[1] - amplitude * omega * std::cos(omega * t)));
            EXPECT_NEAR(s.omega_body[1], s.euler_rates[1], 1e-15);
        }
        // Hermite with fourth-order slopes: the worst error is near the ends, where the slopes
        // are one-sided (derivative error ~ A omega (omega h)^4 / 5); measured about 0.01 and 0.2
        // of the bounds' scales at 16 to 64 samples a period.
        const double wh = 2 * pi / per_period;
        EXPECT_LT(err_value, amplitude * std::pow(wh, 4) / 50) << per_period;
        EXPECT_LT(err_rate, amplitude * omega * std::pow(wh, 4) / 4) << per_period;
    }
}

TEST(MotionInterpolation, ClampsNearTheEndsAndRejectsFarOutside) {
    const Motion m = harmonic_motion(OscillationAxis::roll, 0.2, 1.0, 1, 16);
    const double duration = m.t.back() - m.t.front();
    const MotionState end = m.at(m.t.back());
    EXPECT_FALSE(end.clamped);
    const MotionState after = m.at(m.t.back() + 0.5e-6 * duration);
    EXPECT_TRUE(after.clamped);
    EXPECT_EQ(after.t, m.t.back());
    EXPECT_EQ(after.euler[0], end.euler[0]);
    EXPECT_EQ(after.euler_rates[0], end.euler_rates[0]);
    const MotionState before = m.at(-0.5e-6 * duration);
    EXPECT_TRUE(before.clamped);
    EXPECT_EQ(before.t, 0.0);
    EXPECT_NEAR(before.euler[0], 0.0, 1e-15);
    try {
        (void)m.at(m.t.back() + 1.0);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("outside"), std::string::npos) << e.what();
    }
    EXPECT_THROW((void)m.at(-0.1), InputError);
    EXPECT_NO_THROW((void)m.at(-0.1, 0.2));
    EXPECT_THROW((void)m.at(std::nan("")), InputError);
}

TEST(MotionKinematics, ConingGivesConstantBodyRates) {
    // Coning: the body turns at a steady rate Omega about the frame's z axis with fixed pitch and
    // bank: psi = Omega t, theta = theta0, phi = phi0. Body rates are the constant vector
    // Omega (-sin theta0, sin phi0 cos theta0, cos phi0 cos theta0).
    const double omega = 0.7, theta0 = 0.3, phi0 = -0.4;
    std::vector<double> times;
    for (int i = 0; i <= 40; ++i) times.push_back(0.25 * i);
    const Motion m = sampled(times, [&](double t) {
        std::array<double, 10> v{};
        v[3] = phi0;
        v[4] = theta0;
        v[5] = omega * t;
        return v;
    });
    const std::array<double, 3> expected{-omega * std::sin(theta0),
                                         omega * std::sin(phi0) * std::cos(theta0),
                                         omega * std::cos(phi0) * std::cos(theta0)};
    for (const double t : {0.0, 0.13, 3.3, 7.77, 10.0}) {
        const MotionState s = m.at(t);
        for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(s.omega_body[k], expected[k], 1e-13);
        // |omega| is the coning rate.
        EXPECT_NEAR(std::hypot(s.omega_body[0], s.omega_body[1], s.omega_body[2]), omega, 1e-13);
    }
}

/// Direction cosines from the motion frame to body axes, 3-2-1 Euler angles.
std::array<std::array<double, 3>, 3> dcm(double phi, double theta, double psi) {
    const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), st = std::sin(theta),
                 cp = std::cos(psi), sp = std::sin(psi);
    return {{{ct * cp, ct * sp, -st},
             {sf * st * cp - cf * sp, sf * st * sp + cf * cp, sf * ct},
             {cf * st * cp + sf * sp, cf * st * sp - sf * cp, cf * ct}}};
}

TEST(MotionKinematics, BodyRatesMatchTheRotationOfTheAxes) {
    // Independent check of the Euler-rate formula: [omega x] = -dC/dt C^T for C = C_body<-frame.
    const auto angles = [](double t) {
        return std::array<double, 3>{0.5 * std::sin(1.3 * t), 0.4 * std::cos(0.7 * t) - 0.1,
                                     0.9 * t + 0.2 * std::sin(2.1 * t)};
    };
    const auto rates = [](double t) {
        return std::array<double, 3>{0.65 * std::cos(1.3 * t), -0.28 * std::sin(0.7 * t),
                                     0.9 + 0.42 * std::cos(2.1 * t)};
    };
    for (const double t : {0.0, 0.8, 2.3}) {
        const double h = 1e-5;
        const auto a = angles(t), ap = angles(t + h), am = angles(t - h);
        const auto c = dcm(a[0], a[1], a[2]);
        const auto cp = dcm(ap[0], ap[1], ap[2]);
        const auto cm = dcm(am[0], am[1], am[2]);
        std::array<std::array<double, 3>, 3> w{};  // -dC/dt C^T
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k) w[i][j] -= (cp[i][k] - cm[i][k]) / (2 * h) * c[j][k];
        const auto pqr = manta::core::body_rates_from_euler_rates(a, rates(t));
        EXPECT_NEAR(pqr[0], w[2][1], 1e-8);
        EXPECT_NEAR(pqr[1], w[0][2], 1e-8);
        EXPECT_NEAR(pqr[2], w[1][0], 1e-8);
    }
}

TEST(HarmonicMotion, SamplesWholePeriods) {
    const double amplitude = 0.02, omega = 4.0;
    const int n_periods = 3, per = 24;
    const double period = 2 * pi / omega;
    for (const OscillationAxis axis : {OscillationAxis::roll, OscillationAxis::pitch,
                                       OscillationAxis::yaw, OscillationAxis::plunge}) {
        MotionMetadata meta;
        meta.v0 = 100.0;
        const Motion m = harmonic_motion(axis, amplitude, omega, n_periods, per, 0.1, meta);
        ASSERT_EQ(m.n_samples(), static_cast<std::size_t>(n_periods * per + 1)) << to_string(axis);
        EXPECT_EQ(m.t.front(), 0.0);
        EXPECT_NEAR(m.t.back(), n_periods * period, 1e-14);
        EXPECT_EQ(*m.metadata.v0, 100.0);
        EXPECT_EQ(m.mode_names, (std::vector<std::string>{"elevator", "aileron", "rudder"}));
        const std::vector<double>& moving = axis == OscillationAxis::roll    ? m.angles[0]
                                            : axis == OscillationAxis::pitch ? m.angles[1]
                                            : axis == OscillationAxis::yaw   ? m.angles[2]
                                                                             : m.position[2];
        for (std::size_t i = 0; i < m.n_samples(); ++i) {
            EXPECT_NEAR(moving[i], 0.1 + amplitude * std::sin(omega * m.t[i]), 1e-15);
            if (i >= static_cast<std::size_t>(per)) {
                EXPECT_EQ(moving[i], moving[i - per]);  // every period the same values
            }
        }
        // Everything else is zero.
        double others = 0.0;
        for (const auto& c : m.position)
            if (&c != &moving)
                for (const double v : c) others += std::abs(v);
        for (const auto& c : m.angles)
            if (&c != &moving)
                for (const double v : c) others += std::abs(v);
        for (const auto& c : m.modes)
            for (const double v : c) others += std::abs(v);
        EXPECT_EQ(others, 0.0) << to_string(axis);
    }
    // Plunge moves the reference point down: z_ref = h sin(omega t).
    const MotionState s = harmonic_motion(OscillationAxis::plunge, 0.5, 2.0, 2, 64).at(pi);
    EXPECT_NEAR(s.velocity[2], 1.0, 1e-5);  // z_dot = h omega cos(omega t) at t = T
    EXPECT_NEAR(s.omega_body[1], 0.0, 1e-15);

    EXPECT_THROW((void)harmonic_motion(OscillationAxis::pitch, 0.1, 0.0, 1, 16), InputError);
    EXPECT_THROW((void)harmonic_motion(OscillationAxis::pitch, 0.1, 1.0, 0, 16), InputError);
    EXPECT_THROW((void)harmonic_motion(OscillationAxis::pitch, 0.1, 1.0, 1, 3), InputError);
    EXPECT_THROW((void)harmonic_motion(OscillationAxis::pitch, std::nan(""), 1.0, 1, 16),
                 InputError);
}

}  // namespace
}  // namespace manta::aero
