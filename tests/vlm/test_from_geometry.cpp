// The vortex-lattice model of a MANTA aircraft description: sections at control edges, control
// names, gains and signs, components of joined surfaces, and the Ranger 2000's derivative signs.

#include <gtest/gtest.h>

#include <filesystem>

#include "manta/core/config.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/steady.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta::vlm;

Model ranger_model(const LatticeDensity& density = {4, 1.0, 0.03, 1.0}) {
    const fs::path file = fs::path(MANTA_SOURCE_DIR) / "examples" / "ranger2000" / "aircraft.yaml";
    const auto root = manta::core::ConfigNode::parse_file(file);
    manta::core::ConfigMap gmap(root.child("geometry"));
    const auto geometry = manta::geometry::parse_geometry(gmap, file.parent_path());
    // Reference values and moment reference point (25 % MAC, x = 4.911 m) of the aircraft file.
    Reference ref{15.5, 10.46, 1.545, Eigen::Vector3d(4.911, 0.0, 0.0)};
    return from_geometry(geometry, ref, density, "Ranger 2000");
}

TEST(VlmFromGeometry, RangerModel) {
    const Model m = ranger_model();
    ASSERT_EQ(m.surfaces.size(), 3u);
    const Surface& wing = m.surfaces[0];
    const Surface& tail = m.surfaces[1];
    const Surface& fin = m.surfaces[2];
    // The aileron spans 55-95 % of the semi-span: sections at both edges besides root and tip.
    ASSERT_EQ(wing.sections.size(), 4u);
    EXPECT_NEAR(wing.sections[1].leading_edge.y(), 0.55 * 5.23, 1e-9);
    EXPECT_NEAR(wing.sections[2].leading_edge.y(), 0.95 * 5.23, 1e-9);
    EXPECT_EQ(wing.sections[1].controls.at(0).name, "aileron");
    EXPECT_DOUBLE_EQ(wing.sections[1].controls.at(0).gain, -1.0);            // right side up
    EXPECT_DOUBLE_EQ(wing.sections[1].controls.at(0).duplicate_sign, -1.0);  // left side down
    EXPECT_TRUE(wing.sections[3].controls.empty());
    // Fin and T-tail touch: one component; the wing is another.
    EXPECT_EQ(tail.component, fin.component);
    EXPECT_NE(wing.component, tail.component);
    EXPECT_EQ(fin.sections.front().controls.size(), 0u);  // the rudder starts at 5 % span
    const Lattice L = build_lattice(m);
    EXPECT_EQ(L.control_names, (std::vector<std::string>{"aileron", "elevator", "rudder"}));
}

// Derivative signs of a conventional stable aircraft and the paper's control conventions.
TEST(VlmFromGeometry, RangerDerivativeSigns) {
    const Model m = ranger_model();
    const SteadySolver solver(m, build_lattice(m), 0.3);
    FlowState s;
    s.alpha = 0.035;
    const Derivatives d = solver.derivatives(s);
    const auto& S = d.stability;
    EXPECT_GT(S(0, 0), 4.5);  // CL_alpha
    EXPECT_LT(S(0, 0), 6.0);
    EXPECT_LT(S(4, 0), 0.0);  // Cm_alpha: statically stable
    EXPECT_GT(d.static_margin, 0.1);
    EXPECT_LT(S(3, 1), 0.0);  // Cl_beta: dihedral effect
    EXPECT_GT(S(5, 1), 0.0);  // Cn_beta: weathercock stability
    EXPECT_LT(S(4, 3), 0.0);  // Cm_q
    EXPECT_LT(S(3, 2), 0.0);  // Cl_p
    EXPECT_LT(S(5, 4), 0.0);  // Cn_r
    const Lattice& L = solver.lattice();
    const auto e = L.control_index("elevator");
    const auto a = L.control_index("aileron");
    const auto r = L.control_index("rudder");
    EXPECT_LT(d.control(4, e), 0.0);  // elevator trailing edge down: nose down
    EXPECT_GT(d.control(0, e), 0.0);
    EXPECT_GT(d.control(3, a), 0.0);  // left trailing edge down: roll right
    EXPECT_LT(d.control(5, r), 0.0);  // rudder trailing edge left: yaw left
    EXPECT_GT(d.control(2, r), 0.0);  // and side force to the right
}

}  // namespace
