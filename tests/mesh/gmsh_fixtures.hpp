#pragma once
/// @file gmsh_fixtures.hpp
/// Test meshes made with the gmsh C++ API (gmsh 4.8): a box meshed with tetrahedra, prisms or
/// hexahedra, and a plane rectangle, each boundary surface (curve)
/// a named physical group.

#include <gmsh.h>

#include <filesystem>
#include <string>
#include <vector>

// gmsh 4.8 keeps a few small allocations to the end of the process (seen by LeakSanitizer in
// `make test-asan`, all inside libgmsh); each test program includes this header once.
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libgmsh\n";
}

namespace manta::mesh::test {

/// How the box volume is meshed. (gmsh 4.8's own tetrahedra-with-pyramids meshes abort in
/// RelocateVerticesOfPyramids; tests/mesh/test_readers.cpp splits hexahedra instead.)
enum class BoxKind { tets, prisms, hexes };

/// A scratch directory for one test program.
inline std::filesystem::path scratch_dir(const std::string& name) {
    const auto d = std::filesystem::temp_directory_path() / ("manta-mesh-" + name);
    std::filesystem::create_directories(d);
    return d;
}

/// Mesh the box [0,lx] x [0,ly] x [0,lz] with cells of about size h and write it to each of
/// `files` (format from the extension; `msh_version` 2.2 or 4.1 for .msh, binary if `binary`).
/// Surfaces are physical groups "side_<tag>", the volume "fluid".
inline void make_box(BoxKind kind, double lx, double ly, double lz, double h,
                     const std::vector<std::filesystem::path>& files, double msh_version = 4.1,
                     bool binary = false) {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::model::add("box");
    namespace geo = gmsh::model::geo;
    const int p1 = geo::addPoint(0, 0, 0, h), p2 = geo::addPoint(lx, 0, 0, h);
    const int p3 = geo::addPoint(lx, ly, 0, h), p4 = geo::addPoint(0, ly, 0, h);
    const int l1 = geo::addLine(p1, p2), l2 = geo::addLine(p2, p3);
    const int l3 = geo::addLine(p3, p4), l4 = geo::addLine(p4, p1);
    const int loop = geo::addCurveLoop({l1, l2, l3, l4});
    const int s = geo::addPlaneSurface({loop});
    gmsh::vectorpair out;
    const int layers = std::max(1, static_cast<int>(lz / h + 0.5));
    if (kind == BoxKind::hexes) {
        for (int l : {l1, l2, l3, l4})
            geo::mesh::setTransfiniteCurve(l, std::max(2, static_cast<int>(lx / h) + 1));
        geo::mesh::setTransfiniteSurface(s);
        geo::mesh::setRecombine(2, s);
    }
    if (kind == BoxKind::prisms || kind == BoxKind::hexes)
        geo::extrude({{2, s}}, 0, 0, lz, out, {layers}, {}, true);
    else
        geo::extrude({{2, s}}, 0, 0, lz, out);
    geo::synchronize();
    gmsh::vectorpair surfaces;
    gmsh::model::getEntities(surfaces, 2);
    for (const auto& [dim, tag] : surfaces) {
        const int g = gmsh::model::addPhysicalGroup(2, {tag});
        gmsh::model::setPhysicalName(2, g, "side_" + std::to_string(tag));
    }
    gmsh::vectorpair volumes;
    gmsh::model::getEntities(volumes, 3);
    const int gv = gmsh::model::addPhysicalGroup(3, {volumes.at(0).second});
    gmsh::model::setPhysicalName(3, gv, "fluid");
    gmsh::model::mesh::generate(3);
    gmsh::option::setNumber("Mesh.MshFileVersion", msh_version);
    gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
    for (const auto& f : files) gmsh::write(f.string());
    gmsh::finalize();
}

/// Mesh the rectangle [0,lx] x [0,ly] (z = 0) with triangles (or quadrilaterals) of size h and
/// write it; edges are physical groups "edge_<tag>", the surface "fluid".
inline void make_rectangle(double lx, double ly, double h, bool quads,
                           const std::filesystem::path& file, double msh_version = 4.1) {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::model::add("rect");
    namespace geo = gmsh::model::geo;
    const int p1 = geo::addPoint(0, 0, 0, h), p2 = geo::addPoint(lx, 0, 0, h);
    const int p3 = geo::addPoint(lx, ly, 0, h), p4 = geo::addPoint(0, ly, 0, h);
    const std::vector<int> lines{geo::addLine(p1, p2), geo::addLine(p2, p3), geo::addLine(p3, p4),
                                 geo::addLine(p4, p1)};
    const int s = geo::addPlaneSurface({geo::addCurveLoop(lines)});
    if (quads) geo::mesh::setRecombine(2, s);
    geo::synchronize();
    for (int l : lines) {
        const int g = gmsh::model::addPhysicalGroup(1, {l});
        gmsh::model::setPhysicalName(1, g, "edge_" + std::to_string(l));
    }
    const int gs = gmsh::model::addPhysicalGroup(2, {s});
    gmsh::model::setPhysicalName(2, gs, "fluid");
    gmsh::model::mesh::generate(2);
    gmsh::option::setNumber("Mesh.MshFileVersion", msh_version);
    gmsh::option::setNumber("Mesh.Binary", 0);
    gmsh::write(file.string());
    gmsh::finalize();
}

}  // namespace manta::mesh::test
