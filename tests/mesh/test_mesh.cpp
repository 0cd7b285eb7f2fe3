/// @file test_mesh.cpp
/// Mesh storage and validation, and the median-dual metrics on single reference cells of every
/// type and on a perturbed mixed mesh (closure, volumes, boundary normals).

#include "manta/mesh/mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include "manta/core/error.hpp"
#include "manta/mesh/dual.hpp"
#include "metrics_checks.hpp"

namespace manta::mesh {
namespace {

/// Every face of every cell that has no neighbour becomes a boundary face of marker "wall",
/// given in reversed order so that `finalize` must orient it.
void close_with_wall(Mesh& m, const std::vector<std::pair<CellType, std::vector<Index>>>& cells) {
    const int wall = m.add_marker("wall");
    std::map<std::vector<Index>, std::vector<Index>> count;
    for (const auto& [t, nodes] : cells)
        for (const auto& f : cell_faces(t)) {
            std::vector<Index> fn;
            for (int k = 0; k < (f[3] < 0 ? 3 : 4); ++k) fn.push_back(nodes[f[k]]);
            auto key = fn;
            std::sort(key.begin(), key.end());
            if (count.count(key))
                count.erase(key);
            else
                count[key] = fn;
        }
    for (auto& [key, fn] : count) {
        std::reverse(fn.begin(), fn.end());
        m.add_face(fn.size() == 3 ? FaceType::triangle : FaceType::quad, fn, wall);
    }
}

Mesh single_cell(CellType t, const std::vector<Eigen::Vector3d>& x) {
    Mesh m("unit");
    for (const auto& p : x) m.add_node(p);
    std::vector<Index> nodes(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) nodes[i] = static_cast<Index>(i);
    m.add_cell(t, nodes);
    close_with_wall(m, {{t, nodes}});
    m.finalize();
    return m;
}

const std::vector<Eigen::Vector3d> tet_x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<Eigen::Vector3d> hex_x{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
// VTK wedge: (0,1,2) clockwise seen from +z (normal away from the top triangle).
const std::vector<Eigen::Vector3d> prism_x{{0, 0, 0}, {0, 1, 0}, {1, 0, 0},
                                           {0, 0, 1}, {0, 1, 1}, {1, 0, 1}};
const std::vector<Eigen::Vector3d> pyramid_x{
    {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};

TEST(Mesh, ReferenceCellVolumesAndClosure) {
    struct Case {
        CellType t;
        const std::vector<Eigen::Vector3d>* x;
        double volume;
    };
    for (const auto& c :
         {Case{CellType::tetra, &tet_x, 1.0 / 6.0}, Case{CellType::hexa, &hex_x, 1.0},
          Case{CellType::prism, &prism_x, 0.5}, Case{CellType::pyramid, &pyramid_x, 1.0 / 3.0}}) {
        SCOPED_TRACE(name(c.t));
        const Mesh m = single_cell(c.t, *c.x);
        EXPECT_NEAR(m.cell_volume(0), c.volume, 1e-15);
        const DualMetrics d = test::check_dual(m, c.volume);
        // A single cell: every node's dual cell is closed by its boundary normal alone plus its
        // edges; the boundary normal of each node points out of the cell's centre.
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (Index i = 0; i < m.n_nodes(); ++i) centre += m.node(i) / m.n_nodes();
        for (std::size_t k = 0; k < d.boundary[0].nodes.size(); ++k)
            EXPECT_GT(d.boundary[0]
                          .normals.col(static_cast<Eigen::Index>(k))
                          .dot(m.node(d.boundary[0].nodes[k]) - centre),
                      0.0);
        // Edge normals point from the lower to the higher node number.
        for (Index e = 0; e < d.n_edges(); ++e) {
            const auto [i, j] = d.edges[e];
            EXPECT_GT(d.edge_normals.col(e).dot(m.node(j) - m.node(i)), 0.0);
        }
    }
}

TEST(Mesh, HexDualVolumesAreEighths) {
    const Mesh m = single_cell(CellType::hexa, hex_x);
    const DualMetrics d = compute_dual_metrics(m);
    for (double v : d.dual_volumes) EXPECT_NEAR(v, 0.125, 1e-15);
    // Dual face of a cube edge: a 0.5 x 0.5 square.
    for (Index e = 0; e < d.n_edges(); ++e) EXPECT_NEAR(d.edge_normals.col(e).norm(), 0.25, 1e-15);
}

/// A hexahedron with a pyramid on top, a prism beside and a tetrahedron on the pyramid, nodes
/// perturbed so that the quadrilateral faces are not planar.
TEST(Mesh, PerturbedMixedMeshIsClosed) {
    Mesh m("mixed");
    std::vector<Eigen::Vector3d> x = hex_x;
    x.push_back({0.5, 0.5, 1.7});  // 8: pyramid apex
    x.push_back({1, 0.5, 1.6});    // 9: apex of the tetrahedra on the pyramid's side
    x.push_back({2, 0, 0});        // 10
    x.push_back({2, 0, 1});        // 11
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.08, 0.08);
    for (auto& p : x) p += Eigen::Vector3d(u(rng), u(rng), u(rng));
    for (const auto& p : x) m.add_node(p);
    const std::vector<std::pair<CellType, std::vector<Index>>> cells{
        {CellType::hexa, {0, 1, 2, 3, 4, 5, 6, 7}},
        {CellType::pyramid, {4, 5, 6, 7, 8}},
        {CellType::prism, {1, 2, 10, 5, 6, 11}},  // on the hexa's face x = 1
        {CellType::tetra, {5, 6, 8, 9}},
    };
    for (const auto& [t, n] : cells) m.add_cell(t, n);
    close_with_wall(m, cells);
    ASSERT_NO_THROW(m.finalize());
    EXPECT_EQ(m.n_cells(), 4);
    test::check_dual(m, -1.0);
}

TEST(Mesh, ErrorsNameTheProblem) {
    const auto expect_error = [](Mesh m, const std::string& part) {
        try {
            m.finalize();
            ADD_FAILURE() << "no error, expected one with: " << part;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    {  // dangling node index
        Mesh m("dangling.su2");
        for (const auto& p : tet_x) m.add_node(p);
        const std::vector<Index> n{0, 1, 2, 7};
        m.add_cell(CellType::tetra, n, 12);
        expect_error(m, "dangling.su2: line 12: cell 0 (tetra) refers to node 7; expected 0 to 3");
    }
    {  // inverted cell
        Mesh m("inverted");
        for (const auto& p : tet_x) m.add_node(p);
        const std::vector<Index> n{0, 2, 1, 3};
        m.add_cell(CellType::tetra, n, 3);
        expect_error(m, "has volume -0.166667 m^3; expected > 0");
    }
    {  // no marker on the boundary
        Mesh m("bare");
        for (const auto& p : tet_x) m.add_node(p);
        const std::vector<Index> n{0, 1, 2, 3};
        m.add_cell(CellType::tetra, n);
        expect_error(m, "4 cell faces on the boundary belong to no marker");
    }
    {  // a boundary face that is no cell face
        Mesh m = single_cell(CellType::hexa, hex_x);
        const std::vector<Index> f{0, 1, 6};
        m.add_face(FaceType::triangle, f, 0, 40);
        expect_error(m, "line 40: boundary face 6 of marker 'wall' (nodes 0 1 6) is not a face");
    }
    {  // an unnamed marker
        Mesh m = single_cell(CellType::tetra, tet_x);
        m.add_marker("");
        expect_error(m, "marker 1 has no name");
    }
    {  // wrong node count
        Mesh m("count");
        const std::vector<Index> n{0, 1, 2};
        EXPECT_THROW(m.add_cell(CellType::tetra, n, 5), InputError);
    }
}

}  // namespace
}  // namespace manta::mesh
