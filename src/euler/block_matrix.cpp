/// @file block_matrix.cpp
/// Block sparse matrix on the edge graph, block ILU(0) and restarted flexible GMRES
/// (manta/euler/block_matrix.hpp, docs/euler.md).

#include "manta/euler/block_matrix.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

#include "manta/core/error.hpp"

namespace manta::euler {

namespace {

constexpr int bs = n_vars;           // block size
constexpr int bb = n_vars * n_vars;  // values per block

// ------------------------------------------------------------------------------ block kernels
// Hand-unrolled 5x5 kernels: blocks are row-major, single precision in storage; arithmetic in
// double. Small fixed loops the compiler unrolls completely.

/// y += A x for a stored (float) block.
[[gnu::always_inline]] inline void gemv_add(const float* a, const double* x, double* y) noexcept {
    const double x0 = x[0], x1 = x[1], x2 = x[2], x3 = x[3], x4 = x[4];
    for (int r = 0; r < bs; ++r) {
        const float* ar = a + bs * r;
        y[r] += double(ar[0]) * x0 + double(ar[1]) * x1 + double(ar[2]) * x2 + double(ar[3]) * x3 +
                double(ar[4]) * x4;
    }
}

/// y -= A x for a stored (float) block.
[[gnu::always_inline]] inline void gemv_sub(const float* a, const double* x, double* y) noexcept {
    const double x0 = x[0], x1 = x[1], x2 = x[2], x3 = x[3], x4 = x[4];
    for (int r = 0; r < bs; ++r) {
        const float* ar = a + bs * r;
        y[r] -= double(ar[0]) * x0 + double(ar[1]) * x1 + double(ar[2]) * x2 + double(ar[3]) * x3 +
                double(ar[4]) * x4;
    }
}

/// y = A x for a stored (float) block.
[[gnu::always_inline]] inline void gemv(const float* a, const double* x, double* y) noexcept {
    const double x0 = x[0], x1 = x[1], x2 = x[2], x3 = x[3], x4 = x[4];
    for (int r = 0; r < bs; ++r) {
        const float* ar = a + bs * r;
        y[r] = double(ar[0]) * x0 + double(ar[1]) * x1 + double(ar[2]) * x2 + double(ar[3]) * x3 +
               double(ar[4]) * x4;
    }
}

/// C = A B (Sub = false) or C -= A B (Sub = true) with A in double (a working row) and B stored
/// (float). B is widened once; each row of C is a sum of B's rows, which the compiler turns into
/// short vector multiply-adds.
template <bool Sub>
[[gnu::always_inline]] inline void gemm_df(const double* a, const float* b, double* c) noexcept {
    double bd[bb];
    for (int q = 0; q < bb; ++q) bd[q] = b[q];
    for (int r = 0; r < bs; ++r) {
        double acc[bs];
        for (int col = 0; col < bs; ++col) acc[col] = a[bs * r] * bd[col];
        for (int k = 1; k < bs; ++k) {
            const double ark = a[bs * r + k];
            for (int col = 0; col < bs; ++col) acc[col] += ark * bd[bs * k + col];
        }
        double* cr = c + bs * r;
        for (int col = 0; col < bs; ++col) {
            if constexpr (Sub)
                cr[col] -= acc[col];
            else
                cr[col] = acc[col];
        }
    }
}

/// Invert the 5x5 block `a` (row-major, double) into `inv` by LU with partial pivoting.
/// Returns false if a pivot is zero, not finite or below round-off relative to the block's
/// largest entry.
[[gnu::always_inline]] inline bool invert5(const double* a, double* inv) noexcept {
    double lu[bb];
    std::memcpy(lu, a, sizeof(lu));
    int perm[bs] = {0, 1, 2, 3, 4};
    double scale = 0.0;
    for (int i = 0; i < bb; ++i) scale = std::max(scale, std::abs(a[i]));
    const double tiny = scale * 64.0 * std::numeric_limits<double>::epsilon();
    for (int k = 0; k < bs; ++k) {
        int p = k;
        double big = std::abs(lu[bs * k + k]);
        for (int r = k + 1; r < bs; ++r) {
            const double v = std::abs(lu[bs * r + k]);
            if (v > big) {
                big = v;
                p = r;
            }
        }
        // Written so that a NaN pivot fails as well.
        if (!(big > tiny) || !std::isfinite(big)) return false;
        if (p != k) {
            for (int c = 0; c < bs; ++c) std::swap(lu[bs * k + c], lu[bs * p + c]);
            std::swap(perm[k], perm[p]);
        }
        const double inv_pivot = 1.0 / lu[bs * k + k];
        for (int r = k + 1; r < bs; ++r) {
            const double l = lu[bs * r + k] * inv_pivot;
            lu[bs * r + k] = l;
            for (int c = k + 1; c < bs; ++c) lu[bs * r + c] -= l * lu[bs * k + c];
        }
    }
    // Solve LU X = P I column by column.
    for (int col = 0; col < bs; ++col) {
        double y[bs];
        for (int r = 0; r < bs; ++r) {
            double s = perm[r] == col ? 1.0 : 0.0;
            for (int c = 0; c < r; ++c) s -= lu[bs * r + c] * y[c];
            y[r] = s;
        }
        for (int r = bs - 1; r >= 0; --r) {
            double s = y[r];
            for (int c = r + 1; c < bs; ++c) s -= lu[bs * r + c] * y[c];
            y[r] = s / lu[bs * r + r];
        }
        for (int r = 0; r < bs; ++r) inv[bs * r + col] = y[r];
    }
    for (int i = 0; i < bb; ++i)
        if (!std::isfinite(inv[i])) return false;
    return true;
}

template <class T>
std::size_t capacity_bytes(const std::vector<T>& v) noexcept {
    return v.capacity() * sizeof(T);
}

// ------------------------------------------------------------------------------ loop kernels
// The sweeps over the matrix, written once as always-inlined templates and instantiated in a
// baseline x86-64 and an AVX2+FMA wrapper; the AVX2 one is called on processors that have it
// (the block kernels vectorise four doubles wide and fuse multiply-adds there).

/// CSR arrays of a block matrix.
struct Csr {
    Index n_rows;
    const std::int64_t* rows;
    const Index* cols;
    const std::int64_t* diag;
    const float* values;
};

#define MANTA_ALWAYS_INLINE [[gnu::always_inline]] inline

MANTA_ALWAYS_INLINE void multiply_impl(const Csr& a, const double* x, double* y) noexcept {
    for (Index r = 0; r < a.n_rows; ++r) {
        double acc[bs] = {0.0, 0.0, 0.0, 0.0, 0.0};
        for (std::int64_t k = a.rows[r]; k < a.rows[r + 1]; ++k)
            gemv_add(a.values + k * bb, x + std::int64_t{bs} * a.cols[k], acc);
        double* yr = y + std::int64_t{bs} * r;
        for (int c = 0; c < bs; ++c) yr[c] = acc[c];
    }
}

MANTA_ALWAYS_INLINE void solve_impl(const Csr& a, const double* r, double* z) noexcept {
    // Forward: (I + L) y = r, y in z.
    for (Index i = 0; i < a.n_rows; ++i) {
        double acc[bs];
        for (int c = 0; c < bs; ++c) acc[c] = r[std::int64_t{bs} * i + c];
        for (std::int64_t p = a.rows[i]; p < a.diag[i]; ++p)
            gemv_sub(a.values + p * bb, z + std::int64_t{bs} * a.cols[p], acc);
        for (int c = 0; c < bs; ++c) z[std::int64_t{bs} * i + c] = acc[c];
    }
    // Backward: (D + U) z = y, D^-1 stored.
    for (Index i = a.n_rows - 1; i >= 0; --i) {
        double acc[bs];
        double* zi = z + std::int64_t{bs} * i;
        for (int c = 0; c < bs; ++c) acc[c] = zi[c];
        for (std::int64_t p = a.diag[i] + 1; p < a.rows[i + 1]; ++p)
            gemv_sub(a.values + p * bb, z + std::int64_t{bs} * a.cols[p], acc);
        gemv(a.values + a.diag[i] * bb, acc, zi);
    }
}

/// Block symmetric Gauss-Seidel z = M^-1 r, M = (D + L) D^-1 (D + U), on the owned rows and
/// columns of `a` (ghost columns, numbered after the owned ones, dropped); `dinv` holds the
/// inverted diagonal blocks.
MANTA_ALWAYS_INLINE void sgs_impl(const Csr& a, const float* dinv, const double* r,
                                  double* z) noexcept {
    const Index n = a.n_rows;
    // Forward: (D + L) w = r, w in z.
    // The sums are accumulated from zero, as in the product, so that the AVX2 build vectorises
    // the block kernels the same way.
    for (Index i = 0; i < n; ++i) {
        double acc[bs] = {0.0, 0.0, 0.0, 0.0, 0.0};
        for (std::int64_t p = a.rows[i]; p < a.diag[i]; ++p)
            gemv_add(a.values + p * bb, z + std::int64_t{bs} * a.cols[p], acc);
        double w[bs];
        for (int c = 0; c < bs; ++c) w[c] = r[std::int64_t{bs} * i + c] - acc[c];
        gemv(dinv + std::int64_t{bb} * i, w, z + std::int64_t{bs} * i);
    }
    // Backward: z = w - D^-1 U z (owned columns only).
    for (Index i = n - 1; i >= 0; --i) {
        double acc[bs] = {0.0, 0.0, 0.0, 0.0, 0.0};
        bool any = false;
        for (std::int64_t p = a.diag[i] + 1; p < a.rows[i + 1] && a.cols[p] < n; ++p) {
            gemv_add(a.values + p * bb, z + std::int64_t{bs} * a.cols[p], acc);
            any = true;
        }
        if (!any) continue;
        double corr[bs];
        gemv(dinv + std::int64_t{bb} * i, acc, corr);
        for (int c = 0; c < bs; ++c) z[std::int64_t{bs} * i + c] -= corr[c];
    }
}

/// Numeric block ILU(0) in place on `lu` (values of the owned pattern `a`, a.values unused)
/// from the values `src` (row i's blocks at src_offsets[i]). `row` holds a working row,
/// `where` is -1 for every column on entry and exit. Returns the first row whose pivot block
/// is singular, or -1.
MANTA_ALWAYS_INLINE Index factorize_impl(const Csr& a, float* lu, const float* src,
                                         const std::int64_t* src_offsets, double* row,
                                         std::int64_t* where) noexcept {
    double lik[bb];
    double inv[bb];
    for (Index i = 0; i < a.n_rows; ++i) {
        const std::int64_t begin = a.rows[i], end = a.rows[i + 1];
        const float* s = src + src_offsets[i] * bb;
        for (std::int64_t q = 0; q < (end - begin) * bb; ++q) row[q] = s[q];
        for (std::int64_t p = begin; p < end; ++p) where[a.cols[p]] = p - begin;
        for (std::int64_t p = begin; p < a.diag[i]; ++p) {
            const Index k = a.cols[p];
            double* aik = row + (p - begin) * bb;
            gemm_df<false>(aik, lu + a.diag[k] * bb, lik);
            for (int q = 0; q < bb; ++q) aik[q] = lik[q];
            for (std::int64_t q = a.diag[k] + 1; q < a.rows[k + 1]; ++q) {
                const std::int64_t slot = where[a.cols[q]];
                if (slot >= 0) gemm_df<true>(lik, lu + q * bb, row + slot * bb);
            }
        }
        for (std::int64_t p = begin; p < end; ++p) where[a.cols[p]] = -1;
        const std::int64_t d = a.diag[i] - begin;
        if (!invert5(row + d * bb, inv)) return i;
        for (int q = 0; q < bb; ++q) row[d * bb + q] = inv[q];
        float* dst = lu + begin * bb;
        for (std::int64_t q = 0; q < (end - begin) * bb; ++q) dst[q] = static_cast<float>(row[q]);
    }
    return -1;
}

void multiply_base(const Csr& a, const double* x, double* y) noexcept {
    multiply_impl(a, x, y);
}
void solve_base(const Csr& a, const double* r, double* z) noexcept {
    solve_impl(a, r, z);
}
void sgs_base(const Csr& a, const float* dinv, const double* r, double* z) noexcept {
    sgs_impl(a, dinv, r, z);
}
Index factorize_base(const Csr& a, float* lu, const float* src, const std::int64_t* offsets,
                     double* row, std::int64_t* where) noexcept {
    return factorize_impl(a, lu, src, offsets, row, where);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MANTA_HAVE_AVX2_PATH 1
[[gnu::target("avx2,fma")]] void multiply_avx2(const Csr& a, const double* x, double* y) noexcept {
    multiply_impl(a, x, y);
}
[[gnu::target("avx2,fma")]] void solve_avx2(const Csr& a, const double* r, double* z) noexcept {
    solve_impl(a, r, z);
}
/// acc03 (rows 0-3) and acc4 (row 4) += A x for a stored (float) block, four rows at a time:
/// the compiler leaves the Gauss-Seidel sweeps' block products scalar otherwise.
[[gnu::target("avx2,fma")]] [[gnu::always_inline]] inline void block_add_avx2(
    const float* a, const double* x, __m256d& acc03, __m256d& acc4) noexcept {
    for (int c = 0; c < bs; ++c) {
        const __m256d col = _mm256_cvtps_pd(_mm_setr_ps(a[c], a[5 + c], a[10 + c], a[15 + c]));
        acc03 = _mm256_fmadd_pd(col, _mm256_broadcast_sd(x + c), acc03);
    }
    // Row 4: a[20..24] . x as four lanes and one.
    const __m256d r4 = _mm256_cvtps_pd(_mm_loadu_ps(a + 20));
    acc4 = _mm256_fmadd_pd(r4, _mm256_loadu_pd(x), acc4);
    acc4 = _mm256_add_pd(acc4, _mm256_set_pd(0.0, 0.0, 0.0, double(a[24]) * x[4]));
}

/// Sum of the four lanes.
[[gnu::target("avx2,fma")]] [[gnu::always_inline]] inline double hsum_avx2(__m256d v) noexcept {
    const __m128d lo = _mm256_castpd256_pd128(v), hi = _mm256_extractf128_pd(v, 1);
    const __m128d s = _mm_add_pd(lo, hi);
    return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
}

[[gnu::target("avx2,fma")]] void sgs_avx2(const Csr& a, const float* dinv, const double* r,
                                          double* z) noexcept {
    const Index n = a.n_rows;
    double w[bs];
    for (Index i = 0; i < n; ++i) {
        __m256d acc03 = _mm256_setzero_pd(), acc4 = _mm256_setzero_pd();
        for (std::int64_t p = a.rows[i]; p < a.diag[i]; ++p)
            block_add_avx2(a.values + p * bb, z + std::int64_t{bs} * a.cols[p], acc03, acc4);
        const double* ri = r + std::int64_t{bs} * i;
        _mm256_storeu_pd(w, _mm256_sub_pd(_mm256_loadu_pd(ri), acc03));
        w[4] = ri[4] - hsum_avx2(acc4);
        gemv(dinv + std::int64_t{bb} * i, w, z + std::int64_t{bs} * i);
    }
    for (Index i = n - 1; i >= 0; --i) {
        __m256d acc03 = _mm256_setzero_pd(), acc4 = _mm256_setzero_pd();
        bool any = false;
        for (std::int64_t p = a.diag[i] + 1; p < a.rows[i + 1] && a.cols[p] < n; ++p) {
            block_add_avx2(a.values + p * bb, z + std::int64_t{bs} * a.cols[p], acc03, acc4);
            any = true;
        }
        if (!any) continue;
        _mm256_storeu_pd(w, acc03);
        w[4] = hsum_avx2(acc4);
        double corr[bs];
        gemv(dinv + std::int64_t{bb} * i, w, corr);
        for (int c = 0; c < bs; ++c) z[std::int64_t{bs} * i + c] -= corr[c];
    }
}
[[gnu::target("avx2,fma")]] Index factorize_avx2(const Csr& a, float* lu, const float* src,
                                                 const std::int64_t* offsets, double* row,
                                                 std::int64_t* where) noexcept {
    return factorize_impl(a, lu, src, offsets, row, where);
}
bool use_avx2() noexcept {
    static const bool yes = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return yes;
}
#else
bool use_avx2() noexcept {
    return false;
}
#endif

void multiply_kernel(const Csr& a, const double* x, double* y) noexcept {
#ifdef MANTA_HAVE_AVX2_PATH
    if (use_avx2()) return multiply_avx2(a, x, y);
#endif
    multiply_base(a, x, y);
}
void solve_kernel(const Csr& a, const double* r, double* z) noexcept {
#ifdef MANTA_HAVE_AVX2_PATH
    if (use_avx2()) return solve_avx2(a, r, z);
#endif
    solve_base(a, r, z);
}
void sgs_kernel(const Csr& a, const float* dinv, const double* r, double* z) noexcept {
#ifdef MANTA_HAVE_AVX2_PATH
    if (use_avx2()) return sgs_avx2(a, dinv, r, z);
#endif
    sgs_base(a, dinv, r, z);
}
Index factorize_kernel(const Csr& a, float* lu, const float* src, const std::int64_t* offsets,
                       double* row, std::int64_t* where) noexcept {
#ifdef MANTA_HAVE_AVX2_PATH
    if (use_avx2()) return factorize_avx2(a, lu, src, offsets, row, where);
#endif
    return factorize_base(a, lu, src, offsets, row, where);
}

/// The blocks of A's owned rows and columns whose row and column carry the same label in
/// `block` (one per owned row): CSR offsets, columns (ascending, as in A), diagonal positions
/// and each kept block's position in A.
void kept_pattern(const BlockMatrix& A, std::span<const int> block, std::vector<std::int64_t>& rows,
                  std::vector<Index>& cols, std::vector<std::int64_t>& diag,
                  std::vector<std::int64_t>& pos) {
    const Index n = A.n_rows();
    if (block.size() != static_cast<std::size_t>(n))
        throw InputError(fmt::format(
            "preconditioner blocks: {} labels for {} owned rows; expected one per owned row",
            block.size(), n));
    const auto a_rows = A.row_offsets();
    const auto a_cols = A.columns();
    rows.assign(static_cast<std::size_t>(n) + 1, 0);
    diag.assign(static_cast<std::size_t>(n), 0);
    cols.clear();
    pos.clear();
    for (Index r = 0; r < n; ++r) {
        for (std::int64_t k = a_rows[r]; k < a_rows[r + 1]; ++k) {
            const Index c = a_cols[k];
            if (c >= n || block[c] != block[r]) continue;
            if (c == r) diag[r] = static_cast<std::int64_t>(cols.size());
            cols.push_back(c);
            pos.push_back(k);
        }
        rows[r + 1] = static_cast<std::int64_t>(cols.size());
    }
}

/// dst = the blocks of `values` at `pos`, in order.
void gather_blocks(std::span<const float> values, std::span<const std::int64_t> pos,
                   std::vector<float>& dst) {
    dst.resize(pos.size() * bb);
    for (std::size_t k = 0; k < pos.size(); ++k)
        std::memcpy(dst.data() + k * bb, values.data() + pos[k] * bb, bb * sizeof(float));
}

}  // namespace

// ------------------------------------------------------------------------------ BlockMatrix

BlockMatrix::BlockMatrix(Index n_rows, Index n_cols, std::span<const std::array<Index, 2>> edges)
    : n_rows_(n_rows), n_cols_(n_cols) {
    if (n_rows < 0 || n_cols < n_rows)
        throw InputError(fmt::format(
            "block matrix: {} rows and {} columns; expected 0 <= rows <= columns", n_rows, n_cols));
    const auto n_edges = static_cast<std::int64_t>(edges.size());
    if (n_edges > std::numeric_limits<Index>::max())
        throw InputError(fmt::format("block matrix: {} edges; at most {} supported", n_edges,
                                     std::numeric_limits<Index>::max()));
    // Count the entries of each row: the diagonal and one per edge end that is owned.
    rows_.assign(static_cast<std::size_t>(n_rows) + 1, 0);
    for (Index r = 0; r < n_rows; ++r) rows_[r + 1] = 1;
    for (std::int64_t e = 0; e < n_edges; ++e) {
        const Index i = edges[e][0], j = edges[e][1];
        if (i < 0 || j < 0 || i >= n_cols || j >= n_cols || i == j)
            throw InputError(fmt::format(
                "block matrix: edge {} joins nodes {} and {}; expected two different nodes in "
                "[0, {})",
                e, i, j, n_cols));
        if (i < n_rows) ++rows_[i + 1];
        if (j < n_rows) ++rows_[j + 1];
    }
    for (Index r = 0; r < n_rows; ++r) rows_[r + 1] += rows_[r];
    cols_.resize(static_cast<std::size_t>(rows_[n_rows]));
    std::vector<std::int64_t> fill(rows_.begin(), rows_.end() - 1);
    for (Index r = 0; r < n_rows; ++r) cols_[fill[r]++] = r;
    for (std::int64_t e = 0; e < n_edges; ++e) {
        const Index i = edges[e][0], j = edges[e][1];
        if (i < n_rows) cols_[fill[i]++] = j;
        if (j < n_rows) cols_[fill[j]++] = i;
    }
    fill = {};
    // Sort each row and drop repeated edges, compacting in place.
    std::int64_t out = 0;
    for (Index r = 0; r < n_rows; ++r) {
        const auto begin = cols_.begin() + rows_[r];
        const auto end = cols_.begin() + rows_[r + 1];
        std::sort(begin, end);
        const auto last = std::unique(begin, end);
        const std::int64_t start = out;
        for (auto it = begin; it != last; ++it) cols_[out++] = *it;
        rows_[r] = start;
    }
    rows_[n_rows] = out;
    cols_.resize(static_cast<std::size_t>(out));
    cols_.shrink_to_fit();

    const auto find = [this](Index r, Index c) {
        const auto begin = cols_.begin() + rows_[r];
        const auto end = cols_.begin() + rows_[r + 1];
        return static_cast<std::int64_t>(std::lower_bound(begin, end, c) - cols_.begin());
    };
    diag_.resize(static_cast<std::size_t>(n_rows));
    for (Index r = 0; r < n_rows; ++r) diag_[r] = find(r, r);
    edge_ij_.resize(static_cast<std::size_t>(n_edges));
    edge_ji_.resize(static_cast<std::size_t>(n_edges));
    for (std::int64_t e = 0; e < n_edges; ++e) {
        const Index i = edges[e][0], j = edges[e][1];
        edge_ij_[e] = i < n_rows ? find(i, j) : -1;
        edge_ji_[e] = j < n_rows ? find(j, i) : -1;
    }
    values_.assign(cols_.size() * bb, 0.0f);
}

void BlockMatrix::set_zero() noexcept {
    std::fill(values_.begin(), values_.end(), 0.0f);
    std::fill(diag_sum_.begin(), diag_sum_.end(), 0.0);
    diag_open_ = !diag_sum_.empty();
}

void BlockMatrix::add_diagonal(Index r, const Mat5& b) noexcept {
    if (!diag_open_) {
        add(diag_[r], b);
        return;
    }
    double* a = diag_sum_.data() + static_cast<std::size_t>(r) * bb;
    for (int i = 0; i < bs; ++i)
        for (int c = 0; c < bs; ++c) a[bs * i + c] += b(i, c);
}

void BlockMatrix::accumulate_diagonals(bool on) {
    if (on)
        diag_sum_.assign(static_cast<std::size_t>(n_rows_) * bb, 0.0);
    else
        diag_sum_ = {};
    diag_open_ = false;
}

void BlockMatrix::flush_diagonals() noexcept {
    if (!diag_open_) return;
    for (Index r = 0; r < n_rows_; ++r) {
        float* a = values_.data() + diag_[r] * bb;
        const double* d = diag_sum_.data() + static_cast<std::size_t>(r) * bb;
        for (int q = 0; q < bb; ++q) a[q] += static_cast<float>(d[q]);
    }
    diag_open_ = false;
}

void BlockMatrix::add(std::int64_t position, const Mat5& b) noexcept {
    if (position < 0) return;
    float* a = values_.data() + position * bb;
    for (int r = 0; r < bs; ++r)
        for (int c = 0; c < bs; ++c) a[bs * r + c] += static_cast<float>(b(r, c));
}

void BlockMatrix::add_to_diagonal(Index r, double s) noexcept {
    float* a = values_.data() + diag_[r] * bb;
    for (int k = 0; k < bs; ++k) a[(bs + 1) * k] += static_cast<float>(s);
}

void BlockMatrix::transform_row(Index r, const Mat5& T) noexcept {
    for (std::int64_t q = rows_[r]; q < rows_[r + 1]; ++q) {
        const Mat5 b = T * block(q);
        float* a = values_.data() + q * bb;
        for (int i = 0; i < bs; ++i)
            for (int c = 0; c < bs; ++c) a[bs * i + c] = static_cast<float>(b(i, c));
    }
}

Mat5 BlockMatrix::block(std::int64_t position) const noexcept {
    const float* a = values_.data() + position * bb;
    Mat5 m;
    for (int r = 0; r < bs; ++r)
        for (int c = 0; c < bs; ++c) m(r, c) = a[bs * r + c];
    return m;
}

void BlockMatrix::multiply(std::span<const double> x, std::span<double> y) const noexcept {
    MANTA_ASSERT(x.size() >= static_cast<std::size_t>(bs) * n_cols_);
    MANTA_ASSERT(y.size() >= static_cast<std::size_t>(bs) * n_rows_);
    const Csr a{n_rows_, rows_.data(), cols_.data(), diag_.data(), values_.data()};
    multiply_kernel(a, x.data(), y.data());
}

std::size_t BlockMatrix::memory_bytes() const noexcept {
    return sizeof(*this) + capacity_bytes(rows_) + capacity_bytes(cols_) + capacity_bytes(values_) +
           capacity_bytes(diag_) + capacity_bytes(edge_ij_) + capacity_bytes(edge_ji_) +
           capacity_bytes(diag_sum_);
}

// ------------------------------------------------------------------------------ BlockIlu0

void BlockIlu0::factorize(const BlockMatrix& A) {
    const auto a_rows = A.row_offsets();
    const auto a_cols = A.columns();
    const auto a_values = A.values();
    const Index n = A.n_rows();
    if (!block_.empty()) {
        // Blocks: the ILU(0) of the kept blocks only (their pattern built once per matrix
        // pattern and labels, their values gathered each time).
        if (blocks_changed_ || n_rows_ != n || kept_for_ != A.n_blocks()) {
            kept_pattern(A, block_, rows_, cols_, diag_, pos_);
            n_rows_ = n;
            kept_for_ = A.n_blocks();
            blocks_changed_ = false;
        }
        gather_blocks(a_values, pos_, kept_);
        values_.resize(cols_.size() * bb);
        std::int64_t max_len = 0;
        for (Index r = 0; r < n; ++r) max_len = std::max(max_len, rows_[r + 1] - rows_[r]);
        std::vector<double> row(static_cast<std::size_t>(max_len) * bb);
        std::vector<std::int64_t> where(static_cast<std::size_t>(n), -1);
        const Csr a{n, rows_.data(), cols_.data(), diag_.data(), nullptr};
        const Index bad = factorize_kernel(a, values_.data(), kept_.data(), rows_.data(),
                                           row.data(), where.data());
        if (bad >= 0)
            throw SingularBlockError(
                fmt::format(
                    "block ILU(0): singular pivot block in row {} (local node) of the implicit "
                    "matrix; expected an invertible 5x5 diagonal block",
                    bad),
                bad);
        return;
    }

    // Symbolic part: the owned columns of each row. Columns are sorted and ghosts are numbered
    // after the owned nodes, so they are a prefix of each row of A. Rebuilt only when the
    // pattern changes (checked cheaply by size; the pattern of a BlockMatrix never changes).
    const auto owned_prefix = [&](Index r) {
        const auto begin = a_cols.begin() + a_rows[r];
        const auto end = a_cols.begin() + a_rows[r + 1];
        return static_cast<std::int64_t>(std::lower_bound(begin, end, n) - begin);
    };
    blocks_changed_ = true;  // a later factorisation with blocks rebuilds their pattern
    bool same = n_rows_ == n && rows_.size() == static_cast<std::size_t>(n) + 1;
    if (same) {
        for (Index r = 0; r < n && same; ++r)
            same = rows_[r + 1] - rows_[r] == owned_prefix(r) &&
                   std::equal(cols_.begin() + rows_[r], cols_.begin() + rows_[r + 1],
                              a_cols.begin() + a_rows[r]);
    }
    if (!same) {
        n_rows_ = n;
        rows_.assign(static_cast<std::size_t>(n) + 1, 0);
        for (Index r = 0; r < n; ++r) rows_[r + 1] = rows_[r] + owned_prefix(r);
        cols_.resize(static_cast<std::size_t>(rows_[n]));
        diag_.resize(static_cast<std::size_t>(n));
        for (Index r = 0; r < n; ++r) {
            std::copy(a_cols.begin() + a_rows[r], a_cols.begin() + a_rows[r] + owned_prefix(r),
                      cols_.begin() + rows_[r]);
            diag_[r] = A.diagonal(r) - a_rows[r] + rows_[r];
        }
        values_.resize(cols_.size() * bb);
    }

    // Numeric part, row by row (Saad 2003, Algorithm 10.4 in block form). Row i is gathered
    // into a double working row; for each k < i in the row, L_ik = A_ik U_kk^-1 and
    // A_ij -= L_ik U_kj for the j > k of row k that are in row i's pattern. The stored
    // diagonal block is the inverse of U_ii.
    std::int64_t max_len = 0;
    for (Index r = 0; r < n; ++r) max_len = std::max(max_len, rows_[r + 1] - rows_[r]);
    std::vector<double> row(static_cast<std::size_t>(max_len) * bb);
    std::vector<std::int64_t> where(static_cast<std::size_t>(n), -1);  // column -> slot in row
    const Csr a{n, rows_.data(), cols_.data(), diag_.data(), nullptr};
    const Index bad = factorize_kernel(a, values_.data(), a_values.data(), a_rows.data(),
                                       row.data(), where.data());
    if (bad >= 0)
        throw SingularBlockError(
            fmt::format("block ILU(0): singular pivot block in row {} (local node) of the implicit "
                        "matrix; expected an invertible 5x5 diagonal block",
                        bad),
            bad);
}

void BlockIlu0::apply(std::span<const double> r, std::span<double> z) const noexcept {
    MANTA_ASSERT(r.size() >= static_cast<std::size_t>(bs) * n_rows_);
    MANTA_ASSERT(z.size() >= static_cast<std::size_t>(bs) * n_rows_);
    const Csr a{n_rows_, rows_.data(), cols_.data(), diag_.data(), values_.data()};
    solve_kernel(a, r.data(), z.data());
}

std::size_t BlockIlu0::memory_bytes() const noexcept {
    return sizeof(*this) + capacity_bytes(rows_) + capacity_bytes(cols_) + capacity_bytes(diag_) +
           capacity_bytes(values_) + capacity_bytes(pos_) + capacity_bytes(kept_) +
           capacity_bytes(block_);
}

// ------------------------------------------------------------------------------ BlockSgs

void BlockSgs::factorize(const BlockMatrix& A) {
    A_ = &A;
    const Index n = A.n_rows();
    if (!block_.empty()) {
        if (blocks_changed_ || rows_.size() != static_cast<std::size_t>(n) + 1 ||
            kept_for_ != A.n_blocks()) {
            kept_pattern(A, block_, rows_, cols_, diag_, pos_);
            kept_for_ = A.n_blocks();
            blocks_changed_ = false;
        }
        gather_blocks(A.values(), pos_, values_);
    } else {
        blocks_changed_ = true;
        rows_.clear();
        cols_.clear();
        diag_.clear();
        pos_.clear();
        values_.clear();
    }
    dinv_.resize(static_cast<std::size_t>(n) * bb);
    double d[bb], inv[bb];
    for (Index r = 0; r < n; ++r) {
        const Mat5 b = A.block(A.diagonal(r));
        for (int q = 0; q < bb; ++q) d[q] = b(q / bs, q % bs);
        if (!invert5(d, inv))
            throw SingularBlockError(
                fmt::format("block SGS: singular diagonal block in row {} (local node) of the "
                            "implicit matrix; expected an invertible 5x5 block",
                            r),
                r);
        for (int q = 0; q < bb; ++q)
            dinv_[static_cast<std::size_t>(r) * bb + static_cast<std::size_t>(q)] =
                static_cast<float>(inv[q]);
    }
}

void BlockSgs::apply(std::span<const double> r, std::span<double> z) const noexcept {
    MANTA_ASSERT(A_ != nullptr);
    const Csr a = rows_.empty()
                      ? Csr{A_->n_rows(), A_->row_offsets().data(), A_->columns().data(),
                            A_->diagonals().data(), A_->values().data()}
                      : Csr{A_->n_rows(), rows_.data(), cols_.data(), diag_.data(), values_.data()};
    sgs_kernel(a, dinv_.data(), r.data(), z.data());
}

std::size_t BlockSgs::memory_bytes() const noexcept {
    return sizeof(*this) + capacity_bytes(dinv_) + capacity_bytes(rows_) + capacity_bytes(diag_) +
           capacity_bytes(pos_) + capacity_bytes(cols_) + capacity_bytes(values_) +
           capacity_bytes(block_);
}

// ------------------------------------------------------------------------------ Fgmres

KrylovResult Fgmres::solve(const BlockMatrix& A, const Preconditioner& M, std::span<const double> b,
                           std::span<double> x, const parallel::Communicator& comm,
                           const parallel::Halo& halo, const KrylovOptions& options) {
    const int m = std::max(1, options.restart);
    const std::int64_t n_own = std::int64_t{bs} * A.n_rows();
    const std::int64_t n_all = std::int64_t{bs} * A.n_cols();
    MANTA_REQUIRE(
        b.size() >= static_cast<std::size_t>(n_own) && x.size() >= static_cast<std::size_t>(n_all),
        "fgmres: b needs 5 n_rows values and x 5 n_cols values");

    // Workspace: V (m + 1 vectors, owned entries), the product input t (all local entries),
    // the Hessenberg matrix (column-major, (m + 1) x m), Givens cosines and sines, g and y; Z
    // (m vectors, owned entries, single precision).
    const std::size_t need = static_cast<std::size_t>((m + 1) * n_own + n_all) +
                             static_cast<std::size_t>((m + 1) * m + 2 * m + (m + 1) + m);
    if (work_.size() < need) work_.assign(need, 0.0);
    if (z_.size() < static_cast<std::size_t>(m * n_own))
        z_.assign(static_cast<std::size_t>(m * n_own), 0.0f);
    double* V = work_.data();
    double* t = V + (m + 1) * n_own;
    double* H = t + n_all;
    double* cs = H + (m + 1) * m;
    double* sn = cs + m;
    double* g = sn + m;
    double* y = g + (m + 1);
    const std::span<double> t_all(t, static_cast<std::size_t>(n_all));
    const auto v = [&](int k) { return V + k * n_own; };
    const auto zk = [&](int k) { return z_.data() + k * n_own; };
    const auto h = [&](int row, int col) -> double& { return H[col * (m + 1) + row]; };
    const auto dot = [&](const double* a, const double* c) {
        double s = 0.0;
        for (std::int64_t i = 0; i < n_own; ++i) s += a[i] * c[i];
        return comm.sum(s);
    };

    std::fill(x.begin(), x.end(), 0.0);
    KrylovResult result;
    const double b_norm = std::sqrt(dot(b.data(), b.data()));
    if (!(b_norm > 0.0)) {
        result.relative_residual = 0.0;
        return result;
    }
    const double target = options.relative_tolerance * b_norm;
    double residual = b_norm;
    bool first = true;
    while (result.iterations < options.max_iterations) {
        // r = b - A x into v0 (x = 0 on the first cycle: r = b).
        double* v0 = v(0);
        if (first) {
            std::copy(b.begin(), b.begin() + n_own, v0);
        } else {
            halo.exchange(x, bs);
            A.multiply(x, std::span<double>(v0, static_cast<std::size_t>(n_own)));
            for (std::int64_t i = 0; i < n_own; ++i) v0[i] = b[i] - v0[i];
            residual = std::sqrt(dot(v0, v0));
        }
        first = false;
        if (residual <= target) break;
        for (std::int64_t i = 0; i < n_own; ++i) v0[i] /= residual;
        g[0] = residual;
        int j = 0;
        for (; j < m && result.iterations < options.max_iterations; ++j) {
            ++result.iterations;
            float* z = zk(j);
            double* w = v(j + 1);
            // z_j = M^-1 v_j, rounded to single precision; the product takes the rounded values.
            M.apply(std::span<const double>(v(j), static_cast<std::size_t>(n_own)),
                    t_all.first(static_cast<std::size_t>(n_own)));
            for (std::int64_t i = 0; i < n_own; ++i) {
                z[i] = static_cast<float>(t[i]);
                t[i] = z[i];
            }
            halo.exchange(t_all, bs);
            A.multiply(t_all, std::span<double>(w, static_cast<std::size_t>(n_own)));
            // Modified Gram-Schmidt.
            for (int i = 0; i <= j; ++i) {
                const double* vi = v(i);
                const double hij = dot(w, vi);
                h(i, j) = hij;
                for (std::int64_t k = 0; k < n_own; ++k) w[k] -= hij * vi[k];
            }
            const double h_next = std::sqrt(dot(w, w));
            h(j + 1, j) = h_next;
            if (h_next > 0.0)
                for (std::int64_t k = 0; k < n_own; ++k) w[k] /= h_next;
            // Apply the earlier rotations to the new column, then make a new one.
            for (int i = 0; i < j; ++i) {
                const double top = cs[i] * h(i, j) + sn[i] * h(i + 1, j);
                h(i + 1, j) = -sn[i] * h(i, j) + cs[i] * h(i + 1, j);
                h(i, j) = top;
            }
            const double denom = std::hypot(h(j, j), h(j + 1, j));
            cs[j] = denom > 0.0 ? h(j, j) / denom : 1.0;
            sn[j] = denom > 0.0 ? h(j + 1, j) / denom : 0.0;
            h(j, j) = denom;
            h(j + 1, j) = 0.0;
            g[j + 1] = -sn[j] * g[j];
            g[j] = cs[j] * g[j];
            residual = std::abs(g[j + 1]);
            if (residual <= target || !(h_next > 0.0)) {
                ++j;
                break;
            }
        }
        // Solve the triangular system H y = g and update x += Z y (owned entries).
        for (int i = j - 1; i >= 0; --i) {
            double s = g[i];
            for (int k = i + 1; k < j; ++k) s -= h(i, k) * y[k];
            y[i] = h(i, i) != 0.0 ? s / h(i, i) : 0.0;
        }
        for (int k = 0; k < j; ++k) {
            const float* z = zk(k);
            const double yk = y[k];
            for (std::int64_t i = 0; i < n_own; ++i) x[i] += yk * double(z[i]);
        }
        if (residual <= target) break;
    }
    halo.exchange(x, bs);
    result.relative_residual = residual / b_norm;
    return result;
}

std::size_t Fgmres::memory_bytes() const noexcept {
    return sizeof(*this) + capacity_bytes(work_) + capacity_bytes(z_);
}

}  // namespace manta::euler
