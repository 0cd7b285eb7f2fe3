#pragma once
/// @file vtu.hpp
/// VTK XML unstructured-grid (.vtu) output of meshes for ParaView (Kitware, "VTK File Formats",
/// XML UnstructuredGrid), ASCII.

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "manta/mesh/mesh.hpp"

namespace manta::mesh {

/// A named field with `components` values per node (or per cell or face, see the writers):
/// 1 for a scalar, 3 for a vector (x, y, z of each entity in turn; ParaView's glyph and stream
/// tracer filters take it as one vector array).
struct VtuField {
    std::string name;                ///< array name shown in ParaView
    std::span<const double> values;  ///< `components` values per entity, entity-major
    int components = 1;              ///< values per entity (1 to 9)
};

/// Write the volume cells with optional node fields and the cell volume as cell data. The file
/// is written atomically. InputError if a field has the wrong length; IoError if not writable.
void write_vtu_volume(const std::filesystem::path& file, const Mesh& mesh,
                      const std::vector<VtuField>& node_fields = {});

/// Write the boundary faces (only the nodes they use) with the marker number as cell data
/// "marker" and optional node fields given for all mesh nodes.
void write_vtu_surface(const std::filesystem::path& file, const Mesh& mesh,
                       const std::vector<VtuField>& node_fields = {});

}  // namespace manta::mesh
