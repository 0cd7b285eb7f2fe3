// NASA NESC 6-DoF check cases (Jackson et al., NASA/TM-2015-218675): the tumbling brick.
//
// Data: MANTA_SHARED_DIR/reference/nasa_checkcases/ (README.md there: provenance, vehicle, units).
// Atmos_02: a brick (8 x 4 x 2.25 in face brick, 5 lbm) released at 30 000 ft, lat 0, lon 0, with
// body rates w.r.t. inertial space p, q, r = 10, 20, 30 deg/s and no aerodynamics: torque-free
// rotation. Atmos_03: the same with rate damping Clp = Cmq = Cnr = -1 (needs air data).
//
// Each reference quantity is compared at every reference sample (0.1 s) with the band spanned by
// the NESC tools at that time (min..max over the simulation files), widened by a stated margin.
//  - Body rates: the rates w.r.t. inertial space need no correction (MANTA's earth axes are an
//    inertial frame). All four tools are in the band.
//  - Euler angles: the references are the attitude relative to the local North-East-Down frame of
//    a rotating Earth. At lat 0, lon 0 that frame turns about its own north axis at
//    omega_E = 7.292115e-5 rad/s (the body hardly moves over the Earth: it falls ~4.4 km and drifts
//    ~6 m east, so the transport rate is < 1e-7 rad/s and is neglected). MANTA's flat, non-rotating
//    earth axes coincide with that NED frame at t = 0, so
//        C_ned_from_body(t) = R_x(omega_E t)^T C_earth_from_body(t),
//    where R_x(a) is the active rotation by a about north (it turns east towards down). Without
//    this the roll angle would drift by omega_E t = 0.125 deg after 30 s, which is what Atmos_01 (a
//    non-rotating sphere) shows: roll -0.1254 deg at 30 s.
//    In Atmos_02 sim_02 is left out of the Euler-angle bands: its attitude departs from the others
//    by up to 3.7 deg (the README's "sim_02 outlier"; its rates agree with the others).
// The test prints the largest deviation outside the band for each quantity.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/simulate.hpp"

namespace fd = manta::flightdyn;
namespace fs = std::filesystem;
using manta::core::deg_to_rad;
using manta::core::rad_to_deg;

namespace {

constexpr double omega_earth = 7.292115e-5;  // [rad/s], WGS-84

fs::path checkcase_dir() {
    return fs::path(MANTA_SHARED_DIR) / "reference" / "nasa_checkcases";
}

/// One NESC reference file: column name -> values.
struct Reference {
    std::string name;
    std::map<std::string, std::vector<double>> columns;
};

std::vector<Reference> load_references(const fs::path& dir, const std::string& prefix) {
    std::vector<Reference> refs;
    for (const char* sim : {"01", "02", "04", "06"}) {
        const fs::path file = dir / (prefix + "_sim_" + sim + ".csv");
        if (!fs::exists(file)) continue;
        const auto t = manta::core::read_csv(file);
        Reference r;
        r.name = std::string("sim_") + sim;
        for (std::size_t c = 0; c < t.columns.size(); ++c) r.columns[t.columns[c]] = t.column(c);
        refs.push_back(std::move(r));
    }
    return refs;
}

/// The brick of the NESC cases in SI units (README: m = 0.155404754 slug, Ixx = 0.00189422,
/// Iyy = 0.006211019, Izz = 0.007194665 slug ft^2, no products of inertia; S = 0.22222 ft^2,
/// b = 0.33333 ft, c = 0.66667 ft).
fd::FlightModel brick(bool damping) {
    using namespace manta::core;
    fd::FlightModel m;
    m.name = "NESC brick";
    m.mass.name = "5 lbm";
    m.mass.mass = 0.155404754 * slug;
    m.mass.inertia = Eigen::Vector3d(0.00189422, 0.006211019, 0.007194665).asDiagonal();
    m.mass.inertia *= slug_ft2;
    m.engine.static_thrust_sl = 0.0;
    m.reference.area = 0.22222 * foot * foot;
    m.reference.span = 0.33333 * foot;
    m.reference.chord = 0.66667 * foot;
    // Effective gravity of the rotating Earth at the equator between 30 000 and 15 600 ft
    // (J2 gravitation 9.786..9.800 m/s^2 less the centripetal 0.034 m/s^2): the mean that makes
    // the flat-earth fall match Atmos_01's 14 401 ft in 30 s. Only the air data of Atmos_03 feel
    // it.
    m.environment.gravity = 2.0 * (30000.0 - 15598.905) * foot / (30.0 * 30.0);
    if (damping) {
        manta::aero::LinearDerivatives d;
        d.Cl_p = -1.0;
        d.Cm_q = -1.0;
        d.Cn_r = -1.0;
        manta::aero::DerivativeGrids g;
        g.alpha = {0.0};
        g.mach = {0.0};
        g.beta = {0.0};
        manta::aero::DatabaseInfo info;
        info.name = "NESC brick damping";
        info.source = "NASA/TM-2015-218675 brick_aero.dml";
        m.aero = std::make_shared<const manta::aero::AeroDatabase>(
            manta::aero::AeroDatabase::from_derivatives(d, g, info));
    }
    fd::finalize(m);
    return m;
}

fd::SimulationResult fly_brick(const fd::FlightModel& m) {
    fd::EulerState<double> s = fd::EulerState<double>::Zero();
    s[fd::euler::z] = -30000.0 * manta::core::foot;
    s[fd::euler::p] = 10.0 * deg_to_rad;
    s[fd::euler::q] = 20.0 * deg_to_rad;
    s[fd::euler::r] = 30.0 * deg_to_rad;
    fd::SimulationOptions opt;
    opt.duration = 30.0;
    opt.dt = 0.001;  // RK4 error ~ (|w| dt)^5 per step: far below the tools' spread
    opt.output_interval = 0.1;
    opt.form = fd::StateForm::quaternion;  // V = 0 at release
    return fd::simulate(m, s, fd::InputHistory(), opt);
}

/// Euler angles (phi, theta, psi) of the body relative to the rotating local NED frame.
Eigen::Vector3d euler_wrt_rotating_ned(const std::vector<double>& row) {
    const double a = omega_earth * row[0];
    Eigen::Matrix3d rx;  // active rotation about north by a
    rx << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
    const Eigen::Matrix3d c =
        rx.transpose() * manta::core::dcm_earth_from_body(row[4], row[5], row[6]);
    return {std::atan2(c(2, 1), c(2, 2)), -std::asin(std::clamp(c(2, 0), -1.0, 1.0)),
            std::atan2(c(1, 0), c(0, 0))};
}

double wrap_deg(double d) {
    return d - 360.0 * std::round(d / 360.0);
}

/// Deviation of `ours` from the band of the references at one time (0 inside the band).
double outside_band(double ours, const std::vector<double>& refs, bool angle) {
    double lo = 1e300, hi = -1e300;
    for (double r : refs) {
        const double d = angle ? wrap_deg(r - ours) : r - ours;
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    if (lo <= 0.0 && hi >= 0.0) return 0.0;
    return lo > 0.0 ? lo : -hi;
}

struct Quantity {
    const char* column;  // NESC column
    const char* label;
    bool angle;
    bool sim02;     // sim_02 in the band
    double margin;  // [deg] or [deg/s]
};

/// Compare MANTA's run with the band at every reference sample; returns the worst deviation per
/// quantity.
void compare_with_band(const fd::SimulationResult& r, const std::vector<Reference>& refs,
                       const std::vector<Quantity>& quantities, const char* case_name) {
    ASSERT_GE(refs.size(), 3u);
    const auto& times = refs.front().columns.at("time");
    ASSERT_EQ(r.rows.size(), times.size());
    std::printf("%s: %zu samples, tools:", case_name, times.size());
    for (const auto& ref : refs) std::printf(" %s", ref.name.c_str());
    std::printf("\n  %-8s %14s %16s %12s %10s\n", "quantity", "max outside", "(at t [s])",
                "band width", "margin");
    for (const auto& qn : quantities) {
        double worst = 0.0, worst_t = 0.0, widest = 0.0;
        for (std::size_t i = 0; i < times.size(); ++i) {
            const auto& row = r.rows[i];
            ASSERT_NEAR(row[0], times[i], 1e-9);
            std::vector<double> band;
            for (const auto& ref : refs) {
                if (!qn.sim02 && ref.name == "sim_02") continue;
                ASSERT_NEAR(ref.columns.at("time")[i], times[i], 1e-6) << ref.name;
                band.push_back(ref.columns.at(qn.column)[i]);
            }
            double ours = 0.0;
            const std::string col = qn.column;
            if (col.find("Rate") != std::string::npos) {
                const int k = col.ends_with("Roll") ? 0 : col.ends_with("Pitch") ? 1 : 2;
                ours = row[10 + k] * rad_to_deg;
            } else {
                const Eigen::Vector3d e = euler_wrt_rotating_ned(row) * rad_to_deg;
                ours = col.ends_with("Roll") ? e[0] : col.ends_with("Pitch") ? e[1] : e[2];
            }
            const double out = outside_band(ours, band, qn.angle);
            const auto [lo, hi] = std::minmax_element(band.begin(), band.end());
            widest = std::max(widest, qn.angle ? std::abs(wrap_deg(*hi - *lo)) : *hi - *lo);
            if (out > worst) {
                worst = out;
                worst_t = times[i];
            }
        }
        std::printf("  %-8s %14.3e %16.1f %12.3e %10.1e\n", qn.label, worst, worst_t, widest,
                    qn.margin);
        EXPECT_LE(worst, qn.margin)
            << qn.label << " leaves the NESC band by " << worst << " at t = " << worst_t << " s";
    }
}

}  // namespace

TEST(NasaCheckCase, Atmos02TumblingBrickNoDamping) {
    const fs::path dir = checkcase_dir() / "Atmos_02_TumblingBrickNoDamping";
    if (!fs::exists(dir)) GTEST_SKIP() << "NESC check-case data not found in " << dir;
    const auto refs = load_references(dir, "Atmos_02");
    const auto r = fly_brick(brick(false));
    ASSERT_EQ(r.end_reason, fd::EndReason::completed);
    // Margins: rates 1e-4 deg/s (a thirtieth of the tools' own spread, 3e-3 deg/s); angles
    // 1e-3 deg (the tools without sim_02 spread by up to 1e-2 deg).
    const std::vector<Quantity> q = {
        {"bodyAngularRateWrtEi_deg_s_Roll", "p", false, true, 1e-4},
        {"bodyAngularRateWrtEi_deg_s_Pitch", "q", false, true, 1e-4},
        {"bodyAngularRateWrtEi_deg_s_Yaw", "r", false, true, 1e-4},
        {"eulerAngle_deg_Roll", "phi", true, false, 1e-3},
        {"eulerAngle_deg_Pitch", "theta", true, false, 1e-3},
        {"eulerAngle_deg_Yaw", "psi", true, false, 1e-3},
    };
    compare_with_band(r, refs, q, "Atmos_02");
}

TEST(NasaCheckCase, Atmos03TumblingBrickDamping) {
    const fs::path dir = checkcase_dir() / "Atmos_03_TumblingBrickDamping";
    if (!fs::exists(dir)) GTEST_SKIP() << "NESC check-case data not found in " << dir;
    const auto refs = load_references(dir, "Atmos_03");
    const auto r = fly_brick(brick(true));
    ASSERT_EQ(r.end_reason, fd::EndReason::completed);
    // The damping moment is proportional to rho V, so the attitude depends on the fall speed:
    // a 0.05 % change of gravity (hence of V) moves phi by 0.05 deg at the end. The NESC tools'
    // own air densities differ by 0.07 % at release, which is why their band is 0.3-0.6 deg wide.
    // MANTA's constant flat-earth gravity (the mean of the J2 + centripetal value that falls from
    // 30 000 to 15 599 ft in 30 s, as Atmos_01 does) leaves V within 0.03 % of the references',
    // worth ~0.02 deg; the angle margin is half that and the run stays inside it (worst 0.005 deg).
    // sim_02 is in the band here, as in the README's Atmos_03 row: its attitude is no outlier in
    // this case. Rates: margin 1e-3 deg/s against a band up to 0.07 deg/s wide.
    const std::vector<Quantity> q = {
        {"bodyAngularRateWrtEi_deg_s_Roll", "p", false, true, 1e-3},
        {"bodyAngularRateWrtEi_deg_s_Pitch", "q", false, true, 1e-3},
        {"bodyAngularRateWrtEi_deg_s_Yaw", "r", false, true, 1e-3},
        {"eulerAngle_deg_Roll", "phi", true, true, 1e-2},
        {"eulerAngle_deg_Pitch", "theta", true, true, 1e-2},
        {"eulerAngle_deg_Yaw", "psi", true, true, 1e-2},
    };
    compare_with_band(r, refs, q, "Atmos_03");
}
