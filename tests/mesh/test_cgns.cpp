/// @file test_cgns.cpp
/// The CGNS reader on files written here with the CGNS library from gmsh meshes: cells in one
/// section per type or in a MIXED section; boundary conditions given by face-element ranges,
/// by vertex lists, or absent (face sections name the markers); the box split into three
/// unstructured zones; structured blocks, also with point-list boundary conditions and next to
/// an unstructured zone.

#include <cgnslib.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "gmsh_fixtures.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/readers.hpp"
#include "metrics_checks.hpp"
#include "zone_split.hpp"

namespace manta::mesh {
namespace {

namespace fs = std::filesystem;

enum class BcStyle { element_range, vertex_list, none };

CGNS_ENUMT(ElementType_t) cgns_of(CellType t) {
    switch (t) {
        case CellType::tetra:
            return CGNS_ENUMV(TETRA_4);
        case CellType::hexa:
            return CGNS_ENUMV(HEXA_8);
        case CellType::prism:
            return CGNS_ENUMV(PENTA_6);
        case CellType::pyramid:
            return CGNS_ENUMV(PYRA_5);
    }
    return CGNS_ENUMV(ElementTypeNull);
}

/// CGNS node order of a cell (1-based): VTK except the prism (its two triangles reversed).
std::vector<cgsize_t> cgns_nodes(CellType t, std::span<const Index> n) {
    std::vector<cgsize_t> out(n.begin(), n.end());
    if (t == CellType::prism) {
        std::swap(out[1], out[2]);
        std::swap(out[4], out[5]);
    }
    for (auto& v : out) ++v;
    return out;
}

void ok(int rc) {
    ASSERT_EQ(rc, CG_OK) << cg_get_error();
}

void write_cgns(const Mesh& m, const fs::path& file, bool mixed, BcStyle bc) {
    int fn = 0, B = 0, Z = 0, C = 0, S = 0;
    ok(cg_open(file.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 3, 3, &B));
    cgsize_t size[3] = {m.n_nodes(), m.n_cells(), 0};
    ok(cg_zone_write(fn, B, "Fluid", size, CGNS_ENUMV(Unstructured), &Z));
    const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
    for (int k = 0; k < 3; ++k) {
        std::vector<double> c(m.n_nodes());
        for (Index i = 0; i < m.n_nodes(); ++i) c[i] = m.node(i)[k];
        ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), names[k], c.data(), &C));
    }
    cgsize_t next = 1;
    if (mixed) {
        std::vector<cgsize_t> conn, offs{0};
        for (Index c = 0; c < m.n_cells(); ++c) {
            conn.push_back(cgns_of(m.cell_type(c)));
            for (auto v : cgns_nodes(m.cell_type(c), m.cell(c))) conn.push_back(v);
            offs.push_back(static_cast<cgsize_t>(conn.size()));
        }
        ok(cg_poly_section_write(fn, B, Z, "Cells", CGNS_ENUMV(MIXED), 1, m.n_cells(), 0,
                                 conn.data(), offs.data(), &S));
        next = m.n_cells() + 1;
    } else {
        std::map<CellType, std::vector<cgsize_t>> by_type;
        for (Index c = 0; c < m.n_cells(); ++c)
            for (auto v : cgns_nodes(m.cell_type(c), m.cell(c)))
                by_type[m.cell_type(c)].push_back(v);
        for (const auto& [t, conn] : by_type) {
            const auto n = static_cast<cgsize_t>(conn.size()) / node_count(t);
            ok(cg_section_write(fn, B, Z, name(t), cgns_of(t), next, next + n - 1, 0, conn.data(),
                                &S));
            next += n;
        }
    }
    for (int k = 0; k < m.n_markers(); ++k) {
        std::vector<cgsize_t> conn, offs{0};
        std::vector<cgsize_t> verts;
        for (Index f = 0; f < m.n_faces(); ++f)
            if (m.face_marker(f) == k) {
                conn.push_back(m.face_type(f) == FaceType::triangle ? CGNS_ENUMV(TRI_3)
                                                                    : CGNS_ENUMV(QUAD_4));
                for (Index v : m.face(f)) {
                    conn.push_back(v + 1);
                    verts.push_back(v + 1);
                }
                offs.push_back(static_cast<cgsize_t>(conn.size()));
            }
        const auto n = static_cast<cgsize_t>(offs.size()) - 1;
        ok(cg_poly_section_write(fn, B, Z, m.markers()[k].c_str(), CGNS_ENUMV(MIXED), next,
                                 next + n - 1, 0, conn.data(), offs.data(), &S));
        const std::string bcname = "bc_" + m.markers()[k];
        int BC = 0;
        if (bc == BcStyle::element_range) {
            const cgsize_t range[2] = {next, next + n - 1};
            ok(cg_boco_write(fn, B, Z, bcname.c_str(), CGNS_ENUMV(BCWall), CGNS_ENUMV(PointRange),
                             2, range, &BC));
            ok(cg_boco_gridlocation_write(fn, B, Z, BC, CGNS_ENUMV(FaceCenter)));
        } else if (bc == BcStyle::vertex_list) {
            std::sort(verts.begin(), verts.end());
            verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
            ok(cg_boco_write(fn, B, Z, bcname.c_str(), CGNS_ENUMV(BCWall), CGNS_ENUMV(PointList),
                             static_cast<cgsize_t>(verts.size()), verts.data(), &BC));
        }
        next += n;
    }
    ok(cg_close(fn));
}

TEST(Cgns, ReadsWhatItWrote) {
    const fs::path dir = test::scratch_dir("cgns");
    for (auto kind : {test::BoxKind::tets, test::BoxKind::prisms, test::BoxKind::hexes}) {
        const fs::path msh = dir / "box.msh";
        test::make_box(kind, 1.0, 0.5, 0.5, 0.25, {msh});
        const Mesh ref = read_gmsh(msh);
        for (bool mixed : {false, true})
            for (auto bc : {BcStyle::element_range, BcStyle::vertex_list, BcStyle::none}) {
                const fs::path f = dir / "box.cgns";
                fs::remove(f);
                write_cgns(ref, f, mixed, bc);
                SCOPED_TRACE(::testing::Message() << "kind " << static_cast<int>(kind) << " mixed "
                                                  << mixed << " bc " << static_cast<int>(bc));
                const Mesh m = read_mesh(f);
                EXPECT_EQ(m.n_nodes(), ref.n_nodes());
                EXPECT_EQ(m.n_cells(), ref.n_cells());
                EXPECT_EQ(m.n_faces(), ref.n_faces());
                ASSERT_EQ(m.n_markers(), ref.n_markers());
                const std::string prefix = bc == BcStyle::none ? "" : "bc_";
                for (int k = 0; k < ref.n_markers(); ++k)
                    EXPECT_GE(m.find_marker(prefix + ref.markers()[k]), 0);
                for (Index f2 = 0; f2 < m.n_faces(); ++f2)
                    EXPECT_EQ(m.markers()[m.face_marker(f2)],
                              prefix + ref.markers()[ref.face_marker(f2)]);
                test::check_dual(m, 0.25);
            }
    }
}

/// Write a structured zone of ni x nj x nk vertices, x = x0 + dx * i (or reversed), y and z on
/// [0,1]; interior y and z wavy; boundary conditions as vertex point ranges.
void write_block(int fn, int B, const char* zname, double x0, bool reversed_i, int ni, int nj,
                 int nk, const std::vector<std::pair<std::string, std::array<cgsize_t, 6>>>& bcs) {
    int Z = 0, C = 0, BC = 0;
    cgsize_t size[9] = {ni, nj, nk, ni - 1, nj - 1, nk - 1, 0, 0, 0};
    ok(cg_zone_write(fn, B, zname, size, CGNS_ENUMV(Structured), &Z));
    std::vector<double> x, y, z;
    for (int k = 0; k < nk; ++k)
        for (int j = 0; j < nj; ++j)
            for (int i = 0; i < ni; ++i) {
                const double u = static_cast<double>(reversed_i ? ni - 1 - i : i) / (ni - 1);
                const double v = static_cast<double>(j) / (nj - 1);
                const double w = static_cast<double>(k) / (nk - 1);
                const double bump = 0.05 * std::sin(M_PI * v) * std::sin(M_PI * w);
                x.push_back(x0 + u);
                y.push_back(v + bump * std::sin(M_PI * u));
                z.push_back(w - bump * std::sin(M_PI * u));
            }
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateX", x.data(), &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateY", y.data(), &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateZ", z.data(), &C));
    for (const auto& [name, r] : bcs) {
        ok(cg_boco_write(fn, B, Z, name.c_str(), CGNS_ENUMV(BCWall), CGNS_ENUMV(PointRange), 2,
                         r.data(), &BC));
        if (name == "inlet") {  // given by face centres (cell indices), not vertices
            ok(cg_boco_gridlocation_write(fn, B, Z, BC, CGNS_ENUMV(IFaceCenter)));
        }
        if (name.starts_with("wall")) {  // the four wall patches form the family "walls"
            ok(cg_goto(fn, B, "Zone_t", Z, "ZoneBC_t", 1, "BC_t", BC, "end"));
            ok(cg_famname_write("walls"));
        }
    }
}

/// Two structured blocks meeting at x = 1, the second with its i direction reversed (a
/// left-handed block), become one closed hexahedral mesh; the wall patches share a family, the
/// inlet is a face-centre range.
TEST(Cgns, StructuredBlocksBecomeHexahedra) {
    const fs::path f = test::scratch_dir("cgns") / "blocks.cgns";
    fs::remove(f);
    int fn = 0, B = 0;
    ok(cg_open(f.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 3, 3, &B));
    const int ni = 5, nj = 4, nk = 3;
    write_block(fn, B, "Left", 0.0, false, ni, nj, nk,
                {{"inlet", {1, 1, 1, 1, nj - 1, nk - 1}},
                 {"wall_jmin", {1, 1, 1, ni, 1, nk}},
                 {"wall_jmax", {1, nj, 1, ni, nj, nk}},
                 {"wall_kmin", {1, 1, 1, ni, nj, 1}},
                 {"wall_kmax", {1, 1, nk, ni, nj, nk}}});
    write_block(fn, B, "Right", 1.0, true, ni, nj, nk,
                {{"outlet", {1, 1, 1, 1, nj, nk}},
                 {"wall_jmin", {1, 1, 1, ni, 1, nk}},
                 {"wall_jmax", {1, nj, 1, ni, nj, nk}},
                 {"wall_kmin", {1, 1, 1, ni, nj, 1}},
                 {"wall_kmax", {1, 1, nk, ni, nj, nk}}});
    ok(cg_close(fn));
    const Mesh m = read_mesh(f);
    EXPECT_EQ(m.n_cells(), 2 * (ni - 1) * (nj - 1) * (nk - 1));
    EXPECT_EQ(m.n_nodes(), (2 * ni - 1) * nj * nk);  // the interface nodes merged
    ASSERT_EQ(m.n_markers(), 3);
    EXPECT_GE(m.find_marker("walls"), 0);
    test::check_dual(m, 2.0);
}

/// A 2-D structured block becomes a slab of hexahedra.
TEST(Cgns, StructuredPlaneBlockBecomesSlab) {
    const fs::path f = test::scratch_dir("cgns") / "plane.cgns";
    fs::remove(f);
    int fn = 0, B = 0, Z = 0, C = 0, BC = 0;
    ok(cg_open(f.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 2, 2, &B));
    const int ni = 6, nj = 4;
    cgsize_t size[6] = {ni, nj, ni - 1, nj - 1, 0, 0};
    ok(cg_zone_write(fn, B, "Plane", size, CGNS_ENUMV(Structured), &Z));
    std::vector<double> x, y;
    for (int j = 0; j < nj; ++j)
        for (int i = 0; i < ni; ++i) {
            x.push_back(2.0 * i / (ni - 1));
            y.push_back(1.0 * j / (nj - 1));
        }
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateX", x.data(), &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateY", y.data(), &C));
    const std::vector<std::pair<std::string, std::array<cgsize_t, 4>>> bcs{
        {"left", {1, 1, 1, nj}},
        {"right", {ni, 1, ni, nj}},
        {"bottom", {1, 1, ni, 1}},
        {"top", {1, nj, ni, nj}}};
    for (const auto& [name, r] : bcs)
        ok(cg_boco_write(fn, B, Z, name.c_str(), CGNS_ENUMV(BCWall), CGNS_ENUMV(PointRange), 2,
                         r.data(), &BC));
    ok(cg_close(fn));
    ReadOptions opt;
    opt.slab_thickness = 0.5;
    const Mesh m = read_cgns(f, opt);
    EXPECT_EQ(m.n_cells(), (ni - 1) * (nj - 1));
    EXPECT_EQ(m.n_markers(), 6);
    test::check_dual(m, 1.0);
}

TEST(Cgns, ErrorsNameFileAndZone) {
    const fs::path dir = test::scratch_dir("cgns");
    const fs::path f = dir / "bad.cgns";
    fs::remove(f);
    int fn = 0, B = 0, Z = 0, C = 0, S = 0;
    ok(cg_open(f.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 3, 3, &B));
    cgsize_t size[3] = {4, 1, 0};
    ok(cg_zone_write(fn, B, "Block", size, CGNS_ENUMV(Unstructured), &Z));
    const double x[4] = {0, 1, 0, 0}, y[4] = {0, 0, 1, 0}, z[4] = {0, 0, 0, 1};
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateX", x, &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateY", y, &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateZ", z, &C));
    const cgsize_t tet[4] = {1, 2, 3, 7};
    ok(cg_section_write(fn, B, Z, "Cells", CGNS_ENUMV(TETRA_4), 1, 1, 0, tet, &S));
    ok(cg_close(fn));
    try {
        (void)read_cgns(f);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("zone 'Block' section 'Cells' element 1: node 7; "
                                             "expected 1 to 4"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW((void)read_cgns(dir / "missing.cgns"), IoError);
}

/// Write the zones of a split mesh as unstructured CGNS zones "Block1".. (ICEM/Pointwise
/// style: one zone per block, nodes repeated on the interfaces): cells in a MIXED section,
/// one face section per marker with a boundary condition "bc_<marker>" (element range) unless
/// `bcs` is false, and the interface faces in a section "interface" if `interfaces`.
void write_cgns_zones(const Mesh& m, const std::vector<test::Zone>& zones, const fs::path& file,
                      bool bcs, bool interfaces) {
    int fn = 0, B = 0, C = 0, S = 0;
    ok(cg_open(file.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 3, 3, &B));
    for (std::size_t z = 0; z < zones.size(); ++z) {
        const test::Zone& zn = zones[z];
        int Z = 0;
        cgsize_t size[3] = {static_cast<cgsize_t>(zn.nodes.size()),
                            static_cast<cgsize_t>(zn.cells.size()), 0};
        const std::string zname = "Block" + std::to_string(z + 1);
        ok(cg_zone_write(fn, B, zname.c_str(), size, CGNS_ENUMV(Unstructured), &Z));
        const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
        for (int k = 0; k < 3; ++k) {
            std::vector<double> c;
            for (Index g : zn.nodes) c.push_back(m.node(g)[k]);
            ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), names[k], c.data(), &C));
        }
        std::vector<cgsize_t> conn, offs{0};
        for (Index c : zn.cells) {
            conn.push_back(cgns_of(m.cell_type(c)));
            std::vector<Index> local;
            for (Index v : m.cell(c)) local.push_back(zn.local(v));
            for (auto v : cgns_nodes(m.cell_type(c), local)) conn.push_back(v);
            offs.push_back(static_cast<cgsize_t>(conn.size()));
        }
        const auto ncells = static_cast<cgsize_t>(zn.cells.size());
        ok(cg_poly_section_write(fn, B, Z, "Cells", CGNS_ENUMV(MIXED), 1, ncells, 0, conn.data(),
                                 offs.data(), &S));
        cgsize_t next = ncells + 1;
        std::map<int, std::vector<const test::ZoneFace*>> by_marker;
        for (const auto& f : zn.faces)
            if (f.marker >= 0 || interfaces) by_marker[f.marker].push_back(&f);
        for (const auto& [mk, fs] : by_marker) {
            std::vector<cgsize_t> fconn, foffs{0};
            for (const auto* f : fs) {
                fconn.push_back(f->type == FaceType::triangle ? CGNS_ENUMV(TRI_3)
                                                              : CGNS_ENUMV(QUAD_4));
                for (Index v : f->nodes) fconn.push_back(zn.local(v) + 1);
                foffs.push_back(static_cast<cgsize_t>(fconn.size()));
            }
            const auto n = static_cast<cgsize_t>(fs.size());
            const std::string sname = mk < 0 ? "interface" : m.markers()[mk];
            ok(cg_poly_section_write(fn, B, Z, sname.c_str(), CGNS_ENUMV(MIXED), next, next + n - 1,
                                     0, fconn.data(), foffs.data(), &S));
            if (bcs && mk >= 0) {
                int BC = 0;
                const cgsize_t range[2] = {next, next + n - 1};
                ok(cg_boco_write(fn, B, Z, ("bc_" + sname).c_str(), CGNS_ENUMV(BCWall),
                                 CGNS_ENUMV(PointRange), 2, range, &BC));
                ok(cg_boco_gridlocation_write(fn, B, Z, BC, CGNS_ENUMV(FaceCenter)));
            }
            next += n;
        }
    }
    ok(cg_close(fn));
}

/// Faces per marker name.
std::map<std::string, int> faces_per_marker(const Mesh& m) {
    std::map<std::string, int> out;
    for (Index f = 0; f < m.n_faces(); ++f) ++out[m.markers()[m.face_marker(f)]];
    return out;
}

/// The box split into three unstructured zones (nodes repeated on the two interfaces) reads
/// back to the single-zone mesh: same node, cell and face counts, markers (each boundary
/// condition name appears in several zones and becomes one marker), closed dual cells.
TEST(Cgns, UnstructuredZonesAreJoined) {
    const fs::path dir = test::scratch_dir("cgns");
    for (auto kind : {test::BoxKind::tets, test::BoxKind::hexes}) {
        const fs::path msh = dir / "zbox.msh";
        test::make_box(kind, 1.5, 0.5, 0.5, 0.25, {msh});
        const Mesh ref = read_gmsh(msh);
        const auto zones = test::split_by_x(ref, {0.45, 1.05});
        ASSERT_EQ(zones.size(), 3U);
        for (const auto& z : zones) ASSERT_FALSE(z.cells.empty());
        for (bool bcs : {true, false})
            for (bool interfaces : {true, false}) {
                SCOPED_TRACE(::testing::Message() << "kind " << static_cast<int>(kind) << " bcs "
                                                  << bcs << " interfaces " << interfaces);
                const fs::path f = dir / "zones.cgns";
                fs::remove(f);
                write_cgns_zones(ref, zones, f, bcs, interfaces);
                const Mesh m = read_mesh(f);
                EXPECT_EQ(m.n_nodes(), ref.n_nodes());
                EXPECT_EQ(m.n_cells(), ref.n_cells());
                EXPECT_EQ(m.n_faces(), ref.n_faces());
                std::map<std::string, int> expected;
                for (const auto& [name, n] : faces_per_marker(ref))
                    expected[(bcs ? "bc_" : "") + name] = n;
                EXPECT_EQ(faces_per_marker(m), expected);
                EXPECT_NEAR(m.volume(), ref.volume(), 1e-13);
                test::check_dual(m, 1.5 * 0.5 * 0.5);
            }
    }
}

/// A structured block (boundary conditions as point lists: an IFaceCenter list for the inlet,
/// a vertex list for the walls) next to an unstructured zone of hexahedra whose face sections
/// name the markers; the structured walls' family and the unstructured section share the name
/// "walls"; the unstructured interface section is dropped.
TEST(Cgns, StructuredAndUnstructuredZonesWithPointLists) {
    const fs::path f = test::scratch_dir("cgns") / "mixed_zones.cgns";
    fs::remove(f);
    int fn = 0, B = 0;
    ok(cg_open(f.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 3, 3, &B));
    const int ni = 5, nj = 4, nk = 3, ni2 = 4;
    write_block(fn, B, "Left", 0.0, false, ni, nj, nk, {});
    {
        int BC = 0;
        std::vector<cgsize_t> inlet, walls;
        for (int k = 1; k < nk; ++k)
            for (int j = 1; j < nj; ++j) inlet.insert(inlet.end(), {1, j, k});
        for (int k = 1; k <= nk; ++k)
            for (int j = 1; j <= nj; ++j)
                for (int i = 1; i <= ni; ++i)
                    if (j == 1 || j == nj || k == 1 || k == nk)
                        walls.insert(walls.end(), {i, j, k});
        ok(cg_boco_write(fn, B, 1, "inlet", CGNS_ENUMV(BCInflow), CGNS_ENUMV(PointList),
                         static_cast<cgsize_t>(inlet.size() / 3), inlet.data(), &BC));
        ok(cg_boco_gridlocation_write(fn, B, 1, BC, CGNS_ENUMV(IFaceCenter)));
        ok(cg_boco_write(fn, B, 1, "wall_vertices", CGNS_ENUMV(BCWall), CGNS_ENUMV(PointList),
                         static_cast<cgsize_t>(walls.size() / 3), walls.data(), &BC));
        ok(cg_goto(fn, B, "Zone_t", 1, "ZoneBC_t", 1, "BC_t", BC, "end"));
        ok(cg_famname_write("walls"));
    }
    {
        int Z = 0, C = 0, S = 0;
        cgsize_t size[3] = {ni2 * nj * nk, (ni2 - 1) * (nj - 1) * (nk - 1), 0};
        ok(cg_zone_write(fn, B, "Right", size, CGNS_ENUMV(Unstructured), &Z));
        std::vector<double> x, y, z;
        for (int k = 0; k < nk; ++k)
            for (int j = 0; j < nj; ++j)
                for (int i = 0; i < ni2; ++i) {
                    x.push_back(1.0 + static_cast<double>(i) / (ni2 - 1));
                    y.push_back(static_cast<double>(j) / (nj - 1));
                    z.push_back(static_cast<double>(k) / (nk - 1));
                }
        ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateX", x.data(), &C));
        ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateY", y.data(), &C));
        ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateZ", z.data(), &C));
        const auto id = [&](int i, int j, int k) { return 1 + i + ni2 * (j + nj * k); };
        std::vector<cgsize_t> hexa;
        for (int k = 0; k + 1 < nk; ++k)
            for (int j = 0; j + 1 < nj; ++j)
                for (int i = 0; i + 1 < ni2; ++i)
                    hexa.insert(hexa.end(), {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k),
                                             id(i, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1),
                                             id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
        const auto nh = static_cast<cgsize_t>(hexa.size() / 8);
        ok(cg_section_write(fn, B, Z, "Hexa", CGNS_ENUMV(HEXA_8), 1, nh, 0, hexa.data(), &S));
        std::map<std::string, std::vector<cgsize_t>> quads;
        for (int k = 0; k + 1 < nk; ++k)
            for (int j = 0; j + 1 < nj; ++j) {
                quads["interface"].insert(
                    quads["interface"].end(),
                    {id(0, j, k), id(0, j, k + 1), id(0, j + 1, k + 1), id(0, j + 1, k)});
                const int e = ni2 - 1;
                quads["outlet"].insert(
                    quads["outlet"].end(),
                    {id(e, j, k), id(e, j + 1, k), id(e, j + 1, k + 1), id(e, j, k + 1)});
            }
        for (int i = 0; i + 1 < ni2; ++i) {
            for (int k = 0; k + 1 < nk; ++k)
                for (int j : {0, nj - 1})
                    quads["walls"].insert(
                        quads["walls"].end(),
                        {id(i, j, k), id(i + 1, j, k), id(i + 1, j, k + 1), id(i, j, k + 1)});
            for (int j = 0; j + 1 < nj; ++j)
                for (int k : {0, nk - 1})
                    quads["walls"].insert(
                        quads["walls"].end(),
                        {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k)});
        }
        cgsize_t next = nh + 1;
        for (const auto& [name, q] : quads) {
            const auto n = static_cast<cgsize_t>(q.size() / 4);
            ok(cg_section_write(fn, B, Z, name.c_str(), CGNS_ENUMV(QUAD_4), next, next + n - 1, 0,
                                q.data(), &S));
            next += n;
        }
    }
    ok(cg_close(fn));
    const Mesh m = read_mesh(f);
    EXPECT_EQ(m.n_nodes(), (ni + ni2 - 1) * nj * nk);
    EXPECT_EQ(m.n_cells(), (ni + ni2 - 2) * (nj - 1) * (nk - 1));
    const std::map<std::string, int> expected{
        {"inlet", (nj - 1) * (nk - 1)},
        {"outlet", (nj - 1) * (nk - 1)},
        {"walls", 2 * (ni + ni2 - 2) * ((nj - 1) + (nk - 1))}};
    EXPECT_EQ(faces_per_marker(m), expected);
    test::check_dual(m, 2.0);
}

/// Point lists a structured zone cannot take give one-line errors naming zone and condition.
TEST(Cgns, StructuredPointListErrors) {
    const fs::path f = test::scratch_dir("cgns") / "bad_list.cgns";
    const int ni = 4, nj = 3, nk = 3;
    const auto write = [&](CGNS_ENUMT(GridLocation_t) loc, std::vector<cgsize_t> pts) {
        fs::remove(f);
        int fn = 0, B = 0, BC = 0;
        ok(cg_open(f.string().c_str(), CG_MODE_WRITE, &fn));
        ok(cg_base_write(fn, "Base", 3, 3, &B));
        write_block(fn, B, "Blk", 0.0, false, ni, nj, nk, {});
        ok(cg_boco_write(fn, B, 1, "side", CGNS_ENUMV(BCWall), CGNS_ENUMV(PointList),
                         static_cast<cgsize_t>(pts.size() / 3), pts.data(), &BC));
        ok(cg_boco_gridlocation_write(fn, B, 1, BC, loc));
        ok(cg_close(fn));
    };
    const auto message = [&]() -> std::string {
        try {
            (void)read_cgns(f);
        } catch (const InputError& e) {
            return e.what();
        }
        return "no error";
    };
    write(CGNS_ENUMV(IFaceCenter), {2, 1, 1});
    EXPECT_NE(message().find("zone 'Blk' boundary condition 1 'side': face 1 lies inside the zone "
                             "(index 2 in direction 1); expected a block face (1 or 4)"),
              std::string::npos)
        << message();
    write(CGNS_ENUMV(CellCenter), {1, 1, 1});
    EXPECT_NE(message().find("'side': a point list at location CellCenter; expected Vertex"),
              std::string::npos)
        << message();
    write(CGNS_ENUMV(Vertex), {1, 1, 9});
    EXPECT_NE(message().find("'side': point 1 has index 9 in direction 3; expected 1 to 3"),
              std::string::npos)
        << message();
}

}  // namespace
}  // namespace manta::mesh
