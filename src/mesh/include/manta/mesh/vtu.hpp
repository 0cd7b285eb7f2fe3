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

/// A named scalar field with one value per node (or per cell or face, see the writers).
struct VtuField {
    std::string name;                ///< array name shown in ParaView
    std::span<const double> values;  ///< one value per entity
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
