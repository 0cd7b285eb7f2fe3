#pragma once
/// @file block_matrix.hpp
/// The implicit operator's sparse matrix: 5x5 blocks on the pattern of the mesh's edge graph,
/// its block ILU(0) factorisation and a restarted flexible GMRES (docs/euler.md).
///
/// Rows are the nodes this process owns, [0, n_rows); columns are all partition-local nodes,
/// [0, n_cols), ghosts included. Block values are stored in single precision (the first-order
/// Jacobian only steers the implicit iteration; half the memory of double), vectors and
/// arithmetic are double. Across processes the preconditioner is block Jacobi: the ILU(0) of
/// each process's owned rows and columns, ghost couplings dropped; the Krylov solve itself is
/// global (halo exchange before each product, global dot products).

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/euler/gas.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/parallel/communicator.hpp"

namespace manta::euler {

using mesh::Index;

/// A preconditioner's factorisation met a singular 5x5 block: `row()` is its local node.
class SingularBlockError : public NumericalError {
public:
    SingularBlockError(const std::string& what, Index row) : NumericalError(what), row_(row) {}
    [[nodiscard]] Index row() const noexcept { return row_; }

private:
    Index row_;
};

/// Block sparse matrix (BCSR) with one 5x5 block per edge direction and per diagonal.
class BlockMatrix {
public:
    BlockMatrix() = default;
    /// Pattern: in each row r < n_rows, the diagonal (r, r) and (r, j) for every edge (r, j) or
    /// (j, r) of `edges`; edges between two ghosts (both nodes >= n_rows) add nothing. Columns
    /// within a row ascending (so a row's owned columns come before its ghost columns); an edge
    /// given twice adds one block. InputError if an edge joins a node to itself or leaves
    /// [0, n_cols), or if n_cols < n_rows.
    BlockMatrix(Index n_rows, Index n_cols, std::span<const std::array<Index, 2>> edges);

    [[nodiscard]] Index n_rows() const noexcept { return n_rows_; }
    [[nodiscard]] Index n_cols() const noexcept { return n_cols_; }
    [[nodiscard]] std::int64_t n_blocks() const noexcept {
        return static_cast<std::int64_t>(cols_.size());
    }

    /// Position of the diagonal block of row `r`.
    [[nodiscard]] std::int64_t diagonal(Index r) const noexcept { return diag_[r]; }
    /// Position of block (i, j) of edge `e` = (i, j) given to the constructor, -1 if i is a ghost.
    [[nodiscard]] std::int64_t edge_ij(Index e) const noexcept { return edge_ij_[e]; }
    /// Position of block (j, i) of edge `e` = (i, j), -1 if j is a ghost.
    [[nodiscard]] std::int64_t edge_ji(Index e) const noexcept { return edge_ji_[e]; }

    /// All blocks to zero.
    void set_zero() noexcept;
    /// Add `b` to the block at `position`; nothing if `position` < 0.
    void add(std::int64_t position, const Mat5& b) noexcept;
    /// Add `b` to the diagonal block of owned row `r`: in single precision as `add`, or, while
    /// the double accumulation is on and not yet flushed, to a double-precision sum.
    void add_diagonal(Index r, const Mat5& b) noexcept;
    /// Sum the diagonal blocks' contributions in double precision from each `set_zero` to the
    /// next `flush_diagonals` (off: the default). A diagonal block collects one contribution per
    /// edge of its node, in the order of the edges, which differs between a process's part and
    /// the whole mesh: summed in single precision the blocks of 1 and N processes differ in
    /// their last bits at the parts' border; rounded once from a double sum they agree (docs/
    /// parallel.md, "The same history on 1 and N processes"). 200 bytes per owned row.
    void accumulate_diagonals(bool on);
    /// Round the double sums into the diagonal blocks (after the assembly, before any other
    /// change of the matrix); `add_diagonal` adds in single precision again until `set_zero`.
    /// Nothing when the accumulation is off.
    void flush_diagonals() noexcept;
    /// Add `s` to the diagonal entries of the diagonal block of row `r`.
    void add_to_diagonal(Index r, double s) noexcept;
    /// Left-multiply every block of owned row `r` by `T`.
    void transform_row(Index r, const Mat5& T) noexcept;
    /// The block at `position` (row-major, single precision).
    [[nodiscard]] Mat5 block(std::int64_t position) const noexcept;

    /// y = A x over the owned rows: x holds 5 n_cols values (ghost values current), y 5 n_rows.
    void multiply(std::span<const double> x, std::span<double> y) const noexcept;

    /// Bytes held (capacity), for memory reports.
    [[nodiscard]] std::size_t memory_bytes() const noexcept;

    // CSR arrays, for the factorisation.
    [[nodiscard]] std::span<const std::int64_t> row_offsets() const noexcept { return rows_; }
    [[nodiscard]] std::span<const Index> columns() const noexcept { return cols_; }
    [[nodiscard]] std::span<const float> values() const noexcept { return values_; }
    /// Positions of the diagonal blocks, one per owned row.
    [[nodiscard]] std::span<const std::int64_t> diagonals() const noexcept { return diag_; }

private:
    Index n_rows_ = 0;
    Index n_cols_ = 0;
    std::vector<std::int64_t> rows_;  ///< n_rows + 1 offsets into cols_
    std::vector<Index> cols_;         ///< block columns
    std::vector<float> values_;       ///< 25 per block, row-major
    std::vector<std::int64_t> diag_;
    std::vector<std::int64_t> edge_ij_;
    std::vector<std::int64_t> edge_ji_;
    std::vector<double> diag_sum_;  ///< accumulate_diagonals: 25 per owned row
    bool diag_open_ = false;        ///< diag_sum_ collects add_diagonal
};

/// A preconditioner of the owned block of a BlockMatrix (ghost columns dropped: block Jacobi
/// across processes).
class Preconditioner {
public:
    virtual ~Preconditioner() = default;
    /// Block Jacobi within this process as well: `block` holds one label per owned row, and
    /// the couplings between rows of different labels are dropped like the ghost columns
    /// (empty: none dropped, the default). With the labels of the parts an N-process run
    /// distributes, one process applies the N processes' preconditioner in the same
    /// arithmetic (docs/parallel.md, "The same history on 1 and N processes"). Takes effect
    /// at the next `factorize`.
    void set_blocks(std::vector<int> block) {
        block_ = std::move(block);
        blocks_changed_ = true;
    }
    /// Set up for `A` (its pattern and values). NumericalError naming the row if a diagonal
    /// block is singular.
    virtual void factorize(const BlockMatrix& A) = 0;
    /// z = M^-1 r over the owned rows (5 n_rows values each).
    virtual void apply(std::span<const double> r, std::span<double> z) const noexcept = 0;
    /// Bytes held (capacity).
    [[nodiscard]] virtual std::size_t memory_bytes() const noexcept = 0;

protected:
    std::vector<int> block_;      ///< per owned row: its block (empty: one block)
    bool blocks_changed_ = true;  ///< the kept pattern is to be rebuilt
    std::int64_t kept_for_ = -1;  ///< n_blocks() of the matrix the kept pattern was built for
};

/// Block ILU(0) of the owned rows and columns of a BlockMatrix (ghost columns dropped), with
/// the diagonal blocks' inverses stored.
class BlockIlu0 final : public Preconditioner {
public:
    /// Factorise `A` (same pattern on every later call: the symbolic part is kept).
    /// NumericalError naming the row if a pivot block is singular.
    void factorize(const BlockMatrix& A) override;
    /// z = M^-1 r over the owned rows (5 n_rows values each).
    void apply(std::span<const double> r, std::span<double> z) const noexcept override;
    [[nodiscard]] std::size_t memory_bytes() const noexcept override;

private:
    Index n_rows_ = 0;
    std::vector<std::int64_t> rows_;
    std::vector<Index> cols_;
    std::vector<std::int64_t> diag_;
    std::vector<float> values_;      ///< L and U blocks, inverted diagonal blocks
    std::vector<std::int64_t> pos_;  ///< with blocks: the kept blocks' positions in A
    std::vector<float> kept_;        ///< with blocks: their values, gathered
};

/// Block symmetric Gauss-Seidel of the owned rows and columns of a BlockMatrix: M = (D + L)
/// D^-1 (D + U) with D the diagonal blocks, L and U the strictly lower and upper owned blocks
/// (Saad 2003, sec. 10.2). It keeps only the inverted diagonal blocks (100 bytes per node) and
/// reads the matrix itself, which must outlive it unchanged between `factorize` and `apply`: the
/// memory-lean alternative to ILU(0) (which stores a factor as large as the matrix).
class BlockSgs final : public Preconditioner {
public:
    void factorize(const BlockMatrix& A) override;
    void apply(std::span<const double> r, std::span<double> z) const noexcept override;
    [[nodiscard]] std::size_t memory_bytes() const noexcept override;

private:
    const BlockMatrix* A_ = nullptr;
    std::vector<float> dinv_;  ///< inverted diagonal blocks, row-major
    // With blocks (`set_blocks`): the pattern of the kept blocks, their positions in A and
    // their values (a copy as large as the kept part of A).
    std::vector<std::int64_t> rows_, diag_, pos_;
    std::vector<Index> cols_;
    std::vector<float> values_;
};

/// Settings of `fgmres`.
struct KrylovOptions {
    int restart = 20;                  ///< Krylov vectors before a restart
    int max_iterations = 20;           ///< total iterations
    double relative_tolerance = 0.05;  ///< stop when |b - A x| <= tol |b|
};

/// Outcome of `fgmres`.
struct KrylovResult {
    int iterations = 0;
    /// |b - A x| / |b| at exit, from the Arnoldi recurrence (equal to the true residual up to
    /// round-off); 0 if b = 0 (x = 0 then)
    double relative_residual = 1.0;
};

/// Restarted flexible GMRES (Saad 1993) for A x = b, right-preconditioned by `M`, from x = 0,
/// with modified Gram-Schmidt and Givens rotations. b and x hold 5 values per local node
/// (5 n_cols): only owned entries of b are read; on return x's ghost entries are current (halo
/// exchange). Every product exchanges its input vector first; dot products are global through
/// `comm`. The preconditioned vectors z_j = M^-1 v_j are kept in single precision (half the
/// memory): flexible GMRES only needs A z_j for the z_j it stores, so the rounding changes
/// the preconditioner, not the accuracy of the reported residual. Workspace is kept between
/// calls (no allocation after the first call of a size): about (8 (m + 1) + 4 m) 5 bytes per
/// owned node and 40 per local node for restart length m.
class Fgmres {
public:
    KrylovResult solve(const BlockMatrix& A, const Preconditioner& M, std::span<const double> b,
                       std::span<double> x, const parallel::Communicator& comm,
                       const parallel::Halo& halo, const KrylovOptions& options);
    [[nodiscard]] std::size_t memory_bytes() const noexcept;

private:
    std::vector<double> work_;  ///< Arnoldi basis V (owned entries), product input, Hessenberg
    std::vector<float> z_;      ///< preconditioned vectors Z (owned entries, single precision)
};

}  // namespace manta::euler
