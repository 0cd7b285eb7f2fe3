/// @file test_reorder.cpp
/// Reverse Cuthill-McKee renumbering (mesh/reorder.hpp): the renumbered mesh is the same mesh
/// (volume, dual volumes and boundary normals move with their nodes), and its bandwidth is far
/// below that of a randomly numbered mesh (Cuthill & McKee 1969: the ordering is a breadth-first
/// level structure, so the bandwidth is bounded by twice the widest level).

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "gmsh_fixtures.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/mesh/reorder.hpp"
#include "metrics_checks.hpp"

namespace {

using namespace manta::mesh;

/// The box mesh with its nodes shuffled.
Mesh shuffled_box() {
    const auto dir = test::scratch_dir("reorder");
    test::make_box(test::BoxKind::tets, 1.0, 0.8, 0.6, 0.12, {dir / "box.msh"});
    const Mesh m = read_mesh(dir / "box.msh");
    std::vector<Index> perm(static_cast<std::size_t>(m.n_nodes()));
    std::iota(perm.begin(), perm.end(), 0);
    std::mt19937 rng(7);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<Index> inv(perm.size());
    for (std::size_t k = 0; k < perm.size(); ++k)
        inv[static_cast<std::size_t>(perm[k])] = static_cast<Index>(k);
    Mesh s("shuffled box");
    for (std::size_t k = 0; k < perm.size(); ++k) s.add_node(m.node(perm[k]));
    for (const std::string& n : m.markers()) s.add_marker(n);
    std::vector<Index> b;
    for (Index c = 0; c < m.n_cells(); ++c) {
        b.clear();
        for (Index v : m.cell(c)) b.push_back(inv[static_cast<std::size_t>(v)]);
        s.add_cell(m.cell_type(c), b);
    }
    for (Index f = 0; f < m.n_faces(); ++f) {
        b.clear();
        for (Index v : m.face(f)) b.push_back(inv[static_cast<std::size_t>(v)]);
        s.add_face(m.face_type(f), b, m.face_marker(f));
    }
    s.finalize();
    return s;
}

TEST(Reorder, SameMeshSmallerBandwidth) {
    const Mesh s = shuffled_box();
    const ReorderedMesh r = reorder_reverse_cuthill_mckee(s);
    ASSERT_EQ(r.mesh.n_nodes(), s.n_nodes());
    EXPECT_EQ(r.mesh.n_cells(), s.n_cells());
    EXPECT_EQ(r.mesh.n_faces(), s.n_faces());
    EXPECT_EQ(r.mesh.markers(), s.markers());
    EXPECT_NEAR(r.mesh.volume(), s.volume(), 1e-12);
    // The permutation is one, and coordinates follow it.
    for (Index i = 0; i < s.n_nodes(); ++i) {
        const Index j = r.new_from_old[static_cast<std::size_t>(i)];
        ASSERT_EQ(r.old_from_new[static_cast<std::size_t>(j)], i);
        EXPECT_EQ(r.mesh.node(j), s.node(i));
    }
    const Index before = bandwidth(s), after = bandwidth(r.mesh);
    std::printf("nodes %d, bandwidth shuffled %d, reverse Cuthill-McKee %d\n", s.n_nodes(), before,
                after);
    EXPECT_LT(after * 4, before);
    // Dual metrics move with the nodes.
    const DualMetrics a = test::check_dual(s, 0.48);
    const DualMetrics b = test::check_dual(r.mesh, 0.48);
    for (Index i = 0; i < s.n_nodes(); ++i)
        EXPECT_NEAR(
            a.dual_volumes[static_cast<std::size_t>(i)],
            b.dual_volumes[static_cast<std::size_t>(r.new_from_old[static_cast<std::size_t>(i)])],
            1e-14);
}

TEST(Reorder, UnfinalizedMeshIsAnError) {
    Mesh m("raw");
    m.add_node({0, 0, 0});
    EXPECT_THROW((void)reorder_reverse_cuthill_mckee(m), manta::InputError);
}

}  // namespace
