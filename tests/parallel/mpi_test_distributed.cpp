/// @file mpi_test_distributed.cpp
/// Two-process tests of the MPI communicator, the distribution of a mesh and the halo, run by
/// ctest under `mpirun -np 2` (tests/parallel/CMakeLists.txt). Every process builds the same
/// global mesh to compare with; only rank 0 hands it to `distribute`. Started without an MPI
/// launcher, the program runs the same checks with one process.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "box_mesh.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/dual.hpp"
#include "manta/mesh/readers.hpp"
#include "manta/parallel/distributed.hpp"
#include "manta/parallel/mpi.hpp"

namespace manta::parallel {
namespace {

const Communicator* world = nullptr;

using test::BoxCells;
using test::make_box_mesh;

TEST(MpiCommunicator, Reductions) {
    const auto& c = *world;
    const int n = c.size();
    EXPECT_EQ(c.sum(c.rank() + 1.0), n * (n + 1) / 2.0);
    EXPECT_EQ(c.max(c.rank() + 0.5), n - 0.5);
    EXPECT_EQ(c.min(c.rank() + 0.5), 0.5);
    std::vector<double> v{1.0, static_cast<double>(c.rank())};
    c.sum(v);
    EXPECT_EQ(v[0], n);
    EXPECT_EQ(v[1], n * (n - 1) / 2.0);
    c.barrier();
}

/// A test value of component k at global node g.
double value(std::int64_t g, int k) {
    return 1000.0 * static_cast<double>(g) + k + 0.25;
}

/// The checks of a distributed mesh against the global one, which every process holds.
void check_distribution(const mesh::Mesh& global) {
    const auto& c = *world;
    const auto lm = distribute(c.rank() == 0 ? &global : nullptr, c);
    const auto& m = lm.mesh;
    ASSERT_TRUE(m.is_finalized());
    EXPECT_EQ(lm.n_global_nodes, global.n_nodes());
    EXPECT_EQ(m.markers(), global.markers());
    ASSERT_EQ(lm.global_node.size(), static_cast<std::size_t>(m.n_nodes()));
    EXPECT_TRUE(std::is_sorted(lm.global_node.begin(), lm.global_node.begin() + lm.n_owned));
    EXPECT_TRUE(std::is_sorted(lm.global_node.begin() + lm.n_owned, lm.global_node.end()));
    for (mesh::Index n = 0; n < m.n_nodes(); ++n)
        ASSERT_EQ(m.node(n), global.node(static_cast<mesh::Index>(lm.global_node[n])));
    if (c.size() > 1) {
        EXPECT_GT(lm.n_ghosts(), 0);
        EXPECT_LT(lm.n_owned, global.n_nodes());
    }

    // The owned nodes of all processes are every global node exactly once.
    std::vector<double> owners(static_cast<std::size_t>(global.n_nodes()), 0.0);
    for (mesh::Index n = 0; n < lm.n_owned; ++n) owners[lm.global_node[n]] += 1.0;
    c.sum(owners);
    EXPECT_TRUE(std::all_of(owners.begin(), owners.end(), [](double o) { return o == 1.0; }));
    // Each boundary face of the global mesh is on some process, on the same marker.
    std::vector<double> faces_per_marker(global.markers().size(), 0.0);
    for (mesh::Index f = 0; f < m.n_faces(); ++f) faces_per_marker[m.face_marker(f)] += 1.0;
    c.sum(faces_per_marker);
    for (int k = 0; k < global.n_markers(); ++k) {
        std::int64_t n_global = 0;
        for (mesh::Index f = 0; f < global.n_faces(); ++f) n_global += global.face_marker(f) == k;
        EXPECT_GE(faces_per_marker[k], static_cast<double>(n_global));
    }

    // Dual metrics of owned nodes, and of edges with an owned node, equal the global ones.
    const auto dl = mesh::compute_dual_metrics(m);
    const auto dg = mesh::compute_dual_metrics(global);
    const double v_scale = global.volume() / global.n_nodes();
    double owned_volume = 0.0;
    for (mesh::Index n = 0; n < lm.n_owned; ++n) {
        EXPECT_NEAR(dl.dual_volumes[n], dg.dual_volumes[lm.global_node[n]], 1e-12 * v_scale);
        owned_volume += dl.dual_volumes[n];
    }
    EXPECT_NEAR(c.sum(owned_volume), global.volume(), 1e-12 * global.volume());
    double a_scale = 0.0;
    for (Eigen::Index e = 0; e < dg.edge_normals.cols(); ++e)
        a_scale = std::max(a_scale, dg.edge_normals.col(e).norm());
    std::vector<double> edge_seen(dg.edges.size(), 0.0);
    for (mesh::Index e = 0; e < dl.n_edges(); ++e) {
        const auto [i, j] = dl.edges[e];
        if (i >= lm.n_owned && j >= lm.n_owned) continue;
        auto gi = static_cast<mesh::Index>(lm.global_node[i]);
        auto gj = static_cast<mesh::Index>(lm.global_node[j]);
        const double sign = gi < gj ? 1.0 : -1.0;
        if (gi > gj) std::swap(gi, gj);
        const auto it =
            std::lower_bound(dg.edges.begin(), dg.edges.end(), std::array<mesh::Index, 2>{gi, gj});
        ASSERT_TRUE(it != dg.edges.end() && (*it == std::array<mesh::Index, 2>{gi, gj}));
        const auto eg = it - dg.edges.begin();
        EXPECT_LT((sign * dl.edge_normals.col(e) - dg.edge_normals.col(eg)).norm(),
                  1e-12 * a_scale);
        edge_seen[static_cast<std::size_t>(eg)] = 1.0;
    }
    c.sum(edge_seen);
    EXPECT_TRUE(std::all_of(edge_seen.begin(), edge_seen.end(), [](double s) { return s >= 1.0; }))
        << "some global edge has an owned node on no process";
    for (int b = 0; b < global.n_markers(); ++b) {
        const auto& bl = dl.boundary[b];
        const auto& bg = dg.boundary[b];
        double n_owned_here = 0.0;
        for (std::size_t k = 0; k < bl.nodes.size(); ++k) {
            if (bl.nodes[k] >= lm.n_owned) continue;
            n_owned_here += 1.0;
            const auto g = static_cast<mesh::Index>(lm.global_node[bl.nodes[k]]);
            const auto it = std::lower_bound(bg.nodes.begin(), bg.nodes.end(), g);
            ASSERT_TRUE(it != bg.nodes.end() && *it == g);
            const auto kg = it - bg.nodes.begin();
            EXPECT_LT((bl.normals.col(static_cast<Eigen::Index>(k)) - bg.normals.col(kg)).norm(),
                      1e-12 * a_scale);
        }
        // Every node of the marker is owned by exactly one process.
        EXPECT_EQ(c.sum(n_owned_here), static_cast<double>(bg.nodes.size())) << global.markers()[b];
    }

    // The halo delivers owned values to the ghosts, for any number of components (twice, so
    // the reused buffers are exercised with different sizes).
    for (const int nc : {5, 1, 3}) {
        std::vector<double> data(static_cast<std::size_t>(m.n_nodes()) * nc,
                                 std::numeric_limits<double>::quiet_NaN());
        for (mesh::Index n = 0; n < lm.n_owned; ++n)
            for (int k = 0; k < nc; ++k) data[n * nc + k] = value(lm.global_node[n], k);
        lm.halo->exchange(data, nc);
        for (mesh::Index n = 0; n < m.n_nodes(); ++n)
            for (int k = 0; k < nc; ++k)
                ASSERT_EQ(data[n * nc + k], value(lm.global_node[n], k))
                    << "node " << n << " (global " << lm.global_node[n] << ") of " << m.n_nodes()
                    << ", owned " << lm.n_owned << ", component " << k << " of " << nc;
    }

    // Gather restores the global order on rank 0; sums over owned nodes count each node once.
    std::vector<double> local(static_cast<std::size_t>(lm.n_owned) * 2);
    for (mesh::Index n = 0; n < lm.n_owned; ++n)
        for (int k = 0; k < 2; ++k) local[n * 2 + k] = value(lm.global_node[n], k);
    const auto all = gather_owned(lm, local, 2, c);
    if (c.rank() == 0) {
        ASSERT_EQ(all.size(), 2 * static_cast<std::size_t>(global.n_nodes()));
        for (mesh::Index g = 0; g < global.n_nodes(); ++g)
            for (int k = 0; k < 2; ++k) ASSERT_EQ(all[g * 2 + k], value(g, k));
    } else {
        EXPECT_TRUE(all.empty());
    }
    const auto sums = sum_owned(lm, local, 2, c);
    const double n = global.n_nodes();
    EXPECT_DOUBLE_EQ(sums[0], 1000.0 * n * (n - 1) / 2 + 0.25 * n);
    EXPECT_DOUBLE_EQ(sums[1], 1000.0 * n * (n - 1) / 2 + 1.25 * n);
}

TEST(Distribute, Tetrahedra) {
    check_distribution(make_box_mesh(8, BoxCells::tets));
}

TEST(Distribute, Hexahedra) {
    check_distribution(make_box_mesh(8, BoxCells::hexes));
}

TEST(Distribute, HexahedraAndPrisms) {
    check_distribution(make_box_mesh(8, BoxCells::mixed));
}

TEST(Distribute, OneraM6CoarseMesh) {
    const std::filesystem::path file = std::filesystem::path(MANTA_SHARED_DIR) /
                                       "reference/onera_m6/mesh_ONERAM6_inv_gmsh_coarse.su2.gz";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not found";
    check_distribution(mesh::read_mesh(file));
}

TEST(Distribute, AnErrorOnRankZeroReachesEveryProcess) {
    // Rank 0 passes no mesh, then a mesh that is not finalized: every process gets the
    // InputError, with rank 0's message.
    EXPECT_THROW((void)distribute(nullptr, *world), InputError);
    mesh::Mesh open("open.su2");
    open.add_node({0.0, 0.0, 0.0});
    try {
        (void)distribute(&open, *world);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(
            std::string(e.what()).find("open.su2: distributing a mesh needs a finalized mesh"),
            std::string::npos)
            << e.what();
    }
    // The communicator still works afterwards.
    EXPECT_EQ(world->sum(1.0), world->size());
}

TEST(RethrowRootError, EveryProcessThrowsRankZerosError) {
    const auto& c = *world;
    std::exception_ptr err;
    if (c.rank() == 0) {
        try {
            throw IoError("wing.su2: cannot open the file");
        } catch (...) {
            err = std::current_exception();
        }
    }
    try {
        rethrow_root_error(err, c);
        ADD_FAILURE() << "no error on rank " << c.rank();
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("wing.su2: cannot open the file", 0), 0u) << e.what();
    }
    EXPECT_NO_THROW(rethrow_root_error(nullptr, c));
    EXPECT_EQ(c.sum(1.0), c.size());
}

}  // namespace
}  // namespace manta::parallel

/// MPI is started before the tests and stopped after them; the exit status is the worst of all
/// processes, so a failure on any rank fails the ctest test.
int main(int argc, char** argv) {
    const manta::parallel::MpiEnvironment env;
    manta::parallel::world = &env.communicator();
    ::testing::InitGoogleTest(&argc, argv);
    const int rc = RUN_ALL_TESTS();
    return static_cast<int>(env.communicator().max(static_cast<double>(rc)));
}
