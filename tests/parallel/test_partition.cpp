/// @file test_partition.cpp
/// METIS node partitioning: every node in a part, parts balanced, the quality figures right.

#include <gtest/gtest.h>

#include <algorithm>

#include "box_mesh.hpp"
#include "manta/core/error.hpp"
#include "manta/parallel/partition.hpp"

namespace manta::parallel {
namespace {

using test::BoxCells;
using test::make_box_mesh;

TEST(NodeGraph, IsTheSymmetricEdgeGraphOfTheCells) {
    // One hexahedron: 8 nodes, 12 edges, 3 neighbours per node.
    const auto m = make_box_mesh(1, BoxCells::hexes);
    const auto g = node_graph(m);
    ASSERT_EQ(g.offsets.size(), 9u);
    EXPECT_EQ(g.adjacency.size(), 24u);
    for (int n = 0; n < 8; ++n) {
        EXPECT_EQ(g.offsets[n + 1] - g.offsets[n], 3);
        for (auto k = g.offsets[n]; k < g.offsets[n + 1]; ++k) {
            const int q = g.adjacency[k];
            EXPECT_NE(q, n);
            EXPECT_TRUE(std::binary_search(g.adjacency.begin() + g.offsets[q],
                                           g.adjacency.begin() + g.offsets[q + 1], n));
        }
    }
    // Kuhn tetrahedra of one cube add the 6 face diagonals and the body diagonal.
    EXPECT_EQ(node_graph(make_box_mesh(1, BoxCells::tets)).adjacency.size(), 2u * 19u);
}

class PartitionBox : public ::testing::TestWithParam<std::tuple<BoxCells, int>> {};

TEST_P(PartitionBox, CoversEveryNodeBalancedWithinFivePercent) {
    const auto [kind, n_parts] = GetParam();
    const auto m = make_box_mesh(12, kind);
    const auto part = partition_nodes(m, n_parts);
    ASSERT_EQ(part.size(), static_cast<std::size_t>(m.n_nodes()));
    for (int p : part) {
        ASSERT_GE(p, 0);
        ASSERT_LT(p, n_parts);
    }
    const auto q = partition_quality(m, part, n_parts);
    std::int64_t total = 0;
    for (auto s : q.sizes) {
        EXPECT_GT(s, 0);
        total += s;
    }
    EXPECT_EQ(total, m.n_nodes());
    EXPECT_LE(q.imbalance, 1.05) << "parts " << n_parts;
    // A box of 13^3 nodes cut into slabs would cut ~13^2 x (edges per node across a plane) per
    // cut; METIS should stay near that, far below a random split (half the edges).
    EXPECT_GT(q.edge_cut, 0);
    EXPECT_LT(q.cut_fraction(), 0.12 * (n_parts - 1));
    for (int p = 0; p < n_parts; ++p) EXPECT_GT(q.ghosts[p], 0);
    // Same mesh, same parts.
    EXPECT_EQ(partition_nodes(m, n_parts), part);
}

INSTANTIATE_TEST_SUITE_P(Kinds, PartitionBox,
                         ::testing::Combine(::testing::Values(BoxCells::hexes, BoxCells::tets,
                                                              BoxCells::mixed),
                                            ::testing::Values(2, 3, 8)));

TEST(Partition, OnePartIsAllZeros) {
    const auto m = make_box_mesh(3, BoxCells::tets);
    const auto part = partition_nodes(m, 1);
    EXPECT_TRUE(std::all_of(part.begin(), part.end(), [](int p) { return p == 0; }));
    const auto q = partition_quality(m, part, 1);
    EXPECT_EQ(q.edge_cut, 0);
    EXPECT_DOUBLE_EQ(q.imbalance, 1.0);
    EXPECT_EQ(q.ghosts[0], 0);
}

TEST(PartitionQuality, CountsCutEdgesAndGhostsOfAGivenSplit) {
    // The 2^3 box of hexahedra (nodes at x = 0, 0.5, 1) with the nodes at x = 0 in part 0.
    const auto m = make_box_mesh(2, BoxCells::hexes, 0.0);
    std::vector<int> part(static_cast<std::size_t>(m.n_nodes()));
    for (mesh::Index n = 0; n < m.n_nodes(); ++n) part[n] = m.node(n).x() > 0.25 ? 1 : 0;
    const auto q = partition_quality(m, part, 2);
    // Part 0: the 9 nodes at x = 0; part 1: the 18 others. Edges along x between x = 0 and
    // x = 0.5: 9. Ghosts of part 0: the 9 nodes at x = 0.5; of part 1: the 9 at x = 0.
    EXPECT_EQ(q.sizes[0], 9);
    EXPECT_EQ(q.sizes[1], 18);
    EXPECT_EQ(q.n_edges, 54);
    EXPECT_EQ(q.edge_cut, 9);
    EXPECT_EQ(q.ghosts[0], 9);
    EXPECT_EQ(q.ghosts[1], 9);
    EXPECT_DOUBLE_EQ(q.imbalance, 18.0 * 2 / 27.0);
}

TEST(Partition, RejectsBadPartCounts) {
    const auto m = make_box_mesh(1, BoxCells::hexes);
    EXPECT_THROW((void)partition_nodes(m, 0), InputError);
    EXPECT_THROW((void)partition_nodes(m, 9), InputError);
    const std::vector<int> bad(8, 2);
    EXPECT_THROW((void)partition_quality(m, bad, 2), InputError);
    EXPECT_THROW((void)partition_quality(m, std::vector<int>(7, 0), 1), InputError);
    try {
        (void)partition_nodes(m, 9);
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "box: cannot split 8 nodes into 9 parts; expected 1 to 8");
    }
}

}  // namespace
}  // namespace manta::parallel
