/// @file test_ranger_levels_slow.cpp
/// The half Ranger 2000 at the three levels of `manta mesh` (minutes): each closed with positive
/// volumes and the expected markers, the node counts about 2.5x apart (within 1.8x to 3.5x).
/// Prints the nodes, cells, quality and times that docs/meshgen.md quotes.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "manta/aircraft/aircraft.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "ranger_text.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta;

meshgen::MeshResult level(meshgen::Level l, meshgen::Model model = meshgen::Model::half) {
    static const auto a = aircraft::load_aircraft(test::ranger_file);
    const fs::path dir =
        fs::temp_directory_path() / ("manta-meshgen-levels-" + std::to_string(getpid()));
    fs::create_directories(dir);
    meshgen::MeshOptions o;
    o.level = l;
    o.model = model;
    auto r = meshgen::generate_mesh(a, o, dir / (std::string(meshgen::to_string(l)) + ".su2"));
    const auto& q = r.quality;
    std::printf(
        "%s %s: %lld nodes, %lld cells, dihedral %.2f-%.2f deg, %lld slivers, volume "
        "ratio %.1f, closed %d, positive %d, CAD %.1f s, mesh %.1f s, total %.1f s\n",
        std::string(meshgen::to_string(model)).c_str(), std::string(meshgen::to_string(l)).c_str(),
        q.nodes, q.cells, q.min_dihedral_deg, q.max_dihedral_deg, q.slivers, q.max_volume_ratio,
        q.surface_closed, q.volume_positive, r.seconds_cad, r.seconds_mesh, r.seconds_total);
    EXPECT_TRUE(q.surface_closed);
    EXPECT_TRUE(q.volume_positive);
    return r;
}

TEST(RangerLevels, NodesAbout2p5xApart) {
    const auto coarse = level(meshgen::Level::coarse);
    const auto medium = level(meshgen::Level::medium);
    const auto fine = level(meshgen::Level::fine);
    const double r1 = static_cast<double>(medium.quality.nodes) / coarse.quality.nodes;
    const double r2 = static_cast<double>(fine.quality.nodes) / medium.quality.nodes;
    EXPECT_GT(r1, 1.8);
    EXPECT_LT(r1, 3.5);
    EXPECT_GT(r2, 1.8);
    EXPECT_LT(r2, 3.5);
}

TEST(RangerLevels, FullCoarse) {
    const auto r = level(meshgen::Level::coarse, meshgen::Model::full);
    EXPECT_EQ(r.markers.size(), 7u);
}

}  // namespace
