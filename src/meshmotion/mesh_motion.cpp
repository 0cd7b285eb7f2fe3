/// @file mesh_motion.cpp
/// MeshMotion (mesh_motion.hpp): rigid pose, control-surface fields with their blend, greedy
/// reduction and inverse-distance weighting into the volume, per-step deformation and checks.

#include "manta/meshmotion/mesh_motion.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"

namespace manta::meshmotion {

using Eigen::ArrayXd;
using Eigen::Matrix3d;
using Eigen::Matrix3Xd;
using Eigen::Vector3d;
using mesh::CellType;
using mesh::Index;

namespace {

using Clock = std::chrono::steady_clock;

/// Geometry (mesh) axes <-> body axes, a rotation by pi about y: v_body = D v_geometry; the same
/// matrix turns motion-frame components into the flow frame's mesh-like axes.
const Matrix3d D = core::dcm_body_from_geometry();

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string text(const Vector3d& v) {
    return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x(), v.y(), v.z());
}

/// C1 step from 0 at u <= 0 to 1 at u >= 1: 3u^2 - 2u^3.
double smoothstep(double u) {
    if (u <= 0.0) return 0.0;
    if (u >= 1.0) return 1.0;
    return u * u * (3.0 - 2.0 * u);
}

/// The cut-off's decay: (1 - (rho / R)^2)^2 for rho < R, else 0 (C1 at R, 1 - O(rho^2) near 0).
double decay(double rho, double R) {
    if (rho >= R) return 0.0;
    const double u = rho / R;
    const double v = 1.0 - u * u;
    return v * v;
}

/// Cross-product matrix: cross_matrix(e) v = e x v.
Matrix3d cross_matrix(const Vector3d& e) {
    Matrix3d m;
    m << 0.0, -e.z(), e.y(),  //
        e.z(), 0.0, -e.x(),   //
        -e.y(), e.x(), 0.0;
    return m;
}

/// Distance from p to the segment [a, b] (a != b).
double segment_distance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
    const Vector3d ab = b - a;
    const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (p - (a + s * ab)).norm();
}

/// Distance from p to the axis-aligned box [lo, hi] (0 inside).
double box_distance(const Vector3d& p, const Vector3d& lo, const Vector3d& hi) {
    return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).norm();
}

/// Number of sub-tetrahedra of the validity check: the tetrahedron itself, else one per face
/// triangle (quadrilaterals split into four about their node average) with the cell's node
/// average as apex.
int n_sub_tetrahedra(CellType t) {
    switch (t) {
        case CellType::tetra:
            return 1;
        case CellType::pyramid:
            return 4 + 4;
        case CellType::prism:
            return 2 + 3 * 4;
        case CellType::hexa:
            return 6 * 4;
    }
    return 1;
}

/// Smallest sub-tetrahedron volume of a cell (see n_sub_tetrahedra) at coordinates y. These
/// pieces contain the median-dual pieces of the cell (each is split by an edge midpoint into two
/// dual pieces of half its volume), so all of them positive means every dual piece is positive.
double min_sub_volume(CellType t, const Index* nd, const Matrix3Xd& y) {
    if (t == CellType::tetra) {
        const Vector3d a = y.col(nd[0]);
        return (y.col(nd[1]) - a).cross(y.col(nd[2]) - a).dot(y.col(nd[3]) - a) / 6.0;
    }
    const int n = mesh::node_count(t);
    Vector3d o = Vector3d::Zero();
    for (int k = 0; k < n; ++k) o += y.col(nd[k]);
    o /= n;
    double vmin = std::numeric_limits<double>::infinity();
    for (const auto& f : mesh::cell_faces(t)) {
        if (f[3] < 0) {
            const Vector3d a = y.col(nd[f[0]]) - o, b = y.col(nd[f[1]]) - o,
                           c = y.col(nd[f[2]]) - o;
            vmin = std::min(vmin, a.cross(b).dot(c) / 6.0);
        } else {
            Vector3d fc = Vector3d::Zero();
            for (int k = 0; k < 4; ++k) fc += y.col(nd[f[k]]);
            fc = 0.25 * fc - o;
            for (int k = 0; k < 4; ++k) {
                const Vector3d a = y.col(nd[f[k]]) - o, b = y.col(nd[f[(k + 1) % 4]]) - o;
                vmin = std::min(vmin, a.cross(b).dot(fc) / 6.0);
            }
        }
    }
    return vmin;
}

/// The mesh's boundary as the set-up needs it.
struct Boundary {
    std::vector<int> node_marker;  // marker of the node's faces; -1 interior, -2 several markers
    std::vector<double> h;         // shortest distance to a node sharing a cell [m]
};

/// `sliding`: markers left out (their nodes count as interior unless on another marker).
Boundary boundary_of(const mesh::Mesh& mesh, const Matrix3Xd& x,
                     const std::vector<char>& sliding = {}) {
    const auto n = static_cast<std::size_t>(mesh.n_nodes());
    Boundary b;
    b.node_marker.assign(n, -1);
    for (Index f = 0; f < mesh.n_faces(); ++f) {
        const int m = mesh.face_marker(f);
        if (!sliding.empty() && sliding[static_cast<std::size_t>(m)]) continue;
        for (const Index v : mesh.face(f)) {
            int& nm = b.node_marker[static_cast<std::size_t>(v)];
            if (nm == -1)
                nm = m;
            else if (nm != m)
                nm = -2;
        }
    }
    b.h.assign(n, std::numeric_limits<double>::infinity());
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto nodes = mesh.cell(c);
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            if (b.node_marker[static_cast<std::size_t>(nodes[i])] == -1) continue;
            for (std::size_t j = 0; j < nodes.size(); ++j) {
                if (i == j) continue;
                const double d = (x.col(nodes[i]) - x.col(nodes[j])).norm();
                double& h = b.h[static_cast<std::size_t>(nodes[i])];
                h = std::min(h, d);
            }
        }
    }
    return b;
}

/// Surface points carrying the two fields of one control surface and their gradients, for the
/// modified Shepard interpolation (Shepard's inverse-distance weights with linear nodal
/// functions, Franke & Nielson, Int. J. Numer. Meth. Eng. 15, 1980; rotations carried into the
/// volume as in Luke, Collins & Blades, J. Comput. Phys. 231, 2012). At x, with r_j = x - x_j,
/// phi_j = (l / |r_j|)^5 and tau_j = l_j^2 / (l_j^2 + |r_j|^2), field i is
///     sum_j phi_j (d_ij + tau_j G_ij r_j) / sum_j phi_j,
/// d_ij = w_j J_i (x_j - a) the field at x_j, G_ij = w_j J_i + J_i (x_j - a) grad(w)_j^T its
/// gradient (J_1 = [e]x, J_2 = [e]x^2). Linear in the surface values; near the rigidly
/// rotating part of the surface the volume rotates with it, near the blend band it follows the
/// band to first order.
struct PointSet {
    double ell2 = 1.0;  // l^2
    Matrix3d J1, J2;
    ArrayXd px, py, pz, pw, pl2, gx, gy, gz;          // points, w, l_j^2, grad w
    Eigen::Matrix<double, 6, Eigen::Dynamic> pd, pm;  // d1; d2 and J1 (x_j - a); J2 (x_j - a)
    mutable ArrayXd rx, ry, rz, r2, phi, c;           // scratch

    void resize(Eigen::Index m) {
        for (ArrayXd* v : {&px, &py, &pz, &pw, &pl2, &gx, &gy, &gz, &rx, &ry, &rz, &r2, &phi, &c})
            v->resize(m);
        pd.resize(6, m);
        pm.resize(6, m);
    }
    /// The two fields at x.
    void eval(const Vector3d& x, Vector3d& v1, Vector3d& v2) const {
        rx = x.x() - px;
        ry = x.y() - py;
        rz = x.z() - pz;
        r2 = (rx.square() + ry.square() + rz.square()).max(1e-300);
        phi = ell2 / r2;
        phi = phi.square() * phi.sqrt();  // (l / r)^5
        const double den = phi.sum();
        Eigen::Matrix<double, 6, 1> acc = pd * phi.matrix();
        c = phi * pl2 / (pl2 + r2);  // phi tau
        r2 = c * (gx * rx + gy * ry + gz * rz);
        acc += pm * r2.matrix();
        c *= pw;
        const Vector3d s((rx * c).sum(), (ry * c).sum(), (rz * c).sum());
        v1 = (acc.head<3>() + J1 * s) / den;
        v2 = (acc.tail<3>() + J2 * s) / den;
    }
};

}  // namespace

Matrix3d body_from_motion(const std::array<double, 3>& e) {
    return core::dcm_body_from_earth(e);
}

RigidPose rigid_pose(const aero::MotionState& s, const Vector3d& g) {
    const Matrix3d C = body_from_motion(s.euler);
    RigidPose p;
    p.rotation = D * C.transpose() * D;
    p.reference = g + D * Vector3d(s.position[0], s.position[1], s.position[2]);
    p.translation = p.reference - p.rotation * g;
    p.velocity = D * Vector3d(s.velocity[0], s.velocity[1], s.velocity[2]);
    p.omega = D * (C.transpose() * Vector3d(s.omega_body[0], s.omega_body[1], s.omega_body[2]));
    return p;
}

MeshMotion::MeshMotion(const mesh::Mesh& mesh, aero::Motion motion, MotionPlacement placement,
                       std::vector<ControlSurfaceSpec> surfaces, const DeformationOptions& options)
    : motion_(std::move(motion)),
      placement_(std::move(placement)),
      options_(options),
      specs_(std::move(surfaces)) {
    const auto t_start = Clock::now();
    if (!mesh.is_finalized())
        throw InputError(fmt::format("mesh motion: the mesh {} is not finalized", mesh.source()));
    motion_.validate(placement_.motion_source);
    if (!placement_.reference_point.allFinite())
        throw InputError("mesh motion: the reference point is not finite");
    auto positive = [](double v, const char* what) {
        if (!(v > 0.0 && std::isfinite(v)))
            throw InputError(fmt::format("mesh motion: {} = {}; expected a number > 0", what, v));
    };
    positive(options_.surface_tolerance, "surface_tolerance");
    positive(options_.hinge_tolerance_fraction, "hinge_tolerance_fraction");
    positive(options_.cutoff_chords, "cutoff_chords");
    positive(options_.min_volume_ratio, "min_volume_ratio");
    if (!(options_.hinge_blend_chords >= 0.0) || !(options_.edge_blend_chords >= 0.0))
        throw InputError("mesh motion: blend widths must be >= 0");
    if (options_.max_points < 1) throw InputError("mesh motion: max_points must be >= 1");

    const Index n = mesh.n_nodes();
    x0_.resize(3, n);
    const auto xs = mesh.coordinates();
    for (Index i = 0; i < n; ++i)
        x0_.col(i) =
            Vector3d(xs[3 * static_cast<std::size_t>(i)], xs[3 * static_cast<std::size_t>(i) + 1],
                     xs[3 * static_cast<std::size_t>(i) + 2]);

    // Modes and markers named by the control surfaces.
    std::string mode_list;
    for (const std::string& m : motion_.mode_names)
        mode_list += (mode_list.empty() ? "" : ", ") + m;
    std::string marker_list;
    for (const std::string& m : mesh.markers())
        marker_list += (marker_list.empty() ? "" : ", ") + m;
    for (std::size_t s = 0; s < specs_.size(); ++s) {
        const ControlSurfaceSpec& c = specs_[s];
        if (motion_.find_mode(c.mode) < 0)
            throw InputError(fmt::format(
                "{}: control surface on marker '{}' is driven by mode '{}', which {} does not "
                "have; expected one of {}",
                c.source, c.marker, c.mode, placement_.motion_source, mode_list));
        if (mesh.find_marker(c.marker) < 0)
            throw InputError(
                fmt::format("{}: marker '{}' is not a marker of the mesh {}; expected one of {}",
                            c.source, c.marker, mesh.source(), marker_list));
        for (std::size_t r = 0; r < s; ++r)
            if (specs_[r].marker == c.marker)
                throw InputError(fmt::format(
                    "{}: marker '{}' is given to two control surfaces (also {}); expected one",
                    c.source, c.marker, specs_[r].source));
        if (!(std::isfinite(c.gain) && c.gain != 0.0))
            throw InputError(
                fmt::format("{}: control surface on marker '{}': gain {}; expected "
                            "a finite number other than 0",
                            c.source, c.marker, c.gain));
    }
    for (std::size_t k = 0; k < motion_.mode_names.size(); ++k) {
        double vmax = 0.0, tmax = 0.0;
        for (std::size_t i = 0; i < motion_.n_samples(); ++i)
            if (std::abs(motion_.modes[k][i]) > vmax) {
                vmax = std::abs(motion_.modes[k][i]);
                tmax = motion_.t[i];
            }
        if (vmax == 0.0) continue;
        const bool driven = std::any_of(specs_.begin(), specs_.end(), [&](const auto& c) {
            return c.mode == motion_.mode_names[k];
        });
        if (!driven) {
            std::string given;
            for (const auto& c : specs_) given += (given.empty() ? "" : ", ") + c.mode;
            throw InputError(fmt::format(
                "{}: mode '{}' deflects (|{}| = {:.6g} rad at t = {:.6g} s) but no control "
                "surface is given for it (control surfaces: {}); expected a control_surfaces "
                "entry with mode: {}",
                placement_.motion_source, motion_.mode_names[k], motion_.mode_names[k], vmax, tmax,
                given.empty() ? "none" : given, motion_.mode_names[k]));
        }
    }

    const Boundary mesh_boundary = boundary_of(mesh, x0_);
    std::vector<char> moved(static_cast<std::size_t>(n), 0);
    for (const ControlSurfaceSpec& c : specs_) {
        const auto t_surface = Clock::now();
        ControlSurfaceInfo info;
        info.mode = c.mode;
        info.marker = c.marker;
        Field field;
        field.mode = motion_.find_mode(c.mode);
        field.gain = c.gain;
        const int marker = mesh.find_marker(c.marker);
        const std::string what =
            fmt::format("{}: control surface '{}' (mode {})", c.source, c.marker, c.mode);

        // The marker's nodes, its seam (nodes shared with another marker) and its box.
        std::vector<char> on_marker(static_cast<std::size_t>(n), 0);
        std::vector<Index> nodes;
        for (Index f = 0; f < mesh.n_faces(); ++f)
            if (mesh.face_marker(f) == marker)
                for (const Index v : mesh.face(f))
                    if (!on_marker[static_cast<std::size_t>(v)]) {
                        on_marker[static_cast<std::size_t>(v)] = 1;
                        nodes.push_back(v);
                    }
        std::sort(nodes.begin(), nodes.end());
        Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
        for (const Index v : nodes) {
            lo = lo.cwiseMin(x0_.col(v));
            hi = hi.cwiseMax(x0_.col(v));
        }
        info.n_marker_nodes = static_cast<int>(nodes.size());

        // Hinge line.
        const Vector3d a = c.hinge[0], b = c.hinge[1];
        if (!a.allFinite() || !b.allFinite() || !((b - a).norm() > 0.0))
            throw InputError(fmt::format("{}: hinge {} - {}; expected two distinct finite points",
                                         what, text(a), text(b)));
        const Vector3d e = (b - a).normalized();
        double hinge_distance = std::numeric_limits<double>::infinity(), chord = 0.0;
        for (const Index v : nodes) {
            const Vector3d p = x0_.col(v);
            hinge_distance = std::min(hinge_distance, segment_distance(p, a, b));
            const Vector3d rp = (p - a) - e * e.dot(p - a);
            chord = std::max(chord, rp.norm());
        }
        const double tolerance =
            c.hinge_tolerance.value_or(options_.hinge_tolerance_fraction * (hi - lo).norm());
        if (!(hinge_distance <= tolerance))
            throw InputError(fmt::format(
                "{}: the hinge line {} - {} is {:.6g} m from the nearest node of marker '{}'; "
                "expected within {:.6g} m (hinge_tolerance)",
                what, text(a), text(b), hinge_distance, c.marker, tolerance));
        if (!(chord > 0.0))
            throw InputError(fmt::format("{}: every node of marker '{}' lies on the hinge line",
                                         what, c.marker));
        info.chord = chord;
        info.hinge_distance = hinge_distance;

        // Sliding planes: another marker whose nodes all lie in one plane normal to the hinge
        // (the slab planes of a 2-D mesh). The rotation moves every point parallel to such a
        // plane, so the surface's nodes on it are not held as seam nodes and the plane's nodes
        // move with the volume, in the plane (docs/mesh-motion.md, "Sliding planes").
        std::vector<char> sliding(static_cast<std::size_t>(mesh.n_markers()), 0);
        {
            std::vector<double> e_lo(sliding.size(), std::numeric_limits<double>::infinity());
            std::vector<double> e_hi(sliding.size(), -std::numeric_limits<double>::infinity());
            std::vector<Vector3d> b_lo(sliding.size(), Vector3d::Constant(e_lo[0]));
            std::vector<Vector3d> b_hi(sliding.size(), Vector3d::Constant(e_hi[0]));
            for (Index f = 0; f < mesh.n_faces(); ++f) {
                const auto m = static_cast<std::size_t>(mesh.face_marker(f));
                for (const Index v : mesh.face(f)) {
                    const double s = e.dot(x0_.col(v));
                    e_lo[m] = std::min(e_lo[m], s);
                    e_hi[m] = std::max(e_hi[m], s);
                    b_lo[m] = b_lo[m].cwiseMin(x0_.col(v));
                    b_hi[m] = b_hi[m].cwiseMax(x0_.col(v));
                }
            }
            for (std::size_t m = 0; m < sliding.size(); ++m)
                sliding[m] = static_cast<int>(m) != marker && e_hi[m] >= e_lo[m] &&
                             e_hi[m] - e_lo[m] <= 1e-9 * (b_hi[m] - b_lo[m]).norm();
        }
        const bool any_sliding =
            std::any_of(sliding.begin(), sliding.end(), [](char c) { return c; });
        const Boundary boundary = any_sliding ? boundary_of(mesh, x0_, sliding) : mesh_boundary;
        info.n_sliding_markers =
            static_cast<int>(std::count(sliding.begin(), sliding.end(), char{1}));
        std::vector<Vector3d> seam;
        for (const Index v : nodes)
            if (boundary.node_marker[static_cast<std::size_t>(v)] == -2) seam.push_back(x0_.col(v));
        info.n_seam_nodes = static_cast<int>(seam.size());
        const double hb = c.hinge_blend.value_or(options_.hinge_blend_chords * chord);
        const double eb = c.edge_blend.value_or(options_.edge_blend_chords * chord);
        const double cutoff = c.cutoff.value_or(options_.cutoff_chords * chord);
        if (!(hb >= 0.0 && eb >= 0.0 && std::isfinite(hb) && std::isfinite(eb)))
            throw InputError(
                fmt::format("{}: blend widths {} and {} m; expected numbers >= 0", what, hb, eb));
        if (!(cutoff > 0.0 && std::isfinite(cutoff)))
            throw InputError(fmt::format("{}: cutoff {} m; expected a number > 0", what, cutoff));
        info.hinge_blend = hb;
        info.edge_blend = eb;
        info.cutoff = cutoff;

        // Exact surface fields: w e x (x - a) and w e x (e x (x - a)); the blend weight w rises
        // from 0 on the seam, w = S(d / b) (S the C1 smoothstep, d the distance to the nearest
        // seam node), over a band whose width b grows from hb at the hinge line to eb one chord
        // away from it.
        const Matrix3d J1 = cross_matrix(e), J2 = J1 * J1;
        const double ell = 0.5 * chord, ell2 = ell * ell;
        std::vector<double> weight(static_cast<std::size_t>(n), 0.0);
        std::vector<double> taper(static_cast<std::size_t>(n), ell2);
        Matrix3Xd grad = Matrix3Xd::Zero(3, n);
        for (const Index v : nodes) {
            const Vector3d p = x0_.col(v);
            double d2 = std::numeric_limits<double>::infinity();
            Vector3d nearest = p;
            for (const Vector3d& q : seam)
                if ((p - q).squaredNorm() < d2) {
                    d2 = (p - q).squaredNorm();
                    nearest = q;
                }
            const double d = std::sqrt(d2);
            const Vector3d rp = (p - a) - e * e.dot(p - a);
            const double band = hb + (eb - hb) * std::min(1.0, rp.norm() / chord);
            const auto vv = static_cast<std::size_t>(v);
            if (!(band > 0.0)) {
                weight[vv] = d > 0.0 ? 1.0 : 0.0;
                continue;
            }
            const double u = d / band;
            weight[vv] = smoothstep(u);
            if (u > 0.0 && u < 1.0) {
                Vector3d grad_band = Vector3d::Zero();
                if (rp.norm() < chord && rp.norm() > 0.0)
                    grad_band = (eb - hb) / chord * rp.normalized();
                const Vector3d grad_u = (p - nearest) / (d * band) - d / (band * band) * grad_band;
                grad.col(v) = 6.0 * u * (1.0 - u) * grad_u;
                taper[vv] = std::min(ell2, band * band);
            }
        }

        // Candidates of the reduction: the boundary nodes within the cut-off.
        std::vector<Index> cand;
        for (Index v = 0; v < n; ++v)
            if (boundary.node_marker[static_cast<std::size_t>(v)] != -1 &&
                box_distance(x0_.col(v), lo, hi) < cutoff)
                cand.push_back(v);
        const auto nc = static_cast<Eigen::Index>(cand.size());
        info.n_candidates = static_cast<int>(nc);
        PointSet cs;  // every candidate, as points
        cs.resize(nc);
        ArrayXd ctol(nc), cdecay(nc);
        Eigen::Index first = -1;
        double dmax = 0.0;
        for (Eigen::Index k = 0; k < nc; ++k) {
            const Index v = cand[static_cast<std::size_t>(k)];
            const auto vv = static_cast<std::size_t>(v);
            const Vector3d p = x0_.col(v);
            const double w = on_marker[vv] ? weight[vv] : 0.0;
            const Vector3d m1 = J1 * (p - a), m2 = J2 * (p - a);
            cs.px[k] = p.x();
            cs.py[k] = p.y();
            cs.pz[k] = p.z();
            cs.pw[k] = w;
            cs.pl2[k] = on_marker[vv] ? taper[vv] : ell2;
            const Vector3d g = on_marker[vv] ? Vector3d(grad.col(v)) : Vector3d::Zero();
            cs.gx[k] = g.x();
            cs.gy[k] = g.y();
            cs.gz[k] = g.z();
            cs.pd.col(k) << w * m1, w * m2;
            cs.pm.col(k) << m1, m2;
            ctol[k] = options_.surface_tolerance * boundary.h[vv];
            cdecay[k] = decay(box_distance(p, lo, hi), cutoff);
            if (w * m1.norm() > dmax) {
                dmax = w * m1.norm();
                first = k;
            }
        }
        if (first < 0)
            throw InputError(fmt::format(
                "{}: no node of marker '{}' is free to move (every node is within the blend band "
                "of its seam with other markers); expected a control surface with nodes off its "
                "seam",
                what, c.marker));

        // Greedy reduction (Witteveen & Bijl, AIAA 2009-3996): add the candidate of largest
        // error relative to its tolerance until all are within it. The sums of every candidate
        // are updated in place, O(candidates) per added point.
        ArrayXd den = ArrayXd::Zero(nc);
        Eigen::Matrix<double, 6, Eigen::Dynamic> acc =
            Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, nc);
        Matrix3Xd S = Matrix3Xd::Zero(3, nc);
        std::vector<char> chosen(static_cast<std::size_t>(nc), 0);
        std::vector<Eigen::Index> points;
        auto add = [&](Eigen::Index j) {
            chosen[static_cast<std::size_t>(j)] = 1;
            points.push_back(j);
            const Vector3d xj(cs.px[j], cs.py[j], cs.pz[j]), gj(cs.gx[j], cs.gy[j], cs.gz[j]);
            const Eigen::Matrix<double, 6, 1> dj = cs.pd.col(j), mj = cs.pm.col(j);
            const double wj = cs.pw[j], lj = cs.pl2[j];
            for (Eigen::Index k = 0; k < nc; ++k) {
                const Vector3d r = Vector3d(cs.px[k], cs.py[k], cs.pz[k]) - xj;
                const double r2 = std::max(r.squaredNorm(), 1e-300);
                const double q = ell2 / r2;
                const double phi = q * q * std::sqrt(q);  // (l / r)^5
                const double pt = phi * lj / (lj + r2);
                den[k] += phi;
                acc.col(k) += phi * dj + (pt * gj.dot(r)) * mj;
                S.col(k) += (pt * wj) * r;
            }
        };
        add(first);
        double worst = 0.0;
        for (;;) {
            worst = 0.0;
            Eigen::Index arg = -1;
            for (Eigen::Index k = 0; k < nc; ++k) {
                if (chosen[static_cast<std::size_t>(k)]) continue;
                const Vector3d s = S.col(k);
                const Vector3d v1 = cdecay[k] * (acc.col(k).head<3>() + J1 * s) / den[k];
                const Vector3d v2 = cdecay[k] * (acc.col(k).tail<3>() + J2 * s) / den[k];
                const double err = std::max((v1 - cs.pd.col(k).head<3>()).norm(),
                                            (v2 - cs.pd.col(k).tail<3>()).norm()) /
                                   ctol[k];
                if (err > worst) {
                    worst = err;
                    arg = k;
                }
            }
            if (worst <= 1.0 || arg < 0 || static_cast<int>(points.size()) >= options_.max_points)
                break;
            add(arg);
        }
        info.n_points = static_cast<int>(points.size());
        info.error_ratio = worst;

        // Volume fields of every node within the cut-off; boundary nodes take their exact
        // surface value (those of other markers stay fixed).
        PointSet ip;
        ip.ell2 = ell2;
        ip.J1 = J1;
        ip.J2 = J2;
        const auto m = static_cast<Eigen::Index>(points.size());
        ip.resize(m);
        for (Eigen::Index j = 0; j < m; ++j) {
            const Eigen::Index k = points[static_cast<std::size_t>(j)];
            ip.px[j] = cs.px[k];
            ip.py[j] = cs.py[k];
            ip.pz[j] = cs.pz[k];
            ip.pw[j] = cs.pw[k];
            ip.pl2[j] = cs.pl2[k];
            ip.gx[j] = cs.gx[k];
            ip.gy[j] = cs.gy[k];
            ip.gz[j] = cs.gz[k];
            ip.pd.col(j) = cs.pd.col(k);
            ip.pm.col(j) = cs.pm.col(k);
        }
        std::vector<Vector3d> f1, f2;
        for (Index v = 0; v < n; ++v) {
            const int nm = boundary.node_marker[static_cast<std::size_t>(v)];
            const Vector3d p = x0_.col(v);
            Vector3d v1, v2;
            if (nm != -1) {
                const double w = on_marker[static_cast<std::size_t>(v)]
                                     ? weight[static_cast<std::size_t>(v)]
                                     : 0.0;
                if (w == 0.0) continue;
                v1 = w * (J1 * (p - a));
                v2 = w * (J2 * (p - a));
            } else {
                const double rho = box_distance(p, lo, hi);
                if (rho >= cutoff) continue;
                ip.eval(p, v1, v2);
                const double f = decay(rho, cutoff);
                v1 *= f;
                v2 *= f;
            }
            field.nodes.push_back(v);
            f1.push_back(v1);
            f2.push_back(v2);
            moved[static_cast<std::size_t>(v)] = 1;
        }
        const auto na = static_cast<Eigen::Index>(field.nodes.size());
        field.m1.resize(3, na);
        field.m2.resize(3, na);
        for (Eigen::Index k = 0; k < na; ++k) {
            field.m1.col(k) = f1[static_cast<std::size_t>(k)];
            field.m2.col(k) = f2[static_cast<std::size_t>(k)];
        }
        info.n_affected = static_cast<int>(na);
        info.setup_seconds = seconds_since(t_surface);
        fields_.push_back(std::move(field));
        info_.push_back(std::move(info));
    }

    // Cells the deformation can change: those with a moved node.
    for (Index c = 0; c < mesh.n_cells(); ++c) {
        const auto cn = mesh.cell(c);
        if (std::none_of(cn.begin(), cn.end(),
                         [&](Index v) { return moved[static_cast<std::size_t>(v)] != 0; }))
            continue;
        const CellType t = mesh.cell_type(c);
        checked_type_.push_back(t);
        checked_cell_.push_back(c);
        checked_nodes_.insert(checked_nodes_.end(), cn.begin(), cn.end());
        checked_offsets_.push_back(static_cast<std::int64_t>(checked_nodes_.size()));
        checked_floor_.push_back(options_.min_volume_ratio * mesh.cell_volume(c) /
                                 n_sub_tetrahedra(t));
    }
    setup_seconds_ = seconds_since(t_start);
}

void MeshMotion::deform(const aero::MotionState& s, double scale, Matrix3Xd& y) const {
    y = x0_;
    for (const Field& f : fields_) {
        const double delta = scale * f.gain * s.modes[static_cast<std::size_t>(f.mode)];
        if (delta == 0.0) continue;
        const double sa = std::sin(delta), h = std::sin(0.5 * delta);
        const double ca = 2.0 * h * h;  // 1 - cos(delta) without cancellation
        for (std::size_t k = 0; k < f.nodes.size(); ++k) {
            const auto kk = static_cast<Eigen::Index>(k);
            y.col(f.nodes[k]) += sa * f.m1.col(kk) + ca * f.m2.col(kk);
        }
    }
}

void MeshMotion::deformed(const std::vector<double>& delta, Matrix3Xd& out) const {
    if (delta.size() != fields_.size())
        throw InputError(fmt::format("mesh motion: {} deflections for {} control surfaces",
                                     delta.size(), fields_.size()));
    out = x0_;
    for (std::size_t i = 0; i < fields_.size(); ++i) {
        const Field& f = fields_[i];
        const double d = delta[i];
        const double sa = std::sin(d), h = std::sin(0.5 * d), ca = 2.0 * h * h;
        for (std::size_t k = 0; k < f.nodes.size(); ++k) {
            const auto kk = static_cast<Eigen::Index>(k);
            out.col(f.nodes[k]) += sa * f.m1.col(kk) + ca * f.m2.col(kk);
        }
    }
}

long MeshMotion::first_bad_cell(const Matrix3Xd& y) const {
    for (std::size_t k = 0; k < checked_type_.size(); ++k) {
        const double v =
            min_sub_volume(checked_type_[k], checked_nodes_.data() + checked_offsets_[k], y);
        if (!(v > checked_floor_[k])) return static_cast<long>(k);
    }
    return -1;
}

void MeshMotion::check(const aero::MotionState& s, const Matrix3Xd& y, long step) const {
    const long bad = first_bad_cell(y);
    if (bad < 0) return;
    // Largest fraction of the deflections that keeps every cell valid (the reference mesh, 0,
    // is valid).
    double lo = 0.0, hi = 1.0;
    Matrix3Xd trial;
    for (int it = 0; it < 30; ++it) {
        const double mid = 0.5 * (lo + hi);
        deform(s, mid, trial);
        (first_bad_cell(trial) < 0 ? lo : hi) = mid;
    }
    const auto k = static_cast<std::size_t>(bad);
    Index node = checked_nodes_[static_cast<std::size_t>(checked_offsets_[k])];
    double dmax = -1.0;
    for (auto i = checked_offsets_[k]; i < checked_offsets_[k + 1]; ++i) {
        const Index v = checked_nodes_[static_cast<std::size_t>(i)];
        const double d = (y.col(v) - x0_.col(v)).norm();
        if (d > dmax) {
            dmax = d;
            node = v;
        }
    }
    std::string now, valid;
    std::vector<int> listed;
    for (const Field& f : fields_) {
        if (std::find(listed.begin(), listed.end(), f.mode) != listed.end()) continue;
        listed.push_back(f.mode);
        const double v = s.modes[static_cast<std::size_t>(f.mode)];
        const std::string& name = motion_.mode_names[static_cast<std::size_t>(f.mode)];
        now += fmt::format("{}{} {:.4g} deg", now.empty() ? "" : ", ", name,
                           v * 180.0 / std::numbers::pi);
        valid += fmt::format("{}{} {:.4g} deg", valid.empty() ? "" : ", ", name,
                             lo * v * 180.0 / std::numbers::pi);
    }
    throw InputError(fmt::format(
        "{}{}: t = {:.9g} s: cell {} ({}) folds at node {} {} with {}; the largest deflection "
        "that keeps every cell valid is {:.4f} of it ({})",
        placement_.motion_source, step >= 0 ? fmt::format(", step {}", step) : std::string(), s.t,
        checked_cell_[k], mesh::name(checked_type_[k]), node, text(x0_.col(node)), now, lo, valid));
}

void MeshMotion::coordinates_at(double t, Matrix3Xd& out, long step) const {
    const aero::MotionState s = motion_.at(t);
    if (out.cols() != x0_.cols()) out.resize(3, x0_.cols());
    deform(s, 1.0, out);
    check(s, out, step);
    const RigidPose p = rigid_pose(s, placement_.reference_point);
    for (Eigen::Index i = 0; i < out.cols(); ++i) {
        const Vector3d y = out.col(i);
        out.col(i) = p.translation + p.rotation * y;
    }
}

void MeshMotion::state_at(double t, Matrix3Xd& x, Matrix3Xd& v, long step) const {
    const aero::MotionState s = motion_.at(t);
    if (x.cols() != x0_.cols()) x.resize(3, x0_.cols());
    if (v.cols() != x0_.cols()) v.resize(3, x0_.cols());
    deform(s, 1.0, x);
    check(s, x, step);
    v.setZero();
    for (const Field& f : fields_) {
        const double delta = f.gain * s.modes[static_cast<std::size_t>(f.mode)];
        const double rate = f.gain * s.mode_rates[static_cast<std::size_t>(f.mode)];
        if (rate == 0.0) continue;
        const double c1 = std::cos(delta) * rate, c2 = std::sin(delta) * rate;
        for (std::size_t k = 0; k < f.nodes.size(); ++k) {
            const auto kk = static_cast<Eigen::Index>(k);
            v.col(f.nodes[k]) += c1 * f.m1.col(kk) + c2 * f.m2.col(kk);
        }
    }
    const RigidPose p = rigid_pose(s, placement_.reference_point);
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
        const Vector3d y = x.col(i), ydot = v.col(i);
        const Vector3d xi = p.translation + p.rotation * y;
        x.col(i) = xi;
        v.col(i) = p.velocity + p.omega.cross(xi - p.reference) + p.rotation * ydot;
    }
}

void MeshMotion::check_motion() const {
    if (fields_.empty()) return;
    Matrix3Xd y;
    for (std::size_t i = 0; i < motion_.n_samples(); ++i) {
        const aero::MotionState s = motion_.at(motion_.t[i]);
        deform(s, 1.0, y);
        check(s, y, -1);
    }
}

}  // namespace manta::meshmotion
