/// @file test_moving_geometry.cpp
/// Moving geometry (dual.hpp): node coordinates replaced with the topology kept, the median-dual
/// metrics recomputed in place without allocating, and the exact swept volumes of the dual faces,
/// checked against the discrete geometric conservation law V_i(b) - V_i(a) = sum of node i's
/// swept volumes (Mavriplis & Yang, J. Comput. Phys. 213, 557-573, 2006) on tetrahedral,
/// prismatic, hexahedral and mixed meshes, for a rigid rotation with translation and for a
/// smooth random deformation.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <random>

#include "gmsh_fixtures.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"

// Counting global operator new: every std::vector or std::string allocation passes here. (GCC
// sees malloc paired with free through inlined new/delete and warns of a mismatch that is none.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<long> n_allocations{0};
}  // namespace
void* operator new(std::size_t n) {
    n_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
#pragma GCC diagnostic pop

namespace manta::mesh {
namespace {

Mesh gmsh_box(test::BoxKind kind) {
    const auto dir = test::scratch_dir("moving");
    const auto file = dir / (std::string("box_") + std::to_string(static_cast<int>(kind)) + ".msh");
    test::make_box(kind, 1.0, 0.75, 0.5, 0.2, {file});
    return read_mesh(file);
}

/// A hexahedron with a pyramid on top, a prism beside and a tetrahedron on the pyramid (every cell
/// type), nodes perturbed so that the quadrilateral faces are not planar.
Mesh mixed_cells() {
    Mesh m("mixed");
    std::vector<Eigen::Vector3d> x{{0, 0, 0},       {1, 0, 0},     {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1},       {1, 0, 1},     {1, 1, 1}, {0, 1, 1},
                                   {0.5, 0.5, 1.7}, {1, 0.5, 1.6}, {2, 0, 0}, {2, 0, 1}};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.08, 0.08);
    for (auto& p : x) p += Eigen::Vector3d(u(rng), u(rng), u(rng));
    for (const auto& p : x) m.add_node(p);
    const std::vector<std::pair<CellType, std::vector<Index>>> cells{
        {CellType::hexa, {0, 1, 2, 3, 4, 5, 6, 7}},
        {CellType::pyramid, {4, 5, 6, 7, 8}},
        {CellType::prism, {1, 2, 10, 5, 6, 11}},
        {CellType::tetra, {5, 6, 8, 9}},
    };
    for (const auto& [t, n] : cells) m.add_cell(t, n);
    // Exposed faces on two markers (split by the sign of the face centre's x - 1), so that nodes
    // lie on two markers.
    const int m0 = m.add_marker("left"), m1 = m.add_marker("right");
    std::map<std::vector<Index>, std::vector<Index>> open;
    for (const auto& [t, nodes] : cells)
        for (const auto& f : cell_faces(t)) {
            std::vector<Index> fn;
            for (int k = 0; k < (f[3] < 0 ? 3 : 4); ++k) fn.push_back(nodes[f[k]]);
            auto key = fn;
            std::sort(key.begin(), key.end());
            if (open.count(key))
                open.erase(key);
            else
                open[key] = fn;
        }
    for (auto& [key, fn] : open) {
        double cx = 0.0;
        for (Index n : fn) cx += x[n].x() / static_cast<double>(fn.size());
        m.add_face(fn.size() == 3 ? FaceType::triangle : FaceType::quad, fn, cx < 1.0 ? m0 : m1);
    }
    m.finalize();
    return m;
}

std::vector<double> coordinates(const Mesh& m) {
    return {m.coordinates().begin(), m.coordinates().end()};
}

/// Rigid motion: rotation by 35 deg about an oblique axis through (0.3, 0.2, 0.1), then a
/// translation.
std::vector<double> rigid(const std::vector<double>& x) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(35.0 * M_PI / 180.0, Eigen::Vector3d(1.0, -2.0, 0.5).normalized())
            .toRotationMatrix();
    const Eigen::Vector3d o(0.3, 0.2, 0.1), t(0.7, -0.4, 1.3);
    std::vector<double> y(x.size());
    for (std::size_t k = 0; k < x.size(); k += 3) {
        const Eigen::Vector3d p(x[k], x[k + 1], x[k + 2]);
        const Eigen::Vector3d q = o + R * (p - o) + t;
        for (int c = 0; c < 3; ++c) y[k + c] = q[c];
    }
    return y;
}

/// Smooth random deformation: a sum of three sine modes with random wave vectors, phases and
/// amplitude vectors, largest displacement about 4 % of the unit length (cells stay valid).
std::vector<double> deformed(const std::vector<double>& x, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    struct Mode {
        Eigen::Vector3d k, a;
        double phase;
    };
    std::vector<Mode> modes;
    for (int i = 0; i < 3; ++i)
        modes.push_back({3.0 * Eigen::Vector3d(u(rng), u(rng), u(rng)),
                         0.013 * Eigen::Vector3d(u(rng), u(rng), u(rng)), 3.0 * u(rng)});
    std::vector<double> y(x.size());
    for (std::size_t k = 0; k < x.size(); k += 3) {
        const Eigen::Vector3d p(x[k], x[k + 1], x[k + 2]);
        Eigen::Vector3d q = p;
        for (const Mode& md : modes) q += md.a * std::sin(md.k.dot(p) + md.phase);
        for (int c = 0; c < 3; ++c) y[k + c] = q[c];
    }
    return y;
}

bool same_bits(const double* a, const double* b, std::size_t n) {
    return std::memcmp(a, b, n * sizeof(double)) == 0;
}

TEST(MovingMesh, SetCoordinatesKeepsTopologyAndChecksInput) {
    Mesh m = mixed_cells();
    const Index nc = m.n_cells(), nf = m.n_faces();
    auto x = coordinates(m);
    x[4] += 0.01;
    m.set_coordinates(x);
    EXPECT_EQ(m.coordinates()[4], x[4]);
    EXPECT_TRUE(m.is_finalized());
    EXPECT_EQ(m.n_cells(), nc);
    EXPECT_EQ(m.n_faces(), nf);
    m.set_node(3, Eigen::Vector3d(0.1, 1.05, -0.02));
    EXPECT_EQ(m.node(3), Eigen::Vector3d(0.1, 1.05, -0.02));
    try {
        m.set_coordinates(std::vector<double>(5, 0.0));
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("5 values; expected 36 (3 per node)"),
                  std::string::npos)
            << e.what();
    }
    x[7] = std::nan("");
    EXPECT_THROW(m.set_coordinates(x), InputError);
    EXPECT_NE(m.coordinates()[7], x[7]);  // unchanged after the refusal
    EXPECT_THROW(m.set_node(12, Eigen::Vector3d::Zero()), InputError);
    EXPECT_THROW(m.set_node(0, Eigen::Vector3d(0.0, INFINITY, 0.0)), InputError);
}

TEST(MovingMesh, UpdatedMetricsEqualFreshOnesBitForBitWithoutAllocating) {
    for (auto kind : {test::BoxKind::tets, test::BoxKind::prisms, test::BoxKind::hexes}) {
        SCOPED_TRACE(static_cast<int>(kind));
        Mesh m = gmsh_box(kind);
        DualMetrics d = compute_dual_metrics(m);
        const double* pe = d.edge_normals.data();
        const double* pv = d.dual_volumes.data();
        const double* pb = d.boundary[0].normals.data();
        const std::size_t cap = d.dual_volumes.capacity();
        m.set_coordinates(deformed(coordinates(m), 3));
        const long before = n_allocations.load();
        update_dual_metrics(m, d);
        EXPECT_EQ(n_allocations.load() - before, 0);
        EXPECT_EQ(d.edge_normals.data(), pe);
        EXPECT_EQ(d.dual_volumes.data(), pv);
        EXPECT_EQ(d.boundary[0].normals.data(), pb);
        EXPECT_EQ(d.dual_volumes.capacity(), cap);
        const DualMetrics fresh = compute_dual_metrics(m);
        ASSERT_EQ(fresh.edges, d.edges);
        EXPECT_TRUE(same_bits(fresh.edge_normals.data(), d.edge_normals.data(),
                              static_cast<std::size_t>(d.edge_normals.size())));
        EXPECT_TRUE(
            same_bits(fresh.dual_volumes.data(), d.dual_volumes.data(), d.dual_volumes.size()));
        for (std::size_t mk = 0; mk < d.boundary.size(); ++mk)
            EXPECT_TRUE(same_bits(fresh.boundary[mk].normals.data(), d.boundary[mk].normals.data(),
                                  static_cast<std::size_t>(d.boundary[mk].normals.size())));
        EXPECT_LT(max_closure_defect(m, d), 1e-12);
    }
}

TEST(MovingMesh, UpdateRefusesMetricsOfAnotherMesh) {
    const Mesh a = mixed_cells();
    const Mesh b = gmsh_box(test::BoxKind::tets);
    DualMetrics d = compute_dual_metrics(b);
    EXPECT_THROW(update_dual_metrics(a, d), InputError);
    DualFaceValues s;
    const auto x = coordinates(a);
    EXPECT_THROW(swept_volumes(a, d, x, x, s), InputError);
    const DualMetrics da = compute_dual_metrics(a);
    EXPECT_THROW(swept_volumes(a, da, x, std::vector<double>(3), s), InputError);
}

/// Sum of the swept volumes of each node's dual faces against its volume change, for one mesh and
/// the motion x_a -> x_b; returns the largest defect relative to the largest dual volume and
/// checks the swept-volume arrays are not reallocated by a second call.
double gcl_defect(Mesh& m, const std::vector<double>& xa, const std::vector<double>& xb,
                  double* largest_change = nullptr) {
    m.set_coordinates(xa);
    const DualMetrics da = compute_dual_metrics(m);
    m.set_coordinates(xb);
    DualMetrics db = da;
    update_dual_metrics(m, db);
    DualFaceValues s;
    swept_volumes(m, db, xa, xb, s);
    const double* p = s.edges.data();
    const long before = n_allocations.load();
    swept_volumes(m, db, xa, xb, s);
    EXPECT_EQ(n_allocations.load() - before, 0);
    EXPECT_EQ(s.edges.data(), p);
    if (largest_change) {
        double c = 0.0, v = 0.0;
        for (std::size_t n = 0; n < da.dual_volumes.size(); ++n) {
            c = std::max(c, std::abs(db.dual_volumes[n] - da.dual_volumes[n]));
            v = std::max(v, db.dual_volumes[n]);
        }
        *largest_change = c / v;
    }
    return max_swept_volume_defect(db, da.dual_volumes, db.dual_volumes, s);
}

TEST(MovingMesh, SweptVolumesSatisfyTheGeometricConservationLaw) {
    std::vector<std::pair<std::string, Mesh>> meshes;
    meshes.emplace_back("tets", gmsh_box(test::BoxKind::tets));
    meshes.emplace_back("prisms", gmsh_box(test::BoxKind::prisms));
    meshes.emplace_back("hexes", gmsh_box(test::BoxKind::hexes));
    meshes.emplace_back("mixed", mixed_cells());
    for (auto& [name, m] : meshes) {
        SCOPED_TRACE(name);
        const auto x0 = coordinates(m);
        double change = 0.0;
        // Rigid motion: the dual volumes do not change, but the linear path between the two
        // positions is not rigid (the cells shrink in the middle), so the faces' swept volumes do
        // not cancel one by one.
        const double dr = gcl_defect(m, x0, rigid(x0), &change);
        EXPECT_LT(dr, 5e-14);  // translation 1.5 m on cells of 0.2 m: swept volumes ~60 V_i
        EXPECT_LT(change, 1e-12);
        const double dd = gcl_defect(m, x0, deformed(x0, 11), &change);
        EXPECT_LT(dd, 1e-14);
        EXPECT_GT(change, 1e-2);  // the deformation changes the volumes by a few per cent
        // Both at once, from a deformed start.
        const double db = gcl_defect(m, deformed(x0, 5), rigid(deformed(x0, 6)));
        EXPECT_LT(db, 5e-14);
        std::printf("%s: GCL defect rigid %.2e, deformation %.2e, both %.2e\n", name.c_str(), dr,
                    dd, db);
        m.set_coordinates(x0);
    }
}

TEST(MovingMesh, SweptVolumesOfATranslatedCellByHand) {
    // The unit cube translated by (0.1, 0, 0): each dual face is swept by its area vector dotted
    // with the translation, and a boundary face with normal -x of node 0 (area 1/4) sweeps -0.025.
    Mesh m("cube");
    const std::vector<Eigen::Vector3d> x{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (const auto& p : x) m.add_node(p);
    const std::vector<Index> nodes{0, 1, 2, 3, 4, 5, 6, 7};
    m.add_cell(CellType::hexa, nodes);
    const int w = m.add_marker("wall");
    for (const auto& f : cell_faces(CellType::hexa)) {
        const std::vector<Index> fn{f[0], f[1], f[2], f[3]};
        m.add_face(FaceType::quad, fn, w);
    }
    m.finalize();
    const DualMetrics d = compute_dual_metrics(m);
    auto xa = coordinates(m), xb = xa;
    for (std::size_t k = 0; k < xb.size(); k += 3) xb[k] += 0.1;
    DualFaceValues s;
    swept_volumes(m, d, xa, xb, s);
    for (Index e = 0; e < d.n_edges(); ++e)
        EXPECT_NEAR(s.edges[e], 0.1 * d.edge_normals(0, e), 1e-16);
    for (std::size_t k = 0; k < d.boundary[0].nodes.size(); ++k)
        EXPECT_NEAR(s.boundary[0][k], 0.1 * d.boundary[0].normals(0, static_cast<Index>(k)), 1e-16);
    EXPECT_NEAR(s.boundary[0][0], -0.025, 1e-16);
}

}  // namespace
}  // namespace manta::mesh
