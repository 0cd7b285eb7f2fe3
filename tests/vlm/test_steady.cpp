// Steady vortex-lattice solver: planar wings against AVL 3.40 and lifting-surface theory.
// References: ../shared/reference/avl/README.md (AVL 3.40 results, double precision, run on this
// project's machine) and the closed-form values cited at each test.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/steady.hpp"

namespace {

using namespace manta::vlm;
using Eigen::Vector3d;

/// Flat rectangular plate, chord 1, span AR, mirrored about y = 0, Xref at c/4.
Model rectangle(double AR, int nc, int ns) {
    Model m;
    m.name = "rect";
    m.reference = {AR, AR, 1.0, Vector3d(0.25, 0, 0)};
    Surface s;
    s.name = "wing";
    s.n_chord = nc;
    s.chord_spacing = 1.0;
    s.n_span = ns;
    s.span_spacing = 1.0;
    s.y_duplicate = 0.0;
    Section root, tip;
    root.leading_edge = Vector3d(0, 0, 0);
    root.chord = 1.0;
    tip.leading_edge = Vector3d(0, 0.5 * AR, 0);
    tip.chord = 1.0;
    s.sections = {root, tip};
    m.surfaces.push_back(s);
    return m;
}

TEST(VlmSteady, RectangularPlatesMatchAvl) {
    // AVL 3.40 DP, 16 x 40 per semispan (README table): CLa, Xnp/c, Clp, Cmq (c/4), CLq.
    struct Case {
        double AR, CLa, xnp, Clp, Cmq;
    };
    const Case cases[] = {{1, 1.4602, 0.1668, -0.0979, -0.4651},
                          {4, 3.6120, 0.2319, -0.3360, -0.6706},
                          {10, 4.8385, 0.2438, -0.5753, -0.7357}};
    for (const Case& c : cases) {
        const Model m = rectangle(c.AR, 16, 40);
        const SteadySolver solver(m, build_lattice(m), 0.0);
        const Derivatives d = solver.derivatives(FlowState{});
        SCOPED_TRACE(c.AR);
        EXPECT_NEAR(d.body(0, 0), c.CLa, 0.005 * c.CLa);
        EXPECT_NEAR(d.x_neutral_point, c.xnp, 0.005 * c.xnp);
        EXPECT_NEAR(d.stability(3, 2), c.Clp, 0.005 * std::abs(c.Clp));
        EXPECT_NEAR(d.stability(4, 3), c.Cmq, 0.005 * std::abs(c.Cmq));
    }
}

}  // namespace

namespace {

// A symmetric deflection of a full-span control on both copies gives lift and no roll; the same
// control with duplicate sign -1 gives roll and no lift (the mirror-copy sign convention).
TEST(VlmSteady, ControlMirrorConvention) {
    for (double dup : {1.0, -1.0}) {
        Model m = rectangle(6.0, 8, 20);
        for (auto& sec : m.surfaces[0].sections) {
            SectionControl c;
            c.name = "flap";
            c.hinge_chord_fraction = 0.75;
            c.duplicate_sign = dup;
            sec.controls.push_back(c);
        }
        const SteadySolver solver(m, build_lattice(m), 0.0);
        const Derivatives d = solver.derivatives(FlowState{});
        SCOPED_TRACE(dup);
        if (dup > 0) {
            EXPECT_GT(d.control(0, 0), 1.0);  // trailing edge down: more lift
            EXPECT_NEAR(d.control(3, 0), 0.0, 1e-9);
        } else {
            EXPECT_NEAR(d.control(0, 0), 0.0, 1e-9);
            // Right trailing edge down, left up: right wing lifts, rolls left (Cl < 0).
            EXPECT_LT(d.control(3, 0), -0.1);
        }
    }
}

// Prandtl-Glauert: the lift slope of a high-aspect-ratio wing scales close to 1/beta, and for a
// 2-D wing exactly so; here AR 10 between Mach 0 and 0.6 lies between the 2-D and the
// lifting-line (Helmbold) scalings.
TEST(VlmSteady, PrandtlGlauertScaling) {
    const Model m = rectangle(10.0, 8, 20);
    const double a0 = SteadySolver(m, build_lattice(m), 0.0).derivatives(FlowState{}).body(0, 0);
    const double a6 = SteadySolver(m, build_lattice(m), 0.6).derivatives(FlowState{}).body(0, 0);
    const double ratio = a6 / a0;
    EXPECT_GT(ratio, 1.10);       // compressibility raises the slope
    EXPECT_LT(ratio, 1.0 / 0.8);  // but less than the 2-D 1/beta = 1.25
}

// A half model with the symmetry image (AVL IYsym = 1) gives the loads of the full model with a
// mirror copy (YDUPLICATE); a solid plane below (IZsym = 1, ground effect) raises the lift slope
// and lowers the induced drag at a given lift.
TEST(VlmSteady, SymmetryPlaneImages) {
    const Model full = rectangle(6.0, 6, 12);
    Model half = full;
    half.surfaces[0].y_duplicate.reset();
    half.y_symmetry = 1;
    FlowState s;
    s.alpha = 4.0 * std::numbers::pi / 180.0;
    // Double precision: the image sums equal the mirrored lattice's to rounding (single
    // precision rounds the two matrices differently, about 1e-7 relative).
    SteadyOptions dbl;
    dbl.single_precision = false;
    const Derivatives df = SteadySolver(full, build_lattice(full), 0.0, dbl).derivatives(s);
    const Derivatives dh = SteadySolver(half, build_lattice(half), 0.0, dbl).derivatives(s);
    const Derivatives dhf = SteadySolver(half, build_lattice(half), 0.0).derivatives(s);
    EXPECT_NEAR(dhf.state.CL, df.state.CL, 1e-6 * df.state.CL);
    EXPECT_NEAR(dhf.state.CD_near_field, df.state.CD_near_field, 1e-6 * df.state.CD_near_field);
    EXPECT_NEAR(dh.state.CL, df.state.CL, 1e-9);
    EXPECT_NEAR(dh.state.CD_induced, df.state.CD_induced, 1e-9);
    EXPECT_NEAR(dh.state.CD_near_field, df.state.CD_near_field, 1e-9);
    EXPECT_NEAR(dh.state.body.Cm, df.state.body.Cm, 1e-9);
    EXPECT_NEAR(dh.stability(0, 0), df.stability(0, 0), 1e-6);
    EXPECT_NEAR(dh.stability(4, 3), df.stability(4, 3), 1e-6);
    Model ground = full;
    ground.z_symmetry = 1;
    ground.z_symmetry_plane = -0.5;  // half a chord below the plate
    const Derivatives dg = SteadySolver(ground, build_lattice(ground), 0.0).derivatives(s);
    EXPECT_GT(dg.stability(0, 0), 1.05 * df.stability(0, 0));
    EXPECT_GT(dg.state.span_efficiency, 1.2 * df.state.span_efficiency);
}

// A surface that sheds no wake (AVL NOWAKE) carries zero net circulation on every strip.
TEST(VlmSteady, NoWakeStripsCarryNoNetCirculation) {
    Model m = rectangle(4.0, 6, 8);
    m.surfaces[0].sheds_wake = false;
    const Lattice L = build_lattice(m);
    FlowState s;
    s.alpha = 0.1;
    const SteadyResult r = SteadySolver(m, L, 0.0).solve(s);
    for (const Strip& st : L.strips)
        EXPECT_NEAR(r.gamma.segment(st.first_panel, st.n_panels).sum(), 0.0, 1e-12);
    EXPECT_NEAR(r.CD_trefftz, 0.0, 1e-12);
}

// A hinge line inside a panel turns that panel by the fraction of its chord behind the hinge:
// the flap derivative varies continuously as the hinge crosses the panel.
TEST(VlmSteady, ControlDerivativeIsContinuousInTheHinge) {
    auto cld = [](double hinge) {
        Model m = rectangle(6.0, 4, 10);  // panel edges at x/c 0, 0.18, 0.50, 0.82, 1 (cosine)
        for (auto& sec : m.surfaces[0].sections) {
            SectionControl c;
            c.name = "flap";
            c.hinge_chord_fraction = hinge;
            sec.controls.push_back(c);
        }
        return SteadySolver(m, build_lattice(m), 0.0).derivatives(FlowState{}).control(0, 0);
    };
    const double a = cld(0.60), b = cld(0.62), c = cld(0.64);
    EXPECT_GT(a, b);
    EXPECT_GT(b, c);
    EXPECT_NEAR(b - a, c - b, 0.05 * std::abs(c - b));  // linear within the panel
}

TEST(VlmSteady, BadInputIsReported) {
    Model m = rectangle(4.0, 4, 4);
    m.surfaces[0].sections[1].chord = 0.0;
    EXPECT_THROW((void)build_lattice(m), manta::InputError);
    Model m2 = rectangle(4.0, 4, 4);
    m2.surfaces[0].sections[1].leading_edge = m2.surfaces[0].sections[0].leading_edge;
    EXPECT_THROW((void)build_lattice(m2), manta::InputError);
    Model m3 = rectangle(4.0, 4, 4);
    SectionControl c;
    c.name = "flap";
    c.hinge_chord_fraction = 1.2;
    m3.surfaces[0].sections[0].controls.push_back(c);
    EXPECT_THROW((void)build_lattice(m3), manta::InputError);
    const Model ok = rectangle(4.0, 4, 4);
    EXPECT_THROW(SteadySolver(ok, build_lattice(ok), 0.97), manta::InputError);
    // Crossing lattices: a second plate cutting through the first.
    Model x = rectangle(4.0, 4, 4);
    Surface v;
    v.name = "cutter";
    v.n_chord = 4;
    v.n_span = 4;
    Section s0, s1;
    s0.leading_edge = Eigen::Vector3d(-0.1, 0.8, -0.4);
    s0.chord = 1.2;
    s1.leading_edge = Eigen::Vector3d(-0.1, 0.8, 0.6);
    s1.chord = 1.2;
    v.sections = {s0, s1};
    x.surfaces.push_back(v);
    EXPECT_THROW(SteadySolver(x, build_lattice(x), 0.0), manta::InputError);
}

}  // namespace

namespace {

// Camber: a wing of aspect ratio 1000 at zero incidence. Thin-airfoil theory: the NACA 2412 mean
// line has alpha_L0 = -2.077 deg, CL0 = 2 pi 0.03625 = 0.2278; the uniform-load (a = 1) mean line
// of the NACA 64-215 carries its design lift coefficient 0.2 at zero angle of attack (Abbott & von
// Doenhoff, Theory of Wing Sections, 1959, sec. 4.3 and 6.4).
TEST(VlmSteady, CamberedSectionsMatchThinAirfoilTheory) {
    struct Case {
        const char* naca;
        double cl0;
    };
    for (const Case c : {Case{"NACA 2412", 0.2278}, Case{"NACA 64-215", 0.2}}) {
        Model m;
        m.reference = {1000.0, 1000.0, 1.0, Eigen::Vector3d(0.25, 0, 0)};
        Surface s;
        s.name = "wing";
        s.n_chord = 24;
        s.n_span = 40;
        s.y_duplicate = 0.0;
        Section r, t;
        r.chord = 1.0;
        t.chord = 1.0;
        t.leading_edge = Eigen::Vector3d(0, 500, 0);
        r.airfoil = manta::geometry::Airfoil::naca(c.naca);
        t.airfoil = r.airfoil;
        s.sections = {r, t};
        m.surfaces.push_back(s);
        const SteadySolver solver(m, build_lattice(m), 0.0);
        SCOPED_TRACE(c.naca);
        EXPECT_NEAR(solver.solve(FlowState{}).CL, c.cl0, 0.02 * c.cl0);
    }
}

}  // namespace
