/// @file test_quality.cpp
/// meshgen::assess_quality on hand-made tetrahedra: the regular tetrahedron's dihedral angle
/// arccos(1/3) = 70.5288 deg (any geometry text, e.g. Coxeter, Regular Polytopes, table I),
/// neighbour volume ratios, slivers, inverted cells and open or unmarked boundaries.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "manta/meshgen/meshgen.hpp"

namespace {

using manta::meshgen::assess_quality;
using Tets = std::vector<std::array<long long, 4>>;
using Tris = std::vector<std::array<long long, 3>>;

// The four outward faces of tetrahedron (a, b, c, d) with a positive volume.
Tris faces_of(long long a, long long b, long long c, long long d) {
    return {{b, c, d}, {a, d, c}, {a, b, d}, {a, c, b}};
}

TEST(Quality, RegularTetrahedron) {
    const std::vector<double> x{1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    const auto q = assess_quality(x, Tets{{0, 2, 1, 3}}, faces_of(0, 2, 1, 3));
    const double expected = std::acos(1.0 / 3.0) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(q.min_dihedral_deg, expected, 1e-9);
    EXPECT_NEAR(q.max_dihedral_deg, expected, 1e-9);
    EXPECT_NEAR(q.volume, 8.0 / 3.0, 1e-12);  // edge 2 sqrt 2: V = a^3 / (6 sqrt 2)
    EXPECT_TRUE(q.volume_positive);
    EXPECT_TRUE(q.surface_closed);
    EXPECT_EQ(q.slivers, 0);
    EXPECT_EQ(q.max_volume_ratio, 1.0);
    EXPECT_EQ(q.nodes, 4);
    EXPECT_EQ(q.cells, 1);
}

TEST(Quality, NeighbourVolumeRatioAndOpenBoundary) {
    // Two cells on the base (0, 1, 2): apexes at heights 1 and 3 on either side.
    const std::vector<double> x{0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 1, 0.2, 0.2, -3};
    const Tets t{{0, 1, 2, 3}, {0, 2, 1, 4}};
    Tris f;
    for (const auto& face : faces_of(0, 1, 2, 3))
        if (!(face == std::array<long long, 3>{0, 2, 1})) f.push_back(face);
    for (const auto& face : faces_of(0, 2, 1, 4))
        if (!(face == std::array<long long, 3>{0, 1, 2})) f.push_back(face);
    auto q = assess_quality(x, t, f);
    EXPECT_NEAR(q.max_volume_ratio, 3.0, 1e-12);
    EXPECT_TRUE(q.volume_positive);
    EXPECT_TRUE(q.surface_closed) << q.open_edges << " " << q.unmarked_faces;
    f.pop_back();  // one exposed face not on a marker: open
    q = assess_quality(x, t, f);
    EXPECT_FALSE(q.surface_closed);
    EXPECT_EQ(q.unmarked_faces, 1);
    EXPECT_EQ(q.open_edges, 3);
}

TEST(Quality, SliverAndInvertedCell) {
    // Four nearly coplanar nodes of a square: a sliver (dihedral angles near 0 and 180 deg).
    const std::vector<double> x{0, 0, 0, 1, 0, 0, 1, 1, 0.01, 0, 1, 0};
    // (0, 2, 1, 3) is right-handed: (p2 - p0) x (p1 - p0) . (p3 - p0) = 0.01 > 0.
    const auto q = assess_quality(x, Tets{{0, 2, 1, 3}}, faces_of(0, 2, 1, 3));
    EXPECT_TRUE(q.volume_positive);
    EXPECT_NEAR(q.volume, 0.01 / 6.0, 1e-12);
    EXPECT_EQ(q.slivers, 1);
    EXPECT_LT(q.min_dihedral_deg, 5.0);
    EXPECT_GT(q.max_dihedral_deg, 175.0);
    // The other order has a negative volume.
    const auto inv = assess_quality(x, Tets{{0, 1, 2, 3}}, faces_of(0, 1, 2, 3));
    EXPECT_FALSE(inv.volume_positive);
    EXPECT_LT(inv.min_cell_volume, 0.0);
}

}  // namespace
