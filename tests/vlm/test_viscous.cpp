// Tests of src/vlm/viscous.cpp: the skin-friction, form-factor and wetted-area ingredients of
// Raymer's component drag build-up (Aircraft Design: A Conceptual Approach, 6th ed., sec. 12.5)
// against values worked out by hand, the exposed planform, a rectangular wing's build-up by hand,
// and the Ranger 2000's total with its trends. Expected numbers below were evaluated from the
// printed formulas with a calculator (digits as quoted), not with the code under test.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/geometry/aircraft_geometry.hpp"
#include "manta/vlm/viscous.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta::vlm;
using manta::geometry::AircraftGeometry;
using manta::geometry::Airfoil;
using manta::geometry::Fuselage;
using manta::geometry::FuselageStation;
using manta::geometry::LiftingSurface;
using manta::geometry::SurfaceSection;
constexpr double pi = std::numbers::pi;

std::string input_error(const std::function<void()>& f) {
    try {
        f();
    } catch (const manta::InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "unexpected exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << "nothing thrown";
    return {};
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

SurfaceSection section(double x, double y, double z, double chord, const char* airfoil) {
    SurfaceSection s;
    s.leading_edge = Eigen::Vector3d(x, y, z);
    s.chord = chord;
    s.airfoil = Airfoil::naca(airfoil);
    return s;
}

/// Rectangular wing, chord `c`, semi-span `b2`, at height z, mirrored about y = 0.
LiftingSurface rectangular_wing(double c, double b2, double z = 0.0,
                                const char* airfoil = "NACA 0012") {
    LiftingSurface w;
    w.name = "wing";
    w.sections = {section(0.0, 0.0, z, c, airfoil), section(0.0, b2, z, c, airfoil)};
    return w;
}

/// Circular cylinder of diameter d from x0 to x1, centred on z = 0.
Fuselage cylinder(double x0, double x1, double d) {
    Fuselage f;
    f.stations = {FuselageStation{x0, d, d, 0.0}, FuselageStation{x1, d, d, 0.0}};
    return f;
}

// ------------------------------------------------------------------------------------ Reynolds

TEST(ViscousReynolds, PerMetreIsDensityTimesSpeedOverViscosity) {
    EXPECT_DOUBLE_EQ(reynolds_per_metre(1.225, 100.0, 1.789e-5), 1.225 * 100.0 / 1.789e-5);
    // ISA at 3000 m (U.S. Standard Atmosphere 1976): rho = 0.90925 kg/m^3, a = 328.58 m/s,
    // mu = 1.6938e-5 Pa s; at M 0.3: 0.90925 * 98.574 / 1.6938e-5 = 5.2916e6 per metre.
    EXPECT_NEAR(reynolds_per_metre(0.90925, 0.3 * 328.58, 1.6938e-5), 5.2916e6, 1e3);
}

TEST(ViscousReynolds, RejectsNonPositiveAndNaN) {
    expect_parts(input_error([] { (void)reynolds_per_metre(0.0, 100.0, 1.8e-5); }),
                 {"density 0", "expected a positive density"});
    expect_parts(input_error([] { (void)reynolds_per_metre(1.2, -5.0, 1.8e-5); }),
                 {"speed -5", "expected a positive airspeed"});
    expect_parts(input_error([] { (void)reynolds_per_metre(1.2, 100.0, std::nan("")); }),
                 {"viscosity nan", "expected a positive dynamic viscosity"});
}

// ------------------------------------------------------------------------------- skin friction

TEST(ViscousSkinFriction, TurbulentMatchesRaymerEq1227ByHand) {
    // Raymer eq. 12.27, Cf = 0.455 / ((log10 Re)^2.58 (1 + 0.144 M^2)^0.65).
    // Re 1e6, M 0: 6^2.58 = exp(2.58 ln 6) = 101.771, Cf = 0.455 / 101.771 = 4.47076e-3.
    EXPECT_NEAR(turbulent_skin_friction(1e6, 0.0), 4.47076e-3, 1e-8);
    // Re 1e7, M 0.5: 7^2.58 = 151.479, (1.036)^0.65 = 1.02325, Cf = 2.93545e-3.
    EXPECT_NEAR(turbulent_skin_friction(1e7, 0.5), 2.93545e-3, 1e-8);
    // Blasius laminar plate (eq. 12.26): 1.328 / sqrt(1e6).
    EXPECT_NEAR(laminar_skin_friction(1e6), 1.328e-3, 1e-15);
    // Decreases with Mach (compressibility correction) and with Reynolds number.
    EXPECT_LT(turbulent_skin_friction(1e7, 0.8), turbulent_skin_friction(1e7, 0.2));
    EXPECT_LT(turbulent_skin_friction(2e7, 0.3), turbulent_skin_friction(1e7, 0.3));
}

TEST(ViscousSkinFriction, RoughnessCutoffAndLaminarMixing) {
    // Raymer Table 12.5: smooth paint k = 0.634e-5 m; eq. 12.28 on l = 1 m:
    // 38.21 (1 / 0.634e-5)^1.053 = 38.21 * 2.9743e5 = 1.13652e7.
    EXPECT_DOUBLE_EQ(roughness_height(SkinRoughness::smooth_paint), 0.634e-5);
    EXPECT_DOUBLE_EQ(roughness_height(SkinRoughness::camouflage_paint), 1.015e-5);
    EXPECT_DOUBLE_EQ(roughness_height(SkinRoughness::smooth_molded_composite), 0.052e-5);
    EXPECT_NEAR(cutoff_reynolds(1.0, 0.634e-5), 1.13652e7, 2e2);
    // Below the cut-off the plate is smooth; above it Cf is held at the cut-off value.
    const double k = 0.634e-5;
    EXPECT_DOUBLE_EQ(skin_friction(5e6, 0.3, 1.0, k, 0.0), turbulent_skin_friction(5e6, 0.3));
    EXPECT_DOUBLE_EQ(skin_friction(5e7, 0.3, 1.0, k, 0.0), skin_friction(9e7, 0.3, 1.0, k, 0.0));
    EXPECT_NEAR(skin_friction(5e7, 0.3, 1.0, k, 0.0),
                turbulent_skin_friction(cutoff_reynolds(1.0, k), 0.3), 1e-15);
    EXPECT_GT(skin_friction(5e7, 0.3, 1.0, k, 0.0), turbulent_skin_friction(5e7, 0.3));
    // A rougher finish lowers the cut-off and raises Cf at high Reynolds number.
    EXPECT_GT(skin_friction(5e7, 0.3, 1.0, roughness_height(SkinRoughness::camouflage_paint), 0.0),
              skin_friction(5e7, 0.3, 1.0, k, 0.0));
    // 20 % laminar at Re 1e6, M 0: 0.2 * 1.328e-3 + 0.8 * 4.47076e-3 = 3.84221e-3.
    EXPECT_NEAR(skin_friction(1e6, 0.0, 1.0, k, 0.2), 3.84221e-3, 1e-8);
    expect_parts(input_error([&] { (void)skin_friction(1e6, 0.0, 1.0, k, 1.5); }),
                 {"laminar fraction 1.5", "expected a fraction in [0, 1]"});
}

// -------------------------------------------------------------------------------- form factors

TEST(ViscousFormFactor, Naca0012WingByHand) {
    // Raymer eq. 12.30 with (x/c)_m = 0.3, t/c = 0.12: 1 + 2 * 0.12 + 100 * 0.12^4 = 1.260736.
    // M 0.5 unswept: 1.34 * 0.5^0.18 = 1.182822, FF = 1.491226.
    EXPECT_NEAR(surface_form_factor(0.12, 0.3, 0.0, 0.5), 1.491226, 1e-6);
    // M 0.3, 30 deg sweep of the maximum-thickness line: 1.34 * 0.3^0.18 = 1.078913,
    // cos(30 deg)^0.28 = 0.960525, FF = 1.306530.
    EXPECT_NEAR(surface_form_factor(0.12, 0.3, pi / 6.0, 0.3), 1.306530, 1e-6);
    // The compressibility term falls below 1 under M = 0.197 (1.34 * 0.1^0.18 = 0.885329) and
    // reaches 0 at M = 0; the default holds it at 1.
    EXPECT_NEAR(form_factor_mach_term(0.1, false), 0.885329, 1e-6);
    EXPECT_DOUBLE_EQ(form_factor_mach_term(0.1), 1.0);
    EXPECT_DOUBLE_EQ(form_factor_mach_term(0.0, false), 0.0);
    EXPECT_NEAR(surface_form_factor(0.12, 0.3, 0.0, 0.0), 1.260736, 1e-12);
    // Thicker sections and a forward maximum-thickness point raise it.
    EXPECT_GT(surface_form_factor(0.15, 0.3, 0.0, 0.3), surface_form_factor(0.12, 0.3, 0.0, 0.3));
    EXPECT_GT(surface_form_factor(0.12, 0.3, 0.0, 0.3), surface_form_factor(0.12, 0.4, 0.0, 0.3));
}

TEST(ViscousFormFactor, FinenessSixBodyByHand) {
    // Classic (RAND/DATCOM, Raymer's earlier eq. 12.31): 1 + 60/216 + 6/400 = 1.292778.
    EXPECT_NEAR(body_form_factor(6.0), 1.292778, 1e-6);
    // Raymer 6th ed. eq. 12.31: 0.9 + 5/6^1.5 + 6/400 = 0.9 + 0.340207 + 0.015 = 1.255207.
    EXPECT_NEAR(body_form_factor(6.0, BodyFormFactor::raymer_2018), 1.255207, 1e-6);
    // The two agree for slender bodies (f = 10: 1.085 and 1.083114).
    EXPECT_NEAR(body_form_factor(10.0), 1.085, 1e-12);
    EXPECT_NEAR(body_form_factor(10.0, BodyFormFactor::raymer_2018), 1.083114, 1e-6);
    expect_parts(input_error([] { (void)body_form_factor(0.0); }),
                 {"fineness ratio 0", "expected a positive"});
}

TEST(ViscousFormFactor, MaximumThicknessPosition) {
    EXPECT_DOUBLE_EQ(max_thickness_position(Airfoil::naca("NACA 0012")), 0.3);
    EXPECT_DOUBLE_EQ(max_thickness_position(Airfoil::naca("NACA 23012")), 0.3);
    EXPECT_DOUBLE_EQ(max_thickness_position(Airfoil::naca("NACA 64-215")), 0.4);
    EXPECT_DOUBLE_EQ(max_thickness_position(Airfoil::naca("NACA 65-410")), 0.5);
    // A coordinate airfoil: the four-digit thickness form peaks at x/c = 0.30 (Jacobs, Ward &
    // Pinkerton, NACA Report 460); found from the points.
    const Airfoil pts =
        Airfoil::from_points("pts", Airfoil::naca("NACA 0012").coordinates(121), "test");
    EXPECT_NEAR(max_thickness_position(pts), 0.30, 0.01);
    // A section thickest at 60 % chord (a symmetric, piecewise-linear shape).
    std::vector<Eigen::Vector2d> diamond{{1.0, 0.0},   {0.8, 0.025},  {0.6, 0.05}, {0.0, 0.0},
                                         {0.6, -0.05}, {0.8, -0.025}, {1.0, 0.0}};
    EXPECT_NEAR(max_thickness_position(Airfoil::from_points("d", diamond, "test")), 0.6, 0.01);
}

// -------------------------------------------------------------------------------- wetted areas

/// Perimeter of an ellipse by direct quadrature of the arc length (midpoint rule, n steps).
double perimeter_numeric(double a, double b, int n = 20000) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) {
        const double t = 2.0 * pi * (i + 0.5) / n;
        s += std::hypot(a * std::sin(t), b * std::cos(t));
    }
    return s * 2.0 * pi / n;
}

/// Area of the ruled body through elliptic stations by brute-force quadrature of the surface
/// element |r_x x r_theta| over x and theta (independent of the code under test).
double body_area_numeric(const Fuselage& f, int nx = 400, int nt = 720) {
    double area = 0.0;
    for (std::size_t i = 0; i + 1 < f.stations.size(); ++i) {
        const auto& s0 = f.stations[i];
        const auto& s1 = f.stations[i + 1];
        const double dx = s1.x - s0.x;
        const double da = 0.5 * (s1.width - s0.width) / dx;
        const double db = 0.5 * (s1.height - s0.height) / dx;
        const double dz = (s1.z_centre - s0.z_centre) / dx;
        for (int j = 0; j < nx; ++j) {
            const double u = (j + 0.5) / nx;
            const double a = 0.5 * (s0.width + u * (s1.width - s0.width));
            const double b = 0.5 * (s0.height + u * (s1.height - s0.height));
            for (int k = 0; k < nt; ++k) {
                const double t = 2.0 * pi * (k + 0.5) / nt;
                // r(x, t) = (x, a(x) cos t, z_c(x) + b(x) sin t)
                const Eigen::Vector3d rx(1.0, da * std::cos(t), dz + db * std::sin(t));
                const Eigen::Vector3d rt(0.0, -a * std::sin(t), b * std::cos(t));
                area += rx.cross(rt).norm() * (dx / nx) * (2.0 * pi / nt);
            }
        }
    }
    return area;
}

TEST(ViscousWettedArea, RamanujanPerimeter) {
    EXPECT_NEAR(ellipse_perimeter(2.0, 2.0), 2.0 * pi, 1e-14);
    EXPECT_NEAR(ellipse_perimeter(1.30, 1.55) / perimeter_numeric(0.65, 0.775), 1.0, 1e-8);
    EXPECT_NEAR(ellipse_perimeter(2.0, 1.0) / perimeter_numeric(1.0, 0.5), 1.0, 4e-6);
    // Flat limit: 4a exactly, Ramanujan gives pi (3 - sqrt 3) a = 3.98338 a.
    EXPECT_NEAR(ellipse_perimeter(2.0, 0.0), pi * (3.0 - std::sqrt(3.0)), 1e-12);
}

TEST(ViscousWettedArea, CylinderAndConeLimits) {
    // Elliptic cylinder: perimeter times length.
    Fuselage c;
    c.stations = {FuselageStation{0.0, 1.30, 1.55, 0.1}, FuselageStation{5.0, 1.30, 1.55, 0.1}};
    EXPECT_NEAR(fuselage_wetted_area(c), 5.0 * perimeter_numeric(0.65, 0.775), 1e-6);
    // Circular cone of base radius 0.5 and length 2: pi r s, slant s = sqrt(4 + 0.25).
    Fuselage k;
    k.stations = {FuselageStation{0.0, 0.0, 0.0, 0.0}, FuselageStation{2.0, 1.0, 1.0, 0.0}};
    EXPECT_NEAR(fuselage_wetted_area(k), pi * 0.5 * std::sqrt(4.25), 1e-12);
    EXPECT_DOUBLE_EQ(fuselage_wetted_area(Fuselage{}), 0.0);
}

TEST(ViscousWettedArea, SphereFromStations) {
    // A sphere of radius 1 drawn with 81 circular stations: 4 pi within the chord error of the
    // polygonal meridian (which is 0.03 % short for 80 intervals).
    Fuselage s;
    const int n = 80;
    for (int i = 0; i <= n; ++i) {
        const double th = pi * i / n;
        const double d = 2.0 * std::sin(th);
        s.stations.push_back(FuselageStation{-std::cos(th), d, d, 0.0});
    }
    EXPECT_NEAR(fuselage_wetted_area(s) / (4.0 * pi), 1.0, 1e-3);
}

TEST(ViscousWettedArea, EllipticBodyAgainstSurfaceQuadrature) {
    // Pointed nose, changing width/height ratio and a drooping then rising centre line.
    Fuselage f;
    f.stations = {{0.0, 0.0, 0.0, 0.0},    {0.4, 0.42, 0.40, -0.02}, {1.0, 0.72, 0.78, 0.02},
                  {2.6, 1.02, 1.48, 0.22}, {4.2, 1.30, 1.55, 0.15},  {7.4, 0.90, 0.95, 0.12},
                  {10.4, 0.36, 0.38, 0.15}};
    const double exact = body_area_numeric(f);
    EXPECT_NEAR(fuselage_wetted_area(f) / exact, 1.0, 3e-3);
    // Raymer's plain integral of the perimeter along x misses the slope of the nose cone.
    double plain = 0.0;
    for (std::size_t i = 0; i + 1 < f.stations.size(); ++i) {
        const auto& a = f.stations[i];
        const auto& b = f.stations[i + 1];
        for (int j = 0; j < 1000; ++j) {
            const double u = (j + 0.5) / 1000;
            plain += ellipse_perimeter(a.width + u * (b.width - a.width),
                                       a.height + u * (b.height - a.height)) *
                     (b.x - a.x) / 1000;
        }
    }
    EXPECT_LT(plain, exact);
    EXPECT_GT(std::abs(plain / exact - 1.0), std::abs(fuselage_wetted_area(f) / exact - 1.0));
}

// ----------------------------------------------------------------------------- exposed planform

TEST(ViscousExposed, WingThroughACylinderLosesTheCentreSection) {
    const auto w = rectangular_wing(1.0, 5.0);
    // No fuselage: the whole planform.
    const auto free = exposed_planform(w, Fuselage{});
    EXPECT_NEAR(free.area, 10.0, 1e-12);
    EXPECT_NEAR(free.thickness_ratio, 0.12, 1e-12);
    EXPECT_NEAR(free.max_thickness_position, 0.3, 1e-12);
    EXPECT_NEAR(free.max_thickness_sweep, 0.0, 1e-12);
    // Cylinder of diameter 1 around the root: both copies lose 0.5 m of span.
    const auto mid = exposed_planform(w, cylinder(-2.0, 8.0, 1.0));
    EXPECT_NEAR(mid.start, 0.5, 1e-12);
    EXPECT_NEAR(mid.area, 9.0, 1e-12);
    // Low wing at z = -0.3 in the same body: the side at that height is sqrt(0.25 - 0.09) = 0.4.
    const auto low = exposed_planform(rectangular_wing(1.0, 5.0, -0.3), cylinder(-2.0, 8.0, 1.0));
    EXPECT_NEAR(low.start, 0.4, 1e-12);
    EXPECT_NEAR(low.area, 9.2, 1e-12);
    // A parasol wing above the body keeps its whole area.
    EXPECT_NEAR(exposed_planform(rectangular_wing(1.0, 5.0, 0.8), cylinder(-2.0, 8.0, 1.0)).area,
                10.0, 1e-12);
    // A body that ends ahead of the wing does not cut it.
    EXPECT_NEAR(exposed_planform(w, cylinder(-5.0, -1.0, 1.0)).area, 10.0, 1e-12);
}

TEST(ViscousExposed, FinOnTopOfTheBodyAndTaperedWeights) {
    LiftingSurface fin;
    fin.name = "fin";
    fin.vertical = true;
    fin.symmetric = false;
    // Root at z = 0 inside a body of diameter 1 (top at 0.5), tip at z = 2.5; chords 2 -> 1.
    fin.sections = {section(0.0, 0.0, 0.0, 2.0, "NACA 0012"),
                    section(1.0, 0.0, 2.5, 1.0, "NACA 0008")};
    const auto e = exposed_planform(fin, cylinder(-2.0, 8.0, 1.0));
    EXPECT_NEAR(e.start, 0.5, 1e-12);
    // Chord at z = 0.5: 1.8; area (1.8 + 1) / 2 * 2 = 2.8 (one copy).
    EXPECT_NEAR(e.area, 2.8, 1e-12);
    // t/c weighted by exposed area = integral of thickness / area: thickness 0.24 - 0.2 * 0.16 =
    // 0.208 m at z = 0.5, 0.08 m at the tip: (0.208 + 0.08) / 2 * 2 / 2.8 = 0.102857.
    EXPECT_NEAR(e.thickness_ratio, 0.288 / 2.8, 1e-12);
    // Maximum-thickness line from x = 0.6 (at chord 2) to 1.3 over 2.5 m: atan(0.7 / 2.5).
    EXPECT_NEAR(e.max_thickness_sweep, std::atan(0.7 / 2.5), 1e-12);
}

// ------------------------------------------------------------------------------------ build-up

TEST(ViscousBuildUp, RectangularWingByHand) {
    AircraftGeometry g;
    g.surfaces.push_back(rectangular_wing(1.0, 5.0));
    // Re/l 5e6, M 0.3, Sref 10 m^2. MAC 1 m, Re 5e6 (cut-off 1.1365e7 not reached):
    // log10 5e6 = 6.698970, ^2.58 = 135.2386, (1.01296)^0.65 = 1.008405, Cf = 3.336381e-3.
    // FF = 1.260736 * 1.34 * 0.3^0.18 = 1.260736 * 1.078913 = 1.360225.
    // Swet = 10 (1.977 + 0.52 * 0.12) = 20.394 m^2; Q = 1 (wing).
    // CD0 = 3.336381e-3 * 1.360225 * 20.394 / 10 = 9.25527e-3.
    const auto r = viscous_drag(g, 10.0, 0.3, 5e6);
    ASSERT_EQ(r.components.size(), 1u);
    const auto& c = r.components[0];
    EXPECT_EQ(c.kind, ComponentKind::wing);
    EXPECT_NEAR(c.reynolds, 5e6, 1e-6);
    EXPECT_NEAR(c.skin_friction, 3.336381e-3, 1e-9);
    EXPECT_NEAR(c.form_factor, 1.360225, 1e-6);
    EXPECT_DOUBLE_EQ(c.interference, 1.0);
    EXPECT_NEAR(c.wetted_area, 20.394, 1e-10);
    EXPECT_NEAR(c.cd0, 9.25527e-3, 1e-8);
    EXPECT_NEAR(r.cd0, 9.25527e-3, 1e-8);
    EXPECT_DOUBLE_EQ(r.leakage_protuberance_cd0, 0.0);
}

TEST(ViscousBuildUp, WingBodyTailByHand) {
    AircraftGeometry g;
    g.surfaces.push_back(rectangular_wing(1.0, 5.0));
    LiftingSurface tail = rectangular_wing(1.0, 1.5);
    tail.name = "tailplane";
    for (auto& s : tail.sections) s.leading_edge.x() = 7.0;
    g.surfaces.push_back(tail);
    g.fuselage = cylinder(-2.0, 8.0, 1.0);
    const auto r = viscous_drag(g, 10.0, 0.3, 5e6);
    ASSERT_EQ(r.components.size(), 3u);
    // Wing: exposed 9 m^2, Swet 18.3546 m^2, CD0 = 3.336381e-3 * 1.360225 * 18.3546 / 10.
    const auto* w = r.find("wing");
    ASSERT_NE(w, nullptr);
    EXPECT_NEAR(w->exposed_area, 9.0, 1e-12);
    EXPECT_NEAR(w->cd0, 8.32974e-3, 1e-8);
    // Tailplane: the smaller horizontal surface is a tail, Q = 1.05; exposed 2 (1.5 - 0.5).
    const auto* t = r.find("tailplane");
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->kind, ComponentKind::tail);
    EXPECT_DOUBLE_EQ(t->interference, 1.05);
    EXPECT_NEAR(t->exposed_area, 2.0, 1e-12);
    EXPECT_NEAR(t->cd0, 3.336381e-3 * 1.360225 * 1.05 * 2.0 * 2.0394 / 10.0, 1e-8);
    // Fuselage: l = 10, d = 1, f = 10, FF = 1.085; Re 5e7 (cut-off 1.284e8 not reached):
    // log10 5e7 = 7.698970, ^2.58 = 193.6405, Cf = 0.455 / 193.8716 / 1.008405 = 2.330130e-3;
    // Swet = pi * 10 (no end caps); CD0 = 2.330130e-3 * 1.085 * 31.41593 / 10 = 7.94255e-3.
    const auto* f = r.find("fuselage");
    ASSERT_NE(f, nullptr);
    EXPECT_NEAR(f->fineness_ratio, 10.0, 1e-12);
    EXPECT_NEAR(f->form_factor, 1.085, 1e-12);
    EXPECT_NEAR(f->skin_friction, 2.330130e-3, 1e-9);
    EXPECT_NEAR(f->wetted_area, 10.0 * pi, 1e-9);
    EXPECT_NEAR(f->cd0, 7.94255e-3, 1e-8);
    EXPECT_NEAR(r.components_cd0, w->cd0 + t->cd0 + f->cd0, 1e-15);
    EXPECT_DOUBLE_EQ(r.cd0, r.components_cd0);

    // Options: interference by name, leakage and protuberances as 5 % of the total.
    ViscousDragOptions o;
    o.interference_by_name["fuselage"] = 1.2;
    o.leakage_protuberance_fraction = 0.05;
    const auto r2 = viscous_drag(g, 10.0, 0.3, 5e6, o);
    EXPECT_NEAR(r2.find("fuselage")->cd0, 1.2 * f->cd0, 1e-15);
    EXPECT_NEAR(r2.leakage_protuberance_cd0 / r2.cd0, 0.05, 1e-14);
    EXPECT_NEAR(r2.cd0, (w->cd0 + t->cd0 + 1.2 * f->cd0) / 0.95, 1e-14);
    // Choosing the tailplane as main wing swaps the interference factors.
    ViscousDragOptions o3;
    o3.main_wing = "tailplane";
    const auto r3 = viscous_drag(g, 10.0, 0.3, 5e6, o3);
    EXPECT_DOUBLE_EQ(r3.find("wing")->interference, 1.05);
    EXPECT_DOUBLE_EQ(r3.find("tailplane")->interference, 1.0);
    // Laminar flow on the surfaces lowers their drag, not the fuselage's.
    ViscousDragOptions o4;
    o4.laminar_fraction_surfaces = 0.3;
    const auto r4 = viscous_drag(g, 10.0, 0.3, 5e6, o4);
    EXPECT_LT(r4.find("wing")->cd0, w->cd0);
    EXPECT_DOUBLE_EQ(r4.find("fuselage")->cd0, f->cd0);
}

TEST(ViscousBuildUp, InvalidInputs) {
    AircraftGeometry g;
    g.surfaces.push_back(rectangular_wing(1.0, 5.0));
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, 0.0); }),
                 {"Reynolds number per metre 0", "expected a positive number"});
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, -4e6); }),
                 {"Reynolds number per metre -4e+06", "expected a positive number"});
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, std::nan("")); }),
                 {"Reynolds number per metre nan", "expected"});
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 1.0, 5e6); }),
                 {"Mach number 1", "expected a subsonic value in [0, 1)"});
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 1.6, 5e6); }),
                 {"Mach number 1.6", "subsonic"});
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, std::nan(""), 5e6); }),
                 {"Mach number nan", "subsonic"});
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, -0.1, 5e6); }),
                 {"Mach number -0.1", "subsonic"});
    expect_parts(input_error([&] { (void)viscous_drag(g, 0.0, 0.3, 5e6); }),
                 {"reference area 0", "expected a positive area"});
    // Reynolds number per metre fine, but a 1 m chord at 100 per metre is not a flat plate.
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, 100.0); }),
                 {"component 'wing'", "Reynolds number 100", "expected at least 10000"});
    ViscousDragOptions o;
    o.interference_by_name["canard"] = 1.1;
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, 5e6, o); }),
                 {"'canard'", "not a component", "expected one of: wing"});
    ViscousDragOptions o2;
    o2.leakage_protuberance_fraction = 0.7;
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, 5e6, o2); }),
                 {"leakage_protuberance_fraction 0.7", "expected a fraction"});
    ViscousDragOptions o3;
    o3.main_wing = "canard";
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, 5e6, o3); }),
                 {"main wing 'canard'", "expected one of: wing"});
    ViscousDragOptions o4;
    o4.interference_tail = 0.0;
    expect_parts(input_error([&] { (void)viscous_drag(g, 10.0, 0.3, 5e6, o4); }),
                 {"interference_tail 0", "expected a positive"});
}

// ---------------------------------------------------------------------------------- Ranger 2000

struct Ranger {
    AircraftGeometry geometry;
    double reference_area = 0.0;
};

/// The `geometry:` and `reference.area` of examples/ranger2000/aircraft.yaml, read as
/// `aircraft::load_aircraft` does (the vlm module cannot depend on the aircraft module).
Ranger load_ranger() {
    const fs::path file = fs::path(MANTA_SOURCE_DIR) / "examples" / "ranger2000" / "aircraft.yaml";
    const auto root = manta::core::ConfigNode::parse_file(file);
    manta::core::ConfigMap geometry(root.child("geometry"));
    Ranger r;
    r.geometry = manta::geometry::parse_geometry(geometry, file.parent_path());
    r.reference_area = root.child("reference").child("area").to_double();
    return r;
}

// M 0.3 at 3000 m (ISA): Reynolds number per metre 5.2916e6 (see ViscousReynolds above).
constexpr double ranger_re_per_m = 5.2916e6;

TEST(ViscousRanger, TotalInTheBandOfJetTrainers) {
    const Ranger a = load_ranger();
    ASSERT_NEAR(a.reference_area, 15.5, 1e-12);
    const auto r = viscous_drag(a.geometry, a.reference_area, 0.3, ranger_re_per_m);
    ASSERT_EQ(r.components.size(), 4u);
    // Clean jet trainers: CD0 about 0.015 to 0.030 (before stores, intakes, gear).
    EXPECT_GT(r.cd0, 0.015);
    EXPECT_LT(r.cd0, 0.030);
    const auto* wing = r.find("wing");
    const auto* htp = r.find("horizontal_tail");
    const auto* fin = r.find("fin");
    const auto* fus = r.find("fuselage");
    ASSERT_TRUE(wing && htp && fin && fus);
    EXPECT_EQ(wing->kind, ComponentKind::wing);
    EXPECT_EQ(htp->kind, ComponentKind::tail);
    EXPECT_EQ(fin->kind, ComponentKind::tail);
    // Wing: MAC 1.531 m; NACA 64-2xx sections, (x/c)_m 0.4; the part inside the fuselage (about
    // 1.25 m wide at the root's mid-chord) is cut; t/c weighted by the exposed area between 15 %
    // at the root and 12 % at the tip, thickness linear in y.
    EXPECT_NEAR(wing->length, 1.531, 1e-3);
    const double cut = exposed_planform(a.geometry.surface("wing"), a.geometry.fuselage).start;
    EXPECT_GT(cut, 0.6);
    EXPECT_LT(cut, 0.65);
    const double u = cut / 5.23;
    const double c_cut = 1.951 + u * (1.0126 - 1.951);
    const double t_cut = 1.951 * 0.15 + u * (1.0126 * 0.12 - 1.951 * 0.15);
    EXPECT_NEAR(wing->thickness_ratio, (t_cut + 1.0126 * 0.12) / (c_cut + 1.0126), 1e-9);
    EXPECT_NEAR(wing->exposed_area, 2.0 * (c_cut + 1.0126) / 2.0 * (5.23 - cut), 1e-9);
    EXPECT_DOUBLE_EQ(wing->max_thickness_position, 0.4);
    EXPECT_GT(wing->exposed_area, 12.5);
    EXPECT_LT(wing->exposed_area, 13.5);
    // T-tail root sits above the fuselage: not cut; the fin's root is inside the tail cone.
    EXPECT_NEAR(htp->exposed_area, a.geometry.surface("horizontal_tail").planform_area(), 1e-12);
    EXPECT_LT(fin->exposed_area, a.geometry.surface("fin").planform_area());
    // Fuselage of fineness 10.39 / sqrt(1.30 * 1.55) = 7.32.
    EXPECT_NEAR(fus->fineness_ratio, 10.39 / std::sqrt(1.30 * 1.55), 1e-9);
    EXPECT_GT(fus->wetted_area, 25.0);
    EXPECT_LT(fus->wetted_area, 40.0);
    // The wing is the largest share, then the fuselage.
    EXPECT_GT(wing->cd0, fus->cd0);
    EXPECT_GT(fus->cd0, htp->cd0);
    EXPECT_GT(htp->cd0, fin->cd0);
}

TEST(ViscousRanger, DecreasesWithReynoldsNumberUntilTheRoughnessCutoff) {
    const Ranger a = load_ranger();
    double previous = 1.0;
    for (double re = 1e6; re <= 1e7 + 1.0; re += 1e6) {
        const double cd0 = viscous_drag(a.geometry, a.reference_area, 0.3, re).cd0;
        EXPECT_LT(cd0, previous) << re;
        previous = cd0;
    }
    // Far above every component's cut-off (smooth paint) the drag no longer changes.
    EXPECT_DOUBLE_EQ(viscous_drag(a.geometry, a.reference_area, 0.3, 1e9).cd0,
                     viscous_drag(a.geometry, a.reference_area, 0.3, 3e9).cd0);
}

TEST(ViscousRanger, IncreasesWithMach) {
    const Ranger a = load_ranger();
    double previous = 0.0;
    for (double m = 0.2; m <= 0.8 + 1e-9; m += 0.1) {
        const double cd0 = viscous_drag(a.geometry, a.reference_area, m, ranger_re_per_m).cd0;
        EXPECT_GT(cd0, previous) << m;
        previous = cd0;
    }
}

}  // namespace
