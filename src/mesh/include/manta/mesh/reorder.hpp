#pragma once
/// @file reorder.hpp
/// Node renumbering for memory locality: reverse Cuthill-McKee (E. Cuthill and J. McKee,
/// "Reducing the bandwidth of sparse symmetric matrices", Proc. 24th ACM National Conference,
/// 1969; A. George, "Computer implementation of the finite element method", Stanford report
/// STAN-CS-71-208, 1971), computed with the Boost Graph Library. Edge-based solvers sweep the
/// node graph; a banded numbering keeps a node's neighbours close in memory, which makes the
/// sparse products and the incomplete factorisation of the implicit solver several times faster
/// than a random order (docs/euler.md, "Linear solver").

#include <vector>

#include "manta/mesh/mesh.hpp"

namespace manta::mesh {

/// A mesh with its nodes renumbered.
struct ReorderedMesh {
    Mesh mesh;                        ///< the renumbered, finalized mesh
    std::vector<Index> new_from_old;  ///< new number of each original node
    std::vector<Index> old_from_new;  ///< original number of each new node
};

/// Renumber the nodes of a finalized mesh in reverse Cuthill-McKee order of its node graph
/// (nodes joined by cell edges), starting each connected part from a pseudo-peripheral node.
/// Cells, faces and markers keep their order; the result is finalized.
[[nodiscard]] ReorderedMesh reorder_reverse_cuthill_mckee(const Mesh& mesh);

/// Half-bandwidth of the node graph: the largest |i - j| over the cell edges (i, j).
[[nodiscard]] Index bandwidth(const Mesh& mesh);

}  // namespace manta::mesh
