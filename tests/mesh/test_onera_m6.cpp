/// @file test_onera_m6.cpp
/// The SU2 reader and the dual metrics on the coarse ONERA M6 mesh of
/// ../shared/reference/onera_m6 (gmsh 4.8 from SU2's IGES, 10 421 nodes; its README gives the
/// counts and the z-projected WING area SU2 v8.1.0 computed on it, 0.749716 m^2). Skipped when
/// the shared data is absent. Prints the read and metric times and the memory of both.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "manta/mesh/readers.hpp"
#include "manta/mesh/vtu.hpp"
#include "metrics_checks.hpp"

namespace manta::mesh {
namespace {

const std::filesystem::path coarse = std::filesystem::path(MANTA_SHARED_DIR) / "reference" /
                                     "onera_m6" / "mesh_ONERAM6_inv_gmsh_coarse.su2.gz";

TEST(OneraM6, CoarseMeshReadAndClosed) {
    if (!std::filesystem::exists(coarse)) GTEST_SKIP() << coarse << " is absent";
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh m = read_mesh(coarse);
    const auto t1 = std::chrono::steady_clock::now();
    const DualMetrics d = compute_dual_metrics(m);
    const auto t2 = std::chrono::steady_clock::now();
    const double read_s = std::chrono::duration<double>(t1 - t0).count();
    const double dual_s = std::chrono::duration<double>(t2 - t1).count();
    std::printf(
        "ONERA M6 coarse: read %.3f s (%.1f MiB), dual metrics %.3f s (%.1f MiB), %d "
        "edges\n",
        read_s, m.memory_bytes() / 1048576.0, dual_s, d.memory_bytes() / 1048576.0, d.n_edges());

    // Counts from the README of the reference folder.
    EXPECT_EQ(m.n_nodes(), 10421);
    EXPECT_EQ(m.n_cells(), 51001);
    ASSERT_EQ(m.n_markers(), 3);
    EXPECT_EQ(m.markers()[0], "WING");
    EXPECT_EQ(m.markers()[1], "SYMMETRY");
    EXPECT_EQ(m.markers()[2], "FARFIELD");
    std::array<int, 3> faces{};
    for (Index f = 0; f < m.n_faces(); ++f) ++faces[m.face_marker(f)];
    EXPECT_EQ(faces, (std::array<int, 3>{5568, 2236, 844}));

    test::check_dual(m, -1.0);

    // The domain: a half-sphere of radius 11 m minus the half wing; the faceted sphere is a
    // little smaller than the exact one, the wing (about 0.04 m^3) smaller still.
    const double half_sphere = 2.0 / 3.0 * M_PI * 11.0 * 11.0 * 11.0;
    EXPECT_NEAR(m.volume() / half_sphere, 1.0, 0.02);

    // z-projected WING area as SU2 computes it (sum of the positive z components of the vertex
    // normals): 0.749716 m^2 (reference README).
    const auto& wing = d.boundary[0];
    double up = 0.0, down = 0.0;
    for (Eigen::Index k = 0; k < wing.normals.cols(); ++k) {
        up += std::max(0.0, wing.normals(2, k));
        down += std::max(0.0, -wing.normals(2, k));
    }
    std::printf("WING z-projected area: %.6f (+z) %.6f (-z) m^2\n", up, down);
    EXPECT_NEAR(up, 0.749716, 5e-6);
    EXPECT_NEAR(down, 0.749716, 5e-6);

    // Symmetry plane y = 0, facing -y (out of the domain y > 0).
    const auto& sym = d.boundary[1];
    EXPECT_NEAR(sym.normals.row(0).cwiseAbs().maxCoeff(), 0.0, 1e-12);
    EXPECT_NEAR(sym.normals.row(2).cwiseAbs().maxCoeff(), 0.0, 1e-12);
    EXPECT_LT(sym.normals.row(1).maxCoeff(), 0.0);

    const auto dir = std::filesystem::temp_directory_path() / "manta-mesh-om6";
    write_vtu_surface(dir / "surface.vtu", m);
    write_vtu_volume(dir / "volume.vtu", m, {{"dual_volume", d.dual_volumes}});
    EXPECT_GT(std::filesystem::file_size(dir / "volume.vtu"), 1000000u);
}

}  // namespace
}  // namespace manta::mesh
