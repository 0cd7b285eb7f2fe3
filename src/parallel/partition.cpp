/// @file partition.cpp
/// The node graph of a mesh, METIS k-way partitioning and the partition's quality figures.

#include "manta/parallel/partition.hpp"

#include <fmt/format.h>
#include <metis.h>

#include <algorithm>
#include <climits>

#include "manta/core/error.hpp"

namespace manta::parallel {

namespace {

static_assert(sizeof(idx_t) == sizeof(std::int32_t),
              "MANTA passes 32-bit CSR arrays to METIS (Debian's libmetis uses IDXTYPEWIDTH 32)");

/// Sorted unique cell edges of the mesh as (a << 32 | b) keys with a < b.
std::vector<std::uint64_t> edge_keys(const mesh::Mesh& mesh) {
    std::vector<std::uint64_t> keys;
    keys.reserve(static_cast<std::size_t>(mesh.n_cells()) * 12);
    for (mesh::Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        for (const auto& f : mesh::cell_faces(mesh.cell_type(c))) {
            const int nf = f[3] < 0 ? 3 : 4;
            for (int k = 0; k < nf; ++k) {
                auto a = static_cast<std::uint32_t>(nodes[f[k]]);
                auto b = static_cast<std::uint32_t>(nodes[f[(k + 1) % nf]]);
                if (a > b) std::swap(a, b);
                keys.push_back((static_cast<std::uint64_t>(a) << 32) | b);
            }
        }
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
}

const char* metis_status(int rc) {
    switch (rc) {
        case METIS_ERROR_INPUT:
            return "input error";
        case METIS_ERROR_MEMORY:
            return "out of memory";
        default:
            return "error";
    }
}

}  // namespace

NodeGraph node_graph(const mesh::Mesh& mesh) {
    const auto keys = edge_keys(mesh);
    if (2 * keys.size() > static_cast<std::size_t>(INT_MAX))
        throw InputError(fmt::format("{}: {} edges are too many for a 32-bit METIS graph",
                                     mesh.source(), keys.size()));
    const mesh::Index nn = mesh.n_nodes();
    NodeGraph g;
    g.offsets.assign(static_cast<std::size_t>(nn) + 1, 0);
    for (const auto k : keys) {
        ++g.offsets[(k >> 32) + 1];
        ++g.offsets[(k & 0xffffffffu) + 1];
    }
    for (mesh::Index n = 0; n < nn; ++n) g.offsets[n + 1] += g.offsets[n];
    g.adjacency.resize(static_cast<std::size_t>(g.offsets[nn]));
    std::vector<std::int32_t> fill(g.offsets.begin(), g.offsets.end() - 1);
    for (const auto k : keys) {
        const auto a = static_cast<std::int32_t>(k >> 32);
        const auto b = static_cast<std::int32_t>(k & 0xffffffffu);
        g.adjacency[fill[a]++] = b;
        g.adjacency[fill[b]++] = a;
    }
    // Sorted keys already give ascending lists (lower neighbours first); sorting states it.
    for (mesh::Index n = 0; n < nn; ++n)
        std::sort(g.adjacency.begin() + g.offsets[n], g.adjacency.begin() + g.offsets[n + 1]);
    return g;
}

std::vector<int> partition_nodes(const mesh::Mesh& mesh, int n_parts) {
    const mesh::Index nn = mesh.n_nodes();
    if (n_parts < 1 || n_parts > nn)
        throw InputError(fmt::format("{}: cannot split {} nodes into {} parts; expected 1 to {}",
                                     mesh.source(), nn, n_parts, nn));
    std::vector<int> part(static_cast<std::size_t>(nn), 0);
    if (n_parts == 1) return part;

    NodeGraph g = node_graph(mesh);
    idx_t n_vertices = nn;
    idx_t n_constraints = 1;
    idx_t parts = n_parts;
    idx_t objective = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_NUMBERING] = 0;
    options[METIS_OPTION_SEED] = 1;  // reproducible parts
    std::vector<idx_t> where(static_cast<std::size_t>(nn), 0);
    const int rc = METIS_PartGraphKway(&n_vertices, &n_constraints, g.offsets.data(),
                                       g.adjacency.data(), nullptr, nullptr, nullptr, &parts,
                                       nullptr, nullptr, options, &objective, where.data());
    if (rc != METIS_OK)
        throw NumericalError(
            fmt::format("{}: METIS_PartGraphKway failed ({}, code {}) splitting {} nodes "
                        "into {} parts",
                        mesh.source(), metis_status(rc), rc, nn, n_parts));
    for (mesh::Index n = 0; n < nn; ++n) {
        if (where[n] < 0 || where[n] >= n_parts)
            throw NumericalError(fmt::format("{}: METIS put node {} in part {}; expected 0 to {}",
                                             mesh.source(), n, where[n], n_parts - 1));
        part[n] = static_cast<int>(where[n]);
    }
    return part;
}

PartitionQuality partition_quality(const mesh::Mesh& mesh, std::span<const int> part, int n_parts) {
    const mesh::Index nn = mesh.n_nodes();
    if (n_parts < 1 || part.size() != static_cast<std::size_t>(nn))
        throw InputError(
            fmt::format("{}: a partition of {} nodes into {} parts has {} entries; "
                        "expected one per node and at least one part",
                        mesh.source(), nn, n_parts, part.size()));
    PartitionQuality q;
    q.n_parts = n_parts;
    q.sizes.assign(n_parts, 0);
    q.ghosts.assign(n_parts, 0);
    for (mesh::Index n = 0; n < nn; ++n) {
        if (part[n] < 0 || part[n] >= n_parts)
            throw InputError(fmt::format("{}: node {} is in part {}; expected 0 to {}",
                                         mesh.source(), n, part[n], n_parts - 1));
        ++q.sizes[part[n]];
    }
    const auto keys = edge_keys(mesh);
    q.n_edges = static_cast<std::int64_t>(keys.size());
    for (const auto k : keys)
        if (part[k >> 32] != part[k & 0xffffffffu]) ++q.edge_cut;
    const auto largest = *std::max_element(q.sizes.begin(), q.sizes.end());
    q.imbalance = static_cast<double>(largest) * n_parts / static_cast<double>(nn);

    // Ghosts of part p: nodes of other parts in a cell holding a node of p (each counted once
    // per part, through a per-node stamp of the last part that counted it).
    std::vector<int> stamp(static_cast<std::size_t>(nn), -1);
    std::vector<std::vector<mesh::Index>> cells_of_part(n_parts);
    std::vector<char> has(n_parts, 0);
    for (mesh::Index c = 0; c < mesh.n_cells(); ++c) {
        std::fill(has.begin(), has.end(), 0);
        for (mesh::Index n : mesh.cell(c)) has[part[n]] = 1;
        for (int p = 0; p < n_parts; ++p)
            if (has[p]) cells_of_part[p].push_back(c);
    }
    for (int p = 0; p < n_parts; ++p)
        for (mesh::Index c : cells_of_part[p])
            for (mesh::Index n : mesh.cell(c))
                if (part[n] != p && stamp[n] != p) {
                    stamp[n] = p;
                    ++q.ghosts[p];
                }
    return q;
}

}  // namespace manta::parallel
