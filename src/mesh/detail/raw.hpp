#pragma once
/// @file raw.hpp
/// Private: what a reader collects before the 3-D mesh is built (2-D meshes are extruded here),
/// and the line cursor the text readers share.

#include <charconv>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "manta/mesh/mesh.hpp"
#include "manta/mesh/readers.hpp"

namespace manta::mesh::detail {

/// Element kinds of any dimension (nodes in VTK order).
enum class RawType : std::uint8_t { line, triangle, quad, tetra, hexa, prism, pyramid };

/// Number of nodes of a raw element kind.
[[nodiscard]] int raw_node_count(RawType t) noexcept;
/// Dimension of a raw element kind (1, 2 or 3).
[[nodiscard]] int raw_dim(RawType t) noexcept;

/// Elements as a list of kinds, CSR node lists and source positions.
struct RawElements {
    std::vector<RawType> types;
    std::vector<std::int64_t> offsets{0};
    std::vector<Index> nodes;
    std::vector<std::int64_t> where;
    std::vector<int> marker;  ///< boundary elements only

    void add(RawType t, const Index* n, std::int64_t w, int m = -1) {
        types.push_back(t);
        nodes.insert(nodes.end(), n, n + raw_node_count(t));
        offsets.push_back(static_cast<std::int64_t>(nodes.size()));
        where.push_back(w);
        marker.push_back(m);
    }
    [[nodiscard]] std::size_t size() const noexcept { return types.size(); }
};

/// A mesh as read: dimension 2 or 3, nodes with three coordinates, cells of that dimension and
/// boundary elements one dimension lower.
struct RawMesh {
    std::string source;
    std::string where_label = "line";
    int dim = 3;
    std::vector<double> x;  ///< x y z per node
    RawElements cells;
    RawElements faces;
    std::vector<std::string> markers;

    int marker(const std::string& name);
};

/// Nodes (sorted, unique) on the exposed faces of the cells: faces (edges of 2-D cells) that
/// belong to one cell only. Where zones or blocks meet, these are the nodes that may coincide.
[[nodiscard]] std::vector<Index> exposed_nodes(const RawMesh& raw);

/// A merge tolerance: `relative` times the diagonal of the nodes' bounding box (m).
[[nodiscard]] double merge_tolerance(const RawMesh& raw, double relative = 1e-10);

/// Merge nodes among `candidates` whose coordinates agree within `tol` in x, y and z, renumber
/// the nodes compactly (first occurrence order) and the cells' and faces' node lists with them.
/// Returns the number of nodes removed.
Index merge_coincident(RawMesh& raw, std::vector<Index> candidates, double tol);

/// Remove the boundary elements that are faces of two cells (zone interfaces once the zones'
/// nodes are merged, listed by one zone or by both) and the markers left without an element.
/// Returns the number of boundary elements removed.
std::size_t drop_interior_faces(RawMesh& raw);

/// Build the finalized 3-D mesh (2-D meshes extruded into a slab, `options`).
[[nodiscard]] Mesh build_mesh(RawMesh raw, const ReadOptions& options);

/// Where a streaming LineCursor gets its bytes: `read` fills up to `n` bytes and returns how
/// many (0 at the end; it throws IoError on a read error); `bound` returns an upper bound on the
/// bytes `read` can still deliver (for a gzip stream: the compressed bytes left times deflate's
/// largest ratio, 1032).
struct ByteStream {
    std::function<std::size_t(char* out, std::size_t n)> read;
    std::function<std::size_t()> bound;
};

/// A ByteStream over `file`, gunzipped if it is gzip-compressed (plain files pass through);
/// `handle` keeps the open file until the last copy of it is dropped. IoError if unreadable.
[[nodiscard]] ByteStream open_mesh_stream(const std::filesystem::path& file,
                                          std::shared_ptr<void>& handle);

/// Splits text into lines and tokens, counting lines (1-based) for messages. Either over text
/// held in memory or over a ByteStream read in chunks (then at most one chunk and the current
/// line are held; a line may not exceed `max_stream_line` bytes).
class LineCursor {
public:
    static constexpr std::size_t max_stream_line = 16u << 20;

    LineCursor(std::string_view text, std::string source)
        : text_(text), source_(std::move(source)) {}
    LineCursor(ByteStream stream, std::string source)
        : stream_(std::move(stream)), streaming_(true), source_(std::move(source)) {}
    /// Next line (without its end), or false at the end of the text.
    bool next(std::string_view& line);
    /// Next line that is not blank (after stripping `comment` and what follows, if non-zero).
    bool next_content(std::string_view& line, char comment = 0);
    [[nodiscard]] std::int64_t line() const noexcept { return line_; }
    /// Bytes not yet read (a bound on the number of lines left: each takes two or more); for a
    /// stream, the bytes buffered plus the stream's bound.
    [[nodiscard]] std::size_t remaining() const {
        const std::size_t here = pos_ < text_.size() ? text_.size() - pos_ : 0;
        return streaming_ && !eof_ ? here + stream_.bound() : here;
    }
    /// InputError unless `n` lines can still follow ("NPOIN= 10^9" in a short file).
    void require_lines(std::int64_t n, std::string_view what) const;
    [[nodiscard]] const std::string& source() const noexcept { return source_; }
    /// Byte offset of the next unread character (binary data follows a text line there).
    [[nodiscard]] std::size_t position() const noexcept { return pos_; }
    /// Continue reading text at byte `pos` (after binary data read by the caller).
    void seek(std::size_t pos) noexcept { pos_ = pos; }
    /// Name places by the byte offset of the current line rather than its line number (line
    /// numbers mean nothing once binary data has been passed).
    void use_byte_offsets() noexcept { bytes_ = true; }
    /// "file: line N" (or "file: byte N") of the current line.
    [[nodiscard]] std::string at() const;
    /// InputError "file:line: what".
    [[noreturn]] void fail(const std::string& what) const;

private:
    /// Stream mode: read more bytes into the buffer (dropping what was read); false at the end.
    bool refill();

    ByteStream stream_;
    bool streaming_ = false;
    bool eof_ = false;
    std::string buffer_;
    std::string_view text_;
    std::size_t pos_ = 0;
    std::int64_t line_ = 0;
    std::size_t line_start_ = 0;
    bool bytes_ = false;
    std::string source_;
};

/// Whitespace tokens of a line.
void split(std::string_view line, std::vector<std::string_view>& out);

/// Parse an integer or a floating-point token; `what` names it in the error.
template <class T>
T parse_number(std::string_view tok, const LineCursor& cur, std::string_view what) {
    T v{};
    const char* b = tok.data();
    const char* e = tok.data() + tok.size();
    if (!tok.empty() && *b == '+') ++b;
    const auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e || b == e)
        cur.fail(std::string("'") + std::string(tok) + "' is not a valid " + std::string(what));
    return v;
}

}  // namespace manta::mesh::detail
