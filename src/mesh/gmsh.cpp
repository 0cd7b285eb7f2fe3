/// @file gmsh.cpp
/// gmsh MSH reader, ASCII versions 2.2 and 4.1 (gmsh reference manual, sec. "MSH file format",
/// gmsh 4.8). Own parser rather than the gmsh API, so that every error names the file line;
/// see docs/mesh.md. First-order elements only; node order converted to VTK (prisms only differ).

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <unordered_map>

#include "detail/raw.hpp"
#include "manta/core/error.hpp"

namespace manta::mesh {

namespace {

using detail::LineCursor;
using detail::RawType;

/// gmsh element type id -> kind; false for types this reader does not take.
bool gmsh_type(int id, RawType& t, int& nodes) {
    switch (id) {
        case 1:
            t = RawType::line;
            nodes = 2;
            return true;
        case 2:
            t = RawType::triangle;
            nodes = 3;
            return true;
        case 3:
            t = RawType::quad;
            nodes = 4;
            return true;
        case 4:
            t = RawType::tetra;
            nodes = 4;
            return true;
        case 5:
            t = RawType::hexa;
            nodes = 8;
            return true;
        case 6:
            t = RawType::prism;
            nodes = 6;
            return true;
        case 7:
            t = RawType::pyramid;
            nodes = 5;
            return true;
        default:
            return false;
    }
}

[[noreturn]] void unsupported_type(const LineCursor& cur, int id) {
    cur.fail(
        fmt::format("element type {} is not supported; expected first-order elements "
                    "(gmsh types 1 to 7, or 15 for points, which are skipped)",
                    id));
}

/// An element before the dimension of the mesh is known.
struct Element {
    RawType type;
    std::array<std::int64_t, 8> tags;  ///< gmsh node tags
    int entity_dim;
    int physical;  ///< physical tag or 0
    std::int64_t line;
};

struct Reader {
    LineCursor cur;
    std::string source;
    std::string_view line;
    std::vector<std::string_view> tok;
    double version = 0.0;
    std::map<std::pair<int, int>, std::string> physical_names;  // (dim, tag) -> name
    std::map<std::pair<int, int>, int> entity_physical;         // (dim, entity) -> tag
    std::unordered_map<std::int64_t, Index> node_index;         // gmsh tag -> index
    std::vector<double> x;
    std::vector<Element> elements;

    Reader(std::string_view text, const std::string& src) : cur(text, src), source(src) {}

    void next_tokens(std::string_view what) {
        if (!cur.next(line))
            throw InputError(
                fmt::format("{}: end of file at line {}; expected {}", source, cur.line(), what));
        detail::split(line, tok);
        if (tok.empty()) cur.fail(fmt::format("empty line; expected {}", what));
        if (tok[0].starts_with("$") && !what.starts_with("$"))
            cur.fail(fmt::format("'{}': the section ends early; expected {}", tok[0], what));
    }
    template <class T>
    T num(std::size_t k, std::string_view what) {
        if (k >= tok.size())
            cur.fail(fmt::format("{} numbers on the line; expected {} at position {}", tok.size(),
                                 what, k + 1));
        return detail::parse_number<T>(tok[k], cur, what);
    }
    void expect_end(std::string_view section) {
        next_tokens(fmt::format("$End{}", section));
        if (tok[0] != fmt::format("$End{}", section))
            cur.fail(fmt::format("'{}'; expected $End{} (a count in the section is wrong?)",
                                 line.substr(0, 40), section));
    }
    void count_check(std::int64_t n, std::string_view what) {
        if (n < 0 || n > std::numeric_limits<Index>::max())
            cur.fail(fmt::format("{} = {}; expected 0 to {}", what, n,
                                 std::numeric_limits<Index>::max()));
        cur.require_lines(n, what);
    }

    void mesh_format() {
        next_tokens("version file-type data-size");
        version = num<double>(0, "format version");
        const int file_type = num<int>(1, "file type");
        if (version != 2.2 && version != 4.1)
            cur.fail(fmt::format("MSH version {}; expected 2.2 or 4.1", version));
        if (file_type != 0)
            cur.fail(
                "binary MSH; expected ASCII (gmsh: Mesh.Binary = 0, or -format msh41 "
                "without -bin)");
        expect_end("MeshFormat");
    }

    void physical_names_section() {
        next_tokens("number of physical names");
        const auto n = num<std::int64_t>(0, "number of physical names");
        count_check(n, "number of physical names");
        for (std::int64_t i = 0; i < n; ++i) {
            next_tokens("dimension tag \"name\"");
            const int dim = num<int>(0, "physical dimension");
            const int tag = num<int>(1, "physical tag");
            const std::size_t a = line.find('"');
            const std::size_t b = line.rfind('"');
            if (a == std::string_view::npos || b == a)
                cur.fail("a physical name without quotes; expected dim tag \"name\"");
            physical_names[{dim, tag}] = std::string(line.substr(a + 1, b - a - 1));
        }
        expect_end("PhysicalNames");
    }

    void entities() {
        next_tokens("numPoints numCurves numSurfaces numVolumes");
        std::array<std::int64_t, 4> n{};
        for (int d = 0; d < 4; ++d) {
            n[d] = num<std::int64_t>(d, "entity count");
            count_check(n[d], "entity count");
        }
        for (int d = 0; d < 4; ++d)
            for (std::int64_t i = 0; i < n[d]; ++i) {
                next_tokens("an entity line");
                const int tag = num<int>(0, "entity tag");
                const std::size_t k = d == 0 ? 4 : 7;  // after the point / the bounding box
                const auto np = num<std::int64_t>(k, "number of physical tags");
                if (np < 0 || static_cast<std::size_t>(np) + k + 1 > tok.size())
                    cur.fail(fmt::format("{} physical tags announced, {} numbers on the line", np,
                                         tok.size()));
                if (np > 0) entity_physical[{d, tag}] = num<int>(k + 1, "physical tag");
            }
        expect_end("Entities");
    }

    Index add_node(std::int64_t tag, double px, double py, double pz) {
        const auto idx = static_cast<Index>(x.size() / 3);
        if (!node_index.emplace(tag, idx).second)
            cur.fail(fmt::format("node tag {} appears twice; expected unique node tags", tag));
        x.insert(x.end(), {px, py, pz});
        return idx;
    }

    void nodes() {
        if (version == 2.2) {
            next_tokens("number of nodes");
            const auto n = num<std::int64_t>(0, "number of nodes");
            count_check(n, "number of nodes");
            node_index.reserve(static_cast<std::size_t>(n));
            for (std::int64_t i = 0; i < n; ++i) {
                next_tokens(fmt::format("node {} of {}", i + 1, n));
                if (tok.size() != 4)
                    cur.fail(fmt::format("{} numbers; expected tag x y z", tok.size()));
                add_node(num<std::int64_t>(0, "node tag"), num<double>(1, "x"), num<double>(2, "y"),
                         num<double>(3, "z"));
            }
        } else {
            next_tokens("numEntityBlocks numNodes minNodeTag maxNodeTag");
            const auto nb = num<std::int64_t>(0, "number of node blocks");
            const auto n = num<std::int64_t>(1, "number of nodes");
            count_check(nb, "number of node blocks");
            count_check(n, "number of nodes");
            node_index.reserve(static_cast<std::size_t>(n));
            std::int64_t total = 0;
            std::vector<std::int64_t> tags;
            for (std::int64_t b = 0; b < nb; ++b) {
                next_tokens("entityDim entityTag parametric numNodesInBlock");
                const int parametric = num<int>(2, "parametric flag");
                const auto m = num<std::int64_t>(3, "nodes in block");
                count_check(m, "nodes in block");
                if (parametric != 0) cur.fail("parametric nodes; expected parametric = 0");
                tags.resize(static_cast<std::size_t>(m));
                for (auto& t : tags) {
                    next_tokens("a node tag");
                    t = num<std::int64_t>(0, "node tag");
                }
                for (std::int64_t i = 0; i < m; ++i) {
                    next_tokens("node coordinates x y z");
                    if (tok.size() != 3)
                        cur.fail(fmt::format("{} numbers; expected x y z", tok.size()));
                    add_node(tags[i], num<double>(0, "x"), num<double>(1, "y"),
                             num<double>(2, "z"));
                }
                total += m;
            }
            if (total != n)
                cur.fail(fmt::format("the node blocks hold {} nodes; the header announced {}",
                                     total, n));
        }
        expect_end("Nodes");
    }

    void add_element(int type_id, std::size_t first, int entity_dim, int physical) {
        RawType t{};
        int nn = 0;
        if (type_id == 15) return;  // points
        if (!gmsh_type(type_id, t, nn)) unsupported_type(cur, type_id);
        if (tok.size() != first + static_cast<std::size_t>(nn))
            cur.fail(fmt::format("element type {} with {} node tags; expected {}", type_id,
                                 tok.size() - std::min(first, tok.size()), nn));
        Element e{t, {}, entity_dim < 0 ? detail::raw_dim(t) : entity_dim, physical, cur.line()};
        for (int k = 0; k < nn; ++k) e.tags[k] = num<std::int64_t>(first + k, "node tag");
        if (t == RawType::prism) {  // gmsh prism: (0,1,2) normal toward (3,4,5); VTK: away
            std::swap(e.tags[1], e.tags[2]);
            std::swap(e.tags[4], e.tags[5]);
        }
        elements.push_back(e);
    }

    void elements_section() {
        if (version == 2.2) {
            next_tokens("number of elements");
            const auto n = num<std::int64_t>(0, "number of elements");
            count_check(n, "number of elements");
            elements.reserve(static_cast<std::size_t>(n));
            for (std::int64_t i = 0; i < n; ++i) {
                next_tokens(fmt::format("element {} of {}", i + 1, n));
                const int type = num<int>(1, "element type");
                const auto ntags = num<std::int64_t>(2, "number of tags");
                if (ntags < 0 || static_cast<std::size_t>(ntags) + 3 > tok.size())
                    cur.fail(fmt::format("{} tags announced, {} numbers on the line", ntags,
                                         tok.size()));
                const int physical = ntags > 0 ? num<int>(3, "physical tag") : 0;
                add_element(type, 3 + static_cast<std::size_t>(ntags), -1, physical);
            }
        } else {
            next_tokens("numEntityBlocks numElements minElementTag maxElementTag");
            const auto nb = num<std::int64_t>(0, "number of element blocks");
            const auto n = num<std::int64_t>(1, "number of elements");
            count_check(nb, "number of element blocks");
            count_check(n, "number of elements");
            elements.reserve(static_cast<std::size_t>(n));
            std::int64_t total = 0;
            for (std::int64_t b = 0; b < nb; ++b) {
                next_tokens("entityDim entityTag elementType numElementsInBlock");
                const int dim = num<int>(0, "entity dimension");
                const int entity = num<int>(1, "entity tag");
                const int type = num<int>(2, "element type");
                const auto m = num<std::int64_t>(3, "elements in block");
                count_check(m, "elements in block");
                const auto it = entity_physical.find({dim, entity});
                const int physical = it == entity_physical.end() ? 0 : it->second;
                for (std::int64_t i = 0; i < m; ++i) {
                    next_tokens("an element line: tag node tags");
                    add_element(type, 1, dim, physical);
                }
                total += m;
            }
            if (total != n)
                cur.fail(fmt::format("the element blocks hold {} elements; the header announced {}",
                                     total, n));
        }
        expect_end("Elements");
    }

    void skip_section(std::string_view name) {
        const std::string end = fmt::format("$End{}", name.substr(1));
        const std::int64_t start = cur.line();
        while (cur.next(line)) {
            detail::split(line, tok);
            if (!tok.empty() && tok[0] == end) return;
        }
        throw InputError(fmt::format("{}: end of file inside section {} (line {}); expected {}",
                                     source, name, start, end));
    }

    detail::RawMesh parse() {
        bool have_format = false, have_nodes = false, have_elements = false;
        while (cur.next(line)) {
            detail::split(line, tok);
            if (tok.empty()) continue;
            const std::string_view s = tok[0];
            if (s == "$MeshFormat") {
                mesh_format();
                have_format = true;
            } else if (!have_format) {
                cur.fail(fmt::format("'{}'; expected $MeshFormat first", line.substr(0, 40)));
            } else if (s == "$PhysicalNames") {
                physical_names_section();
            } else if (s == "$Entities") {
                if (version == 2.2) cur.fail("$Entities in an MSH 2.2 file; expected 4.1");
                entities();
            } else if (s == "$Nodes") {
                nodes();
                have_nodes = true;
            } else if (s == "$Elements") {
                if (!have_nodes) cur.fail("$Elements before $Nodes; expected the nodes first");
                elements_section();
                have_elements = true;
            } else if (s.starts_with("$")) {
                skip_section(s);
            } else {
                cur.fail(fmt::format("'{}'; expected a section start ($Nodes, $Elements, ...)",
                                     line.substr(0, 40)));
            }
        }
        if (!have_format || !have_nodes || !have_elements)
            throw InputError(
                fmt::format("{}: {} section missing; expected $MeshFormat, $Nodes "
                            "and $Elements",
                            source,
                            !have_format  ? "$MeshFormat"
                            : !have_nodes ? "$Nodes"
                                          : "$Elements"));
        return assemble();
    }

    detail::RawMesh assemble() {
        detail::RawMesh raw;
        raw.source = source;
        int dim = 0;
        for (const auto& e : elements) dim = std::max(dim, detail::raw_dim(e.type));
        if (dim < 2)
            throw InputError(
                fmt::format("{}: no 2-D or 3-D elements; expected a volume or plane "
                            "mesh",
                            source));
        raw.dim = dim;
        raw.x = std::move(x);
        std::array<Index, 8> nodes{};
        for (const auto& e : elements) {
            const int d = detail::raw_dim(e.type);
            if (d < dim - 1) continue;  // lower-dimensional entities (curves of a 3-D mesh)
            const int nn = detail::raw_node_count(e.type);
            for (int k = 0; k < nn; ++k) {
                const auto it = node_index.find(e.tags[k]);
                if (it == node_index.end())
                    throw InputError(
                        fmt::format("{}: line {}: node tag {} is not in $Nodes; "
                                    "expected a defined node",
                                    source, e.line, e.tags[k]));
                nodes[k] = it->second;
            }
            if (d == dim) {
                raw.cells.add(e.type, nodes.data(), e.line);
                continue;
            }
            if (e.physical == 0)
                throw InputError(
                    fmt::format("{}: line {}: a boundary element in no physical "
                                "group; expected every boundary element in a named "
                                "physical group (the marker)",
                                source, e.line));
            const auto it = physical_names.find({d, e.physical});
            if (it == physical_names.end() || it->second.empty())
                throw InputError(
                    fmt::format("{}: line {}: physical group {} (dimension {}) has no "
                                "name; expected a name in $PhysicalNames (the "
                                "marker)",
                                source, e.line, e.physical, d));
            raw.faces.add(e.type, nodes.data(), e.line, raw.marker(it->second));
        }
        elements.clear();
        return raw;
    }
};

}  // namespace

Mesh parse_gmsh(std::string_view text, const std::string& source, const ReadOptions& options) {
    Reader r(text, source);
    return detail::build_mesh(r.parse(), options);
}

Mesh read_gmsh(const std::filesystem::path& file, const ReadOptions& options) {
    return parse_gmsh(read_maybe_gzipped(file), file.string(), options);
}

}  // namespace manta::mesh
