/// @file cgns_writer.cpp
/// The mesh as CGNS (Debian's gmsh is built without CGNS): one unstructured zone, the cells as a
/// TETRA_4 section, each marker's faces as a TRI_3 section of its name with a boundary condition
/// of the same name over its element range (what mesh::read_cgns reads back as the marker).

#include <cgnslib.h>
#include <fmt/format.h>

#include <string>
#include <vector>

#include "cgns_writer.hpp"
#include "manta/core/error.hpp"

namespace manta::meshgen::detail {

namespace {

void check(int status, const std::filesystem::path& file, const char* what) {
    if (status != CG_OK)
        throw IoError(fmt::format("{}: cannot write the CGNS mesh ({}: {})", file.string(), what,
                                  cg_get_error()));
}

}  // namespace

void write_cgns(const std::filesystem::path& file, const std::vector<double>& xyz,
                const std::vector<std::array<long long, 4>>& tets,
                const std::vector<std::array<long long, 3>>& tris,
                const std::vector<std::pair<std::string, long long>>& markers,
                const std::vector<std::string>& roles) {
    int fn = 0, base = 0, zone = 0, coord = 0, section = 0, bc = 0;
    check(cg_open(file.c_str(), CG_MODE_WRITE, &fn), file, "open");
    try {
        check(cg_base_write(fn, "Base", 3, 3, &base), file, "base");
        const auto n = static_cast<cgsize_t>(xyz.size() / 3);
        cgsize_t size[3] = {n, static_cast<cgsize_t>(tets.size()), 0};
        check(cg_zone_write(fn, base, "fluid", size, CGNS_ENUMV(Unstructured), &zone), file,
              "zone");
        std::vector<double> c(static_cast<std::size_t>(n));
        const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
        for (int d = 0; d < 3; ++d) {
            for (std::size_t i = 0; i < c.size(); ++i)
                c[i] = xyz[3 * i + static_cast<std::size_t>(d)];
            check(
                cg_coord_write(fn, base, zone, CGNS_ENUMV(RealDouble), names[d], c.data(), &coord),
                file, "coordinates");
        }
        std::vector<cgsize_t> conn;
        conn.reserve(tets.size() * 4);
        for (const auto& t : tets)
            for (auto v : t) conn.push_back(static_cast<cgsize_t>(v + 1));
        cgsize_t next = 1;
        const auto n_tets = static_cast<cgsize_t>(tets.size());
        check(cg_section_write(fn, base, zone, "cells", CGNS_ENUMV(TETRA_4), next,
                               next + n_tets - 1, 0, conn.data(), &section),
              file, "cells");
        next += n_tets;
        std::size_t offset = 0;
        for (std::size_t m = 0; m < markers.size(); ++m) {
            const auto count = static_cast<std::size_t>(markers[m].second);
            if (count == 0) continue;
            conn.clear();
            for (std::size_t f = offset; f < offset + count; ++f)
                for (auto v : tris[f]) conn.push_back(static_cast<cgsize_t>(v + 1));
            const cgsize_t first = next, last = next + static_cast<cgsize_t>(count) - 1;
            check(cg_section_write(fn, base, zone, markers[m].first.c_str(), CGNS_ENUMV(TRI_3),
                                   first, last, 0, conn.data(), &section),
                  file, "marker faces");
            const cgsize_t range[2] = {first, last};
            const auto type = roles[m] == "farfield"   ? CGNS_ENUMV(BCFarfield)
                              : roles[m] == "symmetry" ? CGNS_ENUMV(BCSymmetryPlane)
                                                       : CGNS_ENUMV(BCWallInviscid);
            check(cg_boco_write(fn, base, zone, markers[m].first.c_str(), type,
                                CGNS_ENUMV(PointRange), 2, range, &bc),
                  file, "boundary condition");
            check(cg_boco_gridlocation_write(fn, base, zone, bc, CGNS_ENUMV(FaceCenter)), file,
                  "boundary location");
            next = last + 1;
            offset += count;
        }
    } catch (...) {
        cg_close(fn);
        throw;
    }
    check(cg_close(fn), file, "close");
}

}  // namespace manta::meshgen::detail
