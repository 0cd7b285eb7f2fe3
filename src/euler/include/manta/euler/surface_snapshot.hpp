#pragma once
/// @file surface_snapshot.hpp
/// Surface snapshots of a time-accurate Euler run (docs/formats.md#surface-snapshot): the wall's
/// nodes and triangles once (`wall.csv`), and its pressure coefficients at each instant (one
/// small CSV file per instant), written atomically. `manta replay --source euler
/// --snapshot-every S` writes them into OUT/surface/ and `manta report` draws them as plan views
/// coloured by Cp.

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "manta/aero/source.hpp"
#include "manta/euler/solver.hpp"
#include "manta/mesh/mesh.hpp"

namespace manta::euler {

/// The wall of a mesh: the faces of the markers whose role is `wall` as triangles
/// (quadrilaterals split in two), each turned so that its normal (b - a) x (c - a) points into
/// the flow, over the wall's own node numbering.
struct WallSurface {
    std::vector<std::string> markers;                   ///< the wall markers, mesh order
    std::vector<mesh::Index> nodes;                     ///< mesh node of each wall node
    std::vector<std::array<mesh::Index, 4>> triangles;  ///< a b c (wall nodes), marker index
};
/// InputError naming `what` if the mesh has no wall face.
[[nodiscard]] WallSurface wall_surface(const mesh::Mesh& mesh,
                                       const std::vector<BoundaryKind>& roles,
                                       const std::string& what);

/// Write `wall.csv`: `header` lines, then the wall nodes' coordinates as `mesh` holds them [m]
/// and the triangles. IoError if not writable.
void write_wall_geometry(const std::filesystem::path& file, const mesh::Mesh& mesh,
                         const WallSurface& wall,
                         const std::vector<std::pair<std::string, std::string>>& header);
/// Write one instant: `header` lines, then Cp of each wall node (`cp`: one per mesh node).
void write_wall_cp(const std::filesystem::path& file, const WallSurface& wall,
                   std::span<const double> cp,
                   const std::vector<std::pair<std::string, std::string>>& header);

/// Write the wall of an Euler-source run (`EulerSource::start_unsteady`) at its current instant
/// into `file`, and the wall's geometry into `wall.csv` beside it unless that exists (the mesh at
/// rest: the mesh file's coordinates, the aircraft's geometry axes, control surfaces undeflected,
/// no rigid motion). Cp on the instantaneous airspeed's dynamic pressure (as the run's
/// coefficients). Returns false, writing nothing, when `run` is not an Euler-source run.
bool write_surface_snapshot(const aero::UnsteadyRun& run, const std::filesystem::path& file);

}  // namespace manta::euler
