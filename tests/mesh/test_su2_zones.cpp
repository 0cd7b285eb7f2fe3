/// @file test_su2_zones.cpp
/// SU2 multi-zone files (NZONE=, IZONE=; SU2 documentation, "Mesh File"): a gmsh box split
/// into three zones with nodes repeated on the interfaces reads back to the single-zone mesh;
/// zones that do not touch, a missing zone and node numbers beyond a zone's NPOIN= give
/// one-line errors naming the file.

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "gmsh_fixtures.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/readers.hpp"
#include "metrics_checks.hpp"
#include "zone_split.hpp"

namespace manta::mesh {
namespace {

namespace fs = std::filesystem;

std::map<std::string, int> faces_per_marker(const Mesh& m) {
    std::map<std::string, int> out;
    for (Index f = 0; f < m.n_faces(); ++f) ++out[m.markers()[m.face_marker(f)]];
    return out;
}

std::string slurp(const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string error_of(const std::string& text) {
    try {
        (void)parse_su2(text, "z.su2");
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

TEST(Su2Zones, ZonesAreJoinedToTheSingleZoneMesh) {
    const fs::path dir = test::scratch_dir("su2-zones");
    for (auto kind : {test::BoxKind::tets, test::BoxKind::prisms, test::BoxKind::hexes}) {
        const fs::path msh = dir / "box.msh";
        test::make_box(kind, 1.5, 0.5, 0.5, 0.25, {msh});
        const Mesh ref = read_gmsh(msh);
        const auto zones = test::split_by_x(ref, {0.45, 1.05});
        for (const auto& z : zones) ASSERT_FALSE(z.cells.empty());
        for (const std::string interface : {"interface", ""}) {
            SCOPED_TRACE(::testing::Message() << "kind " << static_cast<int>(kind)
                                              << " interface marker '" << interface << "'");
            const fs::path f = dir / "zones.su2";
            test::write_su2_zones(ref, zones, f, interface);
            const Mesh m = read_mesh(f);
            EXPECT_EQ(m.n_nodes(), ref.n_nodes());
            EXPECT_EQ(m.n_cells(), ref.n_cells());
            EXPECT_EQ(m.n_faces(), ref.n_faces());
            EXPECT_EQ(faces_per_marker(m), faces_per_marker(ref));
            EXPECT_NEAR(m.volume(), ref.volume(), 1e-13);
            test::check_dual(m, 1.5 * 0.5 * 0.5);
        }
    }
}

TEST(Su2Zones, ErrorsNameFileAndZone) {
    const fs::path dir = test::scratch_dir("su2-zones");
    const fs::path msh = dir / "ebox.msh";
    test::make_box(test::BoxKind::hexes, 1.5, 0.5, 0.5, 0.25, {msh});
    const Mesh ref = read_gmsh(msh);
    const auto zones = test::split_by_x(ref, {0.45, 1.05});
    // Zones 1 and 3 only: they do not touch.
    test::write_su2_zones(ref, {zones[0], zones[2]}, dir / "apart.su2");
    EXPECT_EQ(error_of(slurp(dir / "apart.su2")),
              "z.su2: NZONE= 2: zone 2 shares no node with zone 1; expected zones that meet at "
              "coincident nodes (zones joined by sliding or non-matching interfaces are not read)");
    test::write_su2_zones(ref, zones, dir / "three.su2");
    const std::string text = slurp(dir / "three.su2");
    EXPECT_EQ(error_of(text.substr(0, text.find("IZONE= 3"))),
              "z.su2: the file ends after zone 2 of NZONE= 3; expected 1 more (truncated file?)");
    std::string skip = text;
    skip.replace(skip.find("IZONE= 2"), 8, "IZONE= 3");
    EXPECT_NE(error_of(skip).find(": IZONE= 3; expected 2 of NZONE= 3"), std::string::npos)
        << error_of(skip);
    // A node number of zone 1 beyond its NPOIN= (it would name a node of zone 2).
    std::string dangling = text;
    const std::size_t elem = dangling.find('\n', dangling.find("NELEM=")) + 1;
    dangling.replace(elem, dangling.find('\n', elem) - elem, "12 0 1 2 3 4 5 6 99999");
    EXPECT_NE(error_of(dangling).find("z.su2: line 5: node number 99999 of zone 1; expected 0 to"),
              std::string::npos)
        << error_of(dangling);
    EXPECT_NE(
        error_of("NZONE= 2\nIZONE= 1\nNDIME= 3\nNELEM= 0\nNPOIN= 0\nIZONE= 2\nNDIME= 2\nNELEM= 0\n")
            .find("z.su2: line 7: NDIME= 2 in zone 2; expected 3 as in the zones before"),
        std::string::npos);
}

}  // namespace
}  // namespace manta::mesh
