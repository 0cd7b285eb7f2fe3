/// @file su2.cpp
/// SU2 native mesh reader (SU2 documentation, "Mesh File", su2code.github.io/docs_v7/Mesh-File):
/// keyword lines NDIME=, NELEM=, NPOIN=, NMARK=, MARKER_TAG=, MARKER_ELEMS=, element lines
/// "VTK-type node... [index]", point lines "x y [z] [index]"; '%' starts a comment.

#include <fmt/format.h>

#include <algorithm>

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

}  // namespace

Mesh parse_su2(std::string_view text, const std::string& source, const ReadOptions& options) {
    LineCursor cur(text, source);
    detail::RawMesh raw;
    raw.source = source;
    int ndime = 0;
    bool have_points = false, have_elems = false;
    std::string_view line, value;
    std::vector<std::string_view> tok;
    while (cur.next_content(line, '%')) {
        if (keyword(line, "NDIME", value)) {
            ndime = static_cast<int>(count_value(value, cur, "NDIME"));
            if (ndime != 2 && ndime != 3)
                cur.fail(fmt::format("NDIME= {}; expected 2 or 3", ndime));
            raw.dim = ndime;
        } else if (keyword(line, "NZONE", value)) {
            if (count_value(value, cur, "NZONE") != 1)
                cur.fail("NZONE is not 1; expected a single-zone mesh");
        } else if (keyword(line, "NELEM", value)) {
            if (ndime == 0) cur.fail("NELEM= before NDIME=; expected NDIME= first");
            if (have_elems) cur.fail("a second NELEM= section; expected one");
            const auto n = count_value(value, cur, "NELEM");
            read_elements(cur, n, raw.cells, -1, "NELEM=", cur.line());
            have_elems = true;
        } else if (keyword(line, "NPOIN", value)) {
            if (ndime == 0) cur.fail("NPOIN= before NDIME=; expected NDIME= first");
            if (have_points) cur.fail("a second NPOIN= section; expected one");
            const auto n = count_value(value, cur, "NPOIN");
            const std::int64_t header = cur.line();
            raw.x.resize(3 * static_cast<std::size_t>(n), 0.0);
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
                for (int k = 0; k < ndime; ++k)
                    raw.x[3 * i + k] = detail::parse_number<double>(tok[k], cur, "coordinate");
            }
            have_points = true;
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
                if (std::find(raw.markers.begin(), raw.markers.end(), name) != raw.markers.end())
                    cur.fail(fmt::format("marker '{}' appears twice; expected unique names", name));
                const int mk = raw.marker(name);
                if (!cur.next_content(line, '%') || !keyword(line, "MARKER_ELEMS", value))
                    cur.fail(fmt::format("marker '{}': expected MARKER_ELEMS= count", name));
                const auto n = count_value(value, cur, "MARKER_ELEMS");
                read_elements(cur, n, raw.faces, mk, fmt::format("marker '{}'", name), cur.line());
            }
        } else if (line.find('=') == std::string_view::npos) {
            cur.fail(
                fmt::format("unexpected line '{}'; expected a keyword line (NDIME=, NELEM=, "
                            "NPOIN=, NMARK=)",
                            line.substr(0, 40)));
        }
        // Other "KEY=" lines (e.g. FFD_NBOX=) are not needed here and skipped.
    }
    if (ndime == 0)
        throw InputError(fmt::format("{}: no NDIME= line; expected an SU2 mesh", source));
    if (!have_elems) throw InputError(fmt::format("{}: no NELEM= section; expected cells", source));
    if (!have_points)
        throw InputError(fmt::format("{}: no NPOIN= section; expected points", source));
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
    return detail::build_mesh(std::move(raw), options);
}

Mesh read_su2(const std::filesystem::path& file, const ReadOptions& options) {
    return parse_su2(read_maybe_gzipped(file), file.string(), options);
}

}  // namespace manta::mesh
