/// @file raw.cpp
/// Shared reader parts: options, format detection, gzip input, the line cursor and the step
/// from a raw (2-D or 3-D) mesh to a finalized 3-D mesh, extruding 2-D meshes into a slab.

#include "detail/raw.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "manta/core/error.hpp"

namespace manta::mesh {

void ReadOptions::validate() const {
    if (!(slab_thickness > 0.0) || !std::isfinite(slab_thickness))
        throw ConfigError(fmt::format("mesh slab_thickness = {}; expected a finite length > 0 m",
                                      slab_thickness));
    if (slab_marker_back.empty() || slab_marker_front.empty() ||
        slab_marker_back == slab_marker_front)
        throw ConfigError(
            fmt::format("mesh slab markers '{}' and '{}'; expected two different "
                        "non-empty names",
                        slab_marker_back, slab_marker_front));
}

MeshFormat detect_format(const std::filesystem::path& file) {
    std::string name = file.filename().string();
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const auto ends = [&name](std::string_view s) { return name.ends_with(s); };
    if (ends(".su2") || ends(".su2.gz")) return MeshFormat::su2;
    if (ends(".msh") || ends(".msh.gz")) return MeshFormat::gmsh;
    if (ends(".cgns") || ends(".cgn")) return MeshFormat::cgns;
    throw InputError(
        fmt::format("{}: unknown mesh format; expected a name ending in .su2, "
                    ".su2.gz, .msh, .msh.gz, .cgns or .cgn",
                    file.string()));
}

Mesh read_mesh(const std::filesystem::path& file, const ReadOptions& options) {
    switch (detect_format(file)) {
        case MeshFormat::su2:
            return read_su2(file, options);
        case MeshFormat::gmsh:
            return read_gmsh(file, options);
        case MeshFormat::cgns:
            return read_cgns(file, options);
    }
    return read_su2(file, options);
}

std::string read_maybe_gzipped(const std::filesystem::path& file) {
    // gzread passes files that are not gzip-compressed through unchanged.
    gzFile g = gzopen(file.string().c_str(), "rb");
    if (g == nullptr)
        throw IoError(fmt::format("{}: cannot open the mesh file for reading", file.string()));
    std::string out;
    std::error_code ec;
    const auto size = std::filesystem::file_size(file, ec);
    if (!ec) out.reserve(static_cast<std::size_t>(size));
    std::vector<char> buf(1 << 20);
    for (;;) {
        const int n = gzread(g, buf.data(), static_cast<unsigned>(buf.size()));
        if (n < 0) {
            int err = 0;
            const std::string msg = gzerror(g, &err);
            gzclose(g);
            throw IoError(
                fmt::format("{}: read error after {} bytes ({}); expected a readable, "
                            "complete file",
                            file.string(), out.size(), msg));
        }
        if (n == 0) break;
        out.append(buf.data(), static_cast<std::size_t>(n));
        // A compression bomb (issue 16): mesh text compresses 3 to 10 times; refuse to hold
        // more than 256 MiB that expanded over 100 times.
        if (!ec && out.size() > (256u << 20) && out.size() / 100 > size) {
            gzclose(g);
            throw InputError(fmt::format(
                "{}: decompresses to more than {} bytes from {} compressed bytes (ratio over "
                "100); expected a mesh (a damaged or hostile gzip file?)",
                file.string(), out.size(), size));
        }
    }
    gzclose(g);
    return out;
}

detail::ByteStream detail::open_mesh_stream(const std::filesystem::path& file,
                                            std::shared_ptr<void>& handle) {
    gzFile g = gzopen(file.string().c_str(), "rb");
    if (g == nullptr)
        throw IoError(fmt::format("{}: cannot open the mesh file for reading", file.string()));
    handle = std::shared_ptr<void>(g, [](void* p) { gzclose(static_cast<gzFile>(p)); });
    std::error_code ec;
    const auto size = std::filesystem::file_size(file, ec);
    const std::uint64_t file_size = ec ? 0 : static_cast<std::uint64_t>(size);
    auto delivered = std::make_shared<std::uint64_t>(0);
    detail::ByteStream s;
    s.read = [g, file, delivered](char* out, std::size_t n) -> std::size_t {
        const int got = gzread(g, out, static_cast<unsigned>(n));
        if (got < 0) {
            int err = 0;
            const std::string msg = gzerror(g, &err);
            throw IoError(
                fmt::format("{}: read error after {} bytes ({}); expected a readable, "
                            "complete file",
                            file.string(), *delivered, msg));
        }
        *delivered += static_cast<std::uint64_t>(got);
        return static_cast<std::size_t>(got);
    };
    s.bound = [g, file_size]() -> std::size_t {
        // Compressed bytes not yet consumed (zlib reads ahead, hence the 64 KiB of slack) times
        // deflate's largest expansion, 1032 to 1 (zlib technical details, zlib.net/zlib_tech.html).
        const auto consumed = static_cast<std::uint64_t>(std::max<z_off_t>(gzoffset(g), 0));
        const std::uint64_t left = (file_size > consumed ? file_size - consumed : 0) + (64u << 10);
        const std::uint64_t ratio = gzdirect(g) ? 1 : 1032;
        return static_cast<std::size_t>(
            std::min<std::uint64_t>(left * ratio, std::numeric_limits<std::size_t>::max() / 2));
    };
    return s;
}

namespace detail {

int raw_node_count(RawType t) noexcept {
    switch (t) {
        case RawType::line:
            return 2;
        case RawType::triangle:
            return 3;
        case RawType::quad:
            return 4;
        case RawType::tetra:
            return 4;
        case RawType::hexa:
            return 8;
        case RawType::prism:
            return 6;
        case RawType::pyramid:
            return 5;
    }
    return 0;
}

int raw_dim(RawType t) noexcept {
    switch (t) {
        case RawType::line:
            return 1;
        case RawType::triangle:
        case RawType::quad:
            return 2;
        default:
            return 3;
    }
}

int RawMesh::marker(const std::string& name) {
    const auto it = std::find(markers.begin(), markers.end(), name);
    if (it != markers.end()) return static_cast<int>(it - markers.begin());
    markers.push_back(name);
    return static_cast<int>(markers.size()) - 1;
}

namespace {

CellType cell_type_of(RawType t) {
    switch (t) {
        case RawType::tetra:
            return CellType::tetra;
        case RawType::hexa:
            return CellType::hexa;
        case RawType::prism:
            return CellType::prism;
        default:
            return CellType::pyramid;
    }
}

std::string at(const RawMesh& raw, std::int64_t where) {
    return where > 0 ? fmt::format("{}: {} {}", raw.source, raw.where_label, where) : raw.source;
}

Mesh build_3d(RawMesh& raw) {
    Mesh m(raw.source);
    m.set_where_label(raw.where_label);
    const auto nn = static_cast<Index>(raw.x.size() / 3);
    m.reserve(nn, static_cast<Index>(raw.cells.size()), static_cast<Index>(raw.faces.size()));
    for (Index i = 0; i < nn; ++i) m.add_node({raw.x[3 * i], raw.x[3 * i + 1], raw.x[3 * i + 2]});
    for (const auto& name : raw.markers) m.add_marker(name);
    for (std::size_t c = 0; c < raw.cells.size(); ++c) {
        const RawType t = raw.cells.types[c];
        if (raw_dim(t) != 3)
            throw InputError(
                fmt::format("{}: a {}-D element among the cells of a 3-D mesh; "
                            "expected tetra, pyramid, prism or hexa",
                            at(raw, raw.cells.where[c]), raw_dim(t)));
        m.add_cell(cell_type_of(t),
                   std::span<const Index>(raw.cells.nodes.data() + raw.cells.offsets[c],
                                          static_cast<std::size_t>(raw_node_count(t))),
                   raw.cells.where[c]);
    }
    for (std::size_t f = 0; f < raw.faces.size(); ++f) {
        const RawType t = raw.faces.types[f];
        if (raw_dim(t) != 2)
            throw InputError(
                fmt::format("{}: a {}-D element on a boundary marker of a 3-D mesh; "
                            "expected triangles or quadrilaterals",
                            at(raw, raw.faces.where[f]), raw_dim(t)));
        m.add_face(t == RawType::triangle ? FaceType::triangle : FaceType::quad,
                   std::span<const Index>(raw.faces.nodes.data() + raw.faces.offsets[f],
                                          static_cast<std::size_t>(raw_node_count(t))),
                   raw.faces.marker[f], raw.faces.where[f]);
    }
    raw = RawMesh{};
    m.finalize();
    return m;
}

Mesh extrude_2d(RawMesh& raw, const ReadOptions& opt) {
    opt.validate();
    const auto nn = static_cast<Index>(raw.x.size() / 3);
    if (nn == 0) throw InputError(fmt::format("{}: the 2-D mesh has no nodes", raw.source));
    const double z0 = raw.x[2];
    for (Index i = 0; i < nn; ++i)
        if (std::abs(raw.x[3 * i + 2] - z0) > 1e-12 * (1.0 + std::abs(z0)))
            throw InputError(
                fmt::format("{}: node {} of the 2-D mesh has z = {} but node 0 has "
                            "z = {}; expected a plane mesh of constant z",
                            raw.source, i, raw.x[3 * i + 2], z0));
    for (const auto& name : {opt.slab_marker_back, opt.slab_marker_front})
        if (std::find(raw.markers.begin(), raw.markers.end(), name) != raw.markers.end())
            throw InputError(
                fmt::format("{}: the 2-D mesh already has a marker '{}', the name "
                            "of a slab face; expected another name",
                            raw.source, name));
    RawMesh out;
    out.source = raw.source;
    out.where_label = raw.where_label;
    out.markers = raw.markers;
    const int back = out.marker(opt.slab_marker_back);
    const int front = out.marker(opt.slab_marker_front);
    out.x.resize(6 * static_cast<std::size_t>(nn));
    for (Index i = 0; i < nn; ++i)
        for (int k = 0; k < 3; ++k) {
            out.x[3 * i + k] = raw.x[3 * i + k];
            out.x[3 * (i + nn) + k] = raw.x[3 * i + k] + (k == 2 ? opt.slab_thickness : 0.0);
        }
    const auto xy = [&raw](Index i) { return Eigen::Vector2d(raw.x[3 * i], raw.x[3 * i + 1]); };
    for (std::size_t c = 0; c < raw.cells.size(); ++c) {
        const RawType t = raw.cells.types[c];
        const std::int64_t w = raw.cells.where[c];
        if (raw_dim(t) != 2)
            throw InputError(
                fmt::format("{}: a {}-D element among the cells of a 2-D mesh; "
                            "expected triangles or quadrilaterals",
                            at(raw, w), raw_dim(t)));
        const int n = raw_node_count(t);
        std::array<Index, 4> v{};
        std::copy_n(raw.cells.nodes.begin() + raw.cells.offsets[c], n, v.begin());
        for (int k = 0; k < n; ++k)
            if (v[k] < 0 || v[k] >= nn)
                throw InputError(fmt::format("{}: node {} of a 2-D element; expected 0 to {}",
                                             at(raw, w), v[k], nn - 1));
        double area2 = 0.0;  // twice the signed area (shoelace)
        for (int k = 0; k < n; ++k) {
            const auto a = xy(v[k]);
            const auto b = xy(v[(k + 1) % n]);
            area2 += a.x() * b.y() - a.y() * b.x();
        }
        if (area2 == 0.0)
            throw InputError(
                fmt::format("{}: a 2-D element of zero area (nodes {} {} {}); "
                            "expected a non-degenerate element",
                            at(raw, w), v[0], v[1], v[2]));
        if (area2 < 0.0) std::reverse(v.begin(), v.begin() + n);  // now counter-clockwise
        if (t == RawType::triangle) {
            // VTK wedge: (0,1,2) has its normal away from (3,4,5), so clockwise seen from +z.
            const std::array<Index, 6> p{v[0], v[2], v[1], v[0] + nn, v[2] + nn, v[1] + nn};
            out.cells.add(RawType::prism, p.data(), w);
        } else {
            const std::array<Index, 8> h{v[0],      v[1],      v[2],      v[3],
                                         v[0] + nn, v[1] + nn, v[2] + nn, v[3] + nn};
            out.cells.add(RawType::hexa, h.data(), w);
        }
        const std::array<Index, 4> top{v[0] + nn, v[1] + nn, v[2] + nn, v[3] + nn};
        out.faces.add(t, v.data(), w, back);
        out.faces.add(t, top.data(), w, front);
    }
    for (std::size_t f = 0; f < raw.faces.size(); ++f) {
        const std::int64_t w = raw.faces.where[f];
        if (raw.faces.types[f] != RawType::line)
            throw InputError(
                fmt::format("{}: a {}-D element on a boundary marker of a 2-D mesh; "
                            "expected line segments",
                            at(raw, w), raw_dim(raw.faces.types[f])));
        const Index a = raw.faces.nodes[raw.faces.offsets[f]];
        const Index b = raw.faces.nodes[raw.faces.offsets[f] + 1];
        if (a < 0 || a >= nn || b < 0 || b >= nn)
            throw InputError(fmt::format("{}: boundary segment ({}, {}); expected nodes 0 to {}",
                                         at(raw, w), a, b, nn - 1));
        const std::array<Index, 4> q{a, b, b + nn, a + nn};
        out.faces.add(RawType::quad, q.data(), w, raw.faces.marker[f]);
    }
    raw = RawMesh{};
    return build_3d(out);
}

/// A face (or an edge of a 2-D cell) as its sorted node numbers, padded with -1.
using FaceKey = std::array<Index, 4>;

FaceKey face_key(const Index* n, int count) {
    FaceKey k{-1, -1, -1, -1};
    std::copy_n(n, count, k.begin());
    std::sort(k.begin(), k.begin() + count);
    return k;
}

/// Keys of every face of every cell, sorted (a face shared by two cells appears twice).
std::vector<FaceKey> cell_face_keys(const RawMesh& raw) {
    std::vector<FaceKey> keys;
    keys.reserve(6 * raw.cells.size());
    for (std::size_t c = 0; c < raw.cells.size(); ++c) {
        const RawType t = raw.cells.types[c];
        const Index* n = raw.cells.nodes.data() + raw.cells.offsets[c];
        if (raw_dim(t) == 3) {
            for (const auto& f : cell_faces(cell_type_of(t))) {
                const int nf = f[3] < 0 ? 3 : 4;
                std::array<Index, 4> v{};
                for (int k = 0; k < nf; ++k) v[k] = n[f[k]];
                keys.push_back(face_key(v.data(), nf));
            }
        } else if (raw_dim(t) == 2) {
            const int nn = raw_node_count(t);
            for (int k = 0; k < nn; ++k) {
                const std::array<Index, 2> e{n[k], n[(k + 1) % nn]};
                keys.push_back(face_key(e.data(), 2));
            }
        }
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

}  // namespace

std::vector<Index> exposed_nodes(const RawMesh& raw) {
    const std::vector<FaceKey> keys = cell_face_keys(raw);
    std::vector<Index> out;
    for (std::size_t i = 0; i < keys.size();) {
        std::size_t j = i + 1;
        while (j < keys.size() && keys[j] == keys[i]) ++j;
        if (j - i == 1)
            for (Index n : keys[i])
                if (n >= 0) out.push_back(n);
        i = j;
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

double merge_tolerance(const RawMesh& raw, double relative) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (std::size_t i = 0; i < raw.x.size() / 3; ++i)
        for (int k = 0; k < 3; ++k)
            if (std::isfinite(raw.x[3 * i + k])) {
                lo[k] = std::min(lo[k], raw.x[3 * i + k]);
                hi[k] = std::max(hi[k], raw.x[3 * i + k]);
            }
    const double t = relative * (hi - lo).norm();
    return std::isfinite(t) ? t : 0.0;
}

namespace {

/// Union-find root with path halving.
Index root(std::vector<Index>& parent, Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

}  // namespace

Index merge_coincident(RawMesh& raw, std::vector<Index> candidates, double tol) {
    const auto nn = static_cast<Index>(raw.x.size() / 3);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    // Sweep along an oblique direction: block faces and symmetry planes are often planes
    // x = const, which would put all their nodes in one window of a sweep along x.
    constexpr double d0 = 1.0, d1 = 0.6180339887, d2 = 0.3819660113;
    const auto along = [&raw](Index a) {
        return d0 * raw.x[3 * a] + d1 * raw.x[3 * a + 1] + d2 * raw.x[3 * a + 2];
    };
    std::vector<double> key(static_cast<std::size_t>(nn), 0.0);
    for (Index a : candidates) key[a] = along(a);
    // Non-finite coordinates (rejected later by finalize) must not reach the sort's comparison.
    std::erase_if(candidates, [&key](Index a) { return !std::isfinite(key[a]); });
    std::sort(candidates.begin(), candidates.end(),
              [&key](Index a, Index b) { return key[a] < key[b]; });
    const double window = (d0 + d1 + d2) * tol;  // |key difference| of nodes within tol
    std::vector<Index> parent(static_cast<std::size_t>(nn));
    for (Index i = 0; i < nn; ++i) parent[i] = i;
    bool any = false;
    for (std::size_t a = 0; a < candidates.size(); ++a) {
        const Index i = candidates[a];
        for (std::size_t b = a + 1; b < candidates.size(); ++b) {
            const Index j = candidates[b];
            if (key[j] - key[i] > window) break;
            const double dx = raw.x[3 * j] - raw.x[3 * i];
            const double dy = raw.x[3 * j + 1] - raw.x[3 * i + 1];
            const double dz = raw.x[3 * j + 2] - raw.x[3 * i + 2];
            if (std::abs(dx) <= tol && std::abs(dy) <= tol && std::abs(dz) <= tol) {
                const Index ri = root(parent, i), rj = root(parent, j);
                if (ri != rj) parent[std::max(ri, rj)] = std::min(ri, rj);
                any = true;
            }
        }
    }
    if (!any) return 0;
    std::vector<Index> number(static_cast<std::size_t>(nn), -1);
    std::vector<double> x;
    x.reserve(raw.x.size());
    for (Index i = 0; i < nn; ++i) {
        const Index r = root(parent, i);
        if (number[r] < 0) {
            number[r] = static_cast<Index>(x.size() / 3);
            x.insert(x.end(), raw.x.begin() + 3 * r, raw.x.begin() + 3 * r + 3);
        }
        number[i] = number[r];
    }
    const Index removed = nn - static_cast<Index>(x.size() / 3);
    raw.x = std::move(x);
    for (auto& n : raw.cells.nodes) n = number[n];
    for (auto& n : raw.faces.nodes) n = number[n];
    return removed;
}

std::size_t drop_interior_faces(RawMesh& raw) {
    const std::vector<FaceKey> keys = cell_face_keys(raw);
    RawElements kept;
    std::vector<char> used(raw.markers.size(), 0);
    for (std::size_t f = 0; f < raw.faces.size(); ++f) {
        const RawType t = raw.faces.types[f];
        const Index* n = raw.faces.nodes.data() + raw.faces.offsets[f];
        const auto [lo, hi] =
            std::equal_range(keys.begin(), keys.end(), face_key(n, raw_node_count(t)));
        if (hi - lo >= 2) continue;
        kept.add(t, n, raw.faces.where[f], raw.faces.marker[f]);
        const int m = raw.faces.marker[f];
        if (m >= 0 && static_cast<std::size_t>(m) < used.size()) used[m] = 1;
    }
    const std::size_t removed = raw.faces.size() - kept.size();
    std::vector<int> number(raw.markers.size(), -1);
    std::vector<std::string> names;
    for (std::size_t m = 0; m < raw.markers.size(); ++m)
        if (used[m]) {
            number[m] = static_cast<int>(names.size());
            names.push_back(raw.markers[m]);
        }
    for (auto& m : kept.marker)
        if (m >= 0 && static_cast<std::size_t>(m) < number.size()) m = number[m];
    raw.faces = std::move(kept);
    raw.markers = std::move(names);
    return removed;
}

Mesh build_mesh(RawMesh raw, const ReadOptions& options) {
    if (raw.dim == 2) return extrude_2d(raw, options);
    return build_3d(raw);
}

bool LineCursor::refill() {
    if (!streaming_ || eof_) return false;
    buffer_.erase(0, std::min(pos_, buffer_.size()));
    pos_ = 0;
    constexpr std::size_t chunk = 1u << 16;
    const std::size_t old = buffer_.size();
    buffer_.resize(old + chunk);
    const std::size_t got = stream_.read(buffer_.data() + old, chunk);
    buffer_.resize(old + got);
    text_ = buffer_;
    if (got == 0) eof_ = true;
    return got > 0;
}

bool LineCursor::next(std::string_view& line) {
    std::size_t end = text_.find('\n', pos_);
    // A stream reads on until the line is complete (or the stream ends).
    while (streaming_ && end == std::string_view::npos && !eof_) {
        const std::size_t scanned = text_.size() - std::min(pos_, text_.size());
        if (scanned > max_stream_line)
            fail(fmt::format("a line longer than {} bytes; expected mesh text lines",
                             max_stream_line));
        if (!refill()) break;
        end = text_.find('\n', pos_ + scanned);
    }
    if (pos_ >= text_.size()) return false;
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line_start_ = pos_;
    line = text_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = stop + 1;
    ++line_;
    return true;
}

bool LineCursor::next_content(std::string_view& line, char comment) {
    while (next(line)) {
        if (comment != 0) {
            const std::size_t c = line.find(comment);
            if (c != std::string_view::npos) line = line.substr(0, c);
        }
        if (line.find_first_not_of(" \t\f\v") != std::string_view::npos) return true;
    }
    return false;
}

void LineCursor::require_lines(std::int64_t n, std::string_view what) const {
    if (n > 0 && static_cast<std::size_t>(n) > remaining() / 2 + 1)
        fail(
            fmt::format("{} = {}, but only {} bytes follow; expected {} more lines (truncated "
                        "file or wrong count?)",
                        what, n, remaining(), n));
}

std::string LineCursor::at() const {
    return bytes_ ? fmt::format("{}: byte {}", source_, line_start_)
                  : fmt::format("{}: line {}", source_, line_);
}

void LineCursor::fail(const std::string& what) const {
    throw InputError(fmt::format("{}: {}", at(), what));
}

void split(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() &&
               (line[i] == ' ' || line[i] == '\t' || line[i] == '\f' || line[i] == '\v'))
            ++i;
        if (i >= line.size()) break;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\f' &&
               line[j] != '\v')
            ++j;
        out.push_back(line.substr(i, j - i));
        i = j;
    }
}

}  // namespace detail
}  // namespace manta::mesh
