#pragma once
/// @file zone_split.hpp
/// Splits a read mesh into zones (cells by the x of their node average, like the blocks of a
/// multi-block export) with each zone's own node numbering, its boundary faces and the
/// interface faces it shares with other zones; writes the zones as a multi-zone SU2 file. The
/// multi-zone readers must give back the mesh that was split.

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "manta/mesh/mesh.hpp"

namespace manta::mesh::test {

/// A face of a zone: its type, nodes (global numbers) and marker (-1: a zone interface).
struct ZoneFace {
    FaceType type;
    std::vector<Index> nodes;
    int marker;
};

/// One zone: cells, the global numbers of its nodes (local number = position) and faces.
struct Zone {
    std::vector<Index> cells;
    std::vector<Index> nodes;
    std::vector<ZoneFace> faces;
    /// Local number of global node `g` (0-based).
    [[nodiscard]] Index local(Index g) const {
        return static_cast<Index>(std::lower_bound(nodes.begin(), nodes.end(), g) - nodes.begin());
    }
};

/// Split `m` at the planes x = cuts[k] (ascending) into cuts.size() + 1 zones.
inline std::vector<Zone> split_by_x(const Mesh& m, const std::vector<double>& cuts) {
    std::vector<Zone> zones(cuts.size() + 1);
    std::vector<int> zone_of(static_cast<std::size_t>(m.n_cells()));
    // Sorted face node lists -> (zone, oriented nodes) of the cells having the face.
    std::map<std::vector<Index>, std::vector<std::pair<int, std::vector<Index>>>> faces;
    for (Index c = 0; c < m.n_cells(); ++c) {
        const auto n = m.cell(c);
        double x = 0.0;
        for (Index v : n) x += m.node(v).x();
        x /= static_cast<double>(n.size());
        const int z =
            static_cast<int>(std::upper_bound(cuts.begin(), cuts.end(), x) - cuts.begin());
        zone_of[c] = z;
        zones[z].cells.push_back(c);
        for (Index v : n) zones[z].nodes.push_back(v);
        for (const auto& f : cell_faces(m.cell_type(c))) {
            std::vector<Index> fn;
            for (int k = 0; k < (f[3] < 0 ? 3 : 4); ++k) fn.push_back(n[f[k]]);
            std::vector<Index> key = fn;
            std::sort(key.begin(), key.end());
            faces[key].push_back({z, fn});
        }
    }
    for (auto& z : zones) {
        std::sort(z.nodes.begin(), z.nodes.end());
        z.nodes.erase(std::unique(z.nodes.begin(), z.nodes.end()), z.nodes.end());
    }
    for (const auto& [key, owners] : faces)
        if (owners.size() == 2 && owners[0].first != owners[1].first)
            for (const auto& [z, fn] : owners)
                zones[z].faces.push_back(
                    {fn.size() == 3 ? FaceType::triangle : FaceType::quad, fn, -1});
    for (Index f = 0; f < m.n_faces(); ++f) {
        std::vector<Index> key(m.face(f).begin(), m.face(f).end());
        std::sort(key.begin(), key.end());
        const int z = faces.at(key).front().first;
        zones[z].faces.push_back({m.face_type(f),
                                  std::vector<Index>(m.face(f).begin(), m.face(f).end()),
                                  m.face_marker(f)});
    }
    return zones;
}

/// VTK cell type id (SU2 uses them) of a cell or face type.
inline int vtk_id(CellType t) {
    return static_cast<int>(t);
}

/// Write the zones as an SU2 multi-zone file (NZONE=, IZONE=); the interface faces of each
/// zone become its marker `interface_name` unless that is empty.
inline void write_su2_zones(const Mesh& m, const std::vector<Zone>& zones,
                            const std::filesystem::path& file,
                            const std::string& interface_name = "interface") {
    std::ofstream out(file);
    out.precision(17);
    out << "NZONE= " << zones.size() << "\n";
    for (std::size_t z = 0; z < zones.size(); ++z) {
        const Zone& zn = zones[z];
        out << "IZONE= " << z + 1 << "\nNDIME= 3\nNELEM= " << zn.cells.size() << "\n";
        for (Index c : zn.cells) {
            out << vtk_id(m.cell_type(c));
            for (Index v : m.cell(c)) out << ' ' << zn.local(v);
            out << "\n";
        }
        out << "NPOIN= " << zn.nodes.size() << "\n";
        for (Index g : zn.nodes)
            out << m.node(g).x() << ' ' << m.node(g).y() << ' ' << m.node(g).z() << "\n";
        std::map<int, std::vector<const ZoneFace*>> by_marker;
        for (const auto& f : zn.faces)
            if (f.marker >= 0 || !interface_name.empty()) by_marker[f.marker].push_back(&f);
        out << "NMARK= " << by_marker.size() << "\n";
        for (const auto& [mk, fs] : by_marker) {
            out << "MARKER_TAG= " << (mk < 0 ? interface_name : m.markers()[mk]) << "\n";
            out << "MARKER_ELEMS= " << fs.size() << "\n";
            for (const auto* f : fs) {
                out << static_cast<int>(f->type);
                for (Index v : f->nodes) out << ' ' << zn.local(v);
                out << "\n";
            }
        }
    }
}

}  // namespace manta::mesh::test
