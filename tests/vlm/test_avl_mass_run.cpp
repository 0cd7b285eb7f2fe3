// Readers of AVL's mass (.mass) and run-case (.run) files, the choice of the moment reference
// point and the solution of a run case's constraints (issue 16, "AVL users' files"). The sample
// files are AVL 3.40's own (../shared/reference/avl/samples); the values they must give are the
// ones AVL printed when it read them (results/b737_dp.out.txt, results/supra_sp.out.txt) and
// those it wrote into b737.run from b737.mass.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/vlm/avl_mass.hpp"
#include "manta/vlm/avl_reader.hpp"
#include "manta/vlm/avl_run.hpp"
#include "manta/vlm/steady.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta::vlm;
constexpr double deg = std::numbers::pi / 180.0;

const fs::path samples = fs::path(MANTA_SHARED_DIR) / "reference" / "avl" / "samples";

#define REQUIRE_SAMPLES() \
    if (!fs::is_directory(samples)) GTEST_SKIP() << "no AVL samples at " << samples

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
    for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

std::string mass_error(const std::string& text) {
    try {
        (void)parse_avl_mass(text, "test.mass");
    } catch (const manta::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return {};
}

std::string run_error(const std::string& text) {
    try {
        (void)parse_avl_run(text, "test.run");
    } catch (const manta::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return {};
}

double rel(double a, double b) {
    return std::abs(a - b) / std::abs(b);
}

// ----------------------------------------------------------------------------- mass file

// b737.mass against what AVL wrote from it into b737.run (6 digits): mass 77146.0 kg, CG
// 65.2686 0 1.16559 Lunit, Ixx 706684, Iyy 0.270824E+07, Izz 0.330763E+07, Izx 26994.4 kg m^2.
// The file uses a multiplier line of 1.25 on every column (positions too), resets it to 1 and
// adds 14 to x of the last item: all of that is in these numbers.
TEST(AvlMass, B737AsAvlReadsIt) {
    REQUIRE_SAMPLES();
    const AvlMass m = read_avl_mass(samples / "b737.mass");
    EXPECT_EQ(m.items, 11);
    EXPECT_DOUBLE_EQ(m.length_unit, 0.3048);
    EXPECT_EQ(m.length_unit_name, "m");
    EXPECT_DOUBLE_EQ(m.mass_unit, 0.4535);
    EXPECT_EQ(m.mass_unit_name, "kg");
    EXPECT_DOUBLE_EQ(m.time_unit, 1.0);
    EXPECT_DOUBLE_EQ(*m.gravity, 9.81);
    EXPECT_DOUBLE_EQ(*m.density, 0.38);
    EXPECT_LT(rel(m.dimensional_mass(), 77146.0), 1e-5);
    EXPECT_LT(rel(m.cg.x(), 65.2686), 1e-5);
    EXPECT_NEAR(m.cg.y(), 0.0, 1e-12);
    EXPECT_LT(rel(m.cg.z(), 1.16559), 1e-5);
    const Eigen::Matrix3d J = m.dimensional_inertia();
    EXPECT_LT(rel(J(0, 0), 706684.0), 1e-5);
    EXPECT_LT(rel(J(1, 1), 0.270824e7), 1e-5);
    EXPECT_LT(rel(J(2, 2), 0.330763e7), 1e-5);
    EXPECT_LT(rel(J(0, 2), 26994.4), 1e-5);
    EXPECT_DOUBLE_EQ(J(0, 2), J(2, 0));
    EXPECT_NEAR(J(0, 1), 0.0, 1e-6);
    EXPECT_NEAR(J(1, 2), 0.0, 1e-6);
}

// supra.mass against AVL's print-out when it read the file (results/supra_sp.out.txt):
// "Mass = 1358. Munit", "C.G. x,y,z = 3.750 0.000 1.604 Lunit", inertias (kg m^2)
// Ixx 0.4858, -Ixy -0.9703E-04, -Ixz -0.3206E-02, Iyy 0.1008, Izz 0.5829 (4 digits).
TEST(AvlMass, SupraAsAvlPrintsIt) {
    REQUIRE_SAMPLES();
    const AvlMass m = read_avl_mass(samples / "supra.mass");
    EXPECT_EQ(m.items, 51);
    EXPECT_NEAR(m.mass, 1358.0, 0.5);
    EXPECT_NEAR(m.dimensional_mass(), 1.358, 5e-4);
    EXPECT_NEAR(m.cg.x(), 3.750, 5e-4);
    EXPECT_NEAR(m.cg.y(), 0.000, 5e-4);
    EXPECT_NEAR(m.cg.z(), 1.604, 5e-4);
    const Eigen::Matrix3d J = m.dimensional_inertia();
    EXPECT_LT(rel(J(0, 0), 0.4858), 2e-4);
    EXPECT_LT(rel(J(0, 1), -0.9703e-4), 2e-3);
    EXPECT_LT(rel(J(0, 2), -0.3206e-2), 2e-4);
    EXPECT_LT(rel(J(1, 1), 0.1008), 5e-4);
    EXPECT_LT(rel(J(2, 2), 0.5829), 2e-4);
}

TEST(AvlMass, MultipliersAddersAndDefaults) {
    // No unit lines: 1 and AVL's names. Item 1 at x = 2 * 1 + 0.5 with mass 2 * 1; the partial
    // multiplier line leaves the other columns at 1; the second '*' resets the mass column only,
    // the adder stays.
    const AvlMass m = parse_avl_mass(
        "# comment\n* 2 2\n+ 0 0.5\n1 1 0 0 ! item 1\n* 1\n1 1 0 0 3 4 5\n", "test.mass");
    EXPECT_EQ(m.items, 2);
    EXPECT_DOUBLE_EQ(m.length_unit, 1.0);
    EXPECT_EQ(m.length_unit_name, "Lunit");
    EXPECT_FALSE(m.gravity.has_value());
    EXPECT_DOUBLE_EQ(m.mass, 3.0);  // 2 + 1
    // x: item 1 at 2 * 1 + 0.5 = 2.5, item 2 at 2 * 1 + 0.5 = 2.5.
    EXPECT_DOUBLE_EQ(m.cg.x(), 2.5);
    // Own inertias only (both items at the same point), scaled by the multipliers of 1.
    EXPECT_DOUBLE_EQ(m.inertia(0, 0), 3.0);
    EXPECT_DOUBLE_EQ(m.inertia(1, 1), 4.0);
    EXPECT_DOUBLE_EQ(m.inertia(2, 2), 5.0);
    // Parallel axes: two unit masses 2 apart in y about their midpoint: Ixx = Izz = 2, and a
    // product -sum m x y.
    const AvlMass p = parse_avl_mass("Lunit = 0.01 m\n1 1 1 0\n1 -1 -1 0\n", "p.mass");
    EXPECT_DOUBLE_EQ(p.length_unit, 0.01);
    EXPECT_TRUE(p.cg.isZero());
    EXPECT_DOUBLE_EQ(p.inertia(0, 0), 2.0);
    EXPECT_DOUBLE_EQ(p.inertia(1, 1), 2.0);
    EXPECT_DOUBLE_EQ(p.inertia(2, 2), 4.0);
    EXPECT_DOUBLE_EQ(p.inertia(0, 1), -2.0);
}

// Found by fuzz_avl: the products sum m x_i x_j - M x_cg,i x_cg,j must give the same bits above
// and below the diagonal (an inertia tensor that is not exactly symmetric).
TEST(AvlMass, InertiaTensorIsExactlySymmetric) {
    const AvlMass m = parse_avl_mass(
        "Lunit = 0.01 m\n* 2 2\n+ 0 0.5\n1 1 0 0 ! item\n13 -1 -1 0 3 4 5 0.1 0.2 0.3\n"
        "0.7 0.31 -2.9 1.3\n",
        "fuzz.mass");
    EXPECT_TRUE(m.inertia.isApprox(m.inertia.transpose(), 0.0));
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.inertia(i, k), m.inertia(k, i));
}

TEST(AvlMass, MalformedLines) {
    expect_parts(mass_error("Xunit = 1 m\n1 0 0 0\n"),
                 {"test.mass:1: unknown parameter 'Xunit'", "Lunit, Munit, Tunit, g or rho"});
    expect_parts(mass_error("Lunit = nan m\n1 0 0 0\n"),
                 {"test.mass:1: Lunit: 'nan' is not a finite number"});
    expect_parts(mass_error("Lunit = -1 m\n1 0 0 0\n"), {"test.mass:1: Lunit = -1", "positive"});
    expect_parts(mass_error("g =\n1 0 0 0\n"), {"test.mass:1: g: no value"});
    expect_parts(mass_error("rho = dense\n1 0 0 0\n"),
                 {"test.mass:1: rho: 'dense' is not a number"});
    expect_parts(mass_error("1 2 abc 4\n"), {"test.mass:1: 'abc' is not a number", "mass x y z"});
    expect_parts(mass_error("1 2 3\n"), {"test.mass:1: 3 numbers in '1 2 3'", "mass x y z"});
    expect_parts(mass_error("1 2 3 4 5 6 7 8 9 10 11\n"), {"test.mass:1: 11 numbers"});
    expect_parts(mass_error("\n\nnan 0 0 0\n"), {"test.mass:3: 'nan' is not a finite number"});
    expect_parts(mass_error("1 0 inf 0\n"), {"test.mass:1: 'inf' is not a finite number"});
    expect_parts(mass_error("1 0 0 1e999\n"), {"test.mass:1: '1e999' is not a finite number"});
    expect_parts(mass_error("1e300 0 0 0\n"), {"test.mass:1: mass = 1e+300", "magnitude"});
    expect_parts(mass_error("1 0 -1e300 0\n"), {"test.mass:1: y = -1e+300"});
    expect_parts(mass_error("* 1 nan\n1 0 0 0\n"), {"test.mass:1: 'nan' is not a finite number"});
    expect_parts(mass_error("* 1 1e300\n1 0 0 0\n"), {"test.mass:1: multiplier of x = 1e+300"});
    expect_parts(mass_error("+\n1 0 0 0\n"), {"test.mass:1: 0 adders"});
    expect_parts(mass_error("* 1e6\n+ 0 1e6\n1 1 0 0\n"), {"test.mass:3: x = 1e+06"});
    expect_parts(mass_error("1 0 0 0\n-1 0 0 0\n"), {"test.mass:2: the total mass", "positive"});
    expect_parts(mass_error("# nothing\n"), {"test.mass:1: no mass items"});
    EXPECT_THROW((void)read_avl_mass("/nonexistent/x.mass"), manta::IoError);
}

// --------------------------------------------------------------------------- run file

TEST(AvlRun, B737) {
    REQUIRE_SAMPLES();
    const auto cases = read_avl_run(samples / "b737.run");
    ASSERT_EQ(cases.size(), 1u);
    const RunCase& c = cases[0];
    EXPECT_EQ(c.number, 1);
    EXPECT_EQ(c.name, "-unnamed-");
    ASSERT_EQ(c.constraints.size(), 10u);
    EXPECT_EQ(c.constraints[0].variable, "alpha");
    EXPECT_EQ(c.constraints[0].constraint, "CL");
    EXPECT_DOUBLE_EQ(c.constraints[0].value, 0.544438);
    EXPECT_EQ(c.constraints[8].variable, "elevator");
    EXPECT_EQ(c.constraints[8].constraint, "Cm");
    EXPECT_EQ(c.constraints[9].constraint, "rudder");
    EXPECT_EQ(c.parameters.size(), 30u);
    EXPECT_DOUBLE_EQ(*c.parameter("Mach"), 0.7);
    EXPECT_DOUBLE_EQ(*c.parameter("X_cg"), 65.2686);
    EXPECT_DOUBLE_EQ(*c.parameter("Z_cg"), 1.16559);
    EXPECT_DOUBLE_EQ(*c.parameter("visc CM_u"), 0.0);
    EXPECT_DOUBLE_EQ(*c.parameter("Iyy"), 0.270824e7);
    EXPECT_EQ(c.where("X_cg"), (samples / "b737.run").string() + ":32");
}

TEST(AvlRun, SupraFiveCasesAndVanillaWithNulPadding) {
    REQUIRE_SAMPLES();
    const auto supra = read_avl_run(samples / "supra.run");
    ASSERT_EQ(supra.size(), 5u);
    EXPECT_EQ(supra[2].number, 3);
    EXPECT_EQ(supra[2].name, "0 deg bank");
    EXPECT_DOUBLE_EQ(supra[2].constraints.at(0).value, 0.35);
    EXPECT_EQ(supra[0].constraints.at(6).constraint, "Cl");
    EXPECT_EQ(supra[0].constraints.at(8).constraint, "Cn");
    EXPECT_DOUBLE_EQ(*supra[0].parameter("CDo"), 0.015);
    EXPECT_EQ(&find_run_case(supra, 4, "supra.run"), &supra[3]);
    expect_parts(
        [&] {
            try {
                (void)find_run_case(supra, 7, "supra.run");
            } catch (const manta::InputError& e) {
                return std::string(e.what());
            }
            return std::string();
        }(),
        {"supra.run: no run case 7", "1, 2, 3, 4, 5"});
    const auto vanilla = read_avl_run(samples / "vanilla.run");
    ASSERT_GE(vanilla.size(), 2u);
    EXPECT_DOUBLE_EQ(*vanilla[1].parameter("beta"), 5.0);
    EXPECT_EQ(read_avl_run(samples / "square.run").size(), 1u);
}

const std::string case_head = " ---------\n Run case  1:  test\n";  // lines 1 and 2

TEST(AvlRun, MalformedLines) {
    expect_parts(run_error(case_head + " alpha -> Cq pitch = 1\n"),
                 {"test.run:3: constraint 'Cq pitch' of variable 'alpha'", "Cm pitchmom"});
    expect_parts(run_error(case_head + " Cm pitchmom -> CL = 1\n"),
                 {"test.run:3: variable 'Cm pitchmom'", "control name"});
    expect_parts(run_error(case_head + " alpha -> CL = 0.5\n beta -> CL = 0.1\n"),
                 {"test.run:4: constraint 'CL' is used again (first at line 3"});
    expect_parts(run_error(case_head + " alpha -> CL = 0.5\n alpha -> alpha = 1\n"),
                 {"test.run:4: variable 'alpha' is constrained again"});
    expect_parts(run_error(case_head + " alpha -> CL = nan\n"),
                 {"test.run:3: alpha -> CL: 'nan' is not a finite number"});
    expect_parts(run_error(case_head + " elevator -> Cm pitchmom = -inf\n"),
                 {"test.run:3: elevator -> Cm pitchmom: '-inf' is not a finite number"});
    expect_parts(run_error(case_head + " alpha -> alpha = 1e300\n"),
                 {"test.run:3: alpha -> alpha = 1e+300", "[-90, 90]"});
    expect_parts(run_error(case_head + " flap -> flap = 200\n"),
                 {"test.run:3: flap -> flap = 200"});
    expect_parts(run_error(case_head + " alpha -> CL\n"), {"test.run:3:", "no '=' after '->'"});
    expect_parts(run_error(case_head + " alpha -> CL = high\n"),
                 {"test.run:3: alpha -> CL: 'high' is not a number"});
    expect_parts(run_error(case_head + " speed = 3 m/s\n"),
                 {"test.run:3: unknown parameter 'speed'", "velocity"});
    expect_parts(run_error(case_head + " Mach = 0.97\n"), {"test.run:3: Mach = 0.97", "0.95)"});
    expect_parts(run_error(case_head + " X_cg = inf Lunit\n"),
                 {"test.run:3: X_cg: 'inf' is not a finite number"});
    expect_parts(run_error(case_head + " X_cg = 1e300 Lunit\n"), {"test.run:3: X_cg = 1e+300"});
    expect_parts(run_error(case_head + " mass = -5 kg\n"), {"test.run:3: mass = -5"});
    expect_parts(run_error(case_head + " X_cg = 1\n X_cg = 2\n"),
                 {"test.run:4: parameter 'X_cg' again"});
    expect_parts(run_error(case_head + " hello\n"), {"test.run:3: 'hello' is not a run-case line"});
    expect_parts(run_error(" alpha -> CL = 0.5\n"), {"test.run:1: expected 'Run case N: name'"});
    expect_parts(run_error(" Run case x: foo\n"), {"test.run:1: run case number 'x'"});
    expect_parts(run_error(" Run case 2 foo\n"), {"test.run:1:", "no ':'"});
    expect_parts(run_error(case_head + " Run case 1: again\n"), {"test.run:3: run case 1 again"});
    expect_parts(run_error(" ------\n\n"), {"test.run:1: no run case in the file"});
    EXPECT_THROW((void)read_avl_run("/nonexistent/x.run"), manta::IoError);
}

// ------------------------------------------------------------------ reference point

TEST(AvlRun, ReferencePointPrecedence) {
    Model m;
    m.reference.point = Eigen::Vector3d(1, 2, 3);
    AvlMass mass;
    mass.cg = Eigen::Vector3d(4, 5, 6);
    mass.items = 2;
    mass.source = "a.mass";
    const auto run = parse_avl_run(case_head + " X_cg = 7 Lunit\n Z_cg = 9\n", "a.run").at(0);
    const auto none = parse_avl_run(case_head + " Mach = 0.1\n", "b.run").at(0);

    auto c = choose_reference_point(m, nullptr, nullptr, std::nullopt);
    EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(1, 2, 3)));
    EXPECT_NE(c.from.find(".avl header"), std::string::npos);
    c = choose_reference_point(m, &mass, nullptr, std::nullopt);
    EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(4, 5, 6)));
    EXPECT_NE(c.from.find("a.mass"), std::string::npos);
    // The run case gives X_cg and Z_cg: Y_cg stays the mass file's.
    c = choose_reference_point(m, &mass, &run, std::nullopt);
    EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(7, 5, 9)));
    EXPECT_NE(c.from.find("a.run:3 (run case 1 X_cg Z_cg), the rest from a.mass"),
              std::string::npos)
        << c.from;
    c = choose_reference_point(m, nullptr, &none, std::nullopt);
    EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(1, 2, 3)));
    c = choose_reference_point(m, &mass, &run, Eigen::Vector3d(10, 11, 12));
    EXPECT_TRUE(c.point.isApprox(Eigen::Vector3d(10, 11, 12)));
    EXPECT_EQ(c.from, "--xref");

    Model applied;
    apply_run_case(applied, parse_avl_run(case_head + " Mach = 0.3\n CDo = 0.02\n", "r").at(0));
    EXPECT_DOUBLE_EQ(applied.mach, 0.3);
    EXPECT_DOUBLE_EQ(applied.profile_drag, 0.02);
}

// ------------------------------------------------------------------- run-case solution

/// A wing with ailerons and a tail with elevator and rudder (lines 1 to 5 the header).
const std::string plane =
    "Plane\n0.0\n0 0 0\n12.0 1.0 12.0\n0.3 0 0\n"
    "SURFACE\nWing\n6 1.0 10 1.0\nYDUPLICATE\n0\n"
    "SECTION\n0 0 0 1 2\n"
    "SECTION\n0.1 6 0.3 0.8 0\nCONTROL\naileron 1 0.75 0 0 0 -1\n"
    "SECTION\n0.2 9 0.5 0.6 0\nCONTROL\naileron 1 0.75 0 0 0 -1\n"
    "SURFACE\nStab\n4 1.0 6 1.0\nYDUPLICATE\n0\n"
    "SECTION\n4 0 0.2 0.8 -1\nCONTROL\nelevator 1 0.6 0 1 0 1\n"
    "SECTION\n4.2 2.5 0.2 0.6 -1\nCONTROL\nelevator 1 0.6 0 1 0 1\n"
    "SURFACE\nFin\n4 1.0 5 1.0\n"
    "SECTION\n4 0 0.2 0.9 0\nCONTROL\nrudder 1 0.6 0 0 1 1\n"
    "SECTION\n4.4 0 2.0 0.6 0\nCONTROL\nrudder 1 0.6 0 0 1 1\n";

struct Plane {
    Model model;
    SteadySolver solver;
    Plane()
        : model(parse_avl(plane, "plane.avl", fs::temp_directory_path())),
          solver(model, build_lattice(model), 0.0) {}
};

RunCase one_case(const std::string& lines) {
    return parse_avl_run(case_head + lines, "plane.run").at(0);
}

TEST(AvlRunSolve, TrimToCLWithZeroPitchingMoment) {
    const Plane p;
    const auto sol =
        solve_run_case(p.solver, one_case(" alpha -> CL = 0.5\n elevator -> Cm pitchmom = 0\n"));
    const SteadyResult& r = sol.derivatives.state;
    EXPECT_NEAR(r.CL, 0.5, 1e-9);
    EXPECT_NEAR(r.body.Cm, 0.0, 1e-9);
    EXPECT_GT(sol.state.alpha, 0.0);
    EXPECT_LE(sol.iterations, 6);
    // The state is what solve() gives at it.
    const SteadyResult again = p.solver.solve(sol.state);
    EXPECT_NEAR(again.CL, 0.5, 1e-9);
    EXPECT_NEAR(again.body.Cm, 0.0, 1e-9);
    // Variables without a line are held at zero.
    EXPECT_DOUBLE_EQ(sol.state.beta, 0.0);
    const int ail = p.solver.lattice().control_index("aileron");
    EXPECT_DOUBLE_EQ(sol.state.deflection[ail], 0.0);
}

TEST(AvlRunSolve, DirectValuesInDegreesAndStabilityAxisRates) {
    const Plane p;
    const auto sol = solve_run_case(p.solver, one_case(" alpha -> alpha = 4\n beta -> beta = -2\n"
                                                       " pb/2V -> pb/2V = 0.05\n"
                                                       " rb/2V -> rb/2V = 0.02\n"
                                                       " elevator -> elevator = -3\n"));
    EXPECT_NEAR(sol.state.alpha, 4 * deg, 1e-14);
    EXPECT_NEAR(sol.state.beta, -2 * deg, 1e-14);
    EXPECT_NEAR(sol.state.deflection[p.solver.lattice().control_index("elevator")], -3 * deg,
                1e-14);
    // Body rates from the stability-axis ones: p = p' cos a - r' sin a, r = p' sin a + r' cos a.
    const double a = 4 * deg;
    EXPECT_NEAR(sol.state.p_hat, 0.05 * std::cos(a) - 0.02 * std::sin(a), 1e-14);
    EXPECT_NEAR(sol.state.r_hat, 0.05 * std::sin(a) + 0.02 * std::cos(a), 1e-14);
    EXPECT_EQ(sol.iterations, 0);
}

// Sideslip with the lateral controls trimming the stability-axis rolling and yawing moments to
// given values (vanilla.run case 2 has beta = 5 with aileron -> Cl and rudder -> Cn).
TEST(AvlRunSolve, LateralTrimOnStabilityAxisMoments) {
    const Plane p;
    const auto sol = solve_run_case(p.solver, one_case(" alpha -> CL = 0.6\n beta -> beta = 5\n"
                                                       " aileron -> Cl roll mom = 0.002\n"
                                                       " elevator -> Cm pitchmom = 0\n"
                                                       " rudder -> Cn yaw  mom = -0.001\n"));
    const SteadyResult& r = sol.derivatives.state;
    const double a = sol.state.alpha;
    EXPECT_NEAR(r.CL, 0.6, 1e-9);
    EXPECT_NEAR(r.body.Cl * std::cos(a) + r.body.Cn * std::sin(a), 0.002, 1e-9);
    EXPECT_NEAR(r.body.Cn * std::cos(a) - r.body.Cl * std::sin(a), -0.001, 1e-9);
    EXPECT_NEAR(r.body.Cm, 0.0, 1e-9);
    const auto& L = p.solver.lattice();
    EXPECT_NE(sol.state.deflection[L.control_index("aileron")], 0.0);
    EXPECT_NE(sol.state.deflection[L.control_index("rudder")], 0.0);
    // CY as a constraint: the rudder sets the side force instead.
    const auto cy = solve_run_case(
        p.solver, one_case(" alpha -> alpha = 3\n beta -> beta = 4\n rudder -> CY = 0.01\n"));
    EXPECT_NEAR(cy.derivatives.state.body.CY, 0.01, 1e-9);
}

TEST(AvlRunSolve, Errors) {
    const Plane p;
    const auto input_error = [&](const std::string& lines) {
        try {
            (void)solve_run_case(p.solver, one_case(lines));
        } catch (const manta::InputError& e) {
            return std::string(e.what());
        }
        ADD_FAILURE() << "no InputError for " << lines;
        return std::string();
    };
    expect_parts(input_error(" alpha -> CL = 0.5\n flap -> flap = 5\n"),
                 {"plane.run:4: variable 'flap' of run case 1 is not a control",
                  "aileron, elevator, rudder"});
    expect_parts(input_error(" elevator -> slat = 5\n"),
                 {"plane.run:3: constraint 'slat' of run case 1 is not a control"});
    // A one-word constraint that is not AVL's is taken for a control name.
    expect_parts(input_error(" alpha -> CQ = 1\n"),
                 {"plane.run:3: constraint 'cq'", "Cm pitchmom", "aileron, elevator, rudder"});
    // "aileron -> elevator" leaves the elevator's own default constraint "elevator = 0": two
    // variables on one constraint.
    expect_parts(input_error(" aileron -> elevator = 1\n"),
                 {"plane.run:3: run case 1 constrains", "same quantity"});
    // Alpha cannot set the rolling moment of a symmetric aircraft at zero sideslip.
    try {
        (void)solve_run_case(p.solver, one_case(" alpha -> Cl roll mom = 0.01\n"));
        ADD_FAILURE() << "no ConvergenceError";
    } catch (const manta::ConvergenceError& e) {
        expect_parts(e.what(), {"plane.run:2: run case 1", "singular", "line 3"});
    }
}

}  // namespace
