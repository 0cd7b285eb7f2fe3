/// @file test_meshes.cpp
/// The Euler test meshes of support/test_meshes.hpp: each valid (finalized by the reader or the
/// builder), its median-dual cells closed to round-off, its size in the stated range and its
/// geometry right: the NACA 0012 wall nodes on the exact section and the wall's perimeter,
/// the bump levels nested with 4 times the cells, the wing's projected area 3 m^2, the
/// irregular box holding all four cell kinds. Prints each mesh's size and generation time.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>

#include "manta/core/error.hpp"
#include "manta/mesh/dual.hpp"
#include "test_meshes.hpp"

namespace manta::test {
namespace {

using mesh::CellType;
using mesh::Index;
using mesh::Mesh;

/// Time `make` and print the mesh's size.
template <class F>
Mesh timed(const char* what, F make) {
    const auto t0 = std::chrono::steady_clock::now();
    Mesh m = make();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("[ mesh     ] %s: %d nodes, %d cells, %d boundary faces in %.2f s\n", what,
                m.n_nodes(), m.n_cells(), m.n_faces(), s);
    return m;
}

/// Dual metrics with the closure and volume checks every mesh must pass.
mesh::DualMetrics check_closed(const Mesh& m) {
    EXPECT_TRUE(m.is_finalized());
    const mesh::DualMetrics d = mesh::compute_dual_metrics(m);
    EXPECT_LT(mesh::max_closure_defect(m, d), 1e-12) << m.source();
    double sum = 0.0;
    for (double v : d.dual_volumes) {
        EXPECT_GT(v, 0.0) << m.source();
        sum += v;
    }
    EXPECT_NEAR(sum, m.volume(), 1e-12 * m.volume()) << m.source();
    return d;
}

/// Outward area vector of boundary face `f` (m^2): triangles about the face's node average.
Eigen::Vector3d face_area(const Mesh& m, Index f) {
    const auto nodes = m.face(f);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (Index v : nodes) c += m.node(v);
    c /= static_cast<double>(nodes.size());
    Eigen::Vector3d a = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < nodes.size(); ++k)
        a += 0.5 * (m.node(nodes[k]) - c).cross(m.node(nodes[(k + 1) % nodes.size()]) - c);
    return a;
}

/// Sum of the outward face area vectors and of their magnitudes over one marker.
std::pair<Eigen::Vector3d, double> marker_area(const Mesh& m, const std::string& name) {
    const int marker = m.find_marker(name);
    EXPECT_GE(marker, 0) << "marker " << name << " missing in " << m.source();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double magnitude = 0.0;
    for (Index f = 0; f < m.n_faces(); ++f)
        if (m.face_marker(f) == marker) {
            const Eigen::Vector3d a = face_area(m, f);
            sum += a;
            magnitude += a.norm();
        }
    return {sum, magnitude};
}

int count_cells(const Mesh& m, CellType t) {
    int n = 0;
    for (Index c = 0; c < m.n_cells(); ++c) n += m.cell_type(c) == t;
    return n;
}

std::set<std::string> marker_set(const Mesh& m) {
    return {m.markers().begin(), m.markers().end()};
}

TEST(Naca0012Section, ClosedTrailingEdgeAndPerimeter) {
    EXPECT_DOUBLE_EQ(naca0012_half_thickness(0.0), 0.0);
    EXPECT_NEAR(naca0012_half_thickness(1.0), 0.0, 1e-15);
    // Maximum thickness 12 % of the chord at x/c = 0.3 (Abbott and von Doenhoff 1959, app. I).
    EXPECT_NEAR(naca0012_half_thickness(0.3), 0.06, 2e-4);
    // The perimeter of the NACA 0012 is 2.0395 c (arc length of the section, 2 x 1.01977).
    EXPECT_NEAR(naca0012_perimeter(), 2.0395, 1e-4);
    EXPECT_THROW((void)naca0012_half_thickness(1.5), InputError);
}

TEST(TestMeshes, Naca0012SlabLevels) {
    const Mesh m0 = timed("naca0012_slab(0)", [] { return naca0012_slab(0); });
    const Mesh m1 = timed("naca0012_slab(1)", [] { return naca0012_slab(1); });
    for (const Mesh* m : {&m0, &m1}) {
        SCOPED_TRACE(m->source());
        EXPECT_EQ(marker_set(*m), (std::set<std::string>{"airfoil", "farfield", "symmetry_back",
                                                         "symmetry_front"}));
        EXPECT_EQ(count_cells(*m, CellType::prism), m->n_cells());
        const auto d = check_closed(*m);
        // Wall nodes on the exact section, leading edge (0, 0) and trailing edge (1, 0) among
        // them.
        const auto& wall = d.boundary.at(static_cast<std::size_t>(m->find_marker("airfoil")));
        double x_min = 1.0, x_max = 0.0, worst = 0.0;
        for (Index v : wall.nodes) {
            const Eigen::Vector3d p = m->node(v);
            x_min = std::min(x_min, p.x());
            x_max = std::max(x_max, p.x());
            worst = std::max(worst, std::abs(std::abs(p.y()) - naca0012_half_thickness(p.x())));
        }
        EXPECT_EQ(x_min, 0.0);
        EXPECT_EQ(x_max, 1.0);
        EXPECT_LT(worst, 1e-12);
        // Slab thickness 1 m: the wall's area is the polygon's perimeter, within 0.3 % of the
        // exact 2.0395 m at 160 points.
        EXPECT_NEAR(marker_area(*m, "airfoil").second, naca0012_perimeter(),
                    3e-3 * naca0012_perimeter());
        // The far field is a circle of radius 50 about (0.5, 0).
        for (Index v : d.boundary.at(static_cast<std::size_t>(m->find_marker("farfield"))).nodes)
            EXPECT_NEAR(std::hypot(m->node(v).x() - 0.5, m->node(v).y()), 50.0, 1e-9);
    }
    // Level 0: 3 000 to 5 000 nodes per plane, 160 on the airfoil; level 1 twice as fine.
    const int n0 = m0.n_nodes() / 2, n1 = m1.n_nodes() / 2;
    EXPECT_GE(n0, 3000);
    EXPECT_LE(n0, 5000);
    const auto wall_nodes = [](const Mesh& m) {
        const auto d = compute_dual_metrics(m);
        return d.boundary.at(static_cast<std::size_t>(m.find_marker("airfoil"))).nodes.size();
    };
    EXPECT_EQ(wall_nodes(m0), 2u * 160u);
    EXPECT_EQ(wall_nodes(m1), 2u * 320u);
    EXPECT_GT(static_cast<double>(n1) / n0, 3.3);
    EXPECT_LT(static_cast<double>(n1) / n0, 4.5);
    EXPECT_THROW((void)naca0012_slab(3), InputError);
}

TEST(TestMeshes, BumpChannelNestedLevels) {
    std::set<std::tuple<double, double>> coarser;  // (x, y) of the level below, z = 0
    for (int level = 0; level < 3; ++level) {
        const Mesh m = timed(("bump_channel(" + std::to_string(level) + ")").c_str(),
                             [level] { return bump_channel(level); });
        SCOPED_TRACE(m.source());
        EXPECT_EQ(marker_set(m), (std::set<std::string>{"inflow", "outflow", "lower", "upper",
                                                        "symmetry_back", "symmetry_front"}));
        // (24 x 8) 4^level hexahedra.
        EXPECT_EQ(m.n_cells(), 192 << (2 * level));
        EXPECT_EQ(count_cells(m, CellType::hexa), m.n_cells());
        EXPECT_EQ(m.n_nodes(), 2 * (24 * (1 << level) + 1) * (8 * (1 << level) + 1));
        check_closed(m);
        // Area between the walls: 0.8 x 3 minus the bump's integral 0.0625 sqrt(pi / 25)
        // (to the trapezoidal rule's error on the coarsest level).
        EXPECT_NEAR(m.volume(), 2.4 - 0.0625 * std::sqrt(std::numbers::pi / 25.0), 1e-6);
        // Inflow and outflow planes of area 0.8 m^2 facing -x and +x.
        EXPECT_NEAR(marker_area(m, "inflow").first.x(), -0.8, 1e-12);
        EXPECT_NEAR(marker_area(m, "outflow").first.x(), 0.8, 1e-12);
        // Nested: every node of the level below is a node here (bitwise equal coordinates).
        std::set<std::tuple<double, double>> here;
        for (Index v = 0; v < m.n_nodes(); ++v)
            if (m.node(v).z() == 0.0) here.insert({m.node(v).x(), m.node(v).y()});
        for (const auto& p : coarser) {
            EXPECT_TRUE(here.count(p)) << std::get<0>(p) << " " << std::get<1>(p);
        }
        // Lower-wall nodes on the bump.
        const int lower = m.find_marker("lower");
        for (Index f = 0; f < m.n_faces(); ++f) {
            if (m.face_marker(f) != lower) continue;
            for (Index v : m.face(f)) {
                EXPECT_NEAR(m.node(v).y(), bump_lower_wall(m.node(v).x()), 1e-15);
            }
        }
        coarser = std::move(here);
    }
}

TEST(TestMeshes, WingBox) {
    const Mesh m = timed("wing_box(0)", [] { return wing_box(0); });
    EXPECT_EQ(marker_set(m), (std::set<std::string>{"wing", "symmetry", "farfield"}));
    EXPECT_EQ(count_cells(m, CellType::tetra), m.n_cells());
    EXPECT_LE(m.n_nodes(), 30000);
    EXPECT_GE(m.n_nodes(), 5000);
    const auto d = check_closed(m);
    // Planform area: the wing's lower surface projected on z (its outward normals point +z,
    // out of the fluid into the wing) and the upper one (-z), each chord x semi-span = 3 m^2.
    const int wing = m.find_marker("wing");
    double up = 0.0, down = 0.0, y_max = 0.0;
    for (Index f = 0; f < m.n_faces(); ++f)
        if (m.face_marker(f) == wing) {
            const Eigen::Vector3d a = face_area(m, f);
            up += std::max(0.0, a.z());
            down += std::max(0.0, -a.z());
            for (Index v : m.face(f)) y_max = std::max(y_max, m.node(v).y());
        }
    EXPECT_NEAR(up, 3.0, 0.03);
    EXPECT_NEAR(down, 3.0, 0.03);
    EXPECT_DOUBLE_EQ(y_max, 3.0);
    // The symmetry plane is y = 0 with outward normals -y; it has the root section as a hole.
    const auto [sym, sym_area] = marker_area(m, "symmetry");
    EXPECT_NEAR(sym.y(), -sym_area, 1e-9 * sym_area);
    const double section_area = 0.0817;  // NACA 0012 (closed): integral of 2 y_t dx, in c^2
    EXPECT_NEAR(sym_area, 21.0 * 20.0 - section_area, 1e-3);
    for (const auto& bv : d.boundary) {
        if (m.markers()[static_cast<std::size_t>(bv.marker)] != "symmetry") continue;
        for (Index v : bv.nodes) {
            EXPECT_EQ(m.node(v).y(), 0.0);
        }
    }
    EXPECT_THROW((void)wing_box(2), InputError);
}

TEST(TestMeshes, IrregularBoxMixedAndPerturbed) {
    const Mesh m = timed("irregular_box(6)", [] { return irregular_box(); });
    EXPECT_EQ(marker_set(m),
              (std::set<std::string>{"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"}));
    for (CellType t : {CellType::tetra, CellType::pyramid, CellType::prism, CellType::hexa})
        EXPECT_GT(count_cells(m, t), 0) << mesh::name(t);
    EXPECT_NEAR(m.volume(), 1.0, 1e-12);
    check_closed(m);
    // Each side a unit square with its outward normal.
    const std::map<std::string, Eigen::Vector3d> outward{
        {"xmin", -Eigen::Vector3d::UnitX()}, {"xmax", Eigen::Vector3d::UnitX()},
        {"ymin", -Eigen::Vector3d::UnitY()}, {"ymax", Eigen::Vector3d::UnitY()},
        {"zmin", -Eigen::Vector3d::UnitZ()}, {"zmax", Eigen::Vector3d::UnitZ()}};
    for (const auto& [name, n] : outward) {
        const auto [sum, magnitude] = marker_area(m, name);
        EXPECT_NEAR((sum - n).norm(), 0.0, 1e-13) << name;
        EXPECT_NEAR(magnitude, 1.0, 1e-13) << name;
    }
    // Interior nodes moved off the 1/6 grid; the same seed gives the same mesh.
    int off_grid = 0;
    for (Index v = 0; v < 7 * 7 * 7; ++v) {
        const Eigen::Vector3d p = 6.0 * m.node(v);
        off_grid += (p - p.array().round().matrix()).norm() > 1e-3;
    }
    EXPECT_EQ(off_grid, 5 * 5 * 5);
    const Mesh again = irregular_box();
    ASSERT_EQ(again.n_nodes(), m.n_nodes());
    EXPECT_TRUE(
        std::equal(m.coordinates().begin(), m.coordinates().end(), again.coordinates().begin()));
    EXPECT_NE(irregular_box(6, 0.1, 2).n_cells(), 0);
    EXPECT_THROW((void)irregular_box(1), InputError);
    EXPECT_THROW((void)irregular_box(4, 0.3), InputError);
}

}  // namespace
}  // namespace manta::test
