/// @file test_onera_m6_slow.cpp
/// The fine ONERA M6 mesh of ../shared/reference/onera_m6 (108 797 nodes, 601 732 tetrahedra;
/// z-projected WING area from SU2 v8.1.0 on the same mesh: 0.757168 m^2, reference README):
/// read, closed dual cells, and the times and memory printed for docs/mesh.md. Label slow.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "manta/mesh/readers.hpp"
#include "metrics_checks.hpp"

namespace manta::mesh {
namespace {

const std::filesystem::path fine = std::filesystem::path(MANTA_SHARED_DIR) / "reference" /
                                   "onera_m6" / "mesh_ONERAM6_inv_gmsh.su2.gz";

TEST(OneraM6, FineMeshReadAndClosed) {
    if (!std::filesystem::exists(fine)) GTEST_SKIP() << fine << " is absent";
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh m = read_mesh(fine);
    const auto t1 = std::chrono::steady_clock::now();
    const DualMetrics d = test::check_dual(m, -1.0);
    const auto t2 = std::chrono::steady_clock::now();
    std::printf(
        "ONERA M6 fine: read %.3f s (%.1f MiB), dual metrics and checks %.3f s (%.1f "
        "MiB), %d edges\n",
        std::chrono::duration<double>(t1 - t0).count(), m.memory_bytes() / 1048576.0,
        std::chrono::duration<double>(t2 - t1).count(), d.memory_bytes() / 1048576.0, d.n_edges());
    EXPECT_EQ(m.n_nodes(), 108797);
    EXPECT_EQ(m.n_cells(), 601732);
    double up = 0.0;
    for (Eigen::Index k = 0; k < d.boundary[0].normals.cols(); ++k)
        up += std::max(0.0, d.boundary[0].normals(2, k));
    std::printf("WING z-projected area: %.6f m^2\n", up);
    EXPECT_NEAR(up, 0.757168, 5e-6);
}

}  // namespace
}  // namespace manta::mesh
