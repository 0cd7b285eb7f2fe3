// Tests of src/geometry: NACA designations and mean lines, airfoil coordinate files, planform
// quantities against the closed-form trapezoid formulas, and the validated `geometry:` section.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/geometry/aircraft_geometry.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta::geometry;
constexpr double pi = std::numbers::pi;

template <class E>
std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const E& e) {
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

fs::path scratch(const std::string& name) {
    const fs::path p = fs::temp_directory_path() /
                       ("manta_geometry_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

// ------------------------------------------------------------------------------------ NACA parsing

TEST(Naca, FourDigit) {
    const auto d = parse_naca("NACA 2412");
    EXPECT_EQ(d.family, NacaFamily::four_digit);
    EXPECT_DOUBLE_EQ(d.max_camber, 0.02);
    EXPECT_DOUBLE_EQ(d.camber_position, 0.4);
    EXPECT_DOUBLE_EQ(d.thickness, 0.12);
    EXPECT_EQ(d.text, "NACA 2412");
    const auto s = parse_naca("  naca0012 ");
    EXPECT_DOUBLE_EQ(s.max_camber, 0.0);
    EXPECT_DOUBLE_EQ(s.thickness, 0.12);
    EXPECT_EQ(s.text, "NACA 0012");
    EXPECT_EQ(parse_naca("4415").text, "NACA 4415");
}

TEST(Naca, FiveDigit) {
    const auto d = parse_naca("NACA 23012");
    EXPECT_EQ(d.family, NacaFamily::five_digit);
    EXPECT_DOUBLE_EQ(d.design_lift, 0.3);
    EXPECT_DOUBLE_EQ(d.camber_position, 0.15);
    EXPECT_FALSE(d.reflexed);
    EXPECT_DOUBLE_EQ(d.r, 0.2025);
    EXPECT_DOUBLE_EQ(d.k1, 15.957);
    EXPECT_DOUBLE_EQ(d.thickness, 0.12);
    const auto r = parse_naca("NACA 23112");
    EXPECT_TRUE(r.reflexed);
    EXPECT_DOUBLE_EQ(r.k2_over_k1, 0.00677);
    // Design lift 0.45: k1 scales with the design lift.
    EXPECT_NEAR(parse_naca("NACA 33012").k1, 15.957 * 1.5, 1e-12);
}

TEST(Naca, SixSeries) {
    const auto d = parse_naca("NACA 64-215");
    EXPECT_EQ(d.family, NacaFamily::six_series);
    EXPECT_EQ(d.min_pressure_tenths, 4);
    EXPECT_EQ(d.low_drag_range_tenths, 0);
    EXPECT_DOUBLE_EQ(d.design_lift, 0.2);
    EXPECT_DOUBLE_EQ(d.thickness, 0.15);
    EXPECT_DOUBLE_EQ(d.mean_line_a, 1.0);
    EXPECT_EQ(d.text, "NACA 64-215");
    for (const char* s : {"NACA 64(2)-215", "NACA 64_2-215", "NACA 642-215", "naca 64(2)-215"}) {
        const auto e = parse_naca(s);
        EXPECT_EQ(e.low_drag_range_tenths, 2) << s;
        EXPECT_DOUBLE_EQ(e.thickness, 0.15) << s;
        EXPECT_EQ(e.text, "NACA 64(2)-215") << s;
    }
    const auto a = parse_naca("NACA 65-410 a=0.5");
    EXPECT_DOUBLE_EQ(a.mean_line_a, 0.5);
    EXPECT_DOUBLE_EQ(a.design_lift, 0.4);
    EXPECT_EQ(a.text, "NACA 65-410 a=0.5");
    const auto a2 = parse_naca("NACA 65(1)-212a=0.6");
    EXPECT_DOUBLE_EQ(a2.mean_line_a, 0.6);
    const auto m = parse_naca("NACA 64A010");
    EXPECT_TRUE(m.a_modified);
    EXPECT_DOUBLE_EQ(m.thickness, 0.10);
    EXPECT_DOUBLE_EQ(m.design_lift, 0.0);
    EXPECT_DOUBLE_EQ(m.mean_line_a, 0.8);
}

TEST(Naca, InvalidDesignations) {
    const std::vector<std::pair<const char*, const char*>> cases{
        {"", "is empty"},
        {"NACA 2012", "maximum camber position (second digit) is 0"},
        {"NACA 0412", "symmetric section"},
        {"NACA 2400", "thickness 0 %"},
        {"NACA 2450", "thickness 50 %"},
        {"NACA 23312", "third digit 3"},
        {"NACA 26012", "camber-position digit 6"},
        {"NACA 21112", "camber-position digit 1 is outside 2 to 5 for reflexed"},
        {"NACA 03012", "design-lift digit (first) is 0"},
        {"NACA 2412 a=0.5", "6-series sections only"},
        {"NACA 84-215", "not a 4-digit, 5-digit or 6-series"},
        {"NACA 68-215", "minimum-pressure digit 8"},
        {"NACA 64-2152", "not three digits"},
        {"NACA 64215x", "the '-' (or 'A')"},
        {"NACA 64(0)-215", "subscript is 0"},
        {"NACA 64(x)-215", "one digit in parentheses"},
        {"NACA 64-215 a=1.5", "outside [0, 1]"},
        {"NACA 64-215 a=abc", "is not a number"},
        {"Clark Y", "not a 4-digit"},
    };
    for (const auto& [text, problem] : cases) {
        const auto msg = error_of<manta::InputError>([&] { (void)parse_naca(text); });
        expect_parts(
            msg, {std::string("airfoil '") + text + "'", problem, "expected a NACA designation"});
    }
}

// ------------------------------------------------------------------------------------ mean lines

double numeric_slope(const Airfoil& a, double x) {
    const double h = 1e-6;
    return (a.camber(x + h) - a.camber(x - h)) / (2 * h);
}

/// Zero-lift angle of thin-airfoil theory, alpha_0 = -1/pi int_0^pi dy/dx (cos t - 1) dt.
double thin_airfoil_zero_lift(const Airfoil& a) {
    const int n = 200000;
    double s = 0.0;
    for (int i = 0; i < n; ++i) {
        const double t = pi * (i + 0.5) / n;
        s += a.camber_slope(0.5 * (1 - std::cos(t))) * (std::cos(t) - 1.0);
    }
    return -s * (pi / n) / pi;
}

TEST(MeanLine, EndsAtZeroAndSlopeMatchesDerivative) {
    for (const char* name :
         {"NACA 2412", "NACA 4415", "NACA 23012", "NACA 23112", "NACA 25112", "NACA 64-215",
          "NACA 65-410 a=0.5", "NACA 63-412 a=0.0", "NACA 64A210"}) {
        const Airfoil a = Airfoil::naca(name);
        EXPECT_NEAR(a.camber(0.0), 0.0, 1e-12) << name;
        EXPECT_NEAR(a.camber(1.0), 0.0, 1e-12) << name;
        for (double x : {0.03, 0.1, 0.27, 0.45, 0.62, 0.85, 0.97}) {
            if (std::abs(x - a.designation().mean_line_a) < 1e-3) continue;
            EXPECT_NEAR(a.camber_slope(x), numeric_slope(a, x), 1e-6) << name << " x=" << x;
        }
    }
}

TEST(MeanLine, FourDigitMaximumCamber) {
    const Airfoil a = Airfoil::naca("NACA 2412");
    EXPECT_NEAR(a.camber(0.4), 0.02, 1e-15);
    EXPECT_NEAR(a.camber_slope(0.4), 0.0, 1e-15);
    EXPECT_LT(a.camber(0.39), 0.02);
    EXPECT_LT(a.camber(0.41), 0.02);
}

TEST(MeanLine, FiveDigitMaximumCamberAtItsPosition) {
    for (int p = 1; p <= 5; ++p) {
        const Airfoil a = Airfoil::naca("NACA 2" + std::to_string(p) + "012");
        double best = 0, xbest = 0;
        for (int i = 1; i < 10000; ++i) {
            const double x = i / 10000.0;
            if (a.camber(x) > best) best = a.camber(x), xbest = x;
        }
        EXPECT_NEAR(xbest, p / 20.0, 2e-3) << p;
    }
    // NACA 23012: maximum camber 1.84 % of the chord (Abbott & von Doenhoff, app. II).
    EXPECT_NEAR(Airfoil::naca("NACA 23012").camber(0.15), 0.0184, 2e-4);
}

TEST(MeanLine, ThinAirfoilZeroLiftAngles) {
    // NACA 2412: -2.077 deg (Anderson, Fundamentals of Aerodynamics, example 4.6).
    EXPECT_NEAR(thin_airfoil_zero_lift(Airfoil::naca("NACA 2412")) * 180 / pi, -2.077, 0.005);
    // a = 1 mean line: uniform loading, ideal angle 0, so c_l(0) = c_li and alpha_0 = -c_li / (2
    // pi).
    EXPECT_NEAR(thin_airfoil_zero_lift(Airfoil::naca("NACA 64-215")), -0.2 / (2 * pi), 2e-5);
    // a = 1 mean line maximum camber 0.05515 c_li at mid-chord (Abbott & von Doenhoff, app. II).
    EXPECT_NEAR(Airfoil::naca("NACA 64-215").camber(0.5), 0.2 * std::log(2.0) / (4 * pi), 1e-15);
    EXPECT_NEAR(Airfoil::naca("NACA 64-215").camber(0.5) / 0.2, 0.05515, 1e-4);
}

TEST(MeanLine, SymmetricSectionsHaveNoCamber) {
    for (const char* name : {"NACA 0012", "NACA 64A010", "NACA 65-012"}) {
        const Airfoil a = Airfoil::naca(name);
        for (double x : {0.1, 0.5, 0.9}) {
            EXPECT_NEAR(a.camber(x), 0.0, 1e-15) << name;
            EXPECT_NEAR(a.camber_slope(x), 0.0, 1e-15) << name;
        }
    }
}

// ------------------------------------------------------------------------------------ coordinates

TEST(Coordinates, Naca0012Shape) {
    const Airfoil a = Airfoil::naca("NACA 0012");
    const auto pts = a.coordinates(101);
    ASSERT_EQ(pts.size(), 201u);
    EXPECT_NEAR(pts.front().x(), 1.0, 1e-15);
    EXPECT_NEAR(pts.back().x(), 1.0, 1e-15);
    EXPECT_NEAR(pts[100].x(), 0.0, 1e-15);
    EXPECT_NEAR(pts[100].y(), 0.0, 1e-15);
    // Trailing-edge half thickness of the open-TE polynomial: 5 t (0.2969 - 0.126 - 0.3516 + 0.2843
    // - 0.1015).
    EXPECT_NEAR(pts.front().y(), 0.6 * 0.0021, 1e-12);
    double tmax = 0;
    for (const auto& p : pts) tmax = std::max(tmax, 2 * p.y());
    EXPECT_NEAR(tmax, 0.12, 2e-4);
}

TEST(Coordinates, FromPoints) {
    const auto pts = Airfoil::naca("NACA 4412").coordinates(61);
    const Airfoil a = Airfoil::from_points("mine", pts, "test points");
    EXPECT_EQ(a.name(), "mine");
    EXPECT_TRUE(a.file().empty());
    EXPECT_NEAR(a.thickness_ratio(), 0.12, 2e-3);
    EXPECT_EQ(a.coordinates(), pts);
    std::vector<Eigen::Vector2d> bad(pts.begin(), pts.begin() + 5);
    expect_parts(
        error_of<manta::InputError>([&] { (void)Airfoil::from_points("x", bad, "test points"); }),
        {"test points", "has 5 coordinate points"});
}

TEST(Coordinates, SixSeriesAreNotGenerated) {
    const Airfoil a = Airfoil::naca("NACA 64-215");
    EXPECT_FALSE(a.has_coordinates());
    expect_parts(error_of<manta::InputError>([&] { (void)a.coordinates(); }),
                 {"NACA 64-215", "airfoil_file"});
}

// ------------------------------------------------------------------------------------ files

void write(const fs::path& p, const std::string& text) {
    std::ofstream out(p);
    out << text;
}

std::string selig_text(const std::vector<Eigen::Vector2d>& pts, const std::string& name) {
    std::string s = name + "\n";
    for (const auto& p : pts)
        s += manta::core::format_exact(p.x()) + "  " + manta::core::format_exact(p.y()) + "\n";
    return s;
}

TEST(AirfoilFile, SeligRoundTripMatchesNaca) {
    const fs::path dir = scratch("selig");
    const Airfoil naca = Airfoil::naca("NACA 2412");
    write(dir / "n2412.dat", selig_text(naca.coordinates(121), "NACA 2412 from MANTA"));
    const Airfoil a = Airfoil::from_file(dir / "n2412.dat");
    EXPECT_FALSE(a.is_naca());
    EXPECT_EQ(a.name(), "NACA 2412 from MANTA");
    EXPECT_EQ(a.file(), dir / "n2412.dat");
    EXPECT_NEAR(a.thickness_ratio(), 0.12, 1.5e-3);
    // Thickness is laid perpendicular to the mean line, so the mid-point of upper and lower
    // surface at one x departs slightly from the mean line where it slopes (near the nose).
    for (double x : {0.1, 0.3, 0.5, 0.8})
        EXPECT_NEAR(a.camber(x), naca.camber(x), x < 0.2 ? 1e-3 : 2e-4) << x;
    EXPECT_NEAR(a.camber_slope(0.6), naca.camber_slope(0.6), 2e-3);
    EXPECT_EQ(a.coordinates().size(), 241u);
    fs::remove_all(dir);
}

TEST(AirfoilFile, LednicerAndNoNameLine) {
    const fs::path dir = scratch("lednicer");
    const auto pts = Airfoil::naca("NACA 4415").coordinates(41);
    // Lednicer: counts, then upper and lower surfaces from the leading edge.
    std::string s = "NACA 4415 Lednicer\n41. 41.\n\n";
    for (int i = 40; i >= 0; --i)
        s += manta::core::format_exact(pts[i].x()) + " " + manta::core::format_exact(pts[i].y()) +
             "\n";
    s += "\n";
    for (int i = 40; i <= 80; ++i)
        s += manta::core::format_exact(pts[i].x()) + " " + manta::core::format_exact(pts[i].y()) +
             "\n";
    write(dir / "l.dat", s);
    const Airfoil l = Airfoil::from_file(dir / "l.dat");
    EXPECT_EQ(l.name(), "NACA 4415 Lednicer");
    const auto back = l.coordinates();
    ASSERT_EQ(back.size(), pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(back[i], pts[i]) << i;
    // Selig without a name line: the stem names it; comma separators are accepted.
    std::string t;
    for (const auto& p : pts)
        t += manta::core::format_exact(p.x()) + ", " + manta::core::format_exact(p.y()) + "\n";
    write(dir / "plain.dat", t);
    EXPECT_EQ(Airfoil::from_file(dir / "plain.dat").name(), "plain");
    fs::remove_all(dir);
}

TEST(AirfoilFile, Errors) {
    const fs::path dir = scratch("errors");
    const auto pts = Airfoil::naca("NACA 2412").coordinates(21);
    const auto check = [&](const std::string& file, const std::string& text,
                           std::initializer_list<std::string> parts) {
        write(dir / file, text);
        expect_parts(error_of<manta::InputError>([&] { (void)Airfoil::from_file(dir / file); }),
                     parts);
    };
    std::string bad_line = selig_text(pts, "x");
    bad_line.insert(bad_line.find('\n', 10) + 1, "0.5 abc\n");
    check("bad.dat", bad_line,
          {(dir / "bad.dat").string() + ":3", "'0.5 abc' is not a coordinate pair", "two numbers"});
    check("three.dat", "x\n1 0 0\n", {"three.dat:2", "is not a coordinate pair"});
    check("empty.dat", "\n\n", {"empty.dat", "is empty"});
    check("few.dat", "x\n1 0\n0 0\n1 0\n", {"few.dat", "has 3 coordinate points", "at least 7"});
    std::vector<Eigen::Vector2d> scaled;
    for (const auto& p : pts) scaled.push_back(2.0 * p);
    check("scaled.dat", selig_text(scaled, "x"),
          {"scaled.dat", "x runs from 0 to 2", "chord-normalised"});
    std::vector<Eigen::Vector2d> flipped;  // lower surface first (clockwise)
    for (const auto& p : pts) flipped.emplace_back(p.x(), -p.y());
    check("flipped.dat", selig_text(flipped, "x"),
          {"flipped.dat", "upper surface lies below the lower surface", "Selig order"});
    std::vector<Eigen::Vector2d> jumbled = pts;
    std::swap(jumbled[3], jumbled[5]);
    check("jumbled.dat", selig_text(jumbled, "x"),
          {"jumbled.dat:", "increases on the upper surface"});
    std::vector<Eigen::Vector2d> le_first(pts.begin() + 20, pts.end());
    le_first.insert(le_first.end(), pts.begin(), pts.begin() + 20);
    check("lefirst.dat", selig_text(le_first, "x"),
          {"lefirst.dat", "leading edge (smallest x) is the first point"});
    check("ledn.dat", "x\n5 5\n0 0\n0.5 0.05\n1 0\n0 0\n0.5 -0.05\n1 0\n",
          {"ledn.dat:2", "Lednicer header announces 5 upper and 5 lower points but 6 follow"});
    EXPECT_THROW((void)Airfoil::from_file(dir / "missing.dat"), manta::IoError);
    fs::remove_all(dir);
}

// ------------------------------------------------------------------------------------ planforms

LiftingSurface trapezoid(double cr, double ct, double semi, double le_sweep,
                         double dihedral = 0.0) {
    LiftingSurface w;
    w.name = "wing";
    SurfaceSection root, tip;
    root.chord = cr;
    tip.chord = ct;
    tip.leading_edge = {semi * std::tan(le_sweep), semi, semi * std::tan(dihedral)};
    w.sections = {root, tip};
    return w;
}

TEST(Planform, TrapezoidAgainstClosedForms) {
    // Ranger 2000 wing: S = 15.5 m^2, b = 10.46 m, taper 0.519 (Table 1).
    const double b = 10.46, lam = 0.519, cr = 2 * 15.5 / (b * (1 + lam)), ct = lam * cr;
    const double sweep = 0.1;
    const LiftingSurface w = trapezoid(cr, ct, b / 2, sweep, 3 * pi / 180);
    EXPECT_NEAR(w.planform_area(), 15.5, 1e-12);
    EXPECT_NEAR(w.span(), b, 1e-12);
    EXPECT_NEAR(w.semi_span(), b / 2, 1e-12);
    EXPECT_NEAR(w.taper_ratio(), lam, 1e-12);
    EXPECT_NEAR(w.aspect_ratio(), b * b / 15.5, 1e-12);
    // MAC = 2/3 c_r (1 + l + l^2) / (1 + l); its station y = b/6 (1 + 2 l) / (1 + l).
    const double mac = 2.0 / 3.0 * cr * (1 + lam + lam * lam) / (1 + lam);
    const double ybar = b / 6 * (1 + 2 * lam) / (1 + lam);
    EXPECT_NEAR(w.mean_aerodynamic_chord(), mac, 1e-12);
    const Eigen::Vector3d le = w.mac_leading_edge();
    EXPECT_NEAR(le.y(), ybar, 1e-12);
    EXPECT_NEAR(le.x(), ybar * std::tan(sweep), 1e-12);
    EXPECT_NEAR(le.z(), ybar * std::tan(3 * pi / 180), 1e-12);
    EXPECT_NEAR(w.chord_at(le.y() / (b / 2)), mac,
                1e-12);  // straight taper: the MAC is the chord at ybar
    EXPECT_NEAR(w.leading_edge_sweep(0), sweep, 1e-12);
    EXPECT_NEAR(w.dihedral(0), 3 * pi / 180, 1e-12);
    EXPECT_NEAR(w.chord_at(0.5), 0.5 * (cr + ct), 1e-12);
    EXPECT_NEAR(w.leading_edge_at(1.0).y(), b / 2, 1e-12);
    EXPECT_NEAR(w.eta_of(b / 4), 0.5, 1e-12);
}

TEST(Planform, CrankedWingIsTheAreaWeightedSumOfItsPanels) {
    LiftingSurface w = trapezoid(3.0, 2.0, 2.0, 0.3);
    SurfaceSection tip;
    tip.chord = 0.8;
    tip.leading_edge = {2.0 * std::tan(0.3) + 3.0 * std::tan(0.5), 5.0, 0.0};
    w.sections.push_back(tip);
    const LiftingSurface inner = trapezoid(3.0, 2.0, 2.0, 0.3);
    LiftingSurface outer = trapezoid(2.0, 0.8, 3.0, 0.5);
    const double s1 = inner.planform_area(), s2 = outer.planform_area();
    EXPECT_NEAR(w.planform_area(), s1 + s2, 1e-12);
    EXPECT_NEAR(
        w.mean_aerodynamic_chord(),
        (s1 * inner.mean_aerodynamic_chord() + s2 * outer.mean_aerodynamic_chord()) / (s1 + s2),
        1e-12);
    const double x2 = outer.mac_leading_edge().x() + w.sections[1].leading_edge.x();
    EXPECT_NEAR(w.mac_leading_edge().x(), (s1 * inner.mac_leading_edge().x() + s2 * x2) / (s1 + s2),
                1e-12);
    EXPECT_NEAR(w.span(), 10.0, 1e-12);
    EXPECT_NEAR(w.taper_ratio(), 0.8 / 3.0, 1e-12);
    EXPECT_NEAR(w.leading_edge_sweep(1), 0.5, 1e-12);
    EXPECT_NEAR(w.chord_at(0.4), 2.0, 1e-12);
    EXPECT_NEAR(w.chord_at(0.7), 2.0 + (0.8 - 2.0) * 0.5, 1e-12);
}

TEST(Planform, FinUsesHeight) {
    LiftingSurface f;
    f.name = "fin";
    f.vertical = true;
    f.symmetric = false;
    SurfaceSection r, t;
    r.chord = 2.0;
    r.leading_edge = {7.0, 0.0, 0.5};
    t.chord = 1.0;
    t.leading_edge = {8.0, 0.0, 2.0};
    f.sections = {r, t};
    EXPECT_NEAR(f.planform_area(), 1.5 * 1.5, 1e-12);
    EXPECT_NEAR(f.span(), 1.5, 1e-12);
    EXPECT_NEAR(f.aspect_ratio(), 1.5 * 1.5 / 2.25, 1e-12);
    EXPECT_NEAR(f.leading_edge_sweep(0), std::atan2(1.0, 1.5), 1e-12);
    EXPECT_DOUBLE_EQ(f.dihedral(0), 0.0);
    EXPECT_NEAR(f.mac_leading_edge().z(), 0.5 + 1.5 / 3 * (1 + 2 * 0.5) / 1.5, 1e-12);
    // Twin fins: two copies, aspect ratio per fin unchanged.
    f.symmetric = true;
    EXPECT_NEAR(f.planform_area(), 4.5, 1e-12);
    EXPECT_NEAR(f.aspect_ratio(), 1.0, 1e-12);
}

TEST(Planform, FuselageVolume) {
    Fuselage f;
    f.stations = {{0.0, 1.0, 2.0, 0.0}, {4.0, 1.0, 2.0, 0.0}};
    EXPECT_NEAR(f.volume(), pi / 4 * 2.0 * 4.0, 1e-12);
    EXPECT_NEAR(f.length(), 4.0, 1e-15);
    EXPECT_DOUBLE_EQ(f.max_width(), 1.0);
    EXPECT_DOUBLE_EQ(f.max_height(), 2.0);
    EXPECT_DOUBLE_EQ(Fuselage{}.length(), 0.0);
}

TEST(Planform, ControlSurfaceAreaAndHinge) {
    AircraftGeometry g;
    g.length = 10;
    g.surfaces.push_back(trapezoid(2.0, 1.0, 5.0, 0.0));
    ControlSurface a;
    a.name = "aileron";
    a.surface = "wing";
    a.span_fraction = {0.6, 1.0};
    a.hinge_chord_fraction = 0.75;
    a.gain = -1.0;
    a.mirror_gain = 1.0;
    // Chord from 1.4 to 1.0 over 2 m; aft 25 %; two sides.
    EXPECT_NEAR(g.control_surface_area(a), 2 * 0.25 * 2.0 * 1.2, 1e-12);
    const auto h = g.hinge_line(a);
    EXPECT_NEAR(h[0].x(), 0.75 * 1.4, 1e-12);
    EXPECT_NEAR(h[0].y(), 3.0, 1e-12);
    EXPECT_NEAR(h[1].x(), 0.75, 1e-12);
    EXPECT_DOUBLE_EQ(a.deflection(0.1), -0.1);
    EXPECT_DOUBLE_EQ(a.deflection(0.1, true), 0.1);
    EXPECT_EQ(to_string(Control::rudder), "rudder");
    EXPECT_EQ(g.find_control_surface("x"), nullptr);
    expect_parts(error_of<manta::InputError>([&] { (void)g.surface("tail"); }),
                 {"no lifting surface named 'tail'", "wing"});
}

// ------------------------------------------------------------------------------------ parsing

const char* const valid_geometry = R"(length: 10.0
height: 3.0
lifting_surfaces:
  - name: wing
    sections:
      - leading_edge: [4.0, 0.0, 0.0]
        chord: 2.0
        twist_deg: 2
        airfoil: NACA 64-215
      - leading_edge: [4.5, 5.0, 0.2]
        chord: 1.0
        airfoil: NACA 2412
  - name: fin
    vertical: true
    sections:
      - leading_edge: [8.0, 0.0, 0.5]
        chord: 1.5
        airfoil: NACA 0010
      - leading_edge: [8.8, 0.0, 2.0]
        chord: 1.0
        airfoil: NACA 0010
fuselage:
  x: [0, 5, 10]
  width: [0, 1.2, 0.3]
  height: [0, 1.4, 0.3]
  z_centre: [0, 0.1, 0.2]
control_surfaces:
  - name: aileron
    surface: wing
    span_fraction: [0.6, 0.9]
    hinge_chord_fraction: 0.75
    gain_right: -1
    gain_left: 1
  - name: rudder
    surface: fin
    span_position: [0.65, 1.85]
    hinge_chord_fraction: 0.7
    limits_deg: [-20, 20]
  - name: spoiler
    surface: wing
    span_fraction: [0.2, 0.5]
    hinge_chord_fraction: 0.6
)";

AircraftGeometry parse(const std::string& text, const fs::path& base = ".") {
    manta::core::ConfigMap m(manta::core::ConfigNode::parse_string(text, "g.yaml"));
    return parse_geometry(m, base);
}

std::string config_error(const std::string& text, const fs::path& base = ".") {
    return error_of<manta::ConfigError>([&] { (void)parse(text, base); });
}

/// valid_geometry with `from` replaced by `to` (which must occur).
std::string edited(const std::string& from, const std::string& to) {
    std::string s = valid_geometry;
    const auto p = s.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    return s.replace(p, from.size(), to);
}

TEST(ParseGeometry, ValidExample) {
    const AircraftGeometry g = parse(valid_geometry);
    ASSERT_EQ(g.surfaces.size(), 2u);
    const auto& w = g.surface("wing");
    EXPECT_TRUE(w.symmetric);
    EXPECT_FALSE(w.vertical);
    EXPECT_NEAR(w.sections[0].twist, 2 * pi / 180, 1e-15);
    EXPECT_DOUBLE_EQ(w.sections[1].twist, 0.0);
    EXPECT_EQ(w.sections[0].airfoil.designation().text, "NACA 64-215");
    EXPECT_NEAR(w.planform_area(), 15.0, 1e-12);
    const auto& f = g.surface("fin");
    EXPECT_TRUE(f.vertical);
    EXPECT_FALSE(f.symmetric);  // fins default to one copy
    EXPECT_EQ(g.fuselage.stations.size(), 3u);
    ASSERT_EQ(g.control_surfaces.size(), 3u);
    const auto& a = *g.find_control_surface("aileron");
    EXPECT_EQ(a.control, Control::aileron);
    EXPECT_DOUBLE_EQ(a.gain, -1.0);
    EXPECT_DOUBLE_EQ(a.mirror_gain, 1.0);
    const auto& r = *g.find_control_surface("rudder");
    EXPECT_EQ(r.control, Control::rudder);
    EXPECT_NEAR(r.span_fraction[0], 0.1, 1e-12);
    EXPECT_NEAR(r.span_fraction[1], 0.9, 1e-12);
    ASSERT_TRUE(r.limits.has_value());
    EXPECT_NEAR((*r.limits)[1], 20 * pi / 180, 1e-15);
    EXPECT_EQ(g.find_control_surface("spoiler")->control, Control::none);  // user name: not driven
}

TEST(ParseGeometry, AirfoilFileRelativeToBaseDir) {
    const fs::path dir = scratch("base");
    fs::create_directories(dir / "airfoils");
    write(dir / "airfoils" / "root.dat",
          selig_text(Airfoil::naca("NACA 4412").coordinates(41), "root"));
    const AircraftGeometry g =
        parse(edited("airfoil: NACA 64-215", "airfoil_file: airfoils/root.dat"), dir);
    EXPECT_EQ(g.surface("wing").sections[0].airfoil.name(), "root");
    EXPECT_NEAR(g.surface("wing").sections[0].airfoil.thickness_ratio(), 0.12, 2e-3);
    // A broken file is reported with the YAML key that names it and the line in the file.
    write(dir / "airfoils" / "bad.dat", "bad\n1 0\n0.5 x\n");
    const auto msg =
        config_error(edited("airfoil: NACA 64-215", "airfoil_file: airfoils/bad.dat"), dir);
    expect_parts(msg, {"g.yaml:9", "lifting_surfaces[0].sections[0].airfoil_file",
                       "airfoils/bad.dat", "bad.dat:3", "not a coordinate pair"});
    const auto missing =
        config_error(edited("airfoil: NACA 64-215", "airfoil_file: airfoils/none.dat"), dir);
    expect_parts(missing, {"g.yaml:9", "airfoil_file", "none.dat", "cannot open"});
    fs::remove_all(dir);
}

TEST(ParseGeometryErrors, InvalidNacaDesignation) {
    const auto msg = config_error(edited("NACA 64-215", "NACA 64-2x5"));
    expect_parts(msg, {"g.yaml:9", "lifting_surfaces[0].sections[0].airfoil", "value 'NACA 64-2x5'",
                       "is not a valid NACA designation", "expected a NACA designation such as"});
}

TEST(ParseGeometryErrors, AirfoilMissingOrTwice) {
    expect_parts(config_error(edited("        airfoil: NACA 2412\n", "")),
                 {"g.yaml:10", "missing required key 'lifting_surfaces[0].sections[1].airfoil'",
                  "airfoil_file"});
    expect_parts(config_error(edited("airfoil: NACA 2412",
                                     "airfoil: NACA 2412\n        airfoil_file: x.dat")),
                 {"g.yaml:13", "airfoil_file", "duplicates 'airfoil'", "not both"});
}

TEST(ParseGeometryErrors, Sections) {
    expect_parts(
        config_error(edited("[4.5, 5.0, 0.2]", "[4.5, 0.0, 0.2]")),
        {"g.yaml:10", "lifting_surfaces[0].sections[1].leading_edge", "has y = 0",
         "not beyond the previous section's y = 0", "root to tip with y strictly increasing"});
    expect_parts(config_error(edited("[4.0, 0.0, 0.0]", "[4.0, -1.0, 0.0]")),
                 {"g.yaml:6", "sections[0].leading_edge", "y = -1 < 0", "mirrored about y = 0"});
    expect_parts(config_error(edited("[8.8, 0.0, 2.0]\n        chord: 1.0",
                                     "[9.8, 0.0, 2.0]\n        chord: 1.0")),
                 {"g.yaml:19", "lifting_surfaces[1].sections[1].leading_edge",
                  "from x = 9.8 to 10.8", "outside the aircraft length", "within [0, 10] m"});
    expect_parts(
        config_error(edited(R"(      - leading_edge: [4.5, 5.0, 0.2]
        chord: 1.0
        airfoil: NACA 2412
)",
                            "")),
        {"g.yaml:5", "lifting_surfaces[0].sections", "has 1 entry", "at least 2 sections"});
    expect_parts(config_error(edited("chord: 2.0", "chord: 0")),
                 {"g.yaml:7", "sections[0].chord", "value '0'", "is out of range", "(0, 100] [m]"});
    expect_parts(config_error(edited("twist_deg: 2", "twist_deg: 40")),
                 {"g.yaml:8", "twist_deg", "value '40'", "a number in [-30, 30] [deg]"});
    expect_parts(config_error(edited("twist_deg: 2", "twist: 2\n        twist_deg: 2")),
                 {"twist_deg", "duplicates 'twist'"});
    expect_parts(config_error(edited("chord: 2.0", "chord: 2.0\n        chord_ft: 6.5")),
                 {"g.yaml:8", "unknown key 'chord_ft'", "MANTA reads 'chord' in SI units"});
}

TEST(ParseGeometryErrors, DuplicateSurfaceName) {
    expect_parts(config_error(edited("name: fin", "name: wing")),
                 {"g.yaml:13", "lifting_surfaces[1].name", "value 'wing'",
                  "is used by an earlier lifting surface"});
}

TEST(ParseGeometryErrors, Fuselage) {
    expect_parts(config_error(edited("width: [0, 1.2, 0.3]", "width: [0, 1.2]")),
                 {"g.yaml:24", "fuselage.width", "has 2 entries", "a list of 3 numbers"});
    expect_parts(config_error(edited("x: [0, 5, 10]", "x: [0, 5, 5]")),
                 {"fuselage.x[2]", "value '5'", "is not beyond the previous station",
                  "strictly increasing"});
    expect_parts(config_error(edited("x: [0, 5, 10]", "x: [0, 5, 12]")),
                 {"fuselage.x[2]", "value '12'", "outside the aircraft length"});
    expect_parts(config_error(edited("height: [0, 1.4, 0.3]", "height: [0, -1.4, 0.3]")),
                 {"fuselage.height[1]", "value '-1.4'", "[0, 100] [m]"});
}

TEST(ParseGeometryErrors, ControlSurfaces) {
    expect_parts(config_error(edited("surface: wing\n    span_fraction: [0.6",
                                     "surface: wnig\n    span_fraction: [0.6")),
                 {"g.yaml:29", "control_surfaces[0].surface", "value 'wnig'",
                  "is not a lifting surface", "did you mean 'wing'?"});
    expect_parts(
        config_error(edited("[0.6, 0.9]", "[0.9, 0.6]")),
        {"control_surfaces[0].span_fraction", "inboard end not inboard", "inboard < outboard"});
    expect_parts(config_error(edited("[0.6, 0.9]", "[0.6, 1.2]")),
                 {"control_surfaces[0].span_fraction[1]", "value '1.2'", "a number in [0, 1]"});
    expect_parts(
        config_error(edited("span_position: [0.65, 1.85]", "span_position: [0.65, 2.5]")),
        {"control_surfaces[1].span_position[1]", "value '2.5'", "a number in [0.5, 2] [m]"});
    expect_parts(config_error(edited("hinge_chord_fraction: 0.75", "hinge_chord_fraction: 1")),
                 {"control_surfaces[0].hinge_chord_fraction", "value '1'", "a number in (0, 1)"});
    expect_parts(
        config_error(edited("span_position: [0.65, 1.85]",
                            "span_position: [0.65, 1.85]\n    gain_right: 1")),
        {"g.yaml:37", "control_surfaces[1].gain_right", "applies to symmetric surfaces only",
         "'gain' for the one copy of surface 'fin'"});
    expect_parts(config_error(edited("gain_right: -1", "gain: -1")),
                 {"control_surfaces[0].gain", "applies to non-symmetric surfaces only",
                  "'gain_right' and 'gain_left'"});
    expect_parts(config_error(edited("    span_fraction: [0.2, 0.5]\n", "")),
                 {"control_surfaces[2]", "missing required key 'control_surfaces[2].span_fraction'",
                  "span_position"});
    expect_parts(config_error(edited("limits_deg: [-20, 20]", "limits_deg: [20, -20]")),
                 {"limits_deg", "lower bound above its upper bound"});
    expect_parts(config_error(edited("limits_deg: [-20, 20]", "limits_deg: [5, 5]")),
                 {"limits_deg", "equal bounds"});
    expect_parts(config_error(edited("name: spoiler", "name: rudder")),
                 {"control_surfaces[2].name", "is used by an earlier control surface"});
    expect_parts(
        config_error(edited("    hinge_chord_fraction: 0.6\n",
                            "    hinge_chord_fraction: 0.6\n    control: flap\n")),
        {"control_surfaces[2].control", "value 'flap'", "one of none, elevator, aileron, rudder"});
}

TEST(ParseGeometryErrors, UnknownAndMissingKeys) {
    expect_parts(config_error(std::string(valid_geometry) + "fuselaje: {}\n"),
                 {"unknown key 'fuselaje'", "did you mean 'fuselage'?"});
    expect_parts(config_error(edited("length: 10.0\n", "")),
                 {"g.yaml:1", "missing required key 'length'"});
    expect_parts(config_error(edited("length: 10.0", "length: 10 m")),
                 {"key 'length'", "carries a unit in the value"});
}

}  // namespace
