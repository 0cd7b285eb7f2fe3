/// @file test_readers.cpp
/// The SU2 and gmsh readers on meshes the gmsh API makes (a box of tetrahedra, prisms,
/// hexahedra, tetrahedra with pyramids; a rectangle extruded into a slab), each read back from
/// MSH 4.1, MSH 2.2 and SU2 (also gzip-compressed) and checked for volume and dual closure; and
/// their error messages on broken files.

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "gmsh_fixtures.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/mesh/readers.hpp"
#include "metrics_checks.hpp"

namespace manta::mesh {
namespace {

namespace fs = std::filesystem;

void gzip(const fs::path& from, const fs::path& to) {
    const std::string s = core::read_file(from);
    gzFile g = gzopen(to.string().c_str(), "wb");
    ASSERT_NE(g, nullptr);
    gzwrite(g, s.data(), static_cast<unsigned>(s.size()));
    gzclose(g);
}

int count_cells(const Mesh& m, CellType t) {
    int n = 0;
    for (Index c = 0; c < m.n_cells(); ++c) n += m.cell_type(c) == t;
    return n;
}

struct BoxCase {
    test::BoxKind kind;
    const char* name;
    CellType main_type;
};

class BoxReaders : public ::testing::TestWithParam<BoxCase> {};

TEST_P(BoxReaders, AllFormatsGiveTheSameClosedMesh) {
    const auto& c = GetParam();
    const fs::path dir = test::scratch_dir("readers");
    const fs::path msh41 = dir / (std::string(c.name) + "41.msh");
    const fs::path msh22 = dir / (std::string(c.name) + "22.msh");
    const fs::path su2 = dir / (std::string(c.name) + ".su2");
    const fs::path su2gz = dir / (std::string(c.name) + ".su2.gz");
    const double lx = 1.0, ly = 0.75, lz = 0.5, h = 0.25;
    test::make_box(c.kind, lx, ly, lz, h, {msh41, su2});
    test::make_box(c.kind, lx, ly, lz, h, {msh22}, 2.2);
    gzip(su2, su2gz);
    const Mesh a = read_mesh(msh41);
    const Mesh b = read_mesh(msh22);
    const Mesh s = read_mesh(su2);
    const Mesh z = read_mesh(su2gz);
    EXPECT_GT(count_cells(a, c.main_type), 0);
    for (const Mesh* m : {&a, &b, &s, &z}) {
        SCOPED_TRACE(m->source());
        EXPECT_EQ(m->n_nodes(), a.n_nodes());
        EXPECT_EQ(m->n_cells(), a.n_cells());
        EXPECT_EQ(m->n_faces(), a.n_faces());
        EXPECT_EQ(m->n_markers(), 6);
        EXPECT_NEAR(m->volume(), lx * ly * lz, 1e-12);
        test::check_dual(*m, lx * ly * lz);
    }
}

INSTANTIATE_TEST_SUITE_P(Mesh, BoxReaders,
                         ::testing::Values(BoxCase{test::BoxKind::tets, "tets", CellType::tetra},
                                           BoxCase{test::BoxKind::prisms, "prisms",
                                                   CellType::prism},
                                           BoxCase{test::BoxKind::hexes, "hexes", CellType::hexa}),
                         [](const auto& info) { return std::string(info.param.name); });

/// SU2 text of a mesh (cells, points, markers).
std::string to_su2(const Mesh& m) {
    std::string s = fmt::format("NDIME= 3\nNELEM= {}\n", m.n_cells());
    for (Index c = 0; c < m.n_cells(); ++c)
        s += fmt::format("{} {} {}\n", static_cast<int>(m.cell_type(c)), fmt::join(m.cell(c), " "),
                         c);
    s += fmt::format("NPOIN= {}\n", m.n_nodes());
    for (Index i = 0; i < m.n_nodes(); ++i) {
        const auto p = m.node(i);
        s += fmt::format("{} {} {} {}\n", p.x(), p.y(), p.z(), i);
    }
    s += fmt::format("NMARK= {}\n", m.n_markers());
    for (int k = 0; k < m.n_markers(); ++k) {
        std::string body;
        int n = 0;
        for (Index f = 0; f < m.n_faces(); ++f)
            if (m.face_marker(f) == k) {
                body += fmt::format("{} {}\n", static_cast<int>(m.face_type(f)),
                                    fmt::join(m.face(f), " "));
                ++n;
            }
        s += fmt::format("MARKER_TAG= {}\nMARKER_ELEMS= {}\n{}", m.markers()[k], n, body);
    }
    return s;
}

/// A box of hexahedra (gmsh) with every other hexahedron split into six pyramids about its
/// centre: hexahedra and pyramids share quadrilateral faces. Written as SU2 text, read back.
TEST(Readers, HexahedraAndPyramids) {
    const fs::path dir = test::scratch_dir("readers");
    const fs::path f = dir / "hexes_for_pyramids.msh";
    test::make_box(test::BoxKind::hexes, 1.0, 0.75, 0.5, 0.25, {f});
    const Mesh hex = read_gmsh(f);
    Mesh m("split");
    for (Index i = 0; i < hex.n_nodes(); ++i) m.add_node(hex.node(i));
    for (Index c = 0; c < hex.n_cells(); ++c) {
        const auto n = hex.cell(c);
        if (c % 2 == 0) {
            m.add_cell(CellType::hexa, n);
            continue;
        }
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (Index k : n) centre += hex.node(k) / 8.0;
        const Index apex = m.add_node(centre);
        for (const auto& lf : cell_faces(CellType::hexa)) {
            // Outward hexahedron face reversed: the pyramid base's normal points to the apex.
            const std::vector<Index> p{n[lf[0]], n[lf[3]], n[lf[2]], n[lf[1]], apex};
            m.add_cell(CellType::pyramid, p);
        }
    }
    for (const auto& name : hex.markers()) m.add_marker(name);
    for (Index b = 0; b < hex.n_faces(); ++b)
        m.add_face(hex.face_type(b), hex.face(b), hex.face_marker(b));
    m.finalize();
    const Mesh back = parse_su2(to_su2(m), "pyramids.su2");
    EXPECT_GT(count_cells(back, CellType::pyramid), 0);
    EXPECT_GT(count_cells(back, CellType::hexa), 0);
    EXPECT_EQ(back.n_cells(), m.n_cells());
    test::check_dual(back, 1.0 * 0.75 * 0.5);
}

TEST(Readers, PlaneMeshBecomesSlab) {
    const fs::path dir = test::scratch_dir("readers");
    for (bool quads : {false, true})
        for (double version : {2.2, 4.1}) {
            const fs::path f = dir / fmt::format("rect_{}_{}.msh", quads, version);
            test::make_rectangle(2.0, 1.0, 0.3, quads, f, version);
            ReadOptions opt;
            opt.slab_thickness = 0.1;
            const Mesh m = read_gmsh(f, opt);
            SCOPED_TRACE(f.string());
            EXPECT_EQ(count_cells(m, quads ? CellType::hexa : CellType::prism), m.n_cells());
            EXPECT_NEAR(m.volume(), 0.2, 1e-12);
            EXPECT_GE(m.find_marker("symmetry_back"), 0);
            EXPECT_GE(m.find_marker("symmetry_front"), 0);
            EXPECT_EQ(m.n_markers(), 6);
            const DualMetrics d = test::check_dual(m, 0.2);
            // Symmetry-plane normals: along -z on the back, +z on the front, area lx * ly.
            for (const char* name : {"symmetry_back", "symmetry_front"}) {
                const auto& bv = d.boundary[m.find_marker(name)];
                const Eigen::Vector3d sum = bv.normals.rowwise().sum();
                const double sign = std::string(name) == "symmetry_back" ? -1.0 : 1.0;
                EXPECT_NEAR(sum.z(), sign * 2.0, 1e-12);
                EXPECT_NEAR(sum.head<2>().norm(), 0.0, 1e-12);
            }
        }
}

TEST(Readers, Su2TextIn2D) {
    // Two triangles of the unit square, markers on its four sides.
    const std::string text =
        "% unit square\nNDIME= 2\nNELEM= 2\n5 0 1 2 0\n5 0 2 3 1\nNPOIN= 4\n0 0 0\n1 0 1\n1 1 "
        "2\n0 1 3\nNMARK= 2\nMARKER_TAG= wall\nMARKER_ELEMS= 2\n3 0 1\n3 1 2\nMARKER_TAG= "
        "farfield\nMARKER_ELEMS= 2\n3 2 3\n3 3 0\n";
    const Mesh m = parse_su2(text, "square.su2");
    EXPECT_EQ(m.n_nodes(), 8);
    EXPECT_EQ(m.n_cells(), 2);
    EXPECT_NEAR(m.volume(), 1.0, 1e-15);
    EXPECT_EQ(m.n_markers(), 4);
    test::check_dual(m, 1.0);
}

void expect_message(const std::function<void()>& f, const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "no error, expected one with: " << part;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
}

TEST(Readers, Su2ErrorsNameFileAndLine) {
    const std::string head = "NDIME= 3\nNELEM= 1\n";
    const std::string points = "NPOIN= 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    const std::string marks =
        "NMARK= 1\nMARKER_TAG= wall\nMARKER_ELEMS= 4\n5 0 2 1\n5 0 1 3\n5 1 2 3\n5 0 3 2\n";
    ASSERT_NO_THROW((void)parse_su2(head + "10 0 1 2 3\n" + points + marks, "ok.su2"));
    expect_message([&] { (void)parse_su2(head + "11 0 1 2 3\n" + points + marks, "t.su2"); },
                   "t.su2: line 3: unknown element type 11; expected a VTK type id");
    expect_message([&] { (void)parse_su2(head + "10 0 1 2 9\n" + points + marks, "t.su2"); },
                   "t.su2: line 3: cell 0 (tetra) refers to node 9; expected 0 to 3");
    expect_message([&] { (void)parse_su2(head + "10 0 2 1 3\n" + points + marks, "t.su2"); },
                   "t.su2: line 3: cell 0 (tetra) has volume -0.166667 m^3; expected > 0");
    expect_message([&] { (void)parse_su2(head + "10 0 1 2\n" + points + marks, "t.su2"); },
                   "t.su2: line 3: element type 10 with 3 numbers after the type; expected 4");
    expect_message(
        [&] { (void)parse_su2(head + "10 0 1 2 3\nNPOIN= 4\n0 0 0\n1 0 0\n", "t.su2"); },
        "t.su2: end of file after 2 of the 4 points of NPOIN= (line 4); expected 2 more");
    expect_message(
        [&] {
            (void)parse_su2(head + "10 0 1 2 3\n" + points +
                                "NMARK= 1\nMARKER_TAG= "
                                "wall\nMARKER_ELEMS= 4\n5 0 2 1\n",
                            "t.su2");
        },
        "end of file after 1 of the 4 elements of marker 'wall' (line 11)");
    expect_message([&] { (void)parse_su2(head + "10 0 1 2 3\n" + points, "t.su2"); },
                   "4 cell faces on the boundary belong to no marker");
    expect_message([&] { (void)parse_su2(head + "10 0 x 2 3\n" + points + marks, "t.su2"); },
                   "t.su2: line 3: 'x' is not a valid node number");
}

TEST(Readers, GmshErrorsNameFileAndLine) {
    const std::string fmt22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
    const std::string names = "$PhysicalNames\n1\n2 1 \"wall\"\n$EndPhysicalNames\n";
    const std::string nodes = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";
    const std::string elems =
        "$Elements\n5\n1 4 2 0 1 1 2 3 4\n2 2 2 1 1 1 3 2\n3 2 2 1 1 1 2 4\n4 2 2 1 1 2 3 4\n5 2 2 "
        "1 1 1 4 3\n$EndElements\n";
    ASSERT_NO_THROW((void)parse_gmsh(fmt22 + names + nodes + elems, "ok.msh"));
    expect_message([&] { (void)parse_gmsh("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", "b.msh"); },
                   "b.msh: byte 20: the binary integer 1684948260; expected 1 in either byte "
                   "order");
    expect_message([&] { (void)parse_gmsh("$MeshFormat\n4.1 1 6\n", "d.msh"); },
                   "d.msh: line 2: data size 6; expected 4 or 8 (sizeof(size_t))");
    expect_message([&] { (void)parse_gmsh("$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", "v.msh"); },
                   "v.msh: line 2: MSH version 3; expected 2.2 or 4.1");
    std::string bad = elems;
    bad.replace(bad.find("1 4 2 0 1 1 2 3 4"), 17, "1 4 2 0 1 1 2 3 9");
    expect_message([&] { (void)parse_gmsh(fmt22 + names + nodes + bad, "n.msh"); },
                   "n.msh: line 17: node tag 9 is not in $Nodes");
    bad = elems;
    bad.replace(bad.find("1 4 2 0 1"), 9, "1 11 2 0 1");
    expect_message([&] { (void)parse_gmsh(fmt22 + names + nodes + bad, "t.msh"); },
                   "t.msh: line 17: element type 11 is not supported");
    expect_message([&] { (void)parse_gmsh(fmt22 + nodes + elems, "u.msh"); },
                   "u.msh: line 14: physical group 1 (dimension 2) has no name");
    expect_message(
        [&] {
            (void)parse_gmsh(fmt22 + names + "$Nodes\n5\n1 0 0 0\n2 1 0 0\n$EndNodes\n", "c.msh");
        },
        "c.msh: line 12: '$EndNodes': the section ends early; expected node 3 of 5");
}

/// Truncated and corrupted files give manta errors, never another exception or a crash (a
/// small deterministic stand-in for the fuzz targets of issue 7).
TEST(Readers, DamagedFilesGiveInputErrors) {
    const fs::path dir = test::scratch_dir("readers");
    test::make_box(test::BoxKind::prisms, 1.0, 0.5, 0.5, 0.25, {dir / "d41.msh", dir / "d.su2"});
    test::make_box(test::BoxKind::prisms, 1.0, 0.5, 0.5, 0.25, {dir / "d22.msh"}, 2.2);
    std::mt19937 rng(11);
    int errors = 0, runs = 0;
    for (const char* name : {"d41.msh", "d22.msh", "d.su2"}) {
        const std::string text = core::read_file(dir / name);
        const bool su2 = std::string(name).ends_with(".su2");
        const auto parse = [su2](const std::string& t) {
            if (su2)
                (void)parse_su2(t, "x.su2");
            else
                (void)parse_gmsh(t, "x.msh");
        };
        std::vector<std::string> cases;
        for (std::size_t cut = 0; cut < text.size(); cut += 1 + text.size() / 150)
            cases.push_back(text.substr(0, cut));
        const std::string junk = "0123456789 -.e\n$%=x";
        for (int k = 0; k < 150; ++k) {
            std::string t = text;
            for (int j = 0; j < 3; ++j)
                t[std::uniform_int_distribution<std::size_t>(0, t.size() - 1)(rng)] =
                    junk[std::uniform_int_distribution<std::size_t>(0, junk.size() - 1)(rng)];
            cases.push_back(t);
        }
        for (const auto& t : cases) {
            ++runs;
            try {
                parse(t);
            } catch (const Error&) {
                ++errors;
            } catch (const std::exception& e) {
                ADD_FAILURE() << name << ": not a manta error: " << e.what();
            }
        }
    }
    EXPECT_GT(errors, runs / 2);
}

TEST(Readers, UnknownExtensionAndMissingFile) {
    EXPECT_THROW((void)detect_format("mesh.vtk"), InputError);
    EXPECT_THROW((void)read_mesh("/nonexistent/mesh.su2"), IoError);
}

}  // namespace
}  // namespace manta::mesh
