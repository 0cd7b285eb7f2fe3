#pragma once
/// @file mirror.hpp
/// A whole-span mesh from a half model: the half mirrored about its symmetry plane y = 0, for the
/// roll and yaw rates (antisymmetric), which a symmetry plane cannot carry.

#include <map>
#include <string>

#include "manta/mesh/mesh.hpp"

namespace manta::test {

/// `half` (tetrahedra only, its symmetry marker `symmetry_marker` on y = 0 exactly) and its
/// mirror image y -> -y, the nodes on the plane shared and the symmetry marker dropped. The
/// mirrored faces of a marker named in `renamed` go to the marker of the mapped name (e.g. a
/// control surface's left copy), the others to the marker of the same name. InputError if a
/// cell is not a tetrahedron or `finalize` fails.
[[nodiscard]] mesh::Mesh mirrored_about_y(const mesh::Mesh& half,
                                          const std::string& symmetry_marker = "symmetry",
                                          const std::map<std::string, std::string>& renamed = {});

}  // namespace manta::test
