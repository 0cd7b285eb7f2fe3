/// @file make_cgns_seeds.cpp
/// Writes the seed corpus of fuzz_cgns into the folder given as argument: small valid CGNS
/// (HDF5) files covering the reader's paths (an unstructured zone with element sections and a
/// MIXED section, boundary conditions as element ranges and as face sections; a structured 3-D
/// block with vertex point ranges; a structured 2-D block extruded to a slab; two unstructured
/// zones joined at coincident nodes). Each .cgns file in the folder is read back with
/// `mesh::read_cgns`; exit status 1 if one fails.

#include <cgnslib.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "manta/mesh/readers.hpp"

namespace {

namespace fs = std::filesystem;

void ok(int rc) {
    if (rc != CG_OK) throw std::runtime_error(cg_get_error());
}

/// Two unit hexahedra along x; cells in a HEXA_8 section or a MIXED one; the ten boundary
/// quadrilaterals in one section, named by a boundary condition (element range) or not.
void unstructured(const fs::path& file, bool mixed, bool boco) {
    int fn = 0, B = 0, Z = 0, C = 0, S = 0;
    ok(cg_open(file.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 3, 3, &B));
    cgsize_t size[3] = {12, 2, 0};
    ok(cg_zone_write(fn, B, "Fluid", size, CGNS_ENUMV(Unstructured), &Z));
    std::vector<double> x, y, z;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                x.push_back(i);
                y.push_back(j);
                z.push_back(k);
            }
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateX", x.data(), &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateY", y.data(), &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateZ", z.data(), &C));
    auto n = [](int i, int j, int k) { return static_cast<cgsize_t>(1 + i + 3 * (j + 2 * k)); };
    std::vector<cgsize_t> hexa;
    for (int i = 0; i < 2; ++i)
        hexa.insert(hexa.end(), {n(i, 0, 0), n(i + 1, 0, 0), n(i + 1, 1, 0), n(i, 1, 0), n(i, 0, 1),
                                 n(i + 1, 0, 1), n(i + 1, 1, 1), n(i, 1, 1)});
    if (mixed) {
        std::vector<cgsize_t> conn, offsets{0};
        for (int c = 0; c < 2; ++c) {
            conn.push_back(CGNS_ENUMV(HEXA_8));
            conn.insert(conn.end(), hexa.begin() + 8 * c, hexa.begin() + 8 * c + 8);
            offsets.push_back(static_cast<cgsize_t>(conn.size()));
        }
        ok(cg_poly_section_write(fn, B, Z, "Cells", CGNS_ENUMV(MIXED), 1, 2, 0, conn.data(),
                                 offsets.data(), &S));
    } else {
        ok(cg_section_write(fn, B, Z, "Cells", CGNS_ENUMV(HEXA_8), 1, 2, 0, hexa.data(), &S));
    }
    std::vector<cgsize_t> quads;
    auto quad = [&](cgsize_t a, cgsize_t b, cgsize_t c, cgsize_t d) {
        quads.insert(quads.end(), {a, b, c, d});
    };
    quad(n(0, 0, 0), n(0, 1, 0), n(0, 1, 1), n(0, 0, 1));  // x = 0
    quad(n(2, 0, 0), n(2, 1, 0), n(2, 1, 1), n(2, 0, 1));  // x = 2
    for (int i = 0; i < 2; ++i) {
        quad(n(i, 0, 0), n(i + 1, 0, 0), n(i + 1, 0, 1), n(i, 0, 1));  // y = 0
        quad(n(i, 1, 0), n(i + 1, 1, 0), n(i + 1, 1, 1), n(i, 1, 1));  // y = 1
        quad(n(i, 0, 0), n(i + 1, 0, 0), n(i + 1, 1, 0), n(i, 1, 0));  // z = 0
        quad(n(i, 0, 1), n(i + 1, 0, 1), n(i + 1, 1, 1), n(i, 1, 1));  // z = 1
    }
    ok(cg_section_write(fn, B, Z, "walls", CGNS_ENUMV(QUAD_4), 3, 12, 0, quads.data(), &S));
    if (boco) {
        int BC = 0;
        const cgsize_t range[2] = {3, 12};
        ok(cg_boco_write(fn, B, Z, "wall", CGNS_ENUMV(BCWall), CGNS_ENUMV(PointRange), 2, range,
                         &BC));
        ok(cg_boco_gridlocation_write(fn, B, Z, BC, CGNS_ENUMV(FaceCenter)));
    }
    ok(cg_close(fn));
}

/// A structured block of 3 x 3 (x 3) nodes with one boundary condition per side (vertex point
/// ranges); `dim` 2 or 3.
void structured(const fs::path& file, int dim) {
    int fn = 0, B = 0, Z = 0, C = 0;
    ok(cg_open(file.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", dim, dim, &B));
    const int nk = dim == 3 ? 3 : 1;
    std::vector<cgsize_t> size;
    for (int d = 0; d < dim; ++d) size.push_back(3);
    for (int d = 0; d < dim; ++d) size.push_back(2);
    for (int d = 0; d < dim; ++d) size.push_back(0);
    ok(cg_zone_write(fn, B, "Block", size.data(), CGNS_ENUMV(Structured), &Z));
    std::vector<double> x, y, z;
    for (int k = 0; k < nk; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                x.push_back(0.5 * i + 0.05 * j);
                y.push_back(0.5 * j);
                z.push_back(0.5 * k);
            }
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateX", x.data(), &C));
    ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateY", y.data(), &C));
    if (dim == 3) ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateZ", z.data(), &C));
    const char* names[6] = {"imin", "imax", "jmin", "jmax", "kmin", "kmax"};
    for (int side = 0; side < 2 * dim; ++side) {
        std::vector<cgsize_t> lo(dim, 1), hi(dim, 3);
        const int axis = side / 2;
        lo[axis] = hi[axis] = side % 2 == 0 ? 1 : 3;
        std::vector<cgsize_t> range(lo);
        range.insert(range.end(), hi.begin(), hi.end());
        int BC = 0;
        ok(cg_boco_write(fn, B, Z, names[side], CGNS_ENUMV(BCWall), CGNS_ENUMV(PointRange), 2,
                         range.data(), &BC));
    }
    ok(cg_close(fn));
}

/// Two unstructured zones of one unit hexahedron each, meeting at x = 1 with their own copies
/// of the four interface nodes; face sections "walls", "ends" and "interface" (dropped once the
/// zones are joined).
void two_zones(const fs::path& file) {
    int fn = 0, B = 0, C = 0, S = 0;
    ok(cg_open(file.string().c_str(), CG_MODE_WRITE, &fn));
    ok(cg_base_write(fn, "Base", 3, 3, &B));
    for (int zone = 0; zone < 2; ++zone) {
        int Z = 0;
        cgsize_t size[3] = {8, 1, 0};
        const std::string name = zone == 0 ? "Left" : "Right";
        ok(cg_zone_write(fn, B, name.c_str(), size, CGNS_ENUMV(Unstructured), &Z));
        std::vector<double> x, y, z;
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    x.push_back(zone + i);
                    y.push_back(j);
                    z.push_back(k);
                }
        ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateX", x.data(), &C));
        ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateY", y.data(), &C));
        ok(cg_coord_write(fn, B, Z, CGNS_ENUMV(RealDouble), "CoordinateZ", z.data(), &C));
        auto n = [](int i, int j, int k) { return static_cast<cgsize_t>(1 + i + 2 * (j + 2 * k)); };
        const std::vector<cgsize_t> hexa{n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(0, 1, 0),
                                         n(0, 0, 1), n(1, 0, 1), n(1, 1, 1), n(0, 1, 1)};
        ok(cg_section_write(fn, B, Z, "Cells", CGNS_ENUMV(HEXA_8), 1, 1, 0, hexa.data(), &S));
        const std::vector<cgsize_t> walls{n(0, 0, 0), n(1, 0, 0), n(1, 0, 1), n(0, 0, 1),
                                          n(0, 1, 0), n(1, 1, 0), n(1, 1, 1), n(0, 1, 1),
                                          n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(0, 1, 0),
                                          n(0, 0, 1), n(1, 0, 1), n(1, 1, 1), n(0, 1, 1)};
        ok(cg_section_write(fn, B, Z, "walls", CGNS_ENUMV(QUAD_4), 2, 5, 0, walls.data(), &S));
        const int outer = zone == 0 ? 0 : 1, inner = 1 - outer;
        const std::vector<cgsize_t> end{n(outer, 0, 0), n(outer, 1, 0), n(outer, 1, 1),
                                        n(outer, 0, 1)};
        ok(cg_section_write(fn, B, Z, "ends", CGNS_ENUMV(QUAD_4), 6, 6, 0, end.data(), &S));
        const std::vector<cgsize_t> face{n(inner, 0, 0), n(inner, 1, 0), n(inner, 1, 1),
                                         n(inner, 0, 1)};
        ok(cg_section_write(fn, B, Z, "interface", CGNS_ENUMV(QUAD_4), 7, 7, 0, face.data(), &S));
    }
    ok(cg_close(fn));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_cgns_seeds DIR\n");
        return 2;
    }
    const fs::path dir(argv[1]);
    fs::create_directories(dir);
    try {
        unstructured(dir / "hexa_sections.cgns", false, false);
        unstructured(dir / "hexa_mixed_boco.cgns", true, true);
        structured(dir / "block3d.cgns", 3);
        structured(dir / "block2d.cgns", 2);
        two_zones(dir / "two_zones.cgns");
        for (const auto& f : fs::directory_iterator(dir)) {
            if (f.path().extension() != ".cgns") continue;  // kept decoded-mode inputs
            const auto m = manta::mesh::read_cgns(f.path());
            std::printf("%s: %d nodes, %d cells, %d markers\n", f.path().filename().c_str(),
                        m.n_nodes(), m.n_cells(), m.n_markers());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "make_cgns_seeds: %s\n", e.what());
        return 1;
    }
    return 0;
}
