/// @file test_block_matrix.cpp
/// The implicit operator's block matrix, block ILU(0) and FGMRES (manta/euler/block_matrix.hpp).

#include "manta/euler/block_matrix.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <barrier>
#include <cmath>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "manta/core/error.hpp"

namespace manta::euler {
namespace {

using Edge = std::array<Index, 2>;

/// Edge graph of the Freudenthal (Kuhn) tetrahedralisation of an nx x ny x nz grid of nodes: the
/// axis edges, one diagonal per face and the (1, 1, 1) diagonal per cube, so an interior node
/// has 14 neighbours, as in a typical tetrahedral mesh. Edges (i, j) with i < j.
std::vector<Edge> tet_grid_edges(int nx, int ny, int nz) {
    const auto id = [&](int i, int j, int k) { return Index((k * ny + j) * nx + i); };
    static constexpr int offsets[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0},
                                          {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    std::vector<Edge> edges;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                for (const auto& o : offsets) {
                    const int a = i + o[0], b = j + o[1], c = k + o[2];
                    if (a < nx && b < ny && c < nz) edges.push_back({id(i, j, k), id(a, b, c)});
                }
    return edges;
}

Mat5 random_block(std::mt19937_64& rng, double scale) {
    std::uniform_real_distribution<double> u(-scale, scale);
    Mat5 m;
    for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 5; ++c) m(r, c) = u(rng);
    return m;
}

/// Random blocks on A's pattern, made block-row diagonally dominant: the diagonal entries
/// exceed the sum of the magnitudes of the other entries in their row by `margin`. With
/// `diffusion`, the off-diagonal blocks are a negative multiple of the identity plus a small
/// random part, so the matrix is a shifted block graph Laplacian: still diagonally dominant, but
/// with the smooth slowly converging modes of a discretised operator.
void fill_dominant(BlockMatrix& A, std::span<const Edge> edges, std::mt19937_64& rng,
                   double margin = 1.0, bool diffusion = false) {
    A.set_zero();
    std::uniform_real_distribution<double> u(0.5, 1.0);
    const auto off = [&] {
        return diffusion ? Mat5(-u(rng) * Mat5::Identity() + random_block(rng, 0.05))
                         : random_block(rng, 1.0);
    };
    for (Index e = 0; e < Index(edges.size()); ++e) {
        A.add(A.edge_ij(e), off());
        A.add(A.edge_ji(e), off());
    }
    for (Index r = 0; r < A.n_rows(); ++r) A.add(A.diagonal(r), random_block(rng, 1.0));
    const auto rows = A.row_offsets();
    for (Index r = 0; r < A.n_rows(); ++r) {
        double worst = 0.0;
        for (int q = 0; q < 5; ++q) {
            double s = 0.0;
            for (std::int64_t p = rows[r]; p < rows[r + 1]; ++p) {
                const Mat5 b = A.block(p);
                for (int c = 0; c < 5; ++c)
                    if (p != A.diagonal(r) || c != q) s += std::abs(b(q, c));
            }
            worst = std::max(worst, s);
        }
        A.add_to_diagonal(r, worst + margin);
    }
}

std::vector<double> random_vector(std::size_t n, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> v(n);
    for (auto& x : v) x = u(rng);
    return v;
}

double norm(std::span<const double> v) {
    double s = 0.0;
    for (double x : v) s += x * x;
    return std::sqrt(s);
}

/// |b - A x| / |b| over the owned rows (x's ghost entries as given).
double true_relative_residual(const BlockMatrix& A, std::span<const double> b,
                              std::span<const double> x) {
    std::vector<double> r(5 * std::size_t(A.n_rows()));
    A.multiply(x, r);
    for (std::size_t i = 0; i < r.size(); ++i) r[i] = b[i] - r[i];
    return norm(r) / norm(b.first(r.size()));
}

// ------------------------------------------------------------------------------ pattern

TEST(BlockMatrix, PatternFromEdges) {
    // Owned nodes 0..3, ghosts 4 and 5. Edge 5 is given as (j, i) with j > i, edge 6 joins two
    // ghosts (adds nothing), edge 7 repeats edge 0 reversed.
    const std::vector<Edge> edges = {{0, 1}, {1, 2}, {2, 3}, {0, 3},
                                     {3, 4}, {5, 2}, {4, 5}, {1, 0}};
    const BlockMatrix A(4, 6, edges);
    EXPECT_EQ(A.n_rows(), 4);
    EXPECT_EQ(A.n_cols(), 6);
    const std::vector<std::int64_t> rows = {0, 3, 6, 10, 14};
    const std::vector<Index> cols = {0, 1, 3, 0, 1, 2, 1, 2, 3, 5, 0, 2, 3, 4};
    EXPECT_EQ(std::vector<std::int64_t>(A.row_offsets().begin(), A.row_offsets().end()), rows);
    EXPECT_EQ(std::vector<Index>(A.columns().begin(), A.columns().end()), cols);
    EXPECT_EQ(A.n_blocks(), 14);
    EXPECT_EQ(A.diagonal(0), 0);
    EXPECT_EQ(A.diagonal(1), 4);
    EXPECT_EQ(A.diagonal(2), 7);
    EXPECT_EQ(A.diagonal(3), 12);
    // edge (0, 1): block (0, 1) at 1, block (1, 0) at 3
    EXPECT_EQ(A.edge_ij(0), 1);
    EXPECT_EQ(A.edge_ji(0), 3);
    // edge (3, 4): 4 is a ghost, no row
    EXPECT_EQ(A.edge_ij(4), 13);
    EXPECT_EQ(A.edge_ji(4), -1);
    // edge (5, 2): 5 is a ghost
    EXPECT_EQ(A.edge_ij(5), -1);
    EXPECT_EQ(A.edge_ji(5), 9);
    // ghost-ghost edge
    EXPECT_EQ(A.edge_ij(6), -1);
    EXPECT_EQ(A.edge_ji(6), -1);
    // repeated edge, reversed
    EXPECT_EQ(A.edge_ij(7), 3);
    EXPECT_EQ(A.edge_ji(7), 1);
    EXPECT_EQ(A.values().size(), 14u * 25u);
    EXPECT_GE(A.memory_bytes(), 14u * 25u * sizeof(float));
}

TEST(BlockMatrix, RejectsBadEdges) {
    const std::vector<Edge> self = {{0, 1}, {2, 2}};
    const std::vector<Edge> outside = {{0, 3}};
    const std::vector<Edge> negative = {{-1, 0}};
    EXPECT_THROW(BlockMatrix(3, 3, self), InputError);
    EXPECT_THROW(BlockMatrix(3, 3, outside), InputError);
    EXPECT_THROW(BlockMatrix(3, 3, negative), InputError);
    EXPECT_THROW(BlockMatrix(4, 3, outside), InputError);
    try {
        BlockMatrix(3, 3, self);
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("edge 1 joins nodes 2 and 2"), std::string::npos)
            << e.what();
    }
}

TEST(BlockMatrix, AddBlockAndDiagonal) {
    const std::vector<Edge> edges = {{0, 1}, {1, 2}};
    BlockMatrix A(2, 3, edges);
    std::mt19937_64 rng(1);
    const Mat5 b = random_block(rng, 2.0);
    A.add(A.edge_ij(1), b);
    A.add(A.edge_ij(1), b);
    A.add(-1, b);  // ignored
    A.add_to_diagonal(0, 3.0);
    EXPECT_LT((A.block(A.edge_ij(1)) - 2.0 * b).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_EQ(A.block(A.diagonal(0)), (3.0 * Mat5::Identity()).eval());
    EXPECT_EQ(A.block(A.edge_ij(0)), Mat5::Zero().eval());
    A.set_zero();
    EXPECT_EQ(A.block(A.edge_ij(1)), Mat5::Zero().eval());
}

// ------------------------------------------------------------------------------ multiply

TEST(BlockMatrix, MultiplyMatchesDense) {
    // 3 x 3 x 3 tetrahedral grid; the last 7 nodes are ghosts.
    const auto edges = tet_grid_edges(3, 3, 3);
    const Index n_cols = 27, n_rows = 20;
    BlockMatrix A(n_rows, n_cols, edges);
    std::mt19937_64 rng(2);
    fill_dominant(A, edges, rng);
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(5 * n_rows, 5 * n_cols);
    const auto rows = A.row_offsets();
    const auto cols = A.columns();
    for (Index r = 0; r < n_rows; ++r)
        for (std::int64_t p = rows[r]; p < rows[r + 1]; ++p)
            dense.block<5, 5>(5 * r, 5 * cols[p]) = A.block(p);
    // Every edge with an owned end is in the dense matrix exactly once per direction.
    int nonzero_blocks = 0;
    for (Index r = 0; r < n_rows; ++r)
        for (Index c = 0; c < n_cols; ++c)
            if (dense.block<5, 5>(5 * r, 5 * c).cwiseAbs().maxCoeff() > 0.0) ++nonzero_blocks;
    EXPECT_EQ(nonzero_blocks, A.n_blocks());
    const auto x = random_vector(5 * n_cols, rng);
    std::vector<double> y(5 * n_rows);
    A.multiply(x, y);
    const Eigen::VectorXd y_ref = dense * Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
    for (int i = 0; i < 5 * n_rows; ++i)
        EXPECT_NEAR(y[i], y_ref[i], 1e-12 * (1 + std::abs(y_ref[i])));
}

// ------------------------------------------------------------------------------ ILU(0)

/// Block-tridiagonal matrix (a chain 0-1-...-n-1) with two ghost columns: ILU(0) has no fill,
/// so it is the exact block LU of the owned part.
TEST(BlockIlu0, ExactOnBlockTridiagonal) {
    const Index n = 40;
    std::vector<Edge> edges;
    for (Index i = 0; i + 1 < n; ++i) edges.push_back({i, i + 1});
    edges.push_back({3, n});
    edges.push_back({n + 1, 17});
    BlockMatrix A(n, n + 2, edges);
    std::mt19937_64 rng(3);
    BlockIlu0 M;
    for (int pass = 0; pass < 2; ++pass) {  // the second pass reuses the symbolic part
        fill_dominant(A, edges, rng, 0.5);
        M.factorize(A);
        auto x = random_vector(5 * (n + 2), rng);
        std::fill(x.begin() + 5 * n, x.end(), 0.0);  // ghost values: dropped by the ILU
        std::vector<double> y(5 * n), z(5 * n);
        A.multiply(x, y);
        M.apply(y, z);
        double err = 0.0;
        for (int i = 0; i < 5 * n; ++i) err = std::max(err, std::abs(z[i] - x[i]));
        // Factors in single precision: exact to float round-off.
        EXPECT_LT(err, 1e-5) << "pass " << pass;
    }
    EXPECT_GE(M.memory_bytes(), std::size_t(A.n_blocks() - 2) * 25 * sizeof(float));
}

/// On a graph with cycles ILU(0) drops fill: M^-1 A is not the identity, but it is close to it
/// for a diagonally dominant matrix (a check that the test above can tell exact from inexact).
TEST(BlockIlu0, InexactWithFill) {
    const auto edges = tet_grid_edges(4, 4, 4);
    BlockMatrix A(64, 64, edges);
    std::mt19937_64 rng(4);
    fill_dominant(A, edges, rng, 0.5);
    BlockIlu0 M;
    M.factorize(A);
    const auto x = random_vector(5 * 64, rng);
    std::vector<double> y(5 * 64), z(5 * 64);
    A.multiply(x, y);
    M.apply(y, z);
    double err = 0.0;
    for (int i = 0; i < 5 * 64; ++i) err = std::max(err, std::abs(z[i] - x[i]));
    EXPECT_GT(err, 1e-3);
    EXPECT_LT(err, 1.0);
}

TEST(BlockIlu0, SingularPivotNamesRow) {
    std::vector<Edge> edges = {{0, 1}, {1, 2}, {2, 3}};
    BlockMatrix A(4, 4, edges);
    for (Index r = 0; r < 4; ++r) A.add_to_diagonal(r, 2.0);
    // Row 2's diagonal block becomes rank deficient (two equal rows); no coupling to rows 0, 1
    // changes it.
    Mat5 b = Mat5::Zero();
    b(3, 3) = -2.0;
    b(3, 4) = 2.0;
    A.add(A.diagonal(2), b);
    BlockIlu0 M;
    try {
        M.factorize(A);
        FAIL() << "no error on a singular pivot";
    } catch (const SingularBlockError& e) {  // a NumericalError that carries the row
        EXPECT_NE(std::string(e.what()).find("row 2 "), std::string::npos) << e.what();
        EXPECT_EQ(e.row(), 2);
    }
    // A NaN in a block is reported as well.
    BlockMatrix B(4, 4, edges);
    for (Index r = 0; r < 4; ++r) B.add_to_diagonal(r, 2.0);
    Mat5 nan = Mat5::Zero();
    nan(0, 1) = std::nan("");
    B.add(B.edge_ij(0), nan);
    EXPECT_THROW(M.factorize(B), NumericalError);
}

// ------------------------------------------------------------------------------ FGMRES

struct GridSystem {
    std::vector<Edge> edges;
    BlockMatrix A;
    std::vector<double> b;
};

GridSystem grid_system(int nx, int ny, int nz, std::uint64_t seed, double margin,
                       bool diffusion = true) {
    GridSystem s;
    s.edges = tet_grid_edges(nx, ny, nz);
    const Index n = nx * ny * nz;
    s.A = BlockMatrix(n, n, s.edges);
    std::mt19937_64 rng(seed);
    fill_dominant(s.A, s.edges, rng, margin, diffusion);
    s.b = random_vector(5 * std::size_t(n), rng);
    return s;
}

TEST(Fgmres, ConvergesAndReportsTrueResidual) {
    auto s = grid_system(12, 11, 10, 5, 1e-3);
    BlockIlu0 M;
    M.factorize(s.A);
    Fgmres solver;
    const parallel::SerialCommunicator comm;
    const parallel::SerialHalo halo;
    KrylovOptions o;
    o.restart = 40;
    o.max_iterations = 200;
    o.relative_tolerance = 1e-10;
    std::vector<double> x(s.b.size(), 1.0);
    const auto r = solver.solve(s.A, M, s.b, x, comm, halo, o);
    EXPECT_LE(r.relative_residual, 1e-10);
    EXPECT_GT(r.iterations, 2);
    EXPECT_LE(r.iterations, 40);  // no restart needed with ILU(0)
    const double true_res = true_relative_residual(s.A, s.b, x);
    EXPECT_NEAR(true_res, r.relative_residual, 0.01 * r.relative_residual);
    // Workspace is kept: a second solve allocates nothing.
    const std::size_t bytes = solver.memory_bytes();
    solver.solve(s.A, M, s.b, x, comm, halo, o);
    EXPECT_EQ(solver.memory_bytes(), bytes);
}

TEST(Fgmres, RestartsAndStopsAtMaxIterations) {
    auto s = grid_system(12, 11, 10, 6, 1e-3);
    BlockIlu0 M;
    M.factorize(s.A);
    Fgmres solver;
    const parallel::SerialCommunicator comm;
    const parallel::SerialHalo halo;
    KrylovOptions o;
    o.restart = 3;
    o.max_iterations = 300;
    o.relative_tolerance = 1e-10;
    std::vector<double> x(s.b.size());
    const auto r = solver.solve(s.A, M, s.b, x, comm, halo, o);
    EXPECT_LE(r.relative_residual, 1e-10);
    EXPECT_GT(r.iterations, o.restart);
    EXPECT_NEAR(true_relative_residual(s.A, s.b, x), r.relative_residual,
                0.01 * r.relative_residual);

    // Stopped by the iteration limit in the middle of a cycle: the reported residual is the
    // true one of the returned x.
    o.max_iterations = 7;
    const auto r7 = solver.solve(s.A, M, s.b, x, comm, halo, o);
    EXPECT_EQ(r7.iterations, 7);
    EXPECT_GT(r7.relative_residual, 1e-10);
    EXPECT_NEAR(true_relative_residual(s.A, s.b, x), r7.relative_residual,
                1e-6 * r7.relative_residual);

    // The default options: at most 20 iterations, stop at 5 %.
    const auto rd = solver.solve(s.A, M, s.b, x, comm, halo, KrylovOptions{});
    EXPECT_LE(rd.relative_residual, 0.05);
    EXPECT_LE(rd.iterations, 20);
}

TEST(Fgmres, ZeroRightHandSide) {
    auto s = grid_system(3, 3, 3, 7, 0.1);
    BlockIlu0 M;
    M.factorize(s.A);
    Fgmres solver;
    std::vector<double> b(s.b.size(), 0.0), x(s.b.size(), 3.0);
    const auto r = solver.solve(s.A, M, b, x, parallel::SerialCommunicator{},
                                parallel::SerialHalo{}, KrylovOptions{});
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(r.relative_residual, 0.0);
    EXPECT_TRUE(std::all_of(x.begin(), x.end(), [](double v) { return v == 0.0; }));
}

// ------------------------------------------------------------------------------ two processes

/// Two "processes" as two threads of this one: reductions and halo exchanges meet at a barrier.
struct TwoProcessWorld {
    std::barrier<> sync{2};
    std::array<double, 2> slot{};
    std::array<std::vector<double>, 2> slots;
    std::array<std::span<double>, 2> data;
};

class TestCommunicator final : public parallel::Communicator {
public:
    TestCommunicator(TwoProcessWorld& w, int rank) : w_(w), rank_(rank) {}
    [[nodiscard]] int rank() const override { return rank_; }
    [[nodiscard]] int size() const override { return 2; }
    [[nodiscard]] double sum(double value) const override {
        return reduce(value, [](double a, double b) { return a + b; });
    }
    [[nodiscard]] double max(double value) const override {
        return reduce(value, [](double a, double b) { return std::max(a, b); });
    }
    [[nodiscard]] double min(double value) const override {
        return reduce(value, [](double a, double b) { return std::min(a, b); });
    }
    void sum(std::span<double> values) const override {
        w_.slots[rank_].assign(values.begin(), values.end());
        w_.sync.arrive_and_wait();
        for (std::size_t i = 0; i < values.size(); ++i) values[i] = w_.slots[0][i] + w_.slots[1][i];
        w_.sync.arrive_and_wait();
    }
    void barrier() const override { w_.sync.arrive_and_wait(); }

private:
    template <class F>
    double reduce(double value, F f) const {
        w_.slot[rank_] = value;
        w_.sync.arrive_and_wait();
        const double r = f(w_.slot[0], w_.slot[1]);
        w_.sync.arrive_and_wait();
        return r;
    }
    TwoProcessWorld& w_;
    int rank_;
};

/// Ghost g of this part copies node `source[g]` (local index on the other part).
class TestHalo final : public parallel::Halo {
public:
    TestHalo(TwoProcessWorld& w, int rank, Index n_owned, std::vector<Index> source)
        : w_(w), rank_(rank), n_owned_(n_owned), source_(std::move(source)) {}
    void exchange(std::span<double> data, int components) const override {
        w_.data[rank_] = data;
        w_.sync.arrive_and_wait();
        const std::span<double> other = w_.data[1 - rank_];
        for (std::size_t g = 0; g < source_.size(); ++g)
            for (int c = 0; c < components; ++c)
                data[(n_owned_ + g) * components + c] = other[source_[g] * components + c];
        w_.sync.arrive_and_wait();
    }

private:
    TwoProcessWorld& w_;
    int rank_;
    Index n_owned_;
    std::vector<Index> source_;
};

TEST(Fgmres, TwoPartBlockJacobiMatchesWholeSystem) {
    const int nx = 12, ny = 9, nz = 8;
    const auto s = grid_system(nx, ny, nz, 8, 1e-3);
    const Index n = nx * ny * nz;
    KrylovOptions o;
    o.restart = 30;
    o.max_iterations = 300;
    o.relative_tolerance = 1e-10;

    std::vector<double> x_whole(s.b.size());
    {
        BlockIlu0 M;
        M.factorize(s.A);
        Fgmres solver;
        solver.solve(s.A, M, s.b, x_whole, parallel::SerialCommunicator{}, parallel::SerialHalo{},
                     o);
    }

    // Part p owns the nodes with x index < nx / 2 (p = 0) or >= nx / 2 (p = 1).
    std::vector<int> part(n);
    for (Index g = 0; g < n; ++g) part[g] = (g % nx) < nx / 2 ? 0 : 1;
    struct Local {
        std::vector<Index> global;  // local -> global
        std::vector<Index> local;   // global -> local, -1 if absent
        Index n_owned = 0;
        std::vector<Edge> edges;
        std::vector<Index> global_edge;
        BlockMatrix A;
        std::vector<double> b, x;
        KrylovResult result;
    };
    std::array<Local, 2> parts;
    for (int p = 0; p < 2; ++p) {
        Local& L = parts[p];
        L.local.assign(n, -1);
        for (Index g = 0; g < n; ++g)
            if (part[g] == p) {
                L.local[g] = Index(L.global.size());
                L.global.push_back(g);
            }
        L.n_owned = Index(L.global.size());
        std::vector<bool> ghost(n, false);
        for (const auto& e : s.edges)
            for (int end = 0; end < 2; ++end)
                if (part[e[end]] == p && part[e[1 - end]] != p) ghost[e[1 - end]] = true;
        for (Index g = 0; g < n; ++g)
            if (ghost[g]) {
                L.local[g] = Index(L.global.size());
                L.global.push_back(g);
            }
        // Every edge between local nodes, ghost-ghost ones included (they must add nothing).
        for (Index e = 0; e < Index(s.edges.size()); ++e) {
            const Index i = L.local[s.edges[e][0]], j = L.local[s.edges[e][1]];
            if (i >= 0 && j >= 0) {
                L.edges.push_back({j, i});  // reversed on purpose: orientation is free
                L.global_edge.push_back(e);
            }
        }
        L.A = BlockMatrix(L.n_owned, Index(L.global.size()), L.edges);
        for (Index e = 0; e < Index(L.edges.size()); ++e) {
            const Index ge = L.global_edge[e];
            L.A.add(L.A.edge_ij(e), s.A.block(s.A.edge_ji(ge)));
            L.A.add(L.A.edge_ji(e), s.A.block(s.A.edge_ij(ge)));
        }
        for (Index r = 0; r < L.n_owned; ++r)
            L.A.add(L.A.diagonal(r), s.A.block(s.A.diagonal(L.global[r])));
        L.b.assign(5 * L.global.size(), 0.0);
        L.x.assign(5 * L.global.size(), 0.0);
        for (Index r = 0; r < L.n_owned; ++r)
            for (int c = 0; c < 5; ++c) L.b[5 * r + c] = s.b[5 * L.global[r] + c];
    }
    TwoProcessWorld world;
    std::array<std::thread, 2> threads;
    for (int p = 0; p < 2; ++p)
        threads[p] = std::thread([&, p] {
            Local& L = parts[p];
            std::vector<Index> source;
            for (std::size_t g = L.n_owned; g < L.global.size(); ++g)
                source.push_back(parts[1 - p].local[L.global[g]]);
            const TestCommunicator comm(world, p);
            const TestHalo halo(world, p, L.n_owned, source);
            BlockIlu0 M;
            M.factorize(L.A);
            Fgmres solver;
            L.result = solver.solve(L.A, M, L.b, L.x, comm, halo, o);
        });
    for (auto& t : threads) t.join();

    EXPECT_EQ(parts[0].result.iterations, parts[1].result.iterations);
    EXPECT_EQ(parts[0].result.relative_residual, parts[1].result.relative_residual);
    EXPECT_LE(parts[0].result.relative_residual, 1e-10);
    double diff = 0.0, size = 0.0;
    for (int p = 0; p < 2; ++p) {
        const Local& L = parts[p];
        for (std::size_t l = 0; l < L.global.size(); ++l)  // ghosts too: set by the last exchange
            for (int c = 0; c < 5; ++c) {
                diff = std::max(diff, std::abs(L.x[5 * l + c] - x_whole[5 * L.global[l] + c]));
                size = std::max(size, std::abs(x_whole[5 * L.global[l] + c]));
            }
    }
    EXPECT_LT(diff, 1e-8 * size);
}

// ------------------------------------------------------------------------------ block SGS

/// Block symmetric Gauss-Seidel is M = (D + L) D^-1 (D + U) over the owned blocks (Saad 2003,
/// sec. 10.2): applying it to M x, formed densely, gives x back (to the float storage).
TEST(BlockSgs, InvertsItsOwnSplitting) {
    const auto edges = tet_grid_edges(3, 3, 3);
    const Index n_rows = 20, n_cols = 27;  // the last 7 nodes are ghosts (dropped by M)
    BlockMatrix A(n_rows, n_cols, edges);
    std::mt19937_64 rng(8);
    fill_dominant(A, edges, rng, 0.5);
    BlockSgs M;
    M.factorize(A);
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(5 * n_rows, 5 * n_rows), L = D, U = D;
    const auto rows = A.row_offsets();
    const auto cols = A.columns();
    for (Index r = 0; r < n_rows; ++r)
        for (std::int64_t p = rows[r]; p < rows[r + 1]; ++p) {
            const Index c = cols[p];
            if (c >= n_rows) continue;
            Eigen::MatrixXd& T = c < r ? L : c > r ? U : D;
            T.block<5, 5>(5 * r, 5 * c) = A.block(p);
        }
    const Eigen::MatrixXd Mdense = (D + L) * D.inverse() * (D + U);
    const auto x = random_vector(5 * n_rows, rng);
    const Eigen::VectorXd y = Mdense * Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
    std::vector<double> z(5 * n_rows);
    M.apply(std::span<const double>(y.data(), y.size()), z);
    double err = 0.0;
    for (int i = 0; i < 5 * n_rows; ++i) err = std::max(err, std::abs(z[i] - x[i]));
    EXPECT_LT(err, 1e-5);
    EXPECT_LT(M.memory_bytes(), std::size_t(n_rows) * 25 * sizeof(float) + 256);
}

TEST(BlockSgs, FgmresConvergesAndSingularDiagonalNamesRow) {
    auto s = grid_system(12, 11, 10, 5, 1e-3);
    BlockSgs M;
    M.factorize(s.A);
    Fgmres solver;
    std::vector<double> x(5 * std::size_t(s.A.n_cols()), 0.0);
    parallel::SerialCommunicator comm;
    parallel::SerialHalo halo;
    const KrylovResult r = solver.solve(s.A, M, s.b, x, comm, halo, {30, 200, 1e-10});
    EXPECT_LT(r.relative_residual, 1e-10);
    EXPECT_LT(true_relative_residual(s.A, s.b, x), 1e-9);
    std::vector<Edge> edges = {{0, 1}, {1, 2}};
    BlockMatrix B(3, 3, edges);
    B.add_to_diagonal(0, 1.0);
    B.add_to_diagonal(2, 1.0);  // row 1's diagonal block stays zero
    try {
        M.factorize(B);
        FAIL() << "no error on a singular diagonal block";
    } catch (const SingularBlockError& e) {
        EXPECT_NE(std::string(e.what()).find("row 1 "), std::string::npos) << e.what();
        EXPECT_EQ(e.row(), 1);
    }
}

// ------------------------------------------------------------------------------ blocks

/// With `set_blocks`, SGS and ILU(0) drop the couplings between rows of different labels as
/// they drop the ghost columns: they act exactly as on the matrix without those couplings (the
/// preconditioner a process would apply to its part, docs/parallel.md).
TEST(PreconditionerBlocks, ActAsOnTheMatrixWithoutTheCouplingsBetweenBlocks) {
    const int nx = 4, ny = 3, nz = 3;
    const auto edges = tet_grid_edges(nx, ny, nz);
    const Index n_rows = 30, n_cols = 36;  // the last 6 nodes are ghosts
    std::vector<int> label(static_cast<std::size_t>(n_cols));
    for (Index v = 0; v < n_cols; ++v) label[v] = v % nx < 2 ? 0 : 1;  // interleaved numbers
    BlockMatrix A(n_rows, n_cols, edges);
    std::mt19937_64 rng(21);
    fill_dominant(A, edges, rng, 0.5);
    std::vector<Edge> kept;
    std::vector<Index> from;
    for (Index e = 0; e < Index(edges.size()); ++e) {
        const Index i = edges[e][0], j = edges[e][1];
        if (i >= n_rows || j >= n_rows || label[i] == label[j]) {
            kept.push_back(edges[e]);
            from.push_back(e);
        }
    }
    ASSERT_LT(kept.size(), edges.size());
    BlockMatrix B(n_rows, n_cols, kept);
    for (Index k = 0; k < Index(kept.size()); ++k) {
        if (A.edge_ij(from[k]) >= 0) B.add(B.edge_ij(k), A.block(A.edge_ij(from[k])));
        if (A.edge_ji(from[k]) >= 0) B.add(B.edge_ji(k), A.block(A.edge_ji(from[k])));
    }
    for (Index r = 0; r < n_rows; ++r) B.add(B.diagonal(r), A.block(A.diagonal(r)));
    const std::vector<int> rows_label(label.begin(), label.begin() + n_rows);
    const auto r = random_vector(5 * std::size_t(n_rows), rng);
    auto check = [&](Preconditioner& with, Preconditioner& without, const char* what) {
        with.set_blocks(rows_label);
        with.factorize(A);
        without.factorize(B);
        std::vector<double> z1(r.size()), z2(r.size());
        with.apply(r, z1);
        without.apply(r, z2);
        double diff = 0.0, size = 0.0;
        for (std::size_t q = 0; q < r.size(); ++q) {
            diff = std::max(diff, std::abs(z1[q] - z2[q]));
            size = std::max(size, std::abs(z2[q]));
        }
        EXPECT_LE(diff, 1e-14 * size) << what;
        // Without the blocks the couplings count: another result.
        with.set_blocks({});
        with.factorize(A);
        with.apply(r, z1);
        diff = 0.0;
        for (std::size_t q = 0; q < r.size(); ++q) diff = std::max(diff, std::abs(z1[q] - z2[q]));
        EXPECT_GT(diff, 1e-3 * size) << what;
    };
    BlockSgs s1, s2;
    check(s1, s2, "block SGS");
    BlockIlu0 i1, i2;
    check(i1, i2, "block ILU(0)");
    BlockSgs bad;
    bad.set_blocks({0, 1});
    EXPECT_THROW(bad.factorize(A), InputError);
}

/// With the double accumulation the diagonal blocks are the rounded double sums, whatever the
/// order of the contributions (the order of a process's local edges is not the whole mesh's).
TEST(BlockMatrix, DiagonalsSummedInDoubleDoNotDependOnTheOrder) {
    const std::vector<Edge> edges = {{0, 1}, {1, 2}};
    std::mt19937_64 rng(5);
    std::vector<Mat5> c;
    for (int k = 0; k < 14; ++k) c.push_back(random_block(rng, std::pow(10.0, k % 5 - 2)));
    BlockMatrix A(3, 3, edges), B(3, 3, edges), F(3, 3, edges);
    A.accumulate_diagonals(true);
    B.accumulate_diagonals(true);
    A.set_zero();
    B.set_zero();
    F.set_zero();
    Mat5 sum = Mat5::Zero();
    for (std::size_t k = 0; k < c.size(); ++k) {
        A.add_diagonal(1, c[k]);
        B.add_diagonal(1, c[c.size() - 1 - k]);
        F.add_diagonal(1, c[k]);  // off: single precision, as add
        sum += c[k];
    }
    A.flush_diagonals();
    B.flush_diagonals();
    const Mat5 a = A.block(A.diagonal(1)), b = B.block(B.diagonal(1));
    for (int q = 0; q < 25; ++q) {
        EXPECT_EQ(a(q / 5, q % 5), b(q / 5, q % 5));
        EXPECT_EQ(a(q / 5, q % 5), double(float(sum(q / 5, q % 5))));
    }
    EXPECT_NE(F.block(F.diagonal(1)), a);  // summed in single precision: other last bits
    // After the flush add_diagonal adds in single precision again, until the next set_zero.
    A.add_diagonal(1, Mat5::Identity());
    EXPECT_EQ(A.block(A.diagonal(1))(0, 0), double(float(a(0, 0)) + 1.0f));
}
}  // namespace
}  // namespace manta::euler
