#pragma once
/// @file output.hpp
/// Files of a steady vortex-lattice solution: panel loads as VTU (ParaView) and the span loading
/// as CSV (formats in docs/formats.md).

#include <filesystem>

#include "manta/vlm/lattice.hpp"
#include "manta/vlm/model.hpp"
#include "manta/vlm/steady.hpp"

namespace manta::vlm {

/// VTU (XML unstructured grid, ASCII) of the lattice panels with cell data: circulation per unit
/// speed `gamma`, panel normal force coefficient `dcp` (Delta Cp = F.n / (q A)), surface index.
/// Written atomically.
void write_panels_vtu(const std::filesystem::path& file, const Model& model, const Lattice& lattice,
                      const SteadyResult& result);

/// Span loading CSV: one row per strip, columns surface, mirrored, y, z (station of the strip's
/// control points), chord, width, cl (section normal-force coefficient), c_cl_over_cref
/// (c cl / c_ref), gamma (strip circulation per unit speed). Written atomically.
void write_span_loading_csv(const std::filesystem::path& file, const Model& model,
                            const Lattice& lattice, const SteadyResult& result);

}  // namespace manta::vlm
