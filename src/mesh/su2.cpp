/// @file su2.cpp
/// SU2 native mesh reader (SU2 documentation, "Mesh File", su2code.github.io/docs_v7/Mesh-File):
/// keyword lines NDIME=, NELEM=, NPOIN=, NMARK=, MARKER_TAG=, MARKER_ELEMS=, element lines
/// "VTK-type node... [index]", point lines "x y [z] [index]"; '%' starts a comment. Multi-zone
/// files (NZONE= n, each zone after IZONE= k with its own 0-based node numbers) are joined into
/// one mesh where the zones' exposed nodes coincide.

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "detail/raw.hpp"
#include "manta/core/error.hpp"

namespace manta::mesh {

namespace {

using detail::LineCursor;
using detail::RawType;

/// Value after "KEY=" if `line` starts with that key (spaces allowed around '=').
bool keyword(std::string_view line, std::string_view key, std::string_view& value) {
    const std::size_t b = line.find_first_not_of(" \t");
    if (b == std::string_view::npos) return false;
    line = line.substr(b);
    if (!line.starts_with(key)) return false;
    line = line.substr(key.size());
    const std::size_t e = line.find_first_not_of(" \t");
    if (e == std::string_view::npos || line[e] != '=') return false;
    value = line.substr(e + 1);
    return true;
}

bool vtk_type(int id, RawType& t) {
    switch (id) {
        case 3:
            t = RawType::line;
            return true;
        case 5:
            t = RawType::triangle;
            return true;
        case 9:
            t = RawType::quad;
            return true;
        case 10:
            t = RawType::tetra;
            return true;
        case 12:
            t = RawType::hexa;
            return true;
        case 13:
            t = RawType::prism;
            return true;
        case 14:
            t = RawType::pyramid;
            return true;
        default:
            return false;
    }
}

std::int64_t count_value(std::string_view value, const LineCursor& cur, std::string_view key) {
    std::vector<std::string_view> tok;
    detail::split(value, tok);
    if (tok.empty()) cur.fail(fmt::format("{}= has no value; expected a count", key));
    const auto n = detail::parse_number<std::int64_t>(tok[0], cur, fmt::format("{} count", key));
    if (n < 0 || n > std::numeric_limits<Index>::max())
        cur.fail(fmt::format("{}= {}; expected a count from 0 to {}", key, n,
                             std::numeric_limits<Index>::max()));
    cur.require_lines(n, fmt::format("{}=", key));
    return n;
}

/// Read `n` element lines into `out` (marker -1 for cells).
void read_elements(LineCursor& cur, std::int64_t n, detail::RawElements& out, int marker,
                   std::string_view what, std::int64_t header_line) {
    std::string_view line;
    std::vector<std::string_view> tok;
    std::array<Index, 8> nodes{};
    for (std::int64_t i = 0; i < n; ++i) {
        if (!cur.next_content(line, '%'))
            throw InputError(
                fmt::format("{}: end of file after {} of the {} elements of {} "
                            "(line {}); expected {} more",
                            cur.source(), i, n, what, header_line, n - i));
        detail::split(line, tok);
        const int id = detail::parse_number<int>(tok[0], cur, "element type");
        RawType t{};
        if (!vtk_type(id, t))
            cur.fail(
                fmt::format("unknown element type {}; expected a VTK type id 3 (line), 5 "
                            "(triangle), 9 (quadrilateral), 10 (tetrahedron), 12 "
                            "(hexahedron), 13 (prism) or 14 (pyramid)",
                            id));
        const int nn = detail::raw_node_count(t);
        if (static_cast<int>(tok.size()) < nn + 1 || static_cast<int>(tok.size()) > nn + 2)
            cur.fail(
                fmt::format("element type {} with {} numbers after the type; expected {} "
                            "node numbers and an optional element index",
                            id, tok.size() - 1, nn));
        for (int k = 0; k < nn; ++k) {
            const auto v = detail::parse_number<std::int64_t>(tok[k + 1], cur, "node number");
            if (v < 0 || v > std::numeric_limits<Index>::max())
                cur.fail(fmt::format("node number {}; expected 0 or more", v));
            nodes[k] = static_cast<Index>(v);
        }
        out.add(t, nodes.data(), cur.line(), marker);
    }
}

/// Union-find root with path halving (zones joined by shared nodes).
int zone_root(std::vector<int>& parent, int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

}  // namespace

namespace {

/// The SU2 reader over a cursor (text in memory or a stream read line by line).
Mesh parse_su2_lines(LineCursor& cur, const std::string& source, const ReadOptions& options) {
    detail::RawMesh raw;
    raw.source = source;
    int ndime = 0;
    bool have_points = false, have_elems = false;
    std::string_view line, value;
    std::vector<std::string_view> tok;
    // Zones: node numbers are 0-based within a zone; each zone's cells and faces are shifted
    // by the nodes of the zones before it when the zone ends (and checked against the zone's
    // NPOIN= there; a single zone's are checked by Mesh::finalize).
    std::int64_t nzone = 1, zone = 1, zone_header = 0;
    Index node_base = 0, zone_points = 0;
    std::size_t cell_base = 0, face_base = 0;
    std::vector<std::size_t> zone_cells{0};  // first cell of each zone
    std::set<std::string> zone_markers;
    bool zone_points_read = false, zone_elems_read = false;
    const auto end_zone = [&]() {
        const std::string z = nzone > 1 ? fmt::format(" of zone {}", zone) : "";
        if (!zone_elems_read)
            throw InputError(fmt::format("{}: no NELEM= section{}; expected cells", source, z));
        if (!zone_points_read)
            throw InputError(fmt::format("{}: no NPOIN= section{}; expected points", source, z));
        for (auto* el : {&raw.cells, &raw.faces}) {
            const std::size_t first = el == &raw.cells ? cell_base : face_base;
            for (std::size_t e = first; e < el->size(); ++e)
                for (auto k = el->offsets[e]; k < el->offsets[e + 1]; ++k) {
                    if (nzone > 1 && el->nodes[k] >= zone_points)
                        throw InputError(fmt::format(
                            "{}: line {}: node number {}{}; expected 0 to {} "
                            "(NPOIN= {})",
                            source, el->where[e], el->nodes[k], z, zone_points - 1, zone_points));
                    el->nodes[k] += node_base;
                }
        }
        node_base = static_cast<Index>(raw.x.size() / 3);
        cell_base = raw.cells.size();
        face_base = raw.faces.size();
        zone_cells.push_back(cell_base);
        zone_markers.clear();
        zone_points_read = zone_elems_read = false;
    };
    while (cur.next_content(line, '%')) {
        if (keyword(line, "NDIME", value)) {
            const int d = static_cast<int>(count_value(value, cur, "NDIME"));
            if (d != 2 && d != 3) cur.fail(fmt::format("NDIME= {}; expected 2 or 3", d));
            if (ndime != 0 && d != ndime)
                cur.fail(fmt::format("NDIME= {} in zone {}; expected {} as in the zones before", d,
                                     zone, ndime));
            ndime = d;
            raw.dim = ndime;
        } else if (keyword(line, "NZONE", value)) {
            if (have_elems || have_points || zone_header > 0)
                cur.fail("NZONE= after the first zone's data; expected it first");
            nzone = count_value(value, cur, "NZONE");
            if (nzone < 1) cur.fail(fmt::format("NZONE= {}; expected 1 or more", nzone));
        } else if (keyword(line, "IZONE", value)) {
            const auto k = count_value(value, cur, "IZONE");
            const std::int64_t expected = zone_header == 0 ? 1 : zone + 1;
            if (k != expected || k > nzone)
                cur.fail(fmt::format("IZONE= {}; expected {} of NZONE= {}", k, expected, nzone));
            if (zone_header > 0) end_zone();
            zone = k;
            zone_header = cur.line();
        } else if (keyword(line, "NELEM", value)) {
            if (ndime == 0) cur.fail("NELEM= before NDIME=; expected NDIME= first");
            if (zone_elems_read)
                cur.fail(fmt::format("a second NELEM= section{}; expected one per zone",
                                     nzone > 1 ? fmt::format(" in zone {}", zone) : ""));
            const auto n = count_value(value, cur, "NELEM");
            read_elements(cur, n, raw.cells, -1, "NELEM=", cur.line());
            have_elems = zone_elems_read = true;
        } else if (keyword(line, "NPOIN", value)) {
            if (ndime == 0) cur.fail("NPOIN= before NDIME=; expected NDIME= first");
            if (zone_points_read)
                cur.fail(fmt::format("a second NPOIN= section{}; expected one per zone",
                                     nzone > 1 ? fmt::format(" in zone {}", zone) : ""));
            const auto n = count_value(value, cur, "NPOIN");
            if (n + node_base > std::numeric_limits<Index>::max())
                cur.fail(fmt::format("NPOIN= {} makes the mesh too large", n));
            const std::int64_t header = cur.line();
            zone_points = static_cast<Index>(n);
            // Grown as points are read, so a count the file does not hold allocates nothing.
            raw.x.reserve(3 *
                          static_cast<std::size_t>(node_base + std::min<std::int64_t>(n, 1 << 20)));
            for (std::int64_t i = 0; i < n; ++i) {
                if (!cur.next_content(line, '%'))
                    throw InputError(
                        fmt::format("{}: end of file after {} of the {} points of "
                                    "NPOIN= (line {}); expected {} more",
                                    source, i, n, header, n - i));
                detail::split(line, tok);
                if (static_cast<int>(tok.size()) < ndime ||
                    static_cast<int>(tok.size()) > ndime + 1)
                    cur.fail(
                        fmt::format("a point line with {} numbers; expected {} coordinates "
                                    "and an optional index",
                                    tok.size(), ndime));
                raw.x.resize(raw.x.size() + 3, 0.0);
                for (int k = 0; k < ndime; ++k)
                    raw.x[3 * (node_base + i) + k] =
                        detail::parse_number<double>(tok[k], cur, "coordinate");
            }
            have_points = zone_points_read = true;
        } else if (keyword(line, "NMARK", value)) {
            const auto nmark = count_value(value, cur, "NMARK");
            for (std::int64_t m = 0; m < nmark; ++m) {
                if (!cur.next_content(line, '%') || !keyword(line, "MARKER_TAG", value))
                    cur.fail(
                        fmt::format("marker {} of {}: expected MARKER_TAG= name", m + 1, nmark));
                detail::split(value, tok);
                if (tok.size() != 1)
                    cur.fail("MARKER_TAG= without a single name; expected one name without spaces");
                const std::string name(tok[0]);
                if (!zone_markers.insert(name).second)
                    cur.fail(fmt::format("marker '{}' appears twice{}; expected unique names", name,
                                         nzone > 1 ? fmt::format(" in zone {}", zone) : ""));
                const int mk = raw.marker(name);
                if (!cur.next_content(line, '%') || !keyword(line, "MARKER_ELEMS", value))
                    cur.fail(fmt::format("marker '{}': expected MARKER_ELEMS= count", name));
                const auto n = count_value(value, cur, "MARKER_ELEMS");
                read_elements(cur, n, raw.faces, mk, fmt::format("marker '{}'", name), cur.line());
            }
        } else if (line.find('=') == std::string_view::npos) {
            cur.fail(
                fmt::format("unexpected line '{}'; expected a keyword line (NDIME=, NELEM=, "
                            "NPOIN=, NMARK=, NZONE=, IZONE=)",
                            line.substr(0, 40)));
        }
        // Other "KEY=" lines (e.g. FFD_NBOX=) are not needed here and skipped.
    }
    if (ndime == 0)
        throw InputError(fmt::format("{}: no NDIME= line; expected an SU2 mesh", source));
    if (nzone > 1 && zone_header == 0)
        throw InputError(fmt::format("{}: NZONE= {} but no IZONE= line; expected IZONE= 1 to {}",
                                     source, nzone, nzone));
    if (zone != nzone)
        throw InputError(
            fmt::format("{}: the file ends after zone {} of NZONE= {}; expected {} "
                        "more (truncated file?)",
                        source, zone, nzone, nzone - zone));
    end_zone();
    for (std::size_t c = 0; c < raw.cells.size(); ++c)
        if (detail::raw_dim(raw.cells.types[c]) != ndime)
            throw InputError(fmt::format(
                "{}: line {}: a {}-D element in NELEM= of an NDIME= {} "
                "mesh; expected {}-D cells",
                source, raw.cells.where[c], detail::raw_dim(raw.cells.types[c]), ndime, ndime));
    for (std::size_t f = 0; f < raw.faces.size(); ++f)
        if (detail::raw_dim(raw.faces.types[f]) != ndime - 1)
            throw InputError(fmt::format(
                "{}: line {}: a {}-D element in a marker of an NDIME= {} "
                "mesh; expected {}-D boundary elements",
                source, raw.faces.where[f], detail::raw_dim(raw.faces.types[f]), ndime, ndime - 1));
    if (nzone > 1) {
        // Join the zones at coincident nodes on their exposed faces; interface markers, now
        // inside the mesh, are dropped. Zones that touch no other zone cannot be joined.
        detail::merge_coincident(raw, detail::exposed_nodes(raw), detail::merge_tolerance(raw));
        std::vector<int> parent(static_cast<std::size_t>(nzone));
        for (int z = 0; z < nzone; ++z) parent[z] = z;
        std::vector<int> owner(raw.x.size() / 3, -1);
        for (int z = 0; z < nzone; ++z)
            for (std::size_t c = zone_cells[z]; c < zone_cells[z + 1]; ++c)
                for (auto k = raw.cells.offsets[c]; k < raw.cells.offsets[c + 1]; ++k) {
                    int& o = owner[static_cast<std::size_t>(raw.cells.nodes[k])];
                    if (o < 0)
                        o = z;
                    else if (o != z)
                        parent[zone_root(parent, z)] = zone_root(parent, o);
                }
        for (int z = 1; z < nzone; ++z)
            if (zone_root(parent, z) != zone_root(parent, 0))
                throw InputError(
                    fmt::format("{}: NZONE= {}: zone {} shares no node with zone 1; expected "
                                "zones that meet at coincident nodes (zones joined by sliding "
                                "or non-matching interfaces are not read)",
                                source, nzone, z + 1));
        detail::drop_interior_faces(raw);
    }
    return detail::build_mesh(std::move(raw), options);
}

}  // namespace

Mesh parse_su2(std::string_view text, const std::string& source, const ReadOptions& options) {
    LineCursor cur(text, source);
    return parse_su2_lines(cur, source, options);
}

Mesh read_su2(const std::filesystem::path& file, const ReadOptions& options) {
    // Streamed (gunzipped on the fly): the file is never held whole, and a bad line stops the
    // reading there (issue 16: an 8.7 MB .su2.gz once grew to 9.3 GB in memory).
    std::shared_ptr<void> handle;
    LineCursor cur(detail::open_mesh_stream(file, handle), file.string());
    return parse_su2_lines(cur, file.string(), options);
}

}  // namespace manta::mesh
