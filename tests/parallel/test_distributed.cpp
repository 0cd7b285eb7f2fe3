/// @file test_distributed.cpp
/// One-process distribution, the serial communicator and halo, and the mesh option that lets a
/// partition-local mesh keep unmarked cut faces (the two-process tests are in
/// mpi_test_distributed.cpp).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "box_mesh.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/parallel/distributed.hpp"
#include "manta/parallel/mpi.hpp"

namespace manta::parallel {
namespace {

using test::BoxCells;
using test::make_box_mesh;

TEST(MpiEnvironment, StaysSerialWithoutAnMpiLauncher) {
    if (launched_by_mpi()) GTEST_SKIP() << "started by an MPI launcher";
    const MpiEnvironment env;
    EXPECT_FALSE(env.active());
    EXPECT_EQ(env.communicator().size(), 1);
    EXPECT_EQ(env.communicator().rank(), 0);
    EXPECT_EQ(env.communicator().sum(2.5), 2.5);
    std::vector<double> v{1.0, 2.0};
    env.communicator().sum(v);
    EXPECT_EQ(v, (std::vector<double>{1.0, 2.0}));
}

TEST(Distribute, OneProcessCopiesTheMesh) {
    const auto global = make_box_mesh(3, BoxCells::mixed);
    const SerialCommunicator comm;
    const auto lm = distribute(&global, comm);
    EXPECT_EQ(lm.n_owned, global.n_nodes());
    EXPECT_EQ(lm.n_ghosts(), 0);
    EXPECT_EQ(lm.n_global_nodes, global.n_nodes());
    EXPECT_EQ(lm.mesh.n_cells(), global.n_cells());
    EXPECT_EQ(lm.mesh.n_faces(), global.n_faces());
    EXPECT_EQ(lm.mesh.markers(), global.markers());
    ASSERT_NE(dynamic_cast<const SerialHalo*>(lm.halo.get()), nullptr);
    for (mesh::Index n = 0; n < global.n_nodes(); ++n) EXPECT_EQ(lm.global_node[n], n);

    // Gather restores the values; sums are plain sums.
    std::vector<double> v(2 * static_cast<std::size_t>(lm.n_local()));
    std::iota(v.begin(), v.end(), 0.0);
    EXPECT_EQ(gather_owned(lm, v, 2, comm), v);
    const auto s = sum_owned(lm, v, 2, comm);
    const double n = lm.n_local();
    EXPECT_DOUBLE_EQ(s[0], n * (n - 1));
    EXPECT_DOUBLE_EQ(s[1], n * n);
    lm.halo->exchange(v, 2);  // nothing to do
    EXPECT_THROW((void)gather_owned(lm, std::span(v).first(3), 2, comm), InputError);
}

TEST(Distribute, RejectsAMissingMesh) {
    const SerialCommunicator comm;
    EXPECT_THROW((void)distribute(nullptr, comm), InputError);
    mesh::Mesh open("open");
    open.add_node({0, 0, 0});
    EXPECT_THROW((void)serial_local_mesh(std::move(open)), InputError);
}

/// The cells of the box touching x < 0.5 and their boundary faces: like a partition-local
/// mesh, with exposed faces on no marker where the box was cut (box cells of size 0.25).
mesh::Mesh half_box(const mesh::Mesh& g, std::vector<mesh::Index>& global_of_local) {
    std::vector<mesh::Index> local(static_cast<std::size_t>(g.n_nodes()), -1);
    mesh::Mesh m("half");
    std::vector<char> keep(static_cast<std::size_t>(g.n_cells()), 0);
    for (mesh::Index c = 0; c < g.n_cells(); ++c)
        for (mesh::Index n : g.cell(c))
            if (g.node(n).x() < 0.5 - 1e-9) keep[c] = 1;
    for (const auto& name : g.markers()) m.add_marker(name);
    const auto map = [&](std::span<const mesh::Index> nodes) {
        std::vector<mesh::Index> out;
        for (mesh::Index n : nodes) {
            if (local[n] < 0) {
                local[n] = m.add_node(g.node(n));
                global_of_local.push_back(n);
            }
            out.push_back(local[n]);
        }
        return out;
    };
    for (mesh::Index c = 0; c < g.n_cells(); ++c)
        if (keep[c]) m.add_cell(g.cell_type(c), map(g.cell(c)));
    for (mesh::Index f = 0; f < g.n_faces(); ++f) {
        bool inside = true;
        for (mesh::Index n : g.face(f)) inside = inside && g.node(n).x() < 0.5 + 1e-9;
        if (inside) m.add_face(g.face_type(f), map(g.face(f)), g.face_marker(f));
    }
    return m;
}

TEST(FinalizeOptions, UnmarkedCutFacesAllowedOnlyOnRequest) {
    const auto g = make_box_mesh(4, BoxCells::hexes, 0.0);
    std::vector<mesh::Index> global_of_local;
    auto m = half_box(g, global_of_local);
    EXPECT_THROW(m.finalize(), InputError);
    ASSERT_NO_THROW(m.finalize({.allow_unmarked_exposed_faces = true}));
    EXPECT_TRUE(m.is_finalized());
    // Every other check stays: an inverted cell is still an error.
    auto bad = m;
    std::vector<mesh::Index> cell(bad.cell(0).begin(), bad.cell(0).end());
    std::swap(cell[1], cell[3]);
    std::swap(cell[5], cell[7]);
    bad.add_cell(mesh::CellType::hexa, cell);
    EXPECT_THROW(bad.finalize({.allow_unmarked_exposed_faces = true}), InputError);

    // Dual volumes and boundary normals of the nodes with x <= 0.25 (all their cells present)
    // equal the global ones.
    const auto dl = mesh::compute_dual_metrics(m);
    const auto dg = mesh::compute_dual_metrics(g);
    const auto inner = [&](mesh::Index n) { return m.node(n).x() < 0.3; };
    int checked = 0;
    for (mesh::Index n = 0; n < m.n_nodes(); ++n)
        if (inner(n)) {
            EXPECT_NEAR(dl.dual_volumes[n], dg.dual_volumes[global_of_local[n]], 1e-15);
            ++checked;
        }
    EXPECT_EQ(checked, 2 * 25);
    ASSERT_EQ(dl.boundary.size(), dg.boundary.size());
    int checked_boundary = 0;
    for (std::size_t b = 0; b < dl.boundary.size(); ++b) {
        const auto& bl = dl.boundary[b];
        const auto& bg = dg.boundary[b];
        for (std::size_t k = 0; k < bl.nodes.size(); ++k) {
            if (!inner(bl.nodes[k])) continue;
            const auto it =
                std::lower_bound(bg.nodes.begin(), bg.nodes.end(), global_of_local[bl.nodes[k]]);
            ASSERT_NE(it, bg.nodes.end());
            const auto kg = static_cast<Eigen::Index>(it - bg.nodes.begin());
            EXPECT_LT((bl.normals.col(static_cast<Eigen::Index>(k)) - bg.normals.col(kg)).norm(),
                      1e-15);
            ++checked_boundary;
        }
    }
    EXPECT_GT(checked_boundary, 40);
}

}  // namespace
}  // namespace manta::parallel
