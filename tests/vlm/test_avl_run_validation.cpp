// AVL's sample aircraft with their mass and run-case files, as `avl b737` reads them (.avl, then
// .mass, then .run) and runs case 1 (OPER, X, ST): the trimmed state and the stability derivatives
// about the run case's X_cg, Y_cg, Z_cg against AVL 3.40's listings in
// ../shared/reference/avl/results (b737_dp.out.txt, supra_sp.out.txt, vanilla_dp.out.txt; the
// numbers are quoted below with the file they come from).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>

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

double rel(double a, double b) {
    return std::abs(a - b) / std::abs(b);
}

/// What `manta vlm --aircraft NAME.avl [--mass NAME.mass] [--run NAME.run --case N]` computes.
struct Sample {
    Model model;
    std::optional<AvlMass> mass;
    std::optional<RunCase> run;
    ReferenceChoice reference;
    double mach = 0.0;
};

Sample load(const std::string& name, bool with_mass, bool with_run, int number = 1) {
    Sample s;
    s.model = read_avl(samples / (name + ".avl"));
    if (with_mass) s.mass = read_avl_mass(samples / (name + ".mass"));
    if (with_run) {
        const auto file = samples / (name + ".run");
        s.run = find_run_case(read_avl_run(file), number, file.string());
        apply_run_case(s.model, *s.run);
    }
    s.reference = choose_reference_point(s.model, s.mass ? &*s.mass : nullptr,
                                         s.run ? &*s.run : nullptr, std::nullopt);
    s.model.reference.point = s.reference.point;
    s.mach = s.model.mach;
    return s;
}

struct Row {
    const char* name;
    double value, avl, tol;
};

void compare(const char* title, const Row* rows, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        const Row& r = rows[i];
        std::printf("%s %-12s %12.6f  AVL %12.6f  diff %+.3f %%\n", title, r.name, r.value, r.avl,
                    100.0 * (r.value - r.avl) / std::abs(r.avl));
        EXPECT_LT(rel(r.value, r.avl), r.tol) << title << " " << r.name;
    }
}

// b737, run case 1 of b737.run: "alpha -> CL = 0.544438", "elevator -> Cm pitchmom = 0", Mach
// 0.70 and X_cg 65.2686, Z_cg 1.16559 from the run case. AVL (results/b737_dp.out.txt): Xref
// 65.269, Zref 1.1656; Alpha 1.91840, elevator 0.89680; CLa 7.299206, Cma -1.884644, CLq
// 22.200703, Cmq -84.906515, Clb -0.276089, Cnb 0.244427, Clp -0.570732, Cnr -0.491477, elevator
// CLd04 0.015022 and Cmd04 -0.071575 per degree, Xnp 68.108784.
TEST(VlmAvlRunValidation, Boeing737RunCase1) {
    REQUIRE_SAMPLES();
    const Sample s = load("b737", true, true);
    EXPECT_NEAR(s.reference.point.x(), 65.2686, 1e-12);
    EXPECT_NEAR(s.reference.point.z(), 1.16559, 1e-12);
    EXPECT_DOUBLE_EQ(s.mach, 0.70);
    const SteadySolver solver(s.model, build_lattice(s.model), s.mach);
    const RunCaseSolution sol = solve_run_case(solver, *s.run);
    const Derivatives& d = sol.derivatives;
    const auto& L = solver.lattice();
    const double elevator = sol.state.deflection[L.control_index("elevator")];
    std::printf(
        "b737 run case 1: %d Newton iterations, residual %.2e, alpha %.5f deg (AVL "
        "1.91840), elevator %.5f deg (AVL 0.89680), CL %.6f, Cm %.2e\n",
        sol.iterations, sol.residual, sol.state.alpha / deg, elevator / deg, d.state.CL,
        d.state.body.Cm);
    EXPECT_NEAR(d.state.CL, 0.544438, 1e-9);
    EXPECT_NEAR(d.state.body.Cm, 0.0, 1e-9);
    EXPECT_NEAR(sol.state.alpha / deg, 1.91840, 0.01);
    EXPECT_NEAR(elevator / deg, 0.89680, 0.02);
    const auto& S = d.stability;
    const auto ctl = [&](const char* c, int row) {
        return d.control(row, L.control_index(c)) * deg;
    };
    const Row rows[] = {{"CLa", S(0, 0), 7.299206, 0.01},
                        {"Cma", S(4, 0), -1.884644, 0.01},
                        {"CLq", S(0, 3), 22.200703, 0.01},
                        {"Cmq", S(4, 3), -84.906515, 0.01},
                        {"Clb", S(3, 1), -0.276089, 0.01},
                        {"Cnb", S(5, 1), 0.244427, 0.01},
                        {"Clp", S(3, 2), -0.570732, 0.01},
                        {"Cnr", S(5, 4), -0.491477, 0.01},
                        {"CLd_elev", ctl("elevator", 0), 0.015022, 0.01},
                        {"Cmd_elev", ctl("elevator", 4), -0.071575, 0.01},
                        {"Xnp", d.x_neutral_point, 68.108784, 0.001}};
    compare("b737", rows, std::size(rows));
}

// The case: b737.avl alone takes its header Xref 60 (Cm_alpha about -5.4 against AVL's
// -1.885); with b737.mass the moment reference is the mass file's centre of gravity (65.27, 0,
// 1.166 Lunit, as AVL prints on reading it) and Cm_alpha at AVL's trimmed state is AVL's.
TEST(VlmAvlRunValidation, Boeing737MassFileMovesTheMomentReference) {
    REQUIRE_SAMPLES();
    FlowState s;
    s.alpha = 1.91840 * deg;
    const auto cm_alpha = [&](const Sample& b) {
        const Lattice lattice = build_lattice(b.model);
        FlowState t = s;
        t.deflection =
            Eigen::VectorXd::Zero(static_cast<Eigen::Index>(lattice.control_names.size()));
        t.deflection[lattice.control_index("elevator")] = 0.89680 * deg;
        const SteadySolver solver(b.model, lattice, 0.70);
        return solver.derivatives(t).stability(4, 0);
    };
    const Sample header_only = load("b737", false, false);
    const Sample with_mass = load("b737", true, false);
    EXPECT_DOUBLE_EQ(header_only.reference.point.x(), 60.0);
    EXPECT_NEAR(with_mass.reference.point.x(), 65.2686, 5e-5);
    EXPECT_NEAR(with_mass.reference.point.z(), 1.16559, 5e-6);
    const double cma_header = cm_alpha(header_only), cma_mass = cm_alpha(with_mass);
    std::printf("b737 Cm_alpha about the .avl Xref %.4f, about the .mass CG %.4f (AVL -1.884644)\n",
                cma_header, cma_mass);
    EXPECT_LT(cma_header, -5.0);
    EXPECT_LT(rel(cma_mass, -1.884644), 0.01);
}

// supra (F3J sailplane with a fuselage BODY), run case 1: "alpha -> CL = 0.7", aileron -> Cl,
// elevator -> Cm, rudder -> Cn, CDo 0.015, Mach 0, X_cg 3.75, Z_cg 0 (the run case's, over the
// mass file's 1.604: AVL prints Xref 3.7500, Zref 0.0000). AVL (results/supra_sp.out.txt): Alpha
// 3.70979, elevator -0.86968, CDvis 0.01500; CLa 5.881248, Cma -0.658372, CLq 7.732920, Cmq
// -16.955267, Clb -0.136906, Cnb 0.048520, Clp -0.653227, Cnr -0.043253, elevator Cmd03
// -0.030407 and CLd03 0.007088 per degree. The fuselage pod is an AVL BODY, which MANTA reads but
// does not represent (docs/vlm.md, Fuselage): its destabilising moments are absent, so Cma is
// about 4 % and Cnb about 2.6 % away from AVL's (checked within 6 % and 4 %); the rest within 1 %.
TEST(VlmAvlRunValidation, SupraRunCase1) {
    REQUIRE_SAMPLES();
    const Sample s = load("supra", true, true);
    EXPECT_NEAR(s.reference.point.x(), 3.75, 1e-12);
    EXPECT_NEAR(s.reference.point.z(), 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(s.model.profile_drag, 0.015);
    const SteadySolver solver(s.model, build_lattice(s.model), s.mach);
    const RunCaseSolution sol = solve_run_case(solver, *s.run);
    const Derivatives& d = sol.derivatives;
    const auto& L = solver.lattice();
    const double elevator = sol.state.deflection[L.control_index("elevator")];
    std::printf(
        "supra run case 1: %d Newton iterations, alpha %.5f deg (AVL 3.70979), elevator "
        "%.5f deg (AVL -0.86968), CL %.6f, CD_profile %.4f\n",
        sol.iterations, sol.state.alpha / deg, elevator / deg, d.state.CL, d.state.CD_profile);
    EXPECT_NEAR(d.state.CL, 0.7, 1e-9);
    EXPECT_NEAR(d.state.body.Cm, 0.0, 1e-9);
    EXPECT_DOUBLE_EQ(d.state.CD_profile, 0.015);
    EXPECT_NEAR(sol.state.alpha / deg, 3.70979, 0.05);
    EXPECT_NEAR(elevator / deg, -0.86968, 0.05);
    const auto& S = d.stability;
    const auto ctl = [&](const char* c, int row) {
        return d.control(row, L.control_index(c)) * deg;
    };
    const Row rows[] = {{"CLa", S(0, 0), 5.881248, 0.01},
                        {"Cma", S(4, 0), -0.658372, 0.06},
                        {"CLq", S(0, 3), 7.732920, 0.01},
                        {"Cmq", S(4, 3), -16.955267, 0.01},
                        {"Clb", S(3, 1), -0.136906, 0.01},
                        {"Cnb", S(5, 1), 0.048520, 0.04},
                        {"Clp", S(3, 2), -0.653227, 0.01},
                        {"Cnr", S(5, 4), -0.043253, 0.01},
                        {"CLd_elev", ctl("elevator", 0), 0.007088, 0.01},
                        {"Cmd_elev", ctl("elevator", 4), -0.030407, 0.01}};
    compare("supra", rows, std::size(rows));
}

// vanilla (no mass file), run case 1: CL 1.16647 with aileron -> Cl, elevator -> Cm, rudder -> Cn
// about X_cg 0.65. AVL (README, "Sample aircraft vanilla"; results/vanilla_dp.out.txt): alpha
// 8.2403, elevator 5.4073; CLa 4.8629, Cma -0.4988.
TEST(VlmAvlRunValidation, VanillaRunCase1) {
    REQUIRE_SAMPLES();
    const Sample s = load("vanilla", false, true);
    EXPECT_NEAR(s.reference.point.x(), 0.65, 1e-12);
    const SteadySolver solver(s.model, build_lattice(s.model), s.mach);
    const RunCaseSolution sol = solve_run_case(solver, *s.run);
    const Derivatives& d = sol.derivatives;
    const double elevator = sol.state.deflection[solver.lattice().control_index("elevator")];
    std::printf("vanilla run case 1: alpha %.4f deg (AVL 8.2403), elevator %.4f deg (AVL 5.4073)\n",
                sol.state.alpha / deg, elevator / deg);
    EXPECT_NEAR(d.state.CL, 1.16647, 1e-9);
    EXPECT_NEAR(sol.state.alpha / deg, 8.2403, 0.05);
    EXPECT_NEAR(elevator / deg, 5.4073, 0.05);
    const Row rows[] = {{"CLa", d.stability(0, 0), 4.8629, 0.01},
                        {"Cma", d.stability(4, 0), -0.4988, 0.01}};
    compare("vanilla", rows, std::size(rows));
}

}  // namespace
