/// @file gmsh.cpp
/// gmsh MSH reader, versions 2.2 and 4.1, ASCII and binary (gmsh reference manual, sec. "MSH
/// file format", gmsh 4.8). Own parser rather than the gmsh API, so that every error names the
/// file line (byte offset in binary files); see docs/mesh.md. First-order elements only; node
/// order converted to VTK (prisms only differ).

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstring>
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

std::string unsupported_type(std::int64_t id) {
    return fmt::format(
        "element type {} is not supported; expected first-order elements "
        "(gmsh types 1 to 7, or 15 for points, which are skipped)",
        id);
}

/// An element before the dimension of the mesh is known.
struct Element {
    RawType type;
    std::array<std::int64_t, 8> tags;  ///< gmsh node tags
    int entity_dim;
    int physical;       ///< physical tag or 0
    std::int64_t line;  ///< line (ASCII) or byte offset (binary) of the element
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
    std::string_view text;
    bool binary = false;   ///< file type 1: sections after $MeshFormat hold binary data
    bool swap = false;     ///< the file's byte order is not this machine's
    int size_bytes = 8;    ///< MSH 4.1 binary: bytes of a size_t (the header's data size)
    std::size_t bpos = 0;  ///< read position in binary data
    bool in_data = false;  ///< reading binary data (errors name bpos)

    Reader(std::string_view t, const std::string& src) : cur(t, src), source(src), text(t) {}

    [[noreturn]] void bfail(const std::string& what) const {
        throw InputError(fmt::format("{}: byte {}: {}", source, bpos, what));
    }
    /// Error at the current place: the byte in binary data, else the line.
    [[noreturn]] void fail(const std::string& what) const {
        if (in_data) bfail(what);
        cur.fail(what);
    }
    void begin_data() {
        bpos = cur.position();
        in_data = true;
    }
    void end_data() {
        if (bpos < text.size() && text[bpos] == '\n') ++bpos;
        cur.seek(bpos);
        in_data = false;
    }
    /// The next binary value of type T in the file's byte order.
    template <class T>
    T get(std::string_view what) {
        if (bpos > text.size() || text.size() - bpos < sizeof(T))
            bfail(fmt::format("end of file; expected {} ({} bytes; truncated file?)", what,
                              sizeof(T)));
        std::array<char, sizeof(T)> b{};
        std::memcpy(b.data(), text.data() + bpos, sizeof(T));
        if (swap) std::reverse(b.begin(), b.end());
        T v{};
        std::memcpy(&v, b.data(), sizeof(T));
        bpos += sizeof(T);
        return v;
    }
    std::int64_t get_int(std::string_view what) { return get<std::int32_t>(what); }
    double get_double(std::string_view what) { return get<double>(what); }
    /// An MSH 4.1 size_t (4 or 8 bytes, the header's data size).
    std::int64_t get_size(std::string_view what) {
        if (size_bytes == 4) return get<std::uint32_t>(what);
        const auto v = get<std::uint64_t>(what);
        if (v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
            bfail(fmt::format("{} = {}; expected a count or tag below 2^63", what, v));
        return static_cast<std::int64_t>(v);
    }
    /// InputError unless `n` is a valid count and `n` records of at least `each` bytes follow.
    void need(std::int64_t n, std::size_t each, std::string_view what) {
        if (n < 0 || n > std::numeric_limits<Index>::max())
            bfail(fmt::format("{} = {}; expected 0 to {}", what, n,
                              std::numeric_limits<Index>::max()));
        const std::size_t left = bpos < text.size() ? text.size() - bpos : 0;
        if (static_cast<std::size_t>(n) * each > left)
            bfail(
                fmt::format("{} = {}, but only {} bytes follow; expected at least {} "
                            "(truncated file or wrong count?)",
                            what, n, left, static_cast<std::size_t>(n) * each));
    }

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
        if (file_type != 0 && file_type != 1)
            cur.fail(fmt::format("file type {}; expected 0 (ASCII) or 1 (binary)", file_type));
        if (file_type == 1) {
            // Binary: the data size (MSH 4.1: sizeof(size_t); 2.2: sizeof(double)), then the
            // integer 1 written in binary, which gives the byte order.
            const int ds = num<int>(2, "data size");
            if (version == 2.2 ? ds != 8 : ds != 4 && ds != 8)
                cur.fail(
                    fmt::format("data size {}; expected {}", ds,
                                version == 2.2 ? "8 (sizeof(double))" : "4 or 8 (sizeof(size_t))"));
            size_bytes = ds;
            binary = true;
            begin_data();
            const auto one = get<std::uint32_t>("the binary integer 1");
            if (one != 1) {
                swap = true;
                bpos -= 4;
                if (get<std::uint32_t>("the binary integer 1") != 1) {
                    bpos -= 4;
                    bfail(
                        fmt::format("the binary integer {}; expected 1 in either byte order", one));
                }
            }
            end_data();
            cur.use_byte_offsets();
        }
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

    /// MSH 4.1 binary $Entities: counts (size_t), then per entity its tag (int), point or
    /// bounding box (doubles), physical tags (size_t count, ints) and, for curves and up, the
    /// bounding entities (size_t count, ints).
    void entities_binary() {
        begin_data();
        std::array<std::int64_t, 4> n{};
        for (int d = 0; d < 4; ++d) n[d] = get_size("entity count");
        for (int d = 0; d < 4; ++d)
            need(n[d], d == 0 ? 28 + size_bytes : 52 + 2 * size_bytes, "entity count");
        for (int d = 0; d < 4; ++d)
            for (std::int64_t i = 0; i < n[d]; ++i) {
                const auto tag = static_cast<int>(get_int("entity tag"));
                for (int k = 0; k < (d == 0 ? 3 : 6); ++k) (void)get_double("entity coordinate");
                const auto np = get_size("number of physical tags");
                need(np, 4, "number of physical tags");
                for (std::int64_t k = 0; k < np; ++k) {
                    const auto p = static_cast<int>(get_int("physical tag"));
                    if (k == 0) entity_physical[{d, tag}] = p;
                }
                if (d > 0) {
                    const auto nbound = get_size("number of bounding entities");
                    need(nbound, 4, "number of bounding entities");
                    bpos += 4 * static_cast<std::size_t>(nbound);
                }
            }
        end_data();
        expect_end("Entities");
    }

    void entities() {
        if (binary) return entities_binary();
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
            fail(fmt::format("node tag {} appears twice; expected unique node tags", tag));
        x.insert(x.end(), {px, py, pz});
        return idx;
    }

    /// Binary $Nodes. 2.2: count (text line), then per node tag (int) and x y z (doubles).
    /// 4.1: numEntityBlocks numNodes minNodeTag maxNodeTag (size_t), then per block entityDim
    /// entityTag parametric (int) numNodesInBlock (size_t), the block's tags (size_t), then its
    /// coordinates (doubles).
    void nodes_binary() {
        if (version == 2.2) {
            next_tokens("number of nodes");
            const auto n = num<std::int64_t>(0, "number of nodes");
            begin_data();
            need(n, 28, "number of nodes");
            node_index.reserve(static_cast<std::size_t>(n));
            for (std::int64_t i = 0; i < n; ++i) {
                const auto tag = get_int("node tag");
                const double px = get_double("x"), py = get_double("y"), pz = get_double("z");
                add_node(tag, px, py, pz);
            }
        } else {
            begin_data();
            const auto nb = get_size("number of node blocks");
            const auto n = get_size("number of nodes");
            (void)get_size("minimum node tag");
            (void)get_size("maximum node tag");
            const auto sz = static_cast<std::size_t>(size_bytes);
            need(nb, 12 + sz, "number of node blocks");
            need(n, 24 + sz, "number of nodes");
            node_index.reserve(static_cast<std::size_t>(n));
            std::int64_t total = 0;
            std::vector<std::int64_t> tags;
            for (std::int64_t b = 0; b < nb; ++b) {
                (void)get_int("entity dimension");
                (void)get_int("entity tag");
                const auto parametric = get_int("parametric flag");
                const auto m = get_size("nodes in block");
                need(m, 24 + sz, "nodes in block");
                if (parametric != 0) bfail("parametric nodes; expected parametric = 0");
                tags.resize(static_cast<std::size_t>(m));
                for (auto& t : tags) t = get_size("node tag");
                for (std::int64_t i = 0; i < m; ++i) {
                    const double px = get_double("x"), py = get_double("y"), pz = get_double("z");
                    add_node(tags[i], px, py, pz);
                }
                total += m;
            }
            if (total != n)
                bfail(fmt::format("the node blocks hold {} nodes; the header announced {}", total,
                                  n));
        }
        end_data();
        expect_end("Nodes");
    }

    void nodes() {
        if (binary) return nodes_binary();
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

    /// Keep an element (gmsh node order; prisms turned to VTK order).
    void push_element(RawType t, std::array<std::int64_t, 8> tags, int entity_dim, int physical,
                      std::int64_t where) {
        if (t == RawType::prism) {  // gmsh prism: (0,1,2) normal toward (3,4,5); VTK: away
            std::swap(tags[1], tags[2]);
            std::swap(tags[4], tags[5]);
        }
        elements.push_back(
            {t, tags, entity_dim < 0 ? detail::raw_dim(t) : entity_dim, physical, where});
    }

    void add_element(int type_id, std::size_t first, int entity_dim, int physical) {
        RawType t{};
        int nn = 0;
        if (type_id == 15) return;  // points
        if (!gmsh_type(type_id, t, nn)) cur.fail(unsupported_type(type_id));
        if (tok.size() != first + static_cast<std::size_t>(nn))
            cur.fail(fmt::format("element type {} with {} node tags; expected {}", type_id,
                                 tok.size() - std::min(first, tok.size()), nn));
        std::array<std::int64_t, 8> tags{};
        for (int k = 0; k < nn; ++k) tags[k] = num<std::int64_t>(first + k, "node tag");
        push_element(t, tags, entity_dim, physical, cur.line());
    }

    /// Binary $Elements. 2.2: count (text line), then blocks: elementType numElements numTags
    /// (int), then per element its number, tags and node tags (int). 4.1: numEntityBlocks
    /// numElements minElementTag maxElementTag (size_t), then per block entityDim entityTag
    /// elementType (int) numElementsInBlock (size_t) and per element its tag and node tags
    /// (size_t).
    void elements_binary() {
        if (version == 2.2) {
            next_tokens("number of elements");
            const auto n = num<std::int64_t>(0, "number of elements");
            begin_data();
            need(n, 8, "number of elements");
            elements.reserve(static_cast<std::size_t>(n));
            for (std::int64_t done = 0; done < n;) {
                const auto type = get_int("element type");
                const auto m = get_int("number of elements in the block");
                const auto ntags = get_int("number of tags");
                if (m < 1 || m > n - done)
                    bfail(
                        fmt::format("a block of {} elements with {} of the {} left; expected "
                                    "1 to {}",
                                    m, n - done, n, n - done));
                if (ntags < 0 || ntags > 64)
                    bfail(fmt::format("{} tags per element; expected 0 to 64", ntags));
                RawType t{};
                int nn = 1;
                const bool point = type == 15;
                if (!point && !gmsh_type(static_cast<int>(type), t, nn))
                    bfail(unsupported_type(type));
                need(m, 4 * static_cast<std::size_t>(1 + ntags + nn), "elements in the block");
                for (std::int64_t i = 0; i < m; ++i) {
                    const auto where = static_cast<std::int64_t>(bpos);
                    (void)get_int("element number");
                    int physical = 0;
                    for (std::int64_t k = 0; k < ntags; ++k) {
                        const auto tag = get_int("element tag");
                        if (k == 0) physical = static_cast<int>(tag);
                    }
                    std::array<std::int64_t, 8> tags{};
                    for (int k = 0; k < nn; ++k) tags[k] = get_int("node tag");
                    if (!point) push_element(t, tags, -1, physical, where);
                }
                done += m;
            }
        } else {
            begin_data();
            const auto nb = get_size("number of element blocks");
            const auto n = get_size("number of elements");
            (void)get_size("minimum element tag");
            (void)get_size("maximum element tag");
            const auto sz = static_cast<std::size_t>(size_bytes);
            need(nb, 12 + sz, "number of element blocks");
            need(n, 2 * sz, "number of elements");
            elements.reserve(static_cast<std::size_t>(n));
            std::int64_t total = 0;
            for (std::int64_t b = 0; b < nb; ++b) {
                const auto dim = static_cast<int>(get_int("entity dimension"));
                const auto entity = static_cast<int>(get_int("entity tag"));
                const auto type = get_int("element type");
                const auto m = get_size("elements in block");
                RawType t{};
                int nn = 1;
                const bool point = type == 15;
                if (!point && !gmsh_type(static_cast<int>(type), t, nn))
                    bfail(unsupported_type(type));
                need(m, sz * static_cast<std::size_t>(1 + nn), "elements in block");
                const auto it = entity_physical.find({dim, entity});
                const int physical = it == entity_physical.end() ? 0 : it->second;
                for (std::int64_t i = 0; i < m; ++i) {
                    const auto where = static_cast<std::int64_t>(bpos);
                    (void)get_size("element tag");
                    std::array<std::int64_t, 8> tags{};
                    for (int k = 0; k < nn; ++k) tags[k] = get_size("node tag");
                    if (!point) push_element(t, tags, dim, physical, where);
                }
                total += m;
            }
            if (total != n)
                bfail(fmt::format("the element blocks hold {} elements; the header announced {}",
                                  total, n));
        }
        end_data();
        expect_end("Elements");
    }

    void elements_section() {
        if (binary) return elements_binary();
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
        raw.where_label = binary ? "byte" : "line";
        const std::string at = raw.where_label;
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
                        fmt::format("{}: {} {}: node tag {} is not in $Nodes; "
                                    "expected a defined node",
                                    source, at, e.line, e.tags[k]));
                nodes[k] = it->second;
            }
            if (d == dim) {
                raw.cells.add(e.type, nodes.data(), e.line);
                continue;
            }
            if (e.physical == 0)
                throw InputError(
                    fmt::format("{}: {} {}: a boundary element in no physical "
                                "group; expected every boundary element in a named "
                                "physical group (the marker)",
                                source, at, e.line));
            const auto it = physical_names.find({d, e.physical});
            if (it == physical_names.end() || it->second.empty())
                throw InputError(
                    fmt::format("{}: {} {}: physical group {} (dimension {}) has no "
                                "name; expected a name in $PhysicalNames (the "
                                "marker)",
                                source, at, e.line, e.physical, d));
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
