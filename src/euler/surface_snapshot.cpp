/// @file surface_snapshot.cpp
/// The surface snapshot files (surface_snapshot.hpp, docs/formats.md#surface-snapshot).

#include "manta/euler/surface_snapshot.hpp"

#include <fmt/format.h>

#include <array>
#include <iterator>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::euler {

WallSurface wall_surface(const mesh::Mesh& mesh, const std::vector<BoundaryKind>& roles,
                         const std::string& what) {
    WallSurface w;
    std::vector<int> wall_marker(static_cast<std::size_t>(mesh.n_markers()), -1);
    for (int m = 0; m < mesh.n_markers() && m < static_cast<int>(roles.size()); ++m)
        if (roles[static_cast<std::size_t>(m)] == BoundaryKind::wall) {
            wall_marker[static_cast<std::size_t>(m)] = static_cast<int>(w.markers.size());
            w.markers.push_back(mesh.markers()[static_cast<std::size_t>(m)]);
        }
    std::vector<mesh::Index> local(static_cast<std::size_t>(mesh.n_nodes()), -1);
    auto node = [&](mesh::Index i) {
        mesh::Index& l = local[static_cast<std::size_t>(i)];
        if (l < 0) {
            l = static_cast<mesh::Index>(w.nodes.size());
            w.nodes.push_back(i);
        }
        return l;
    };
    for (mesh::Index f = 0; f < mesh.n_faces(); ++f) {
        const int m = wall_marker[static_cast<std::size_t>(mesh.face_marker(f))];
        if (m < 0) continue;
        const std::span<const mesh::Index> v = mesh.face(f);
        // The mesh orients boundary faces out of the domain (into the body): reversed here.
        for (std::size_t k = 1; k + 1 < v.size(); ++k)
            w.triangles.push_back({node(v[0]), node(v[k + 1]), node(v[k]), m});
    }
    if (w.triangles.empty())
        throw InputError(fmt::format(
            "{}: the mesh has no face on a wall marker; expected a wall to write", what));
    return w;
}

namespace {
std::string header_text(const char* format_line,
                        const std::vector<std::pair<std::string, std::string>>& header) {
    std::string text = format_line;
    text += '\n';
    for (const auto& [k, v] : header) text += fmt::format("# {}: {}\n", k, v);
    return text;
}
}  // namespace

void write_wall_geometry(const std::filesystem::path& file, const mesh::Mesh& mesh,
                         const WallSurface& wall,
                         const std::vector<std::pair<std::string, std::string>>& header) {
    std::string text = header_text("# MANTA surface wall 1", header);
    std::string markers;
    for (const auto& n : wall.markers) markers += (markers.empty() ? "" : ",") + n;
    text += fmt::format("# markers: {}\n# nodes: {}\n# triangles: {}\n", markers, wall.nodes.size(),
                        wall.triangles.size());
    text.reserve(text.size() + wall.nodes.size() * 34 + wall.triangles.size() * 22);
    text += "x,y,z\n";
    for (const mesh::Index i : wall.nodes) {
        const Eigen::Vector3d x = mesh.node(i);
        fmt::format_to(std::back_inserter(text), "{:.7g},{:.7g},{:.7g}\n", x.x(), x.y(), x.z());
    }
    text += "a,b,c,marker\n";
    for (const auto& t : wall.triangles)
        fmt::format_to(std::back_inserter(text), "{},{},{},{}\n", t[0], t[1], t[2], t[3]);
    core::write_file_atomic(file, text);
}

void write_wall_cp(const std::filesystem::path& file, const WallSurface& wall,
                   std::span<const double> cp,
                   const std::vector<std::pair<std::string, std::string>>& header) {
    std::string text = header_text("# MANTA surface snapshot 1", header);
    text += fmt::format("# nodes: {}\nCp\n", wall.nodes.size());
    text.reserve(text.size() + wall.nodes.size() * 11);
    for (const mesh::Index i : wall.nodes) {
        if (static_cast<std::size_t>(i) >= cp.size())
            throw InputError(fmt::format("{}: {} pressure coefficients; node {} has none",
                                         file.string(), cp.size(), i));
        fmt::format_to(std::back_inserter(text), "{:.5g}\n", cp[static_cast<std::size_t>(i)]);
    }
    core::write_file_atomic(file, text);
}

}  // namespace manta::euler
