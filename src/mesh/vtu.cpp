/// @file vtu.cpp
/// ASCII VTU writers for volume and boundary meshes.

#include "manta/mesh/vtu.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::mesh {

namespace {

void check_field(const Mesh& mesh, const VtuField& f, std::size_t n, const char* what) {
    if (f.components < 1 || f.components > 9)
        throw InputError(fmt::format("{}: VTU field '{}' has {} components; expected 1 to 9",
                                     mesh.source(), f.name, f.components));
    const std::size_t c = static_cast<std::size_t>(f.components);
    if (f.values.size() != c * n)
        throw InputError(fmt::format("{}: VTU field '{}' has {} values; expected {} per {} ({})",
                                     mesh.source(), f.name, f.values.size(), c, what, c * n));
}

/// The opening tag of a field's DataArray.
std::string array_tag(const VtuField& f) {
    if (f.components == 1)
        return fmt::format("<DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", f.name);
    return fmt::format(
        "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
        f.name, f.components);
}

/// The values of entity `n` of a field, one line.
void append_values(std::string& s, const VtuField& f, std::size_t n) {
    const auto c = static_cast<std::size_t>(f.components);
    s += fmt::format("{}\n", fmt::join(f.values.subspan(c * n, c), " "));
}

void header(std::string& s, std::size_t n_points, std::size_t n_cells) {
    s += "<?xml version=\"1.0\"?>\n";
    s += "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
    s += "<UnstructuredGrid>\n";
    s += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n_points, n_cells);
    s += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
}

void footer(std::string& s) {
    s += "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

}  // namespace

void write_vtu_volume(const std::filesystem::path& file, const Mesh& mesh,
                      const std::vector<VtuField>& node_fields) {
    for (const auto& f : node_fields) check_field(mesh, f, mesh.n_nodes(), "node");
    // Written in pieces of a few MiB (a large mesh's text would otherwise double the memory).
    core::AtomicFileWriter out(file);
    std::string s;
    header(s, mesh.n_nodes(), mesh.n_cells());
    for (Index i = 0; i < mesh.n_nodes(); ++i) {
        const auto p = mesh.node(i);
        s += fmt::format("{} {} {}\n", p.x(), p.y(), p.z());
        out.spill(s);
    }
    s += "</DataArray>\n</Points>\n<Cells>\n";
    s += "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        s += fmt::format("{}\n", fmt::join(mesh.cell(c), " "));
        out.spill(s);
    }
    s += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        s += fmt::format("{}\n", mesh.cell_offsets()[c + 1]);
        out.spill(s);
    }
    s += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (Index c = 0; c < mesh.n_cells(); ++c)
        s += fmt::format("{}\n", static_cast<int>(mesh.cell_type(c)));
    s += "</DataArray>\n</Cells>\n<CellData>\n";
    s += "<DataArray type=\"Float64\" Name=\"volume\" format=\"ascii\">\n";
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        s += fmt::format("{}\n", mesh.cell_volume(c));
        out.spill(s);
    }
    s += "</DataArray>\n</CellData>\n<PointData>\n";
    for (const auto& f : node_fields) {
        s += array_tag(f);
        for (std::size_t n = 0; n < static_cast<std::size_t>(mesh.n_nodes()); ++n) {
            append_values(s, f, n);
            out.spill(s);
        }
        s += "</DataArray>\n";
    }
    s += "</PointData>\n";
    footer(s);
    out.write(s);
    out.commit();
}

void write_vtu_surface(const std::filesystem::path& file, const Mesh& mesh,
                       const std::vector<VtuField>& node_fields) {
    for (const auto& f : node_fields) check_field(mesh, f, mesh.n_nodes(), "node");
    std::vector<Index> local(mesh.n_nodes(), -1);
    std::vector<Index> used;
    for (Index f = 0; f < mesh.n_faces(); ++f)
        for (Index n : mesh.face(f))
            if (local[n] < 0) {
                local[n] = static_cast<Index>(used.size());
                used.push_back(n);
            }
    std::string s;
    header(s, used.size(), mesh.n_faces());
    for (Index n : used) {
        const auto p = mesh.node(n);
        s += fmt::format("{} {} {}\n", p.x(), p.y(), p.z());
    }
    s += "</DataArray>\n</Points>\n<Cells>\n";
    s += "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    std::vector<std::int64_t> offsets;
    std::int64_t off = 0;
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        for (Index n : mesh.face(f)) s += fmt::format("{} ", local[n]);
        s += "\n";
        off += static_cast<std::int64_t>(mesh.face(f).size());
        offsets.push_back(off);
    }
    s += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (auto o : offsets) s += fmt::format("{}\n", o);
    s += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (Index f = 0; f < mesh.n_faces(); ++f)
        s += fmt::format("{}\n", static_cast<int>(mesh.face_type(f)));
    s += "</DataArray>\n</Cells>\n<CellData>\n";
    s += "<DataArray type=\"Int32\" Name=\"marker\" format=\"ascii\">\n";
    for (Index f = 0; f < mesh.n_faces(); ++f) s += fmt::format("{}\n", mesh.face_marker(f));
    s += "</DataArray>\n</CellData>\n<PointData>\n";
    for (const auto& f : node_fields) {
        s += array_tag(f);
        for (Index n : used) append_values(s, f, static_cast<std::size_t>(n));
        s += "</DataArray>\n";
    }
    s += "</PointData>\n";
    footer(s);
    core::write_file_atomic(file, s);
}

}  // namespace manta::mesh
