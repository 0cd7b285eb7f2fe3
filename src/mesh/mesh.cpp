/// @file mesh.cpp
/// Mesh storage, cell geometry and the checks of `Mesh::finalize`.

#include "manta/mesh/mesh.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "manta/core/error.hpp"

namespace manta::mesh {

namespace {

// Outward-oriented faces in VTK node order (checked on the unit reference cells in
// tests/mesh/test_mesh.cpp, which require positive volumes and closed dual cells).
constexpr std::array<std::array<int, 4>, 4> tetra_faces{
    {{0, 2, 1, -1}, {0, 1, 3, -1}, {1, 2, 3, -1}, {0, 3, 2, -1}}};
constexpr std::array<std::array<int, 4>, 6> hexa_faces{
    {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
constexpr std::array<std::array<int, 4>, 5> prism_faces{
    {{0, 1, 2, -1}, {3, 5, 4, -1}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}}};
constexpr std::array<std::array<int, 4>, 5> pyramid_faces{
    {{0, 3, 2, 1}, {0, 1, 4, -1}, {1, 2, 4, -1}, {2, 3, 4, -1}, {3, 0, 4, -1}}};

constexpr Index no_node = std::numeric_limits<Index>::max();

/// A cell face identified by its sorted nodes (triangles padded with `no_node`).
struct FaceRecord {
    std::array<Index, 4> key;
    Index cell;
    int local;
};

std::array<Index, 4> sorted_key(std::span<const Index> nodes) {
    std::array<Index, 4> k{no_node, no_node, no_node, no_node};
    std::copy(nodes.begin(), nodes.end(), k.begin());
    std::sort(k.begin(), k.end());
    return k;
}

std::string list_nodes(std::span<const Index> nodes) {
    return fmt::format("{}", fmt::join(nodes, " "));
}

}  // namespace

int node_count(CellType t) noexcept {
    switch (t) {
        case CellType::tetra:
            return 4;
        case CellType::hexa:
            return 8;
        case CellType::prism:
            return 6;
        case CellType::pyramid:
            return 5;
    }
    return 0;
}

int node_count(FaceType t) noexcept {
    return t == FaceType::triangle ? 3 : 4;
}

const char* name(CellType t) noexcept {
    switch (t) {
        case CellType::tetra:
            return "tetra";
        case CellType::hexa:
            return "hexa";
        case CellType::prism:
            return "prism";
        case CellType::pyramid:
            return "pyramid";
    }
    return "?";
}

std::span<const std::array<int, 4>> cell_faces(CellType t) noexcept {
    switch (t) {
        case CellType::tetra:
            return tetra_faces;
        case CellType::hexa:
            return hexa_faces;
        case CellType::prism:
            return prism_faces;
        case CellType::pyramid:
            return pyramid_faces;
    }
    return {};
}

Mesh::Mesh(std::string source) : source_(std::move(source)) {}

Index Mesh::add_node(const Eigen::Vector3d& x) {
    x_.insert(x_.end(), {x.x(), x.y(), x.z()});
    finalized_ = false;
    return n_nodes() - 1;
}

void Mesh::set_node(Index i, const Eigen::Vector3d& x) {
    if (i < 0 || i >= n_nodes())
        throw InputError(
            fmt::format("{}: set_node: node {}; expected 0 to {}", source_, i, n_nodes() - 1));
    if (!x.allFinite())
        throw InputError(
            fmt::format("{}: set_node: node {} to ({}, {}, {}); expected finite "
                        "coordinates",
                        source_, i, x.x(), x.y(), x.z()));
    const auto k = 3 * static_cast<std::size_t>(i);
    x_[k] = x.x();
    x_[k + 1] = x.y();
    x_[k + 2] = x.z();
}

void Mesh::set_coordinates(std::span<const double> x) {
    if (x.size() != x_.size())
        throw InputError(fmt::format("{}: set_coordinates: {} values; expected {} (3 per node)",
                                     source_, x.size(), x_.size()));
    for (std::size_t k = 0; k < x.size(); ++k)
        if (!std::isfinite(x[k]))
            throw InputError(fmt::format(
                "{}: set_coordinates: node {} has a non-finite coordinate {}; expected finite "
                "coordinates",
                source_, k / 3, x[k]));
    std::copy(x.begin(), x.end(), x_.begin());
}

Index Mesh::add_cell(CellType t, std::span<const Index> nodes, std::int64_t where) {
    if (static_cast<int>(nodes.size()) != node_count(t))
        throw InputError(fmt::format("{}: {} {}: a {} cell needs {} nodes, got {}", source_,
                                     where_label_, where, name(t), node_count(t), nodes.size()));
    cell_types_.push_back(t);
    cell_nodes_.insert(cell_nodes_.end(), nodes.begin(), nodes.end());
    cell_offsets_.push_back(static_cast<std::int64_t>(cell_nodes_.size()));
    cell_where_.resize(cell_types_.size() - 1, 0);  // after finalize dropped them
    cell_where_.push_back(where);
    finalized_ = false;
    return n_cells() - 1;
}

int Mesh::add_marker(const std::string& marker) {
    const int m = find_marker(marker);
    if (m >= 0) return m;
    markers_.push_back(marker);
    return n_markers() - 1;
}

Index Mesh::add_face(FaceType t, std::span<const Index> nodes, int marker, std::int64_t where) {
    if (static_cast<int>(nodes.size()) != node_count(t))
        throw InputError(fmt::format("{}: {} {}: a boundary face of type {} needs {} nodes, got {}",
                                     source_, where_label_, where, static_cast<int>(t),
                                     node_count(t), nodes.size()));
    face_types_.push_back(t);
    face_nodes_.insert(face_nodes_.end(), nodes.begin(), nodes.end());
    face_offsets_.push_back(static_cast<std::int64_t>(face_nodes_.size()));
    face_markers_.push_back(marker);
    face_where_.resize(face_types_.size() - 1, 0);
    face_where_.push_back(where);
    finalized_ = false;
    return n_faces() - 1;
}

void Mesh::reserve(Index n_nodes, Index n_cells, Index n_faces) {
    x_.reserve(3 * static_cast<std::size_t>(n_nodes));
    cell_types_.reserve(n_cells);
    cell_offsets_.reserve(static_cast<std::size_t>(n_cells) + 1);
    cell_nodes_.reserve(4 * static_cast<std::size_t>(n_cells));
    cell_where_.reserve(n_cells);
    face_types_.reserve(n_faces);
    face_offsets_.reserve(static_cast<std::size_t>(n_faces) + 1);
    face_nodes_.reserve(3 * static_cast<std::size_t>(n_faces));
    face_markers_.reserve(n_faces);
    face_where_.reserve(n_faces);
}

int Mesh::find_marker(const std::string& marker) const {
    const auto it = std::find(markers_.begin(), markers_.end(), marker);
    return it == markers_.end() ? -1 : static_cast<int>(it - markers_.begin());
}

double Mesh::cell_volume(Index c) const {
    const auto nodes = cell(c);
    Eigen::Vector3d ce = Eigen::Vector3d::Zero();
    for (Index n : nodes) ce += node(n);
    ce /= static_cast<double>(nodes.size());
    double v = 0.0;
    for (const auto& f : cell_faces(cell_type(c))) {
        const int nf = f[3] < 0 ? 3 : 4;
        Eigen::Vector3d cf = Eigen::Vector3d::Zero();
        for (int k = 0; k < nf; ++k) cf += node(nodes[f[k]]);
        cf /= nf;
        for (int k = 0; k < nf; ++k) {
            const Eigen::Vector3d a = node(nodes[f[k]]) - cf;
            const Eigen::Vector3d b = node(nodes[f[(k + 1) % nf]]) - cf;
            v += a.cross(b).dot(cf - ce) / 6.0;
        }
    }
    return v;
}

double Mesh::volume() const {
    double v = 0.0;
    for (Index c = 0; c < n_cells(); ++c) v += cell_volume(c);
    return v;
}

std::size_t Mesh::memory_bytes() const noexcept {
    return x_.capacity() * sizeof(double) + cell_types_.capacity() +
           cell_offsets_.capacity() * sizeof(std::int64_t) +
           cell_nodes_.capacity() * sizeof(Index) + cell_where_.capacity() * sizeof(std::int64_t) +
           face_types_.capacity() + face_offsets_.capacity() * sizeof(std::int64_t) +
           face_nodes_.capacity() * sizeof(Index) + face_markers_.capacity() * sizeof(int) +
           face_where_.capacity() * sizeof(std::int64_t);
}

std::string Mesh::cell_at(Index c) const {
    const std::int64_t w = static_cast<std::size_t>(c) < cell_where_.size() ? cell_where_[c] : 0;
    if (w > 0)
        return fmt::format("{}: {} {}: cell {} ({})", source_, where_label_, w, c,
                           name(cell_type(c)));
    return fmt::format("{}: cell {} ({})", source_, c, name(cell_type(c)));
}

std::string Mesh::face_at(Index f) const {
    const std::int64_t w = static_cast<std::size_t>(f) < face_where_.size() ? face_where_[f] : 0;
    const std::string marker = face_markers_[f] >= 0 && face_markers_[f] < n_markers()
                                   ? markers_[face_markers_[f]]
                                   : std::to_string(face_markers_[f]);
    if (w > 0)
        return fmt::format("{}: {} {}: boundary face {} of marker '{}'", source_, where_label_, w,
                           f, marker);
    return fmt::format("{}: boundary face {} of marker '{}'", source_, f, marker);
}

void Mesh::finalize(const FinalizeOptions& options) {
    const Index nn = n_nodes();
    if (nn == 0 || n_cells() == 0)
        throw InputError(
            fmt::format("{}: the mesh has {} nodes and {} cells; expected a volume "
                        "mesh with at least one cell",
                        source_, nn, n_cells()));
    for (std::size_t i = 0; i < x_.size(); ++i)
        if (!std::isfinite(x_[i]))
            throw InputError(
                fmt::format("{}: node {} has a non-finite coordinate {}", source_, i / 3, x_[i]));
    for (int m = 0; m < n_markers(); ++m)
        if (markers_[m].empty())
            throw InputError(
                fmt::format("{}: marker {} has no name; expected a named boundary", source_, m));

    // Node indices and volumes.
    std::vector<char> used(nn, 0);
    for (Index c = 0; c < n_cells(); ++c) {
        for (Index n : cell(c)) {
            if (n < 0 || n >= nn)
                throw InputError(
                    fmt::format("{} refers to node {}; expected 0 to {}", cell_at(c), n, nn - 1));
            used[n] = 1;
        }
        const auto nodes = cell(c);
        for (std::size_t i = 0; i < nodes.size(); ++i)
            for (std::size_t j = i + 1; j < nodes.size(); ++j)
                if (nodes[i] == nodes[j])
                    throw InputError(fmt::format("{} uses node {} twice; expected distinct nodes",
                                                 cell_at(c), nodes[i]));
        const double v = cell_volume(c);
        if (!(v > 0.0))
            throw InputError(
                fmt::format("{} has volume {:.6g} m^3; expected > 0 (inverted or "
                            "degenerate cell, nodes {})",
                            cell_at(c), v, list_nodes(nodes)));
    }
    for (Index n = 0; n < nn; ++n)
        if (!used[n])
            throw InputError(
                fmt::format("{}: node {} belongs to no cell; expected every node in "
                            "a cell",
                            source_, n));
    for (Index f = 0; f < n_faces(); ++f) {
        if (face_markers_[f] < 0 || face_markers_[f] >= n_markers())
            throw InputError(fmt::format("{} has an unknown marker", face_at(f)));
        for (Index n : face(f))
            if (n < 0 || n >= nn)
                throw InputError(
                    fmt::format("{} refers to node {}; expected 0 to {}", face_at(f), n, nn - 1));
    }

    // Cell faces: interior (two cells), exposed (one cell), or an error (more).
    std::vector<FaceRecord> rec;
    rec.reserve(static_cast<std::size_t>(n_cells()) * 5);
    for (Index c = 0; c < n_cells(); ++c) {
        const auto nodes = cell(c);
        const auto faces = cell_faces(cell_type(c));
        for (int k = 0; k < static_cast<int>(faces.size()); ++k) {
            std::array<Index, 4> fn{};
            const int nf = faces[k][3] < 0 ? 3 : 4;
            for (int i = 0; i < nf; ++i) fn[i] = nodes[faces[k][i]];
            rec.push_back({sorted_key(std::span<const Index>(fn.data(), nf)), c, k});
        }
    }
    std::sort(rec.begin(), rec.end(), [](const FaceRecord& a, const FaceRecord& b) {
        return a.key < b.key || (a.key == b.key && a.cell < b.cell);
    });
    std::vector<FaceRecord> exposed;
    for (std::size_t i = 0; i < rec.size();) {
        std::size_t j = i + 1;
        while (j < rec.size() && rec[j].key == rec[i].key) ++j;
        if (j - i == 1) exposed.push_back(rec[i]);
        if (j - i > 2)
            throw InputError(
                fmt::format("{} shares a face with {} other cells; expected at most "
                            "one neighbour per face",
                            cell_at(rec[i].cell), j - i - 1));
        i = j;
    }
    rec.clear();
    rec.shrink_to_fit();

    // Boundary faces: each must be an exposed cell face, once; it takes that face's order.
    std::vector<char> covered(exposed.size(), 0);
    const auto less = [](const FaceRecord& a, const std::array<Index, 4>& k) { return a.key < k; };
    for (Index f = 0; f < n_faces(); ++f) {
        const auto nodes = face(f);
        const auto key = sorted_key(nodes);
        const auto it = std::lower_bound(exposed.begin(), exposed.end(), key, less);
        if (it == exposed.end() || it->key != key)
            throw InputError(
                fmt::format("{} (nodes {}) is not a face of a cell on the boundary; "
                            "expected a face of exactly one cell",
                            face_at(f), list_nodes(nodes)));
        const auto e = static_cast<std::size_t>(it - exposed.begin());
        if (covered[e])
            throw InputError(
                fmt::format("{} (nodes {}) repeats another boundary face; expected "
                            "each boundary face once",
                            face_at(f), list_nodes(nodes)));
        covered[e] = 1;
        const auto& lf = cell_faces(cell_type(it->cell))[it->local];
        const auto cn = cell(it->cell);
        for (std::size_t i = 0; i < nodes.size(); ++i)
            face_nodes_[face_offsets_[f] + static_cast<std::int64_t>(i)] = cn[lf[i]];
    }
    std::size_t n_bare = 0;
    std::size_t first_bare = 0;
    for (std::size_t e = 0; e < exposed.size(); ++e)
        if (!covered[e] && n_bare++ == 0) first_bare = e;
    if (n_bare > 0 && !options.allow_unmarked_exposed_faces) {
        const auto& r = exposed[first_bare];
        std::vector<Index> fn;
        for (Index n : r.key)
            if (n != no_node) fn.push_back(n);
        throw InputError(
            fmt::format("{}: {} cell faces on the boundary belong to no marker, the "
                        "first with nodes {} ({}); expected every boundary face in "
                        "a marker",
                        source_, n_bare, list_nodes(fn), cell_at(r.cell)));
    }
    // Source positions serve only the messages above.
    std::vector<std::int64_t>().swap(cell_where_);
    std::vector<std::int64_t>().swap(face_where_);
    finalized_ = true;
}

}  // namespace manta::mesh
