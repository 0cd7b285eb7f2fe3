#pragma once
/// @file metrics_checks.hpp
/// Property checks of the median-dual metrics shared by the mesh tests: every dual cell closed,
/// dual volumes summing to the mesh volume, boundary normals summing to zero over the closed
/// boundary (Blazek, *Computational Fluid Dynamics: Principles and Applications*, 3rd ed.,
/// 2015, sec. 5.2: the discrete form of the divergence theorem for a constant field).

#include <gtest/gtest.h>

#include <cmath>

#include "manta/mesh/dual.hpp"

namespace manta::mesh::test {

/// Check the closure properties; `volume` is the exact domain volume (m^3), or < 0 to skip it.
inline DualMetrics check_dual(const Mesh& mesh, double volume) {
    const DualMetrics d = compute_dual_metrics(mesh);
    EXPECT_LT(max_closure_defect(mesh, d), 1e-12) << mesh.source();
    double vsum = 0.0;
    for (double v : d.dual_volumes) {
        EXPECT_GT(v, 0.0);
        vsum += v;
    }
    EXPECT_NEAR(vsum, mesh.volume(), 1e-12 * mesh.volume());
    if (volume > 0.0) {
        EXPECT_NEAR(vsum, volume, 1e-10 * volume) << mesh.source();
    }
    Eigen::Vector3d nsum = Eigen::Vector3d::Zero();
    double area = 0.0;
    for (const auto& bv : d.boundary)
        for (Eigen::Index k = 0; k < bv.normals.cols(); ++k) {
            nsum += bv.normals.col(k);
            area += bv.normals.col(k).norm();
        }
    EXPECT_LT(nsum.norm(), 1e-13 * area) << mesh.source();
    // Each edge appears once per endpoint in the CSR adjacency.
    EXPECT_EQ(d.node_edges.size(), 2 * d.edges.size());
    return d;
}

}  // namespace manta::mesh::test
