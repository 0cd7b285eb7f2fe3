/// @file unsteady.cpp
/// Unsteady vortex-lattice method (theory and conventions: unsteady.hpp and docs/uvlm.md).
///
/// Layout. The lattice's strips are grouped into chains (consecutive strips of one surface copy
/// sharing an edge), ordered so that each strip's b edge is the next strip's a edge. A chain of
/// m strips n_chord panels deep is a structured grid of (n_chord + 2) x (m + 1) vortex points:
/// rows 0 .. n_chord - 1 on the panels' bound segments (quarter points), row n_chord on the
/// trailing edge, row n_chord + 1 on the shed line behind it (ring row n_chord is the last
/// panel's ring continued: its sides bend at the trailing edge). Chains of equal depth share one
/// grid, side by side; the wake of
/// every shedding chain is one more grid whose rows are the shed rows, newest first. In a grid
/// the ring (row k, column e) has corners (k, e), (k, e+1), (k+1, e+1), (k+1, e) and circulation
/// G(k, e) (zero in the last column of each chain, which closes it); each grid segment carries the
/// difference of the two rings that share it:
///   spanwise  (k, e) -> (k, e+1):  G(k, e) - G(k-1, e)
///   chordwise (k, e) -> (k+1, e):  G(k, e-1) - G(k, e)
/// so that one pass over the grid points (distance to the field point) and one over each family
/// of segments, all contiguous, gives the induced velocity: the O(N x wake) work of a step runs
/// through this vectorisable kernel. The shed line lies UnsteadyOptions::shed_offset v0 dt behind
/// the trailing edge (set at `start`, when v0 and dt are known; the influence matrix is then
/// built and factorised, and kept for later runs with the same v0 dt).
///
/// Compressibility: as in the steady solver, every induced velocity is computed in coordinates
/// stretched by 1/beta in x, beta = sqrt(1 - M^2), and its x component divided by beta. Vortex
/// cores and symmetry images also follow the steady solver (Grid, Impl::induced).

#include "manta/vlm/unsteady.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <numbers>
#include <string>
#include <thread>
#include <utility>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"
#include "manta/vlm/detail/biot_savart.hpp"
#include "manta/vlm/detail/dense_lu.hpp"
#include "manta/vlm/detail/kernels.hpp"

namespace manta::vlm {

using Eigen::ArrayXd;
using Eigen::Index;
using Eigen::Matrix3d;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

std::vector<double> UnsteadyHistory::column(double UnsteadyStep::*member) const {
    std::vector<double> out;
    out.reserve(steps.size());
    for (const UnsteadyStep& s : steps) out.push_back(s.*member);
    return out;
}

namespace {

/// Geometry axes <-> body axes (a rotation by pi about y): (x, y, z)_body = D (x, y, z)_geometry.
const Matrix3d D = core::dcm_body_from_geometry();

/// Trailing-edge point of a strip edge.
Vector3d trailing_edge(const Vector3d& le, double chord) {
    return le + chord * Vector3d::UnitX();
}

/// Corners of the vortex ring of panel i: bound a, bound b, then the next panel's bound b and a;
/// for the last panel of the strip the shed line, `shed` behind the trailing edge along the unit
/// vector `dir`.
std::array<Vector3d, 4> ring_corners(const Lattice& L, int i, double shed,
                                     const Vector3d& dir = Vector3d::UnitX()) {
    const auto ii = static_cast<std::size_t>(i);
    const Strip& st = L.strips[static_cast<std::size_t>(L.strip[ii])];
    if (i + 1 < st.first_panel + st.n_panels) return {L.a[ii], L.b[ii], L.b[ii + 1], L.a[ii + 1]};
    const Vector3d dx = shed * dir;
    return {L.a[ii], L.b[ii], trailing_edge(st.le_b, st.chord_b) + dx,
            trailing_edge(st.le_a, st.chord_a) + dx};
}

Vector3d stretch(const Vector3d& p, double beta) {
    return {p.x() / beta, p.y(), p.z()};
}

/// Scratch arrays of the grid kernel (one block of grid points).
struct Scratch {
    ArrayXd rx, ry, rz, rn, ri;  ///< field point minus grid point, its length and inverse
    void reserve(Index n) {
        for (ArrayXd* a : {&rx, &ry, &rz, &rn, &ri})
            if (a->size() < n) a->resize(n);
    }
};

/// Grid points per block of the kernel (a few tens of kilobytes of scratch: cache-resident).
constexpr Index block_points = 1024;

/// Largest lattice-on-lattice influence kept for the loads (UnsteadySolver::Impl::
/// build_lattice_influence): 3 (N + chordwise segments) x N doubles, about 190 MB for the
/// 2 000-panel Ranger lattice; beyond it the loads sum the kernel every step.
constexpr double lattice_matrix_bytes = 512.0e6;

/// A structured grid of vortex rings (see the file comment). Coordinates are stretched.
struct Grid {
    int rows = 0;  ///< point rows in use
    int cols = 0;
    ArrayXd x, y, z;         ///< points, row-major, capacity rows_max x cols
    ArrayXd ls, lc;          ///< squared lengths of the spanwise / chordwise segments
    ArrayXd ss, sc;          ///< segment strengths
    ArrayXd scl, scr;        ///< chordwise strengths split: ring(k, e-1) and -ring(k, e)
    ArrayXd ring;            ///< ring circulations, (rows - 1) x cols
    bool tail = false;       ///< the last point row continues to infinity (no closing segments)
    ArrayXd tx, ty, tz, ts;  ///< tail directions (unit, stretched) and strengths per column
    ArrayXd tsl, tsr;        ///< tail strengths split like scl, scr
    /// Vortex cores per class of field point (UnsteadySolver::Impl::panel_class): the squared
    /// core radius of each column's strip (`core`) and of the strip before it (`core_left`), and
    /// delta^2 |r0|^2 per segment: spanwise (ks, the column's strip), chordwise (kc, the
    /// column's strip; kcl the strip on the left). Each ring keeps its own strip's core on its
    /// sides, as each horseshoe of the steady solver does: where the cores of neighbouring
    /// strips differ (across components) a chordwise segment is summed as its two rings' sides
    /// (`split`), not as their difference.
    std::vector<ArrayXd> core, core_left, ks, kc, kcl;
    bool split = false;

    void reserve(int max_rows, int c) {
        cols = c;
        const Index n = static_cast<Index>(max_rows) * c;
        for (ArrayXd* a : {&x, &y, &z, &ls, &lc, &ss, &sc, &scl, &scr, &ring}) a->setZero(n);
        for (ArrayXd* a : {&tx, &ty, &tz, &ts, &tsl, &tsr}) a->setZero(c);
        for (std::vector<ArrayXd>* v : {&ks, &kc, &kcl})
            for (ArrayXd& a : *v) a.setZero(n);
    }
    /// Column cores per class (capacity as reserve).
    void set_cores(std::vector<ArrayXd> own, std::vector<ArrayXd> left, bool split_sides,
                   int max_rows) {
        core = std::move(own);
        core_left = std::move(left);
        split = split_sides;
        const ArrayXd zero = ArrayXd::Zero(static_cast<Index>(max_rows) * cols);
        ks.assign(core.size(), zero);
        kc.assign(core.size(), zero);
        kcl.assign(split ? core.size() : 0, zero);
    }
    /// delta^2 |r0|^2 of every segment from the lengths.
    void update_cores() {
        for (std::size_t k = 0; k < ks.size(); ++k)
            for (Index r = 0; r < rows; ++r) {
                ks[k].segment(r * cols, cols) = core[k] * ls.segment(r * cols, cols);
                if (r + 1 < rows) {
                    kc[k].segment(r * cols, cols) = core[k] * lc.segment(r * cols, cols);
                    if (split)
                        kcl[k].segment(r * cols, cols) = core_left[k] * lc.segment(r * cols, cols);
                }
            }
    }
    [[nodiscard]] Index block_rows() const {
        return std::max<Index>(1, block_points / std::max(1, cols));
    }
    [[nodiscard]] Vector3d point(Index j) const { return {x[j], y[j], z[j]}; }

    /// Squared segment lengths from the points.
    void update_lengths() {
        const Index n = static_cast<Index>(rows) * cols;
        if (n == 0) return;
        ls.head(n - 1) = (x.segment(1, n - 1) - x.head(n - 1)).square() +
                         (y.segment(1, n - 1) - y.head(n - 1)).square() +
                         (z.segment(1, n - 1) - z.head(n - 1)).square();
        ls[n - 1] = 0.0;
        const Index m = n - cols;
        if (m > 0)
            lc.head(m) = (x.segment(cols, m) - x.head(m)).square() +
                         (y.segment(cols, m) - y.head(m)).square() +
                         (z.segment(cols, m) - z.head(m)).square();
    }

    /// Segment strengths from the ring circulations; with `with_tail` the last point row carries
    /// no closing segments and its columns continue to infinity along the last chordwise
    /// segments (fallback direction `dir` where those have no length).
    void update_strengths(bool with_tail, const Vector3d& dir) {
        const int nr = rows - 1;  // ring rows
        for (int r = 0; r < rows; ++r)
            for (int e = 0; e < cols; ++e) {
                const Index j = static_cast<Index>(r) * cols + e;
                const double here = r < nr ? ring[j] : 0.0;
                const double before = r > 0 ? ring[j - cols] : 0.0;
                ss[j] = here - before;
                if (r < nr) {
                    scl[j] = e > 0 ? ring[j - 1] : 0.0;
                    scr[j] = -ring[j];
                    sc[j] = scl[j] + scr[j];
                }
            }
        tail = with_tail && nr > 0;
        if (!tail) return;
        const Index last = static_cast<Index>(nr) * cols;
        for (int e = 0; e < cols; ++e) {
            const Index j = last + e;
            ss[j] = 0.0;
            tsl[e] = e > 0 ? ring[j - cols - 1] : 0.0;
            tsr[e] = -ring[j - cols];
            ts[e] = tsl[e] + tsr[e];
            Vector3d d = point(j) - point(j - cols);
            if (!(d.norm() > 0.0)) d = dir;
            d.normalize();
            tx[e] = d.x();
            ty[e] = d.y();
            tz[e] = d.z();
        }
    }
};

/// Accumulate (into a) the velocity of the m segments from point j to point j + step of a block,
/// j = 0 .. m - 1, with strengths S and core terms K = delta^2 |r0|^2: the Biot-Savart law
///   v = S / (4 pi) (r1 x r2) r0 . (r1/|r1| - r2/|r2|) / |r1 x r2|^2,   r0 = r1 - r2,
/// written as (1/|r1| + 1/|r2|) (|r1||r2| - r1 . r2) for the dot product (the same number, fewer
/// operations) and regularised by |r1 x r2|^2 -> |r1 x r2|^2 + delta^2 |r0|^2 (1/d^2 ->
/// 1/(d^2 + delta^2), d the distance to the segment's line). Four segments at a time in
/// fixed-size arrays (vectorised without reassociating a scalar sum), the remainder one by one.
struct Accumulator {
    Eigen::Array4d x = Eigen::Array4d::Zero(), y = Eigen::Array4d::Zero(),
                   z = Eigen::Array4d::Zero();
};

void segment_family(const Scratch& s, Index m, Index step, const double* S, const double* K,
                    double tiny, Accumulator& a) {
    // detail::Kernels::segment_family: four segments at a time (two SSE2 or one AVX2 vector).
    double acc[12];
    Eigen::Map<Eigen::Array4d> head(acc);
    head = a.x;
    Eigen::Map<Eigen::Array4d>(acc + 4) = a.y;
    Eigen::Map<Eigen::Array4d>(acc + 8) = a.z;
    detail::kernels().segment_family(s.rx.data(), s.ry.data(), s.rz.data(), s.rn.data(),
                                     s.ri.data(), m, step, S, K, tiny, acc);
    a.x = Eigen::Map<const Eigen::Array4d>(acc);
    a.y = Eigen::Map<const Eigen::Array4d>(acc + 4);
    a.z = Eigen::Map<const Eigen::Array4d>(acc + 8);
}

/// Velocity at p (stretched coordinates, no 1/beta on x yet) induced by the segments of a grid
/// that start on point rows [row_begin, row_end) (all: 0, -1), and by the tail if row_end is the
/// last row, with the vortex cores of class `cls` (each segment's 1/d^2 becomes
/// 1/(d^2 + delta^2)).
Vector3d grid_velocity(const Grid& g, const Vector3d& p, int cls, double tiny, Scratch& s,
                       Index row_begin = 0, Index row_end = -1) {
    const Index R = g.rows;
    const Index C = g.cols;
    const Index re = row_end < 0 ? R : std::min(row_end, R);
    if (R == 0 || C == 0 || row_begin >= re) return Vector3d::Zero();
    const double eps2 = std::sqrt(tiny);
    const Index B = g.block_rows();
    Accumulator acc;
    for (Index r0 = row_begin; r0 < re; r0 += B) {
        const Index rp = std::min<Index>(B + 1, R - r0);  // point rows in the block
        const Index np = rp * C, off = r0 * C;
        detail::kernels().grid_points(g.x.data() + off, g.y.data() + off, g.z.data() + off, np,
                                      p.data(), eps2, s.rx.data(), s.ry.data(), s.rz.data(),
                                      s.rn.data(), s.ri.data());
        // Spanwise segments on the block's rows (the last grid point starts none).
        const Index rs = std::min<Index>(B, re - r0);
        Index m = rs * C;
        if (r0 + rs == R) m -= 1;
        const auto k = static_cast<std::size_t>(cls);
        if (m > 0) segment_family(s, m, 1, g.ss.data() + off, g.ks[k].data() + off, tiny, acc);
        // Chordwise segments from the block's rows to the next row.
        const Index rc = std::min({B, re - r0, R - 1 - r0});
        if (rc > 0 && g.split) {
            segment_family(s, rc * C, C, g.scl.data() + off, g.kcl[k].data() + off, tiny, acc);
            segment_family(s, rc * C, C, g.scr.data() + off, g.kc[k].data() + off, tiny, acc);
        } else if (rc > 0) {
            segment_family(s, rc * C, C, g.sc.data() + off, g.kc[k].data() + off, tiny, acc);
        }
    }
    double vx = acc.x.sum(), vy = acc.y.sum(), vz = acc.z.sum();
    if (g.tail && re == R) {
        const Index last = (R - 1) * C;
        const auto k = static_cast<std::size_t>(cls);
        for (Index e = 0; e < C; ++e) {
            if (g.tsl[e] == 0.0 && g.tsr[e] == 0.0) continue;
            const Vector3d r1 = p - g.point(last + e);
            const Vector3d d(g.tx[e], g.ty[e], g.tz[e]);
            const Vector3d c = d.cross(r1);
            const double n1 = std::sqrt(r1.squaredNorm() + eps2);
            const double f = (1.0 + d.dot(r1) / n1), c2 = c.squaredNorm();
            const double q = g.split ? g.tsl[e] / (c2 + g.core_left[k][e] + tiny) +
                                           g.tsr[e] / (c2 + g.core[k][e] + tiny)
                                     : g.ts[e] / (c2 + g.core[k][e] + tiny);
            vx += f * q * c.x();
            vy += f * q * c.y();
            vz += f * q * c.z();
        }
    }
    return detail::inv_four_pi * Vector3d(vx, vy, vz);
}

/// One segment x1 -> x2 at p by the kernel's formula (unit circulation, core term K).
Vector3d cored_segment(const Vector3d& p, const Vector3d& x1, const Vector3d& x2, double core2,
                       double tiny) {
    const Vector3d r1 = p - x1, r2 = p - x2;
    const Vector3d c = r1.cross(r2);
    const double n1 = std::sqrt(r1.squaredNorm() + std::sqrt(tiny));
    const double n2 = std::sqrt(r2.squaredNorm() + std::sqrt(tiny));
    const double num = (1.0 / n1 + 1.0 / n2) * (n1 * n2 - r1.dot(r2));
    const double K = core2 * (x2 - x1).squaredNorm();
    return (detail::inv_four_pi * num / (c.squaredNorm() + K + tiny)) * c;
}

/// A semi-infinite line from x1 along the unit vector d at p (unit circulation, core delta^2).
Vector3d cored_semi_infinite(const Vector3d& p, const Vector3d& x1, const Vector3d& d, double core2,
                             double tiny) {
    const Vector3d r1 = p - x1;
    const Vector3d c = d.cross(r1);
    const double n1 = std::sqrt(r1.squaredNorm() + std::sqrt(tiny));
    return (detail::inv_four_pi * (1.0 + d.dot(r1) / n1) / (c.squaredNorm() + core2 + tiny)) * c;
}

/// A grid of the lattice's rings (chains of one chordwise depth side by side).
struct LatticeGrid {
    Grid g;
    int n_chord = 0;
    /// (n_chord + 1) x cols: panel of ring (k, e), -1 in chain-end columns; ring row n_chord, from
    /// the trailing edge to the shed line, is the last panel's ring continued (its sides bend at
    /// the trailing edge, as the steady solver's legs do).
    std::vector<int> panel;
    std::vector<Vector3d> point;  ///< physical points, (n_chord + 2) x cols
    [[nodiscard]] int ring_rows() const { return n_chord + 1; }
    std::vector<Vector3d> te;    ///< trailing-edge point of each column
    std::vector<int> col_strip;  ///< strip of each column (the a-edge's, else the b-edge's)
};

/// Chordwise segment of a lattice grid (for the loads).
struct ChordSegment {
    int left = -1, right = -1;  ///< panels of the rings on its two sides (ring(k, e-1), ring(k, e))
    int cls = 0;                ///< class of field point (its component)
    Vector3d mid, l;            ///< physical midpoint and vector
    std::array<int, 4> near{-1, -1, -1, -1};  ///< panels whose wake velocity is averaged here
};

/// Strips of a lattice as chains: each strip's b edge is the next one's a edge.
std::vector<std::vector<int>> strip_chains(const Lattice& L, double tol) {
    std::vector<std::vector<int>> chains;
    std::size_t t = 0;
    const std::size_t ns = L.strips.size();
    while (t < ns) {
        // One surface copy: consecutive strips of the same surface and side.
        std::size_t u = t;
        while (u < ns && L.strips[u].surface == L.strips[t].surface &&
               L.strips[u].mirrored == L.strips[t].mirrored)
            ++u;
        std::vector<int> order;
        for (std::size_t q = t; q < u; ++q) order.push_back(static_cast<int>(q));
        // A mirror copy is built root to tip with a and b swapped: reversed, b meets the next a.
        if (L.strips[t].mirrored) std::reverse(order.begin(), order.end());
        std::vector<int> chain;
        for (const int s : order) {
            if (!chain.empty()) {
                const Strip& P = L.strips[static_cast<std::size_t>(chain.back())];
                const Strip& S = L.strips[static_cast<std::size_t>(s)];
                bool joined = P.n_panels == S.n_panels && (P.le_b - S.le_a).norm() <= tol &&
                              std::abs(P.chord_b - S.chord_a) <= tol;
                for (int k = 0; joined && k < S.n_panels; ++k)
                    joined = (L.b[static_cast<std::size_t>(P.first_panel + k)] -
                              L.a[static_cast<std::size_t>(S.first_panel + k)])
                                 .norm() <= tol;
                if (!joined) {
                    chains.push_back(std::move(chain));
                    chain.clear();
                }
            }
            chain.push_back(s);
        }
        chains.push_back(std::move(chain));
        t = u;
    }
    return chains;
}

/// Hinge chord fraction of control `name` at strip `st` from the model's sections, or NaN.
double hinge_fraction(const Model& model, const Strip& st, const std::string& name) {
    if (st.surface < 0 || static_cast<std::size_t>(st.surface) >= model.surfaces.size())
        return std::nan("");
    const Surface& S = model.surfaces[static_cast<std::size_t>(st.surface)];
    Vector3d p = st.le_mid;
    if (st.mirrored && S.y_duplicate) p.y() = 2.0 * *S.y_duplicate - p.y();
    for (std::size_t j = 0; j + 1 < S.sections.size(); ++j) {
        const Section& A = S.sections[j];
        const Section& B = S.sections[j + 1];
        const Vector3d d = B.leading_edge - A.leading_edge;
        const double d2 = d.squaredNorm();
        if (!(d2 > 0.0)) continue;
        const double u = (p - A.leading_edge).dot(d) / d2;
        if (u < -1e-9 || u > 1.0 + 1e-9) continue;
        if ((A.leading_edge + u * d - p).norm() > 1e-6 * std::max(A.chord, B.chord)) continue;
        auto find = [&](const Section& s) -> const SectionControl* {
            for (const SectionControl& c : s.controls)
                if (c.name == name) return &c;
            return nullptr;
        };
        const SectionControl* ca = find(A);
        const SectionControl* cb = find(B);
        if (ca == nullptr || cb == nullptr) continue;
        return std::abs(ca->hinge_chord_fraction +
                        u * (cb->hinge_chord_fraction - ca->hinge_chord_fraction));
    }
    return std::nan("");
}

/// The state of the motion at one instant, in the solver's terms.
struct Pose {
    double t = 0.0;
    Matrix3d C = Matrix3d::Identity();  ///< body from motion frame
    Vector3d r_ref = Vector3d::Zero();  ///< reference point, motion frame [m]
    double shift = 0.0;                 ///< v0 (t - t0): motion frame -> still-air frame along x
    Vector3d vinf = Vector3d::Zero();   ///< air velocity relative to the reference point, geometry
    Vector3d omega = Vector3d::Zero();  ///< angular velocity, geometry axes
    double alpha = 0.0, beta = 0.0, airspeed = 0.0;
    VectorXd delta, delta_rate;  ///< lattice controls and their rates
};

}  // namespace

struct UnsteadySolver::Impl {
    Model model;
    Lattice L;
    UnsteadyOptions opt;
    double mach = 0.0, beta = 1.0;
    int N = 0;
    double cref = 1.0;
    double tiny = 0.0;
    // Vortex cores by class of field point, as the steady solver's: within the field point's
    // component core_within x strip width, across components core_between x max(chord, 2 width);
    // one class per Surface::component and a last one, core_radius, for the free wake's points.
    int n_class = 1, free_class = 0;
    std::vector<int> panel_class;
    struct Image {
        double f;
        bool y, z;
    };
    std::vector<Image> images;  // Model::y_symmetry, z_symmetry
    std::vector<ArrayXd> wake_core, wake_core_left;
    bool split_sides = false;
    MatrixXd A;  // influence of unit ring circulations on the control points' normal velocity
    detail::DenseLU lu;

    // Lattice geometry (physical, geometry axes) and its stretched evaluation points.
    std::vector<LatticeGrid> grids;
    std::vector<int> panel_prev;  // ring ahead in the strip, -1 for the first
    std::vector<char> closure;    // last panel of a strip that sheds no wake
    std::vector<Vector3d> cp, mid, lvec, n0, centroid;
    std::vector<double> ring_area;
    std::vector<std::vector<Vector3d>> hinge;  // per panel, per PanelControl: hinge point
    std::vector<ChordSegment> chord;
    std::vector<Vector3d> strip_normal;

    // Wake: columns of every shedding chain side by side.
    int wake_cols = 0;
    std::vector<int> wake_te;  // per column: trailing-edge panel of its strip, or -1
    std::vector<Vector3d> wake_trailing_edge;  // per column: trailing-edge point (geometry axes)
    std::vector<Vector3d> wake_shed;           // per column: shed point (geometry axes)
    double shed_distance = -1.0;               // shed line behind the trailing edge [m]
    Vector3d shed_dir = Vector3d::UnitX();     // ... along this unit vector (geometry axes)
    Grid wake;
    ArrayXd ax, ay, az;  // wake points in the still-air frame (the frame of the motion at t0)
    bool truncated = false;
    std::vector<Scratch> scratch;  // one per worker thread
    int threads = 1;
    Matrix3Xd v_free;  // free wake: velocity of the wake points
    Matrix3Xd v_far;   // far-wake velocity at the control points
    struct Interpolation {
        Index i0 = 0, i1 = 0;
        double w0 = 1.0, w1 = 0.0;
    };
    std::vector<Interpolation> bound_from_cp;  // bound point from its strip's control points
    /// Velocity induced by the lattice's rings at the load points (bound points, then chordwise
    /// segment midpoints) per unit ring circulation, transposed: column 3q + d is component d
    /// at load point q. The lattice is rigid in geometry axes, so this is built once per shed
    /// distance; empty when it would exceed lattice_matrix_bytes (the kernel sums then).
    MatrixXd lattice_influence_t;
    Index near_rows = 0;  // wake point rows summed exactly at bound points

    // Run state.
    bool started = false;
    aero::Motion motion;
    std::vector<int> mode_control;  // per motion mode: lattice control or -1
    double v0 = 0.0, dt = 0.0, t0 = 0.0;
    int n_steps = 0, step = 0, max_rows = 0;
    Pose pose;
    VectorXd gamma, gamma1, gamma2, dgdt, rhs;
    Matrix3Xd v_wake;           // wake-induced velocity at control points, then bound midpoints
    Matrix3Xd v_lattice;        // lattice-induced velocity at bound midpoints, then chord midpoints
    std::vector<Vector3d> nrm;  // deflected normals
    UnsteadyStep current;

    Impl(const Model& m, Lattice lat, UnsteadyOptions o);
    void build_geometry();
    void set_shed(double distance, const Vector3d& dir);
    void assemble();
    void build_lattice_influence();
    void pose_at(double t, Pose& p) const;
    [[nodiscard]] Vector3d to_air(const Pose& p, const Vector3d& g) const;
    void wake_to_geometry(const Pose& p);
    void lattice_strengths(const VectorXd& g);
    void kinematic_rhs(const Pose& p);
    void wake_velocities();
    void convect_free_wake();
    void shed(const Pose& p);
    void start_steady();
    void start_impulsive();
    void loads();
    /// f(begin, end, scratch) over [0, n) split among the worker threads.
    template <class F>
    void parallel(Index n, F&& f) {
        const Index T = std::min<Index>(threads, std::max<Index>(1, n / 8));
        if (T <= 1) {
            f(Index{0}, n, scratch[0]);
            return;
        }
        std::vector<std::thread> pool;
        pool.reserve(static_cast<std::size_t>(T - 1));
        auto chunk = [&](Index t) { return n * t / T; };
        for (Index t = 1; t < T; ++t)
            pool.emplace_back([&f, &chunk, t, this] {
                f(chunk(t), chunk(t + 1), scratch[static_cast<std::size_t>(t)]);
            });
        f(Index{0}, chunk(1), scratch[0]);
        for (std::thread& th : pool) th.join();
    }
    [[nodiscard]] Vector3d reflect_point(const Vector3d& p, const Image& im) const {
        return {p.x(), im.y ? -p.y() : p.y(), im.z ? 2.0 * model.z_symmetry_plane - p.z() : p.z()};
    }
    [[nodiscard]] static Vector3d reflect_vector(const Vector3d& v, const Image& im) {
        return {v.x(), im.y ? -v.y() : v.y(), im.z ? -v.z() : v.z()};
    }
    /// Velocity at the physical point p of class cls induced by the lattice grids (lattice) or by
    /// the wake rows [rb, re), images included, x component returned to physical space.
    Vector3d induced(const Vector3d& p, int cls, bool lattice, Scratch& s, Index rb = 0,
                     Index re = -1) const {
        auto eval = [&](const Vector3d& q) {
            const Vector3d qs = stretch(q, beta);
            if (!lattice) return grid_velocity(wake, qs, cls, tiny, s, rb, re);
            Vector3d v = Vector3d::Zero();
            for (const LatticeGrid& G : grids) v += grid_velocity(G.g, qs, cls, tiny, s);
            return v;
        };
        Vector3d v = eval(p);
        for (const Image& im : images) v += im.f * reflect_vector(eval(reflect_point(p, im)), im);
        v.x() /= beta;
        return v;
    }
    [[nodiscard]] Vector3d kinematic(const Vector3d& x) const {
        return pose.vinf - pose.omega.cross(x - model.reference.point);
    }
};

UnsteadySolver::Impl::Impl(const Model& m, Lattice lat, UnsteadyOptions o)
    : model(m), L(std::move(lat)), opt(std::move(o)) {
    mach = opt.mach ? *opt.mach : model.mach;
    if (!(mach >= 0.0 && mach < 0.95))
        throw InputError(fmt::format(
            "vlm unsteady: Mach {}; expected 0 <= M < 0.95 (Prandtl-Glauert is subsonic)", mach));
    if (!(opt.dt >= 0.0) || !std::isfinite(opt.dt))
        throw InputError(fmt::format("vlm unsteady: time step {} s; expected >= 0", opt.dt));
    if (opt.wake_rows < 0)
        throw InputError(fmt::format("vlm unsteady: wake_rows {}; expected >= 0", opt.wake_rows));
    if (opt.wake_rows == 0 && !(opt.wake_length > 0.0 && std::isfinite(opt.wake_length)))
        throw InputError(fmt::format("vlm unsteady: wake_length {} reference chords; expected > 0",
                                     opt.wake_length));
    if (!(opt.shed_offset >= 0.0 && opt.shed_offset <= 1.0))
        throw InputError(fmt::format(
            "vlm unsteady: shed_offset {} (fraction of v0 dt); expected 0 to 1", opt.shed_offset));
    if (!(opt.core_radius >= 0.0 && std::isfinite(opt.core_radius)))
        throw InputError(fmt::format("vlm unsteady: core_radius {} reference chords; expected >= 0",
                                     opt.core_radius));
    if (!(opt.core_within_component >= 0.0 && opt.core_between_components >= 0.0))
        throw InputError(
            fmt::format("vlm unsteady: vortex core factors {} and {}; expected numbers >= 0",
                        opt.core_within_component, opt.core_between_components));
    if (!(opt.near_wake >= 0.0 && std::isfinite(opt.near_wake)))
        throw InputError(fmt::format("vlm unsteady: near_wake {} reference chords; expected >= 0",
                                     opt.near_wake));
    if (opt.threads < 0)
        throw InputError(fmt::format("vlm unsteady: threads {}; expected >= 0", opt.threads));
    if (opt.speed && !(*opt.speed > 0.0 && std::isfinite(*opt.speed)))
        throw InputError(fmt::format("vlm unsteady: speed {} m/s; expected > 0", *opt.speed));
    check_lattice(model, L);
    beta = std::sqrt(1.0 - mach * mach);
    N = L.size();
    cref = model.reference.chord;
    tiny = std::pow(1e-10 * cref, 4);
    if (model.y_symmetry != 0)
        images.push_back({static_cast<double>(model.y_symmetry), true, false});
    if (model.z_symmetry != 0)
        images.push_back({static_cast<double>(model.z_symmetry), false, true});
    if (model.y_symmetry != 0 && model.z_symmetry != 0)
        images.push_back({static_cast<double>(model.y_symmetry * model.z_symmetry), true, true});
    build_geometry();
}

void UnsteadySolver::Impl::build_geometry() {
    const auto n = static_cast<std::size_t>(N);
    cp = L.control_point;
    n0 = L.normal;
    mid.resize(n);
    lvec.resize(n);
    centroid.resize(n);
    ring_area.resize(n);
    panel_prev.assign(n, -1);
    hinge.resize(n);
    closure.assign(n, 0);
    const bool bound_points = L.bound_point.size() == n;
    for (std::size_t i = 0; i < n; ++i) {
        // Where the bound segment's load acts: the steady solver's point (the control point's
        // spanwise station) when the lattice gives it, else the midpoint.
        mid[i] = bound_points ? L.bound_point[i] : Vector3d(0.5 * (L.a[i] + L.b[i]));
        lvec[i] = L.b[i] - L.a[i];
        // The ring's part on the surface: from its bound segment to the next one, the last to
        // the trailing edge; its potential jump is the ring circulation.
        const Strip& st = L.strips[static_cast<std::size_t>(L.strip[i])];
        std::array<Vector3d, 4> c = ring_corners(L, static_cast<int>(i), 0.0);
        if (static_cast<int>(i) + 1 == st.first_panel + st.n_panels) {
            c[2] = st.le_b + st.chord_b * Vector3d::UnitX();
            c[3] = st.le_a + st.chord_a * Vector3d::UnitX();
            // A strip that sheds no wake (NOWAKE) closes its circulation on itself: as in the
            // steady solver, its last row states that the circulations sum to zero (the last
            // ring carries none) in place of flow tangency.
            closure[i] = st.sheds_wake ? 0 : 1;
        } else {
            panel_prev[i + 1] = static_cast<int>(i);
        }
        ring_area[i] = 0.5 * (c[2] - c[0]).cross(c[3] - c[1]).norm();
        centroid[i] = 0.25 * (c[0] + c[1] + c[2] + c[3]);
        // Hinge points at the control point's station.
        for (const PanelControl& pc : L.controls[i]) {
            double h = std::nan("");
            if (pc.control >= 0 && static_cast<std::size_t>(pc.control) < L.control_names.size())
                h = hinge_fraction(model, st,
                                   L.control_names[static_cast<std::size_t>(pc.control)]);
            const double xc = L.chord_fraction[i];
            const double chord_here = xc > 0.0 ? (cp[i].x() - st.le_mid.x()) / xc : st.chord;
            if (!std::isfinite(h)) {
                // Fallback: the leading point of the first panel of the strip that the control
                // moves, half-way between its bound point and the previous panel's control point.
                int f = static_cast<int>(i);
                while (f > st.first_panel) {
                    const auto& prev = L.controls[static_cast<std::size_t>(f - 1)];
                    if (std::none_of(prev.begin(), prev.end(), [&](const PanelControl& q) {
                            return q.control == pc.control;
                        }))
                        break;
                    --f;
                }
                const auto fi = static_cast<std::size_t>(f);
                const double xb = (mid[fi].x() - st.le_mid.x()) / chord_here;
                h = f > st.first_panel ? 0.5 * (xb + L.chord_fraction[fi - 1]) : 0.0;
            }
            hinge[i].push_back(Vector3d(st.le_mid.x() + h * chord_here, cp[i].y(), cp[i].z()));
        }
    }
    // Bound point k of a strip between control points k-1 and k (linear in x; the first from
    // control points 0 and 1).
    bound_from_cp.assign(n, Interpolation{});
    for (const Strip& S : L.strips)
        for (int k = 0; k < S.n_panels; ++k) {
            Interpolation& w = bound_from_cp[static_cast<std::size_t>(S.first_panel + k)];
            const int k0 = std::max(0, std::min(k - 1, S.n_panels - 2));
            const int k1 = std::min(k0 + 1, S.n_panels - 1);
            w.i0 = S.first_panel + k0;
            w.i1 = S.first_panel + k1;
            const double x0 = cp[static_cast<std::size_t>(w.i0)].x();
            const double x1 = cp[static_cast<std::size_t>(w.i1)].x();
            const double xb = mid[static_cast<std::size_t>(S.first_panel + k)].x();
            w.w1 = k1 != k0 && x1 != x0 ? (xb - x0) / (x1 - x0) : 0.0;
            w.w0 = 1.0 - w.w1;
        }
    strip_normal.resize(L.strips.size());
    for (std::size_t t = 0; t < L.strips.size(); ++t) {
        const Strip& S = L.strips[t];
        const Vector3d e = S.le_b - S.le_a;
        strip_normal[t] = Vector3d::UnitX().cross(Vector3d(0.0, e.y(), e.z()).normalized());
    }

    // Classes of field points: one per component, then the free wake's.
    std::vector<int> components;
    for (const Surface& S : model.surfaces) components.push_back(S.component);
    std::sort(components.begin(), components.end());
    components.erase(std::unique(components.begin(), components.end()), components.end());
    n_class = static_cast<int>(components.size()) + 1;
    free_class = n_class - 1;
    auto class_of_strip = [&](const Strip& st) {
        const int c = model.surfaces[static_cast<std::size_t>(st.surface)].component;
        return static_cast<int>(std::lower_bound(components.begin(), components.end(), c) -
                                components.begin());
    };
    panel_class.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        panel_class[i] = class_of_strip(L.strips[static_cast<std::size_t>(L.strip[i])]);
    // Squared cores of a column's segments for every class of field point.
    auto column_cores = [&](const std::vector<int>& col_strip) {
        std::vector<ArrayXd> c(static_cast<std::size_t>(n_class),
                               ArrayXd::Zero(static_cast<Index>(col_strip.size())));
        for (std::size_t e = 0; e < col_strip.size(); ++e) {
            const Strip& st = L.strips[static_cast<std::size_t>(col_strip[e])];
            const int own = class_of_strip(st);
            const double within = opt.core_within_component * st.width;
            const double across = opt.core_between_components * std::max(st.chord, 2.0 * st.width);
            for (int k = 0; k < n_class; ++k) {
                const double r = k == free_class ? opt.core_radius * cref
                                 : k == own      ? within
                                                 : across;
                c[static_cast<std::size_t>(k)][static_cast<Index>(e)] = r * r;
            }
        }
        return c;
    };

    // Chains and grids.
    const double tol = 1e-9 * std::max(1.0, cref);
    const auto chains = strip_chains(L, tol);
    struct Column {
        int grid, col;
    };
    std::vector<std::pair<std::vector<int>, Column>> placed;
    for (const auto& ch : chains) {
        const int depth = L.strips[static_cast<std::size_t>(ch.front())].n_panels;
        int gi = -1;
        for (std::size_t q = 0; q < grids.size(); ++q)
            if (grids[q].n_chord == depth) gi = static_cast<int>(q);
        if (gi < 0) {
            grids.push_back({});
            grids.back().n_chord = depth;
            gi = static_cast<int>(grids.size()) - 1;
        }
        LatticeGrid& G = grids[static_cast<std::size_t>(gi)];
        placed.push_back({ch, {gi, G.g.cols}});
        G.g.cols += static_cast<int>(ch.size()) + 1;
    }
    for (LatticeGrid& G : grids) {
        G.g.reserve(G.n_chord + 2, G.g.cols);
        G.g.rows = G.n_chord + 2;
        G.panel.assign(static_cast<std::size_t>((G.n_chord + 1) * G.g.cols), -1);
        G.point.assign(static_cast<std::size_t>((G.n_chord + 2) * G.g.cols), Vector3d::Zero());
        G.te.assign(static_cast<std::size_t>(G.g.cols), Vector3d::Zero());
        G.col_strip.assign(static_cast<std::size_t>(G.g.cols), 0);
    }
    std::vector<int> wake_col_strip;
    for (const auto& [ch, at] : placed) {
        LatticeGrid& G = grids[static_cast<std::size_t>(at.grid)];
        const int C = G.g.cols, nc = G.n_chord;
        const auto m = static_cast<int>(ch.size());
        const bool sheds = L.strips[static_cast<std::size_t>(ch.front())].sheds_wake;
        if (sheds) wake_cols += m + 1;
        for (int p = 0; p <= m; ++p) {
            const bool b_edge = p == m;  // the chain's last column: the b edge of its last strip
            const Strip& S = L.strips[static_cast<std::size_t>(
                ch[static_cast<std::size_t>(b_edge ? m - 1 : p)])];
            const int col = at.col + p;
            G.col_strip[static_cast<std::size_t>(col)] =
                ch[static_cast<std::size_t>(b_edge ? m - 1 : p)];
            for (int k = 0; k < nc; ++k) {
                const auto i = static_cast<std::size_t>(S.first_panel + k);
                G.point[static_cast<std::size_t>(k * C + col)] = b_edge ? L.b[i] : L.a[i];
                if (!b_edge) {
                    G.panel[static_cast<std::size_t>(k * C + col)] = static_cast<int>(i);
                }
            }
            const auto last = static_cast<std::size_t>(S.first_panel + nc - 1);
            if (!b_edge) G.panel[static_cast<std::size_t>(nc * C + col)] = static_cast<int>(last);
            const Vector3d te =
                b_edge ? trailing_edge(S.le_b, S.chord_b) : trailing_edge(S.le_a, S.chord_a);
            G.te[static_cast<std::size_t>(col)] = te;
            G.point[static_cast<std::size_t>(nc * C + col)] = te;
            G.point[static_cast<std::size_t>((nc + 1) * C + col)] = te;  // shed line: set_shed
            if (sheds) {
                wake_col_strip.push_back(G.col_strip[static_cast<std::size_t>(col)]);
                wake_trailing_edge.push_back(te);
                wake_te.push_back(b_edge ? -1 : static_cast<int>(last));
            }
        }
    }
    // Several components: the rings' sides keep their strips' cores (see Grid).
    split_sides = n_class > 2;
    auto left_of = [](std::vector<int> col_strip) {
        for (std::size_t e = col_strip.size(); e-- > 1;) col_strip[e] = col_strip[e - 1];
        return col_strip;
    };
    for (LatticeGrid& G : grids)
        G.g.set_cores(column_cores(G.col_strip), column_cores(left_of(G.col_strip)), split_sides,
                      G.n_chord + 2);
    wake_core = column_cores(wake_col_strip);
    wake_core_left = column_cores(left_of(wake_col_strip));
    Index most = 0;
    for (const LatticeGrid& G : grids) most = std::max(most, (G.g.block_rows() + 1) * G.g.cols);
    most = std::max(most, (std::max<Index>(1, block_points / std::max(1, wake_cols)) + 1) *
                              std::max(1, wake_cols));
    threads = opt.threads > 0 ? opt.threads
                              : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    scratch.resize(static_cast<std::size_t>(threads));
    for (Scratch& sc : scratch) sc.reserve(most);
}

void UnsteadySolver::Impl::set_shed(double distance, const Vector3d& dir) {
    // The lattice grids' last row and the wake's first row: the shed line, `distance` behind the
    // trailing edges along `dir`; then the stretched points, segment lengths and chordwise
    // segments.
    shed_distance = distance;
    shed_dir = dir;
    const Vector3d dx = distance * dir;
    for (LatticeGrid& G : grids)
        for (std::size_t e = 0; e < G.te.size(); ++e)
            G.point[static_cast<std::size_t>((G.n_chord + 1) * G.g.cols) + e] = G.te[e] + dx;
    wake_shed.resize(wake_trailing_edge.size());
    for (std::size_t e = 0; e < wake_shed.size(); ++e) wake_shed[e] = wake_trailing_edge[e] + dx;
    chord.clear();
    for (LatticeGrid& G : grids) {
        for (std::size_t j = 0; j < G.point.size(); ++j) {
            const Vector3d s = stretch(G.point[j], beta);
            G.g.x[static_cast<Index>(j)] = s.x();
            G.g.y[static_cast<Index>(j)] = s.y();
            G.g.z[static_cast<Index>(j)] = s.z();
        }
        G.g.update_lengths();
        G.g.update_cores();
        // Chordwise segments: (k, e) -> (k + 1, e), k < n_chord.
        const int C = G.g.cols;
        for (int k = 0; k < G.n_chord; ++k)
            for (int e = 0; e < C; ++e) {
                ChordSegment s;
                const Index j = static_cast<Index>(k) * C + e;
                s.left = e > 0 ? G.panel[static_cast<std::size_t>(j - 1)] : -1;
                s.right = G.panel[static_cast<std::size_t>(j)];
                if (s.left < 0 && s.right < 0) continue;
                // The last rings' sides are loaded up to the trailing edge (row n_chord) only:
                // their part behind it, to the shed line, is wake (as the steady solver's legs).
                const Vector3d& p1 = G.point[static_cast<std::size_t>(j)];
                const Vector3d& p2 = G.point[static_cast<std::size_t>(j + C)];
                s.mid = 0.5 * (p1 + p2);
                s.cls = panel_class[static_cast<std::size_t>(s.right >= 0 ? s.right : s.left)];
                s.l = p2 - p1;
                s.near = {s.left, s.right, -1, -1};
                if (k + 1 < G.n_chord) {
                    s.near[2] = e > 0 ? G.panel[static_cast<std::size_t>(j + C - 1)] : -1;
                    s.near[3] = G.panel[static_cast<std::size_t>(j + C)];
                }
                chord.push_back(s);
            }
    }
}

void UnsteadySolver::Impl::assemble() {
    // A(i, j): normal velocity at control point i (undeflected normal, as the steady solver) of
    // ring j at unit circulation, from the grid segments each ring shares with its neighbours.
    A.setZero(N, N);
    for (const LatticeGrid& G : grids) {
        const Grid& g = G.g;
        const Index C = g.cols;
        auto panel = [&](Index k, Index e) -> int {
            if (k < 0 || k >= G.ring_rows() || e < 0 || e >= C) return -1;
            return G.panel[static_cast<std::size_t>(k * C + e)];
        };
        for (int i = 0; i < N; ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const auto cls = static_cast<std::size_t>(panel_class[ii]);
            auto add = [&](int j, double w) {
                if (j >= 0) A(i, j) += w;
            };
            // The control point itself, then its mirror images (velocity reflected back).
            for (std::size_t im = 0; im <= images.size(); ++im) {
                const Image mirror = im == 0 ? Image{1.0, false, false} : images[im - 1];
                const Vector3d p = stretch(reflect_point(cp[ii], mirror), beta);
                const Vector3d nn = mirror.f * reflect_vector(n0[ii], mirror);
                for (Index k = 0; k <= G.ring_rows(); ++k)
                    for (Index e = 0; e < C; ++e) {
                        const Index j = k * C + e;
                        // (The trailing-edge row's spanwise segments carry nothing: the last
                        // ring continued on both sides.)
                        if (e + 1 < C && k != G.n_chord) {
                            Vector3d v =
                                cored_segment(p, g.point(j), g.point(j + 1), g.core[cls][e], tiny);
                            v.x() /= beta;
                            const double w = v.dot(nn);
                            add(panel(k, e), w);
                            add(panel(k - 1, e), -w);
                        }
                        if (k < G.ring_rows()) {
                            // Each ring's side with its own strip's core.
                            Vector3d v =
                                cored_segment(p, g.point(j), g.point(j + C), g.core[cls][e], tiny);
                            v.x() /= beta;
                            add(panel(k, e), -v.dot(nn));
                            if (e > 0) {
                                v = cored_segment(p, g.point(j), g.point(j + C),
                                                  g.core_left[cls][e], tiny);
                                v.x() /= beta;
                                add(panel(k, e - 1), v.dot(nn));
                            }
                        }
                    }
            }
        }
    }
    for (int i = 0; i < N; ++i)
        if (closure[static_cast<std::size_t>(i)]) {
            A.row(i).setZero();
            A(i, i) = 1.0;
        }
    lu.compute(A);  // a copy: A is kept for the steady start
}

void UnsteadySolver::Impl::build_lattice_influence() {
    // The sums of `induced(p, cls, true, ...)` (every lattice grid segment, images, x / beta)
    // written per ring: a spanwise segment (k, e) -> (k, e+1) carries ring(k, e) - ring(k-1, e),
    // a chordwise one (k, e) -> (k+1, e) ring(k, e-1) - ring(k, e), each with the cores the grid
    // kernel gives it (Grid: the column's core, or each side its own strip's with split sides).
    const Index M = N + static_cast<Index>(chord.size());
    const double bytes = 3.0 * static_cast<double>(M) * N * sizeof(double);
    if (bytes > lattice_matrix_bytes) {
        lattice_influence_t.resize(0, 0);
        return;
    }
    lattice_influence_t.setZero(N, 3 * M);
    parallel(M, [this](Index b, Index e, Scratch&) {
        for (Index q = b; q < e; ++q) {
            const auto qq = static_cast<std::size_t>(q < N ? q : q - N);
            const Vector3d& x = q < N ? mid[qq] : chord[qq].mid;
            const auto cls = static_cast<std::size_t>(q < N ? panel_class[qq] : chord[qq].cls);
            auto col = lattice_influence_t.middleCols(3 * q, 3);
            for (std::size_t im = 0; im <= images.size(); ++im) {
                const Image mirror = im == 0 ? Image{1.0, false, false} : images[im - 1];
                const Vector3d p = stretch(reflect_point(x, mirror), beta);
                auto seg = [&](const Vector3d& x1, const Vector3d& x2, double core2) {
                    Vector3d v = cored_segment(p, x1, x2, core2, tiny);
                    v.x() /= beta;
                    return Vector3d(mirror.f * reflect_vector(v, mirror));
                };
                for (const LatticeGrid& G : grids) {
                    const Grid& g = G.g;
                    const Index C = g.cols;
                    auto add = [&](Index k, Index c, const Vector3d& v) {
                        if (k < 0 || k >= G.ring_rows() || c < 0 || c >= C) return;
                        const int j = G.panel[static_cast<std::size_t>(k * C + c)];
                        if (j >= 0) col.row(j) += v.transpose();
                    };
                    for (Index k = 0; k <= G.ring_rows(); ++k)
                        for (Index c = 0; c < C; ++c) {
                            const Index j = k * C + c;
                            if (c + 1 < C && k != G.n_chord) {
                                const Vector3d v = seg(g.point(j), g.point(j + 1), g.core[cls][c]);
                                add(k, c, v);
                                add(k - 1, c, -v);
                            }
                            if (k < G.ring_rows()) {
                                const Vector3d v = seg(g.point(j), g.point(j + C), g.core[cls][c]);
                                add(k, c, -v);
                                add(k, c - 1,
                                    g.split ? seg(g.point(j), g.point(j + C), g.core_left[cls][c])
                                            : v);
                            }
                        }
                }
            }
        }
    });
}

void UnsteadySolver::Impl::pose_at(double t, Pose& p) const {
    const aero::MotionState s = motion.at(t);
    p.t = t;
    // From the motion frame to body axes (3-2-1): v_body = C v_motion.
    p.C = core::dcm_body_from_earth(s.euler);
    p.r_ref = Vector3d(s.position[0], s.position[1], s.position[2]);
    p.shift = v0 * (t - t0);
    const Vector3d v_motion =
        Vector3d(v0, 0.0, 0.0) + Vector3d(s.velocity[0], s.velocity[1], s.velocity[2]);
    const Vector3d uvw = p.C * v_motion;  // body axes
    p.airspeed = uvw.norm();
    p.alpha = std::atan2(uvw.z(), uvw.x());
    p.beta = p.airspeed > 0.0 ? std::asin(std::clamp(uvw.y() / p.airspeed, -1.0, 1.0)) : 0.0;
    p.vinf = -(D * uvw);
    p.omega = D * Vector3d(s.omega_body[0], s.omega_body[1], s.omega_body[2]);
    const auto nc = static_cast<Index>(L.control_names.size());
    p.delta.setZero(nc);
    p.delta_rate.setZero(nc);
    for (std::size_t k = 0; k < mode_control.size(); ++k) {
        const int c = mode_control[k];
        if (c < 0) continue;
        p.delta[c] = s.modes[k];
        p.delta_rate[c] = s.mode_rates[k];
    }
}

Vector3d UnsteadySolver::Impl::to_air(const Pose& p, const Vector3d& g) const {
    if (opt.wake == WakeModel::planar) return g;  // a planar wake is stored in geometry axes
    return p.r_ref + Vector3d(p.shift, 0.0, 0.0) +
           p.C.transpose() * (D * (g - model.reference.point));
}

void UnsteadySolver::Impl::wake_to_geometry(const Pose& p) {
    const Index n = static_cast<Index>(wake.rows) * wake_cols;
    // g = g_ref + D C (a - r_ref - shift x), then stretched (a planar wake: g = a).
    const bool planar = opt.wake == WakeModel::planar;
    const Matrix3d M = planar ? Matrix3d::Identity() : Matrix3d(D * p.C);
    const Vector3d o = planar ? Vector3d::Zero() : Vector3d(p.r_ref + Vector3d(p.shift, 0.0, 0.0));
    const Vector3d gr = planar ? Vector3d::Zero() : model.reference.point;
    for (Index j = 0; j < n; ++j) {
        const Vector3d a(ax[j] - o.x(), ay[j] - o.y(), az[j] - o.z());
        const Vector3d g = gr + M * a;
        wake.x[j] = g.x() / beta;
        wake.y[j] = g.y();
        wake.z[j] = g.z();
    }
    wake.update_lengths();
    wake.update_cores();
    const Vector3d dir = stretch(p.vinf.norm() > 0.0 ? p.vinf : Vector3d::UnitX(), beta);
    wake.update_strengths(truncated && opt.wake_tail, dir);
}

void UnsteadySolver::Impl::lattice_strengths(const VectorXd& g) {
    for (LatticeGrid& G : grids) {
        for (std::size_t r = 0; r < G.panel.size(); ++r) {
            const int i = G.panel[r];
            G.g.ring[static_cast<Index>(r)] = i >= 0 ? g[i] : 0.0;
        }
        G.g.update_strengths(false, Vector3d::UnitX());
    }
}

void UnsteadySolver::Impl::wake_velocities() {
    // Wake-induced velocity at the control points (boundary condition) and at the bound points
    // (loads): the O(N x wake) part of a step. At the bound points the near wake (the rows
    // within UnsteadyOptions::near_wake of the trailing edge) is summed exactly and the far
    // wake's smooth contribution interpolated along the chord from the control points.
    v_wake.setZero();
    if (wake.rows < 2) return;
    const Index R = wake.rows;
    const Index near = std::min<Index>(near_rows, R);
    parallel(N, [this, near, R](Index b, Index e, Scratch& s) {
        for (Index i = b; i < e; ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const int cls = panel_class[ii];
            const Vector3d v = induced(cp[ii], cls, false, s, 0, near);
            const Vector3d f = induced(cp[ii], cls, false, s, near, R);
            v_wake.col(i) = v + f;
            v_far.col(i) = f;
            v_wake.col(N + i) = induced(mid[ii], cls, false, s, 0, near);
        }
    });
    if (near < R)
        for (Index i = 0; i < N; ++i) {
            const Interpolation& w = bound_from_cp[static_cast<std::size_t>(i)];
            v_wake.col(N + i) += w.w0 * v_far.col(w.i0) + w.w1 * v_far.col(w.i1);
        }
}

void UnsteadySolver::Impl::kinematic_rhs(const Pose& p) {
    for (int i = 0; i < N; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        nrm[ii] = L.controls[ii].empty() ? n0[ii] : L.deflected_normal(i, p.delta);
        Vector3d v = kinematic(cp[ii]);
        if (opt.hinge_rate) {
            const auto& pcs = L.controls[ii];
            for (std::size_t m = 0; m < pcs.size(); ++m) {
                const double rate = pcs[m].gain * p.delta_rate[pcs[m].control];
                if (rate != 0.0) v -= rate * pcs[m].axis.cross(cp[ii] - hinge[ii][m]);
            }
        }
        rhs[i] = closure[ii] ? 0.0 : -v.dot(nrm[ii]) - v_wake.col(i).dot(n0[ii]);
    }
}

void UnsteadySolver::Impl::convect_free_wake() {
    // Velocity of every wake point at the current instant (lattice and wake induced, with the
    // vortex core), then an explicit Euler step in the still-air frame.
    const Index n = static_cast<Index>(wake.rows) * wake_cols;
    if (n == 0) return;
    const Matrix3d back = pose.C.transpose() * D;  // geometry -> still-air components
    parallel(n, [&](Index b, Index e, Scratch& s) {
        for (Index j = b; j < e; ++j) {
            const Vector3d p(wake.x[j] * beta, wake.y[j], wake.z[j]);
            const Vector3d v = induced(p, free_class, false, s) + induced(p, free_class, true, s);
            v_free.col(j) = back * v;
        }
    });
    ax.head(n) += dt * v_free.row(0).head(n).transpose().array();
    ay.head(n) += dt * v_free.row(1).head(n).transpose().array();
    az.head(n) += dt * v_free.row(2).head(n).transpose().array();
}

void UnsteadySolver::Impl::shed(const Pose& p) {
    // Rows move one place back (newest first); the oldest beyond max_rows is dropped.
    const int C = wake_cols;
    if (C == 0) return;
    const int rings = std::min(wake.rows, max_rows);       // ring rows after shedding
    const Index keep_pts = static_cast<Index>(rings) * C;  // old points kept: rows 0 .. rings-1
    if (wake.rows > max_rows) truncated = true;
    std::copy_backward(ax.data(), ax.data() + keep_pts, ax.data() + keep_pts + C);
    std::copy_backward(ay.data(), ay.data() + keep_pts, ay.data() + keep_pts + C);
    std::copy_backward(az.data(), az.data() + keep_pts, az.data() + keep_pts + C);
    const Index keep_rings = static_cast<Index>(rings - 1) * C;
    if (keep_rings > 0)
        std::copy_backward(wake.ring.data(), wake.ring.data() + keep_rings,
                           wake.ring.data() + keep_rings + C);
    for (int e = 0; e < C; ++e) {
        const auto ee = static_cast<std::size_t>(e);
        const Vector3d a = to_air(p, wake_shed[ee]);
        ax[e] = a.x();
        ay[e] = a.y();
        az[e] = a.z();
        wake.ring[e] = wake_te[ee] >= 0 ? gamma[wake_te[ee]] : 0.0;
    }
    wake.rows = rings + 1;
}

void UnsteadySolver::Impl::start_impulsive() {
    wake.rows = wake_cols > 0 ? 1 : 0;
    truncated = false;
    for (int e = 0; e < wake_cols; ++e) {
        const Vector3d a = to_air(pose, wake_shed[static_cast<std::size_t>(e)]);
        ax[e] = a.x();
        ay[e] = a.y();
        az[e] = a.z();
    }
    wake_to_geometry(pose);
    v_wake.setZero();
    kinematic_rhs(pose);
    gamma = lu.solve(rhs);
}

void UnsteadySolver::Impl::start_steady() {
    // A wake of max_rows rows laid straight back along the path (the body's velocity at t0; the
    // rotation is not integrated backwards; a planar wake along body x), every row carrying its
    // strip's trailing-edge circulation: the steady problem (A + W) G = b, W the straight wakes of
    // the trailing-edge rings, solved once with its own factorisation.
    const int C = wake_cols;
    v_wake.setZero();
    kinematic_rhs(pose);
    if (C == 0) {
        wake.rows = 0;
        gamma = lu.solve(rhs);
        return;
    }
    const double speed = pose.vinf.norm();
    const bool planar = opt.wake == WakeModel::planar;
    const Vector3d d =
        speed > 0.0 && !planar ? Vector3d(pose.vinf / speed) : Vector3d(Vector3d::UnitX());
    const double length = max_rows * dt * speed;
    const bool tail = opt.wake_tail;
    const Vector3d ds = stretch(d, beta).normalized();
    MatrixXd M = A;
    for (int e = 0; e + 1 < C; ++e) {
        const auto ee = static_cast<std::size_t>(e);
        const int j = wake_te[ee];
        if (j < 0) continue;
        const Vector3d sa = wake_shed[ee];
        const Vector3d sb = wake_shed[ee + 1];
        const Vector3d a0 = stretch(sa, beta), b0 = stretch(sb, beta);
        const Vector3d a1 = stretch(sa + length * d, beta), b1 = stretch(sb + length * d, beta);
        for (int i = 0; i < N; ++i) {
            const auto ii = static_cast<std::size_t>(i);
            if (closure[ii]) continue;
            const auto k = static_cast<std::size_t>(panel_class[ii]);
            const double cs = wake_core[k][e], ca = cs, cb = cs;  // the strip's own core
            for (std::size_t im = 0; im <= images.size(); ++im) {
                const Image mirror = im == 0 ? Image{1.0, false, false} : images[im - 1];
                const Vector3d p = stretch(reflect_point(cp[ii], mirror), beta);
                Vector3d v = cored_segment(p, a0, b0, cs, tiny) +
                             cored_segment(p, b0, b1, cb, tiny) +
                             cored_segment(p, a1, a0, ca, tiny);
                if (tail)
                    v += cored_semi_infinite(p, b1, ds, cb, tiny) -
                         cored_semi_infinite(p, a1, ds, ca, tiny);
                else
                    v += cored_segment(p, b1, a1, cs, tiny);
                v.x() /= beta;
                M(i, j) += mirror.f * reflect_vector(v, mirror).dot(n0[ii]);
            }
        }
    }
    detail::DenseLU steady_lu;
    steady_lu.compute(std::move(M));
    gamma = steady_lu.solve(rhs);
    // The wake itself.
    const Vector3d step_air = planar ? Vector3d(dt * speed * Vector3d::UnitX())
                                     : Vector3d(pose.C.transpose() * (D * (dt * pose.vinf)));
    wake.rows = max_rows + 1;
    for (int r = 0; r <= max_rows; ++r)
        for (int e = 0; e < C; ++e) {
            const Index j = static_cast<Index>(r) * C + e;
            const Vector3d a = to_air(pose, wake_shed[static_cast<std::size_t>(e)]) + r * step_air;
            ax[j] = a.x();
            ay[j] = a.y();
            az[j] = a.z();
            if (r < max_rows) {
                const int te = wake_te[static_cast<std::size_t>(e)];
                wake.ring[j] = te >= 0 ? gamma[te] : 0.0;
            }
        }
    truncated = true;
    wake_to_geometry(pose);
}

void UnsteadySolver::Impl::loads() {
    // Kutta-Joukowski on every lattice segment with its local velocity, plus rho dG/dt A n.
    // Lattice velocities at the bound points, and at the chordwise segments when their loads
    // take the induced velocity (UnsteadyOptions::chordwise_induced).
    const Index n_load = N + (opt.chordwise_induced ? static_cast<Index>(chord.size()) : 0);
    if (lattice_influence_t.size() > 0) {
        // Rigid lattice: one product with the influence built at `start`.
        parallel(n_load, [this](Index b, Index e, Scratch&) {
            Eigen::Map<VectorXd> v(v_lattice.data() + 3 * b, 3 * (e - b));
            v.noalias() = lattice_influence_t.middleCols(3 * b, 3 * (e - b)).transpose() * gamma;
        });
    } else {
        lattice_strengths(gamma);
        parallel(n_load, [this](Index b, Index e, Scratch& s) {
            for (Index i = b; i < e; ++i) {
                const auto ii = static_cast<std::size_t>(i < N ? i : i - N);
                const Vector3d& p = i < N ? mid[ii] : chord[ii].mid;
                const int cls = i < N ? panel_class[ii] : chord[ii].cls;
                v_lattice.col(i) = induced(p, cls, true, s);
            }
        });
    }
    const Vector3d& ref = model.reference.point;
    Vector3d F_kj = Vector3d::Zero(), M_kj = Vector3d::Zero();
    Vector3d F_t = Vector3d::Zero(), M_t = Vector3d::Zero();
    const bool span = opt.span_loading;
    if (span) current.strips.assign(L.strips.size(), StripLoad{});
    for (int i = 0; i < N; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const int prev = panel_prev[ii];
        const double s = gamma[i] - (prev >= 0 ? gamma[prev] : 0.0);
        const Vector3d v = kinematic(mid[ii]) + v_lattice.col(i) + v_wake.col(N + i);
        const Vector3d f = s * v.cross(lvec[ii]);
        const Vector3d ft = dgdt[i] * ring_area[ii] * nrm[ii];
        F_kj += f;
        M_kj += (mid[ii] - ref).cross(f);
        F_t += ft;
        M_t += (centroid[ii] - ref).cross(ft);
        if (span) {
            StripLoad& sl = current.strips[static_cast<std::size_t>(L.strip[ii])];
            sl.force += f + ft;
        }
    }
    for (std::size_t q = 0; q < chord.size(); ++q) {
        const ChordSegment& c = chord[q];
        const double s =
            (c.left >= 0 ? gamma[c.left] : 0.0) - (c.right >= 0 ? gamma[c.right] : 0.0);
        if (s == 0.0) continue;
        Vector3d vw = Vector3d::Zero();
        int nw = 0;
        for (const int p : c.near)
            if (p >= 0) {
                vw += v_wake.col(N + p);
                ++nw;
            }
        if (nw > 0) vw /= nw;
        // The onset flow only (the steady solver's and AVL's legs), or with the induced velocity.
        const Vector3d v =
            opt.chordwise_induced
                ? Vector3d(kinematic(c.mid) + v_lattice.col(N + static_cast<Index>(q)) + vw)
                : kinematic(c.mid);
        const Vector3d f = s * v.cross(c.l);
        F_kj += f;
        M_kj += (c.mid - ref).cross(f);
        if (span) {
            const int sides = (c.left >= 0 ? 1 : 0) + (c.right >= 0 ? 1 : 0);
            for (const int p : {c.left, c.right})
                if (p >= 0)
                    current.strips[static_cast<std::size_t>(L.strip[static_cast<std::size_t>(p)])]
                        .force += f / sides;
        }
    }
    if (model.y_symmetry == 1) {
        // Symmetric image (AVL IYsym = 1): the lattice is one half of the aircraft, whose loads
        // double the symmetric ones and cancel the antisymmetric ones, as in the steady solver.
        for (Vector3d* F : {&F_kj, &F_t}) *F = Vector3d(2.0 * F->x(), 0.0, 2.0 * F->z());
        for (Vector3d* M : {&M_kj, &M_t}) *M = Vector3d(0.0, 2.0 * M->y(), 0.0);
    }
    // Coefficients (rho = 1): geometry -> body axes as the steady solver.
    const Reference& R = model.reference;
    const double V = pose.airspeed > 0.0 ? pose.airspeed : v0;
    const double qS = 0.5 * V * V * R.area;
    auto body_of = [&](const Vector3d& Fg, const Vector3d& Mg) {
        const Vector3d F = core::body_from_geometry(Fg), M = core::body_from_geometry(Mg);
        aero::BodyCoefficients<double> b;
        b.CX = F.x() / qS;
        b.CY = F.y() / qS;
        b.CZ = F.z() / qS;
        b.Cl = M.x() / (qS * R.span);
        b.Cm = M.y() / (qS * R.chord);
        b.Cn = M.z() / (qS * R.span);
        return b;
    };
    const auto bk = body_of(F_kj, M_kj), bt = body_of(F_t, M_t);
    UnsteadyStep& o = current;
    o.index = step;
    o.t = pose.t;
    o.alpha = pose.alpha;
    o.beta = pose.beta;
    o.airspeed = pose.airspeed;
    o.deflection = pose.delta;
    o.wake_rows = std::max(0, wake.rows - 1);
    o.body.CX = bk.CX + bt.CX;
    o.body.CY = bk.CY + bt.CY;
    o.body.CZ = bk.CZ + bt.CZ;
    o.body.Cl = bk.Cl + bt.Cl;
    o.body.Cm = bk.Cm + bt.Cm;
    o.body.Cn = bk.Cn + bt.Cn;
    const auto wk = aero::wind_from_body(bk.CX, bk.CY, bk.CZ, pose.alpha, pose.beta);
    const auto wt = aero::wind_from_body(bt.CX, bt.CY, bt.CZ, pose.alpha, pose.beta);
    o.CL_circulatory = wk.CL;
    o.CD_circulatory = wk.CD;
    o.CL_added_mass = wt.CL;
    o.CD_added_mass = wt.CD;
    o.CL = wk.CL + wt.CL;
    o.CY = wk.CY + wt.CY;
    const double cdp = model.profile_drag;
    o.CD = wk.CD + wt.CD + cdp;
    if (cdp != 0.0) {
        const double ca = std::cos(pose.alpha), sa = std::sin(pose.alpha);
        const double cb = std::cos(pose.beta), sb = std::sin(pose.beta);
        o.body.CX -= cdp * ca * cb;
        o.body.CY -= cdp * sb;
        o.body.CZ -= cdp * sa * cb;
    }
    if (span) {
        const double q = 0.5 * V * V;
        for (std::size_t t = 0; t < L.strips.size(); ++t) {
            const Strip& S = L.strips[t];
            StripLoad& sl = o.strips[t];
            sl.force /= q;
            const int te = S.first_panel + S.n_panels - 1;
            sl.circulation = gamma[te] / V;
            sl.cl = sl.force.dot(strip_normal[t]) / S.area;
        }
    }
}

UnsteadySolver::UnsteadySolver(const Model& model, Lattice lattice, UnsteadyOptions options)
    : impl_(std::make_unique<Impl>(model, std::move(lattice), std::move(options))) {}
UnsteadySolver::~UnsteadySolver() = default;
UnsteadySolver::UnsteadySolver(UnsteadySolver&&) noexcept = default;
UnsteadySolver& UnsteadySolver::operator=(UnsteadySolver&&) noexcept = default;

const UnsteadyStep& UnsteadySolver::start(const aero::Motion& motion) {
    Impl& m = *impl_;
    m.started = false;
    motion.validate("vlm unsteady: motion");
    if (m.opt.speed)
        m.v0 = *m.opt.speed;
    else if (motion.metadata.v0)
        m.v0 = *motion.metadata.v0;
    else
        throw InputError(
            "vlm unsteady: no free-stream speed; set UnsteadyOptions::speed or the motion's v0 "
            "metadata");
    if (!(m.v0 > 0.0 && std::isfinite(m.v0)))
        throw InputError(fmt::format("vlm unsteady: free-stream speed {} m/s; expected > 0", m.v0));
    int depth = 1;
    for (const Strip& s : m.L.strips) depth = std::max(depth, s.n_panels);
    m.dt = m.opt.dt > 0.0 ? m.opt.dt : m.cref / (depth * m.v0);
    m.t0 = motion.t.front();
    const double duration = motion.t.back() - m.t0;
    m.n_steps = static_cast<int>(std::floor(duration / m.dt + 1e-9));
    if (m.n_steps > 100000000)
        throw InputError(fmt::format(
            "vlm unsteady: {} time steps of {} s over the motion; expected fewer than 1e8",
            m.n_steps, m.dt));
    const double rows = m.opt.wake_rows > 0
                            ? m.opt.wake_rows
                            : std::ceil(m.opt.wake_length * m.cref / (m.v0 * m.dt) - 1e-9);
    if (!(rows >= 1.0 && rows <= 1e6))
        throw InputError(fmt::format(
            "vlm unsteady: {} wake rows (wake_length {} chords, v0 dt {} m); expected 1 to 1e6",
            rows, m.opt.wake_length, m.v0 * m.dt));
    m.max_rows = static_cast<int>(rows);
    m.near_rows =
        static_cast<Index>(std::ceil(m.opt.near_wake * m.cref / (m.v0 * m.dt) - 1e-9)) + 1;
    // Control modes -> lattice controls.
    m.mode_control.assign(motion.mode_names.size(), -1);
    std::string missing;
    for (std::size_t k = 0; k < motion.mode_names.size(); ++k) {
        m.mode_control[k] = m.L.control_index(motion.mode_names[k]);
        if (m.mode_control[k] >= 0) continue;
        const auto& col = motion.modes[k];
        if (std::any_of(col.begin(), col.end(), [](double v) { return v != 0.0; }))
            missing += (missing.empty() ? "" : ", ") + motion.mode_names[k];
    }
    if (!missing.empty() && !m.opt.ignore_missing_controls)
        throw InputError(fmt::format(
            "vlm unsteady: motion mode(s) {} not among the lattice's controls ({}); expected a "
            "control of that name, or set ignore_missing_controls",
            missing,
            m.L.control_names.empty() ? std::string("none")
                                      : fmt::format("{}", fmt::join(m.L.control_names, ", "))));
    m.motion = motion;
    // The shed line: shed_offset v0 dt behind the trailing edges along the free stream of the
    // first instant (the direction the wake leaves in, so that a steady run has the geometry of
    // the steady solver's legs along the free stream); along body x for the planar wake. The
    // influence matrix depends on it: built and factorised again only when it changes.
    {
        Pose p0;
        m.pose_at(m.t0, p0);
        const double speed = p0.vinf.norm();
        const Vector3d dir = m.opt.wake != WakeModel::planar && speed > 0.0 && p0.vinf.x() > 0.0
                                 ? Vector3d(p0.vinf / speed)
                                 : Vector3d(Vector3d::UnitX());
        const double shed = m.opt.shed_offset * m.v0 * m.dt;
        if (shed != m.shed_distance || dir != m.shed_dir) {
            m.set_shed(shed, dir);
            m.assemble();
            m.build_lattice_influence();
        }
    }
    // Storage for the run (no allocation in the steps).
    const int C = m.wake_cols;
    m.wake.reserve(m.max_rows + 2, C);
    m.wake.set_cores(m.wake_core, m.wake_core_left, m.split_sides, m.max_rows + 2);
    m.ax.setZero(static_cast<Index>(m.max_rows + 2) * C);
    m.ay.setZero(m.ax.size());
    m.az.setZero(m.ax.size());
    m.wake.rows = 0;
    m.rhs.setZero(m.N);
    m.dgdt.setZero(m.N);
    m.nrm = m.n0;
    m.v_wake.setZero(3, 2 * m.N);
    m.v_far.setZero(3, m.N);
    m.v_lattice.setZero(3, m.N + static_cast<Index>(m.chord.size()));
    if (m.opt.wake == WakeModel::free) m.v_free.setZero(3, m.ax.size());
    m.step = 0;
    m.pose_at(m.t0, m.pose);
    if (m.opt.start == StartMode::steady)
        m.start_steady();
    else
        m.start_impulsive();
    m.gamma1 = m.gamma;
    m.gamma2 = m.gamma;
    m.dgdt.setZero();
    m.wake_velocities();
    m.loads();
    m.started = true;
    return m.current;
}

bool UnsteadySolver::finished() const {
    return !impl_->started || impl_->step >= impl_->n_steps;
}

int UnsteadySolver::n_steps() const {
    return impl_->n_steps;
}

const UnsteadyStep& UnsteadySolver::step() {
    Impl& m = *impl_;
    if (!m.started) throw InputError("vlm unsteady: step() before start()");
    if (m.step >= m.n_steps)
        throw InputError(fmt::format(
            "vlm unsteady: step {} would pass the motion's end at {} s; expected at most {} steps",
            m.step + 1, m.motion.t.back(), m.n_steps));
    // 1. The wake moves: free, with the velocity at the current instant; planar, straight aft
    // in body axes at the airspeed; prescribed, not at all in the still air where it is kept.
    if (m.opt.wake == WakeModel::free && m.wake.rows > 1) {
        m.lattice_strengths(m.gamma);
        m.convect_free_wake();
    }
    if (m.opt.wake == WakeModel::planar)
        m.ax.head(static_cast<Index>(m.wake.rows) * m.wake_cols) += m.pose.airspeed * m.dt;
    // 2. The body moves; 3. the trailing edges shed the circulation they had.
    ++m.step;
    m.pose_at(m.t0 + m.step * m.dt, m.pose);
    m.shed(m.pose);
    m.wake_to_geometry(m.pose);
    // 4. Wake velocity on the lattice, boundary condition, one back substitution.
    m.wake_velocities();
    m.kinematic_rhs(m.pose);
    m.gamma2.swap(m.gamma1);
    m.gamma1.swap(m.gamma);
    m.gamma = m.lu.solve(m.rhs);
    // 5. dG/dt: second-order backward difference once two earlier levels exist.
    if (m.step >= 2 || m.opt.start == StartMode::steady)
        m.dgdt = (3.0 * m.gamma - 4.0 * m.gamma1 + m.gamma2) / (2.0 * m.dt);
    else
        m.dgdt = (m.gamma - m.gamma1) / m.dt;
    m.loads();
    return m.current;
}

namespace {

/// Magic of a saved run state (and its layout version).
constexpr std::string_view state_magic = "MANTA-UVLM-STATE-1";

/// Appends raw values to a byte string.
struct Writer {
    std::string& s;
    template <class T>
    void put(const T& v) {
        s.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    void array(const double* p, Index n) {
        put(static_cast<std::int64_t>(n));
        if (n > 0)
            s.append(reinterpret_cast<const char*>(p),
                     static_cast<std::size_t>(n) * sizeof(double));
    }
};

/// Reads raw values back; InputError on a truncated state.
struct Reader {
    std::string_view s;
    std::size_t pos = 0;
    void need(std::size_t n) const {
        if (s.size() - pos < n)
            throw InputError(fmt::format(
                "vlm unsteady: saved run state truncated at byte {} of {}; expected {} more bytes",
                pos, s.size(), n));
    }
    template <class T>
    T get() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, s.data() + pos, sizeof v);
        pos += sizeof v;
        return v;
    }
    void array(double* p, Index capacity, Index& n) {
        const auto m = get<std::int64_t>();
        if (m < 0 || m > capacity)
            throw InputError(fmt::format(
                "vlm unsteady: saved run state holds an array of {} values where this run has "
                "room for {}; expected a state of the same lattice and settings",
                m, capacity));
        need(static_cast<std::size_t>(m) * sizeof(double));
        if (m > 0) std::memcpy(p, s.data() + pos, static_cast<std::size_t>(m) * sizeof(double));
        pos += static_cast<std::size_t>(m) * sizeof(double);
        n = static_cast<Index>(m);
    }
};

}  // namespace

std::string UnsteadySolver::save_state() const {
    const Impl& m = *impl_;
    if (!m.started) throw InputError("vlm unsteady: save_state() before start()");
    std::string s(state_magic);
    Writer w{s};
    w.put(static_cast<std::int64_t>(m.N));
    w.put(static_cast<std::int64_t>(m.wake_cols));
    w.put(static_cast<std::int64_t>(m.max_rows));
    w.put(m.dt);
    w.put(m.v0);
    w.put(m.t0);
    w.put(static_cast<std::int64_t>(m.n_steps));
    w.put(static_cast<std::int64_t>(m.step));
    w.put(static_cast<std::int64_t>(m.wake.rows));
    w.put(static_cast<std::uint8_t>(m.truncated ? 1 : 0));
    const Index np = static_cast<Index>(m.wake.rows) * m.wake_cols;
    w.array(m.ax.data(), np);
    w.array(m.ay.data(), np);
    w.array(m.az.data(), np);
    w.array(m.wake.ring.data(), static_cast<Index>(std::max(0, m.wake.rows - 1)) * m.wake_cols);
    for (const VectorXd* v : {&m.gamma, &m.gamma1, &m.gamma2, &m.dgdt})
        w.array(v->data(), v->size());
    return s;
}

const UnsteadyStep& UnsteadySolver::restore_state(const aero::Motion& motion,
                                                  std::string_view state) {
    if (state.substr(0, state_magic.size()) != state_magic)
        throw InputError(
            fmt::format("vlm unsteady: saved run state does not start with '{}'", state_magic));
    start(motion);
    Impl& m = *impl_;
    m.started = false;
    Reader r{state, state_magic.size()};
    const auto n = r.get<std::int64_t>();
    const auto cols = r.get<std::int64_t>();
    const auto rows = r.get<std::int64_t>();
    const auto dt = r.get<double>();
    const auto v0 = r.get<double>();
    const auto t0 = r.get<double>();
    const auto n_steps = r.get<std::int64_t>();
    if (n != m.N || cols != m.wake_cols || rows != m.max_rows || dt != m.dt || v0 != m.v0 ||
        t0 != m.t0 || n_steps != m.n_steps)
        throw InputError(fmt::format(
            "vlm unsteady: saved run state of {} panels, {} wake columns, {} wake rows, dt {} s, "
            "v0 {} m/s, t0 {} s, {} steps; this run has {}, {}, {}, {} s, {} m/s, {} s, {}",
            n, cols, rows, dt, v0, t0, n_steps, m.N, m.wake_cols, m.max_rows, m.dt, m.v0, m.t0,
            m.n_steps));
    const auto step = r.get<std::int64_t>();
    const auto wake_rows = r.get<std::int64_t>();
    if (step < 0 || step > m.n_steps || wake_rows < 0 || wake_rows > m.max_rows + 1)
        throw InputError(fmt::format(
            "vlm unsteady: saved run state at step {} with {} wake rows; expected 0 to {} steps "
            "and at most {} rows",
            step, wake_rows, m.n_steps, m.max_rows + 1));
    m.step = static_cast<int>(step);
    m.wake.rows = static_cast<int>(wake_rows);
    m.truncated = r.get<std::uint8_t>() != 0;
    Index got = 0;
    const Index np = static_cast<Index>(m.wake.rows) * m.wake_cols;
    auto exact = [&](Index want, const char* what) {
        if (got != want)
            throw InputError(
                fmt::format("vlm unsteady: saved run state holds {} values of {}; expected {}", got,
                            what, want));
    };
    r.array(m.ax.data(), m.ax.size(), got);
    exact(np, "wake x");
    r.array(m.ay.data(), m.ay.size(), got);
    exact(np, "wake y");
    r.array(m.az.data(), m.az.size(), got);
    exact(np, "wake z");
    r.array(m.wake.ring.data(), m.wake.ring.size(), got);
    exact(static_cast<Index>(std::max(0, m.wake.rows - 1)) * m.wake_cols, "wake circulations");
    for (VectorXd* v : {&m.gamma, &m.gamma1, &m.gamma2, &m.dgdt}) {
        v->resize(m.N);
        r.array(v->data(), m.N, got);
        exact(m.N, "lattice circulations");
    }
    if (r.pos != state.size())
        throw InputError(
            fmt::format("vlm unsteady: saved run state has {} bytes after its end; expected none",
                        state.size() - r.pos));
    // The derived state, as the step that reached it computed it.
    m.pose_at(m.t0 + m.step * m.dt, m.pose);
    m.wake_to_geometry(m.pose);
    m.wake_velocities();
    m.kinematic_rhs(m.pose);
    m.loads();
    m.started = true;
    return m.current;
}

UnsteadyHistory UnsteadySolver::run(const aero::Motion& motion, const Progress& progress) {
    UnsteadyHistory h;
    start(motion);
    h.dt = impl_->dt;
    h.speed = impl_->v0;
    h.mach = impl_->mach;
    h.max_wake_rows = impl_->max_rows;
    h.steps.reserve(static_cast<std::size_t>(impl_->n_steps) + 1);
    h.steps.push_back(impl_->current);
    if (progress) progress(*this);
    while (!finished()) {
        h.steps.push_back(step());
        if (progress) progress(*this);
    }
    return h;
}

const UnsteadyStep& UnsteadySolver::current() const {
    return impl_->current;
}
const Lattice& UnsteadySolver::lattice() const {
    return impl_->L;
}
const UnsteadyOptions& UnsteadySolver::options() const {
    return impl_->opt;
}
double UnsteadySolver::dt() const {
    return impl_->dt;
}
double UnsteadySolver::speed() const {
    return impl_->v0;
}
double UnsteadySolver::mach() const {
    return impl_->mach;
}
int UnsteadySolver::max_wake_rows() const {
    return impl_->max_rows;
}
const VectorXd& UnsteadySolver::gamma() const {
    return impl_->gamma;
}

UnsteadyWake UnsteadySolver::wake() const {
    const Impl& m = *impl_;
    UnsteadyWake w;
    w.t = m.pose.t;
    w.cols = m.wake_cols;
    w.rows = std::max(0, m.wake.rows - 1);
    w.tail = m.wake.tail;
    const Index np = static_cast<Index>(m.wake.rows) * m.wake_cols;
    w.points.reserve(static_cast<std::size_t>(np));
    for (Index j = 0; j < np; ++j)
        w.points.emplace_back(m.wake.x[j] * m.beta, m.wake.y[j], m.wake.z[j]);
    const Index nr = static_cast<Index>(w.rows) * w.cols;
    w.gamma.assign(m.wake.ring.data(), m.wake.ring.data() + nr);
    w.ring.assign(static_cast<std::size_t>(w.cols), 0);
    for (int e = 0; e < w.cols; ++e)
        w.ring[static_cast<std::size_t>(e)] = m.wake_te[static_cast<std::size_t>(e)] >= 0;
    w.lattice_gamma = m.gamma;
    w.shed_distance = m.shed_distance;
    w.shed_direction = m.shed_dir;
    return w;
}

void write_vtu(const std::filesystem::path& path, const Lattice& lattice,
               const UnsteadyWake& wake) {
    const int N = lattice.size();
    if (wake.lattice_gamma.size() != 0 && wake.lattice_gamma.size() != N)
        throw InputError(
            fmt::format("vlm write_vtu '{}': {} lattice circulations for a lattice of {} panels",
                        path.string(), wake.lattice_gamma.size(), N));
    const auto np_wake =
        static_cast<std::size_t>(wake.rows + 1) * static_cast<std::size_t>(wake.cols);
    if (wake.cols > 0 && (wake.points.size() != np_wake ||
                          wake.gamma.size() != static_cast<std::size_t>(wake.rows * wake.cols) ||
                          wake.ring.size() != static_cast<std::size_t>(wake.cols)))
        throw InputError(fmt::format(
            "vlm write_vtu '{}': wake of {} x {} rings with {} points; inconsistent sizes",
            path.string(), wake.rows, wake.cols, wake.points.size()));
    std::vector<std::array<std::size_t, 4>> cells;
    std::vector<double> g;
    std::vector<int> kind;
    std::vector<Vector3d> pts;
    for (int i = 0; i < N; ++i) {
        const auto c = ring_corners(lattice, i, wake.shed_distance, wake.shed_direction);
        const std::size_t b = pts.size();
        pts.insert(pts.end(), c.begin(), c.end());
        cells.push_back({b, b + 1, b + 2, b + 3});
        g.push_back(wake.lattice_gamma.size() == N ? wake.lattice_gamma[i] : 0.0);
        kind.push_back(0);
    }
    if (wake.cols > 0) {
        const std::size_t base = pts.size();
        pts.insert(pts.end(), wake.points.begin(), wake.points.end());
        const auto C = static_cast<std::size_t>(wake.cols);
        for (std::size_t r = 0; r < static_cast<std::size_t>(wake.rows); ++r)
            for (std::size_t e = 0; e + 1 < C; ++e) {
                if (!wake.ring[e]) continue;
                const std::size_t j = base + r * C + e;
                cells.push_back({j, j + 1, j + C + 1, j + C});
                g.push_back(wake.gamma[r * C + e]);
                kind.push_back(1);
            }
    }
    std::string s;
    auto out = std::back_inserter(s);
    fmt::format_to(out,
                   "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
                   "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" "
                   "NumberOfCells=\"{}\">\n",
                   pts.size(), cells.size());
    fmt::format_to(out,
                   "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
                   "format=\"ascii\">\n");
    for (const Vector3d& p : pts)
        fmt::format_to(out, "{:.10g} {:.10g} {:.10g}\n", p.x(), p.y(), p.z());
    fmt::format_to(out,
                   "</DataArray>\n</Points>\n<Cells>\n"
                   "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for (const auto& c : cells) fmt::format_to(out, "{} {} {} {}\n", c[0], c[1], c[2], c[3]);
    fmt::format_to(out,
                   "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for (std::size_t q = 0; q < cells.size(); ++q) fmt::format_to(out, "{}\n", 4 * (q + 1));
    fmt::format_to(out,
                   "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (std::size_t q = 0; q < cells.size(); ++q) fmt::format_to(out, "9\n");
    fmt::format_to(out,
                   "</DataArray>\n</Cells>\n<CellData Scalars=\"gamma\">\n"
                   "<DataArray type=\"Float64\" Name=\"gamma\" format=\"ascii\">\n");
    for (const double v : g) fmt::format_to(out, "{:.10g}\n", v);
    fmt::format_to(out,
                   "</DataArray>\n<DataArray type=\"Int32\" Name=\"wake\" format=\"ascii\">\n");
    for (const int v : kind) fmt::format_to(out, "{}\n", v);
    fmt::format_to(out, "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    core::write_file_atomic(path, s);
}

}  // namespace manta::vlm
