#include "manta/vlm/steady.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>

#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/vlm/detail/biot_savart.hpp"
#include "manta/vlm/detail/kernels.hpp"

namespace manta::vlm {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

Vector3d omega_geometry(const Reference& ref, double p_hat, double q_hat, double r_hat) {
    // p = 2 V p_hat / b with V = 1.
    return core::geometry_from_body(
        Vector3d(2.0 * p_hat / ref.span, 2.0 * q_hat / ref.chord, 2.0 * r_hat / ref.span));
}

namespace {

/// The horseshoes of the lattice in stretched coordinates (ends stretched by 1/beta in x) and
/// their velocities at a point, the x component returned to physical space (divided by beta).
/// Each horseshoe is a bound segment a -> b with a finite core of squared radius rc^2 (the
/// Scully / Burnham-Hallock profile, tangential velocity Gamma r / (2 pi (r^2 + rc^2)) near an
/// infinite line: the Biot-Savart law with the squared distance from the line and from the end
/// points each increased by rc^2) and two semi-infinite legs along +x with the same core. Every
/// horseshoe has trailing legs, NOWAKE surfaces included: their strips carry zero net
/// circulation (see SteadySolver), so the legs of a strip cancel behind its last bound vortex.
/// Cores as SteadyOptions: a small one within the component of the point, a large one across
/// components. Mirror images (Model::y_symmetry, z_symmetry) are added as further horseshoes.
struct Stretched {
    std::vector<Vector3d> a, b;           // bound ends
    std::vector<int> component;           // component of each horseshoe
    std::vector<double> core_in, core_x;  // squared core radii within / across components
    double beta = 1.0;
    // Images (Model::y_symmetry, z_symmetry): factors and the z of the horizontal plane.
    double fy = 0.0, fz = 0.0, z_plane = 0.0;

    /// Structure-of-arrays copy of the horseshoes and of their mirror images (`prepare_rows`),
    /// padded with copies of the last horseshoe to a multiple of 8 (`row` works on groups of 4,
    /// `row_f` on groups of 8), with single-precision copies of r0, |r0|^2 and the cores.
    struct Set {
        double factor = 1.0;  // image factor (1 for the lattice itself)
        Eigen::ArrayXd ax, ay, az, bx, by, bz, r0x, r0y, r0z, l2;
        Eigen::ArrayXf r0x_f, r0y_f, r0z_f, l2_f;
    };
    std::vector<Set> sets;
    Eigen::ArrayXd cin, cx;
    Eigen::ArrayXf cin_f, cx_f;
    Eigen::ArrayXi comps;
    Eigen::Index padded = 0;

    void prepare_rows() {
        const auto n = static_cast<Eigen::Index>(a.size());
        padded = (n + 7) / 8 * 8;
        // The lattice, then its images: y, z, then both (a mirror image
        // reverses the sense of the bound segment: ends swapped; two restore it).
        auto my = [](const Vector3d& q) { return Vector3d(q.x(), -q.y(), q.z()); };
        auto mz = [&](const Vector3d& q) { return Vector3d(q.x(), q.y(), 2.0 * z_plane - q.z()); };
        struct Image {
            double f;
            std::function<std::pair<Vector3d, Vector3d>(const Vector3d&, const Vector3d&)> ends;
        };
        std::vector<Image> images{{1.0, [](const Vector3d& p, const Vector3d& q) {
                                       return std::pair{p, q};
                                   }}};
        if (fy != 0.0)
            images.push_back({fy, [&](const Vector3d& p, const Vector3d& q) {
                                  return std::pair{my(q), my(p)};
                              }});
        if (fz != 0.0) {
            images.push_back({fz, [&](const Vector3d& p, const Vector3d& q) {
                                  return std::pair{mz(q), mz(p)};
                              }});
            if (fy != 0.0)
                images.push_back({fy * fz, [&](const Vector3d& p, const Vector3d& q) {
                                      return std::pair{my(mz(p)), my(mz(q))};
                                  }});
        }
        sets.clear();
        for (const Image& im : images) {
            Set s;
            s.factor = im.f;
            for (auto* v :
                 {&s.ax, &s.ay, &s.az, &s.bx, &s.by, &s.bz, &s.r0x, &s.r0y, &s.r0z, &s.l2})
                v->resize(padded);
            for (Eigen::Index j = 0; j < padded; ++j) {
                const auto k = static_cast<std::size_t>(std::min(j, n - 1));
                const auto [e1, e2] = im.ends(a[k], b[k]);
                s.ax[j] = e1.x();
                s.ay[j] = e1.y();
                s.az[j] = e1.z();
                s.bx[j] = e2.x();
                s.by[j] = e2.y();
                s.bz[j] = e2.z();
                s.r0x[j] = s.bx[j] - s.ax[j];
                s.r0y[j] = s.by[j] - s.ay[j];
                s.r0z[j] = s.bz[j] - s.az[j];
                s.l2[j] = s.r0x[j] * s.r0x[j] + s.r0y[j] * s.r0y[j] + s.r0z[j] * s.r0z[j];
            }
            s.r0x_f = s.r0x.cast<float>();
            s.r0y_f = s.r0y.cast<float>();
            s.r0z_f = s.r0z.cast<float>();
            s.l2_f = s.l2.cast<float>();
            sets.push_back(std::move(s));
        }
        cin.resize(padded);
        cx.resize(padded);
        comps.resize(padded);
        for (Eigen::Index j = 0; j < padded; ++j) {
            const auto k = static_cast<std::size_t>(std::min(j, n - 1));
            cin[j] = core_in[k];
            cx[j] = core_x[k];
            comps[j] = component[k];
        }
        cin_f = cin.cast<float>();
        cx_f = cx.cast<float>();
        views.clear();
        for (const Set& t : sets)
            views.push_back({t.factor, t.ax.data(), t.ay.data(), t.az.data(), t.bx.data(),
                             t.by.data(), t.bz.data(), t.r0x.data(), t.r0y.data(), t.r0z.data(),
                             t.l2.data(), t.r0x_f.data(), t.r0y_f.data(), t.r0z_f.data(),
                             t.l2_f.data()});
        view = {views.data(), static_cast<int>(views.size()),
                cin.data(),   cx.data(),
                comps.data(), padded,
                beta,         cin_f.data(),
                cx_f.data()};
    }

    /// Velocities at p of every horseshoe at once (detail::Kernels::horseshoe_row: four
    /// horseshoes at a time in vector registers); vx, vy, vz are resized to the padded count
    /// (the padding's values are meaningless).
    void row(const Vector3d& p, int comp, Eigen::ArrayXd& vx, Eigen::ArrayXd& vy,
             Eigen::ArrayXd& vz) const {
        vx.resize(padded);
        vy.resize(padded);
        vz.resize(padded);
        detail::kernels().horseshoe_row(view, p.data(), comp, vx.data(), vy.data(), vz.data());
    }
    /// `row` in single precision (detail::Kernels::horseshoe_row_f: eight at a time).
    void row_f(const Vector3d& p, int comp, Eigen::ArrayXf& vx, Eigen::ArrayXf& vy,
               Eigen::ArrayXf& vz) const {
        vx.resize(padded);
        vy.resize(padded);
        vz.resize(padded);
        detail::kernels().horseshoe_row_f(view, p.data(), comp, vx.data(), vy.data(), vz.data());
    }
    /// Pointers into `sets` for the kernel (set by prepare_rows; the object is not copied after).
    std::vector<detail::HorseshoeSet> views;
    detail::HorseshoeRows view;
};

Vector3d stretch(const Vector3d& p, double beta) {
    return {p.x() / beta, p.y(), p.z()};
}

Stretched make_stretched(const Model& m, const Lattice& L, double beta, const SteadyOptions& o) {
    Stretched s;
    s.beta = beta;
    s.fy = m.y_symmetry;
    s.fz = m.z_symmetry;
    s.z_plane = m.z_symmetry_plane;
    const auto n = static_cast<std::size_t>(L.size());
    s.a.resize(n);
    s.b.resize(n);
    s.component.resize(n);
    s.core_in.resize(n);
    s.core_x.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
        s.a[j] = stretch(L.a[j], beta);
        s.b[j] = stretch(L.b[j], beta);
        const Strip& st = L.strips[static_cast<std::size_t>(L.strip[j])];
        s.component[j] = m.surfaces[static_cast<std::size_t>(st.surface)].component;
        const Vector3d e = L.b[j] - L.a[j];
        const double w = std::hypot(e.y(), e.z());
        s.core_in[j] = std::pow(o.core_within_component * w, 2);
        s.core_x[j] = std::pow(
            std::max(o.core_between_components * st.chord, 2.0 * o.core_between_components * w), 2);
    }
    return s;
}

/// Component of the surface a panel belongs to.
int component_of(const Model& m, const Lattice& L, std::size_t i) {
    const Strip& st = L.strips[static_cast<std::size_t>(L.strip[i])];
    return m.surfaces[static_cast<std::size_t>(st.surface)].component;
}

}  // namespace

/// The horseshoes in the solver's arrays (built once; `induced_at_bound` reuses them), and one
/// horseshoe per strip between its two trailing-edge points (`te`, stretched; physical ends
/// te_a, te_b): every horseshoe of a strip has its legs through those two points, so their parts
/// behind the trailing edge are this horseshoe's legs less its bound segment (leg_bend).
struct SteadySolver::Kernel {
    Stretched st;
    Stretched te;
    std::vector<Vector3d> te_a, te_b;
};

/// Mirror symmetry about y = 0 (see the constructor): the orbits of the reflection and the two
/// half systems.
struct SteadySolver::Mirror {
    std::vector<int> image;           ///< m(i): the panel whose horseshoe is panel i's mirror image
    std::vector<double> sign;         ///< s_i: reflected horseshoe i = s_i x horseshoe m(i)
    std::vector<int> rep;             ///< one panel per orbit (i <= m(i)), increasing
    std::vector<int> sym, anti;       ///< representatives that are unknowns of each half system
    detail::DenseLU lu_sym, lu_anti;  ///< the half systems, factorised
};

namespace {

/// Reflection about y = 0.
Vector3d reflect_y(const Vector3d& q) {
    return {q.x(), -q.y(), q.z()};
}

/// The mirror map of a lattice, if it is exactly symmetric about y = 0 (every test is an exact
/// floating-point equality: build_lattice makes mirror copies by negating y). Panel i and its
/// image m(i) must have reflected, reversed bound segments (a_m = S b_i, b_m = S a_i, sign +1), or
/// panel i lies in the plane y = 0 (S a_i = a_i, S b_i = b_i: it is its own image reversed, sign
/// -1); reflected control points, force points and normals (n_m = s_i S n_i); equal components,
/// cores and NOWAKE closure rows (closure strips mapped onto closure strips with one sign).
bool find_mirror(const Model& model, const Lattice& L, const Stretched& st,
                 const std::vector<char>& closure, std::vector<int>& image,
                 std::vector<double>& sign) {
    if (model.y_symmetry != 0) return false;  // a half lattice with images
    const auto n = static_cast<std::size_t>(L.size());
    std::map<std::array<double, 6>, int> by_ends;
    for (std::size_t i = 0; i < n; ++i)
        by_ends.emplace(std::array<double, 6>{L.a[i].x(), L.a[i].y(), L.a[i].z(), L.b[i].x(),
                                              L.b[i].y(), L.b[i].z()},
                        static_cast<int>(i));
    image.assign(n, -1);
    sign.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const Vector3d sa = reflect_y(L.a[i]), sb = reflect_y(L.b[i]);
        if (sa == L.a[i] && sb == L.b[i]) {
            image[i] = static_cast<int>(i);
            sign[i] = -1.0;
        } else {
            const auto it = by_ends.find({sb.x(), sb.y(), sb.z(), sa.x(), sa.y(), sa.z()});
            if (it == by_ends.end()) return false;
            image[i] = it->second;
            sign[i] = 1.0;
        }
        const auto j = static_cast<std::size_t>(image[i]);
        if (L.control_point[j] != reflect_y(L.control_point[i]) ||
            L.bound_point[j] != reflect_y(L.bound_point[i]) ||
            L.normal[j] != sign[i] * reflect_y(L.normal[i]) || st.component[j] != st.component[i] ||
            st.core_in[j] != st.core_in[i] || st.core_x[j] != st.core_x[i] ||
            closure[j] != closure[i])
            return false;
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (!closure[i]) continue;
        const Strip& S = L.strips[static_cast<std::size_t>(L.strip[i])];
        const int target = L.strip[static_cast<std::size_t>(image[i])];
        for (int k = S.first_panel; k < S.first_panel + S.n_panels; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            if (L.strip[static_cast<std::size_t>(image[kk])] != target || sign[kk] != sign[i])
                return false;
        }
    }
    return true;
}

}  // namespace

struct SteadySolver::Units {
    MatrixXd G;     // N x K circulations
    MatrixXd U;     // 3N x K induced velocity at bound midpoints
    Trefftz plane;  // of the legs' direction
};

void set_wind_forces(SteadyResult& r, double CL, double CD, double CY, double alpha, double beta) {
    r.CL = CL;
    r.CD = CD;
    r.CY = CY;
    const auto f = aero::body_from_wind(CL, CD, CY, alpha, beta);
    r.body.CX = f[0];
    r.body.CY = f[1];
    r.body.CZ = f[2];
}

void add_profile_drag(SteadyResult& r, double CD0, double alpha, double beta) {
    r.CD_profile += CD0;
    set_wind_forces(r, r.CL, r.CD + CD0, r.CY, alpha, beta);
}

SteadySolver::SteadySolver(const Model& model, Lattice lattice, double mach, SteadyOptions options)
    : model_(model), lattice_(std::move(lattice)), mach_(mach), options_(options) {
    if (!(options.core_within_component >= 0.0 && options.core_between_components >= 0.0))
        throw InputError(fmt::format("vlm: vortex core factors {} and {}; expected numbers >= 0",
                                     options.core_within_component,
                                     options.core_between_components));
    if (!(mach >= 0.0 && mach < 0.95))
        throw InputError(fmt::format(
            "vlm: Mach {}; expected 0 <= M < 0.95 (Prandtl-Glauert is subsonic)", mach));
    check_lattice(model_, lattice_);
    beta_pg_ = std::sqrt(1.0 - mach * mach);
    const int n = lattice_.size();
    auto kernel = std::make_shared<Kernel>();
    kernel->st = make_stretched(model_, lattice_, beta_pg_, options_);
    Stretched& st = kernel->st;
    st.prepare_rows();
    {
        // Trailing-edge horseshoes: one per strip, the strip's cores and component, evaluated
        // with beta = 1 (leg_bend rotates the stretched frame and divides x by beta itself).
        Stretched& te = kernel->te;
        te.beta = 1.0;
        te.fy = model_.y_symmetry;
        te.fz = model_.z_symmetry;
        te.z_plane = model_.z_symmetry_plane;
        for (const Strip& S : lattice_.strips) {
            const auto p0 = static_cast<std::size_t>(S.first_panel);
            // The legs of the strip's panels run along x from a and b (build_lattice).
            const Vector3d ta(S.le_a.x() + S.chord_a, lattice_.a[p0].y(), lattice_.a[p0].z());
            const Vector3d tb(S.le_b.x() + S.chord_b, lattice_.b[p0].y(), lattice_.b[p0].z());
            kernel->te_a.push_back(ta);
            kernel->te_b.push_back(tb);
            te.a.push_back(stretch(ta, beta_pg_));
            te.b.push_back(stretch(tb, beta_pg_));
            te.component.push_back(st.component[p0]);
            te.core_in.push_back(st.core_in[p0]);
            te.core_x.push_back(st.core_x[p0]);
        }
        te.prepare_rows();
    }
    // Rows: flow tangency at every control point, except the last control point of each strip
    // of a surface that sheds no wake (NOWAKE), whose row states instead that the strip's
    // circulations sum to zero: such a surface (e.g. a fuselage side plate) carries lift through
    // its chordwise loading but leaves no trailing vorticity behind its last bound vortex.
    closure_row_.assign(static_cast<std::size_t>(n), 0);
    for (const Strip& S : lattice_.strips)
        if (!S.sheds_wake)
            closure_row_[static_cast<std::size_t>(S.first_panel + S.n_panels - 1)] = 1;
    const bool single = options_.single_precision;
    // Row i of the influence matrix: normal velocity at control point i of every horseshoe, in
    // double or (single) in single precision.
    Eigen::ArrayXd vx, vy, vz, vals(n);
    Eigen::ArrayXf fx, fy, fz, vals_f(n);
    auto influence_row = [&](int i) {
        const auto ii = static_cast<std::size_t>(i);
        if (closure_row_[ii]) {
            const Strip& S = lattice_.strips[static_cast<std::size_t>(lattice_.strip[ii])];
            vals.setZero();
            vals.segment(S.first_panel, S.n_panels).setOnes();
            vals_f.setZero();
            vals_f.segment(S.first_panel, S.n_panels).setOnes();
            return;
        }
        const Vector3d p = stretch(lattice_.control_point[ii], beta_pg_);
        const Vector3d& nrm = lattice_.normal[ii];
        if (single) {
            st.row_f(p, component_of(model_, lattice_, ii), fx, fy, fz);
            const Eigen::Vector3f nf = nrm.cast<float>();
            vals_f = fx.head(n) * nf.x() + fy.head(n) * nf.y() + fz.head(n) * nf.z();
            return;
        }
        st.row(p, component_of(model_, lattice_, ii), vx, vy, vz);
        vals = vx.head(n) * nrm.x() + vy.head(n) * nrm.y() + vz.head(n) * nrm.z();
    };
    auto mirror = std::make_shared<Mirror>();
    if (find_mirror(model_, lattice_, st, closure_row_, mirror->image, mirror->sign)) {
        // Mirror symmetry (the image m(i) and sign s_i of every panel: the influence matrix
        // satisfies A(m(i), m(j)) = s_i s_j A(i, j)). Circulations symmetric (G_m(j) = s_j G_j)
        // and antisymmetric (G_m(j) = -s_j G_j) solve two independent systems of half the size,
        // one row and one unknown per orbit {j, m(j)}: A(i, j) +- s_j A(i, m(j)). A panel in the
        // plane y = 0 (sign -1) is an unknown of the antisymmetric system only.
        Mirror& M = *mirror;
        std::vector<int> pos_sym(static_cast<std::size_t>(n), -1),
            pos_anti(static_cast<std::size_t>(n), -1);
        for (int i = 0; i < n; ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const int m = M.image[ii];
            if (m < i) continue;
            M.rep.push_back(i);
            if (m != i || M.sign[ii] > 0) {
                pos_sym[ii] = static_cast<int>(M.sym.size());
                M.sym.push_back(i);
            }
            if (m != i || M.sign[ii] < 0) {
                pos_anti[ii] = static_cast<int>(M.anti.size());
                M.anti.push_back(i);
            }
        }
        // Half-system rows, 16 at a time: gathered contiguously (as columns of a buffer), then
        // copied into the column-major matrix as blocks of 16 consecutive rows.
        auto assemble = [&]<typename Scalar>(const Eigen::Array<Scalar, Eigen::Dynamic, 1>& v,
                                             auto& As, auto& Aa) {
            using Mat = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
            struct Half {
                const std::vector<int>* cols;
                const std::vector<int>* pos;
                Scalar f;
                Mat* A;
                Mat buf;
                Eigen::Index r0 = 0, filled = 0;
            };
            Half halves[2] = {{&M.sym, &pos_sym, Scalar(1), &As, {}, 0, 0},
                              {&M.anti, &pos_anti, Scalar(-1), &Aa, {}, 0, 0}};
            constexpr Eigen::Index block = 16;
            for (Half& h : halves) {
                const auto nh = static_cast<Eigen::Index>(h.cols->size());
                h.A->resize(nh, nh);
                h.buf.resize(nh, block);
            }
            auto flush = [](Half& h) {
                if (h.filled == 0) return;
                h.A->middleRows(h.r0, h.filled) = h.buf.leftCols(h.filled).transpose();
                h.r0 += h.filled;
                h.filled = 0;
            };
            for (const int i : M.rep) {
                influence_row(i);
                for (Half& h : halves) {
                    if ((*h.pos)[static_cast<std::size_t>(i)] < 0) continue;
                    auto col = h.buf.col(h.filled);
                    const auto nh = static_cast<Eigen::Index>(h.cols->size());
                    for (Eigen::Index c = 0; c < nh; ++c) {
                        const auto j =
                            static_cast<std::size_t>((*h.cols)[static_cast<std::size_t>(c)]);
                        const int mj = M.image[j];
                        col[c] = v[static_cast<Eigen::Index>(j)] +
                                 (mj != static_cast<int>(j)
                                      ? h.f * static_cast<Scalar>(M.sign[j]) * v[mj]
                                      : Scalar(0));
                    }
                    if (++h.filled == block) flush(h);
                }
            }
            for (Half& h : halves) flush(h);
        };
        if (single) {
            Eigen::MatrixXf As, Aa;
            assemble(vals_f, As, Aa);
            M.lu_sym.compute_single(std::move(As));
            M.lu_anti.compute_single(std::move(Aa));
        } else {
            MatrixXd As, Aa;
            assemble(vals, As, Aa);
            M.lu_sym.compute(std::move(As));
            M.lu_anti.compute(std::move(Aa));
        }
        mirror_ = std::move(mirror);
    } else if (single) {
        // Assembled transposed (row i of the influence matrix is column i here: contiguous
        // writes).
        Eigen::MatrixXf At(n, n);
        for (int i = 0; i < n; ++i) {
            influence_row(i);
            At.col(i) = vals_f.matrix();
        }
        At.transposeInPlace();
        lu_.compute_single(std::move(At));
    } else {
        MatrixXd At(n, n);
        for (int i = 0; i < n; ++i) {
            influence_row(i);
            At.col(i) = vals.matrix();
        }
        At.transposeInPlace();
        lu_.compute(std::move(At));
    }
    kernel_ = std::move(kernel);
    mid_ = lattice_.bound_point;
    trefftz_x_ = trefftz_plane(Vector3d::UnitX());
}

VectorXd SteadySolver::rhs(const VectorXd& deflection, const Vector3d& v, const Vector3d& w) const {
    const int n = lattice_.size();
    VectorXd b(n);
    for (int i = 0; i < n; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const Vector3d r = lattice_.control_point[ii] - model_.reference.point;
        if (closure_row_[ii]) {
            b[i] = 0.0;
            continue;
        }
        // Deflections to first order (AVL's convention): loads linear in the deflections.
        const Vector3d nrm = lattice_.linearized_normal(i, deflection);
        b[i] = -(v - w.cross(r)).dot(nrm);
    }
    return b;
}

MatrixXd SteadySolver::solve_system(const MatrixXd& B, bool refined) const {
    if (!mirror_) return refined ? lu_.solve(B) : lu_.solve_unrefined(B);
    // Split every right-hand side into its symmetric and antisymmetric parts (rows of the orbit
    // representatives), solve the half systems, and assemble the circulations of both halves.
    const Mirror& M = *mirror_;
    const auto K = B.cols();
    auto part = [&](const std::vector<int>& rows, double f) {
        MatrixXd P(static_cast<Eigen::Index>(rows.size()), K);
        for (std::size_t r = 0; r < rows.size(); ++r) {
            const auto i = static_cast<std::size_t>(rows[r]);
            const auto ri = static_cast<Eigen::Index>(r);
            P.row(ri) = 0.5 * (B.row(rows[r]) + (f * M.sign[i]) * B.row(M.image[i]));
        }
        return P;
    };
    const MatrixXd Xs =
        refined ? M.lu_sym.solve(part(M.sym, 1.0)) : M.lu_sym.solve_unrefined(part(M.sym, 1.0));
    const MatrixXd Xa = refined ? M.lu_anti.solve(part(M.anti, -1.0))
                                : M.lu_anti.solve_unrefined(part(M.anti, -1.0));
    MatrixXd G = MatrixXd::Zero(B.rows(), K);
    auto add = [&](const std::vector<int>& rows, const MatrixXd& X, double f) {
        for (std::size_t r = 0; r < rows.size(); ++r) {
            const auto i = static_cast<std::size_t>(rows[r]);
            const auto ri = static_cast<Eigen::Index>(r);
            G.row(rows[r]) += X.row(ri);
            if (M.image[i] != rows[r]) G.row(M.image[i]) += (f * M.sign[i]) * X.row(ri);
        }
    };
    add(M.sym, Xs, 1.0);
    add(M.anti, Xa, -1.0);
    return G;
}

MatrixXd SteadySolver::induced_at_bound(const MatrixXd& gamma) const {
    const int n = lattice_.size();
    const auto K = gamma.cols();
    const Stretched& st = kernel_->st;
    MatrixXd U = MatrixXd::Zero(3 * n, K);
    // Per target point: the velocities of all horseshoes in one pass, then one small matrix
    // product with the circulations. With mirror symmetry only one point of each orbit: the
    // velocity at the image S p of point p is S sum_k s_k G_m(k) v_k(p).
    MatrixXd GG = gamma;
    if (mirror_) {
        GG.resize(n, 2 * K);
        GG.leftCols(K) = gamma;
        for (int k = 0; k < n; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            GG.row(k).tail(K) = mirror_->sign[kk] * gamma.row(mirror_->image[kk]);
        }
    }
    // Points in blocks of `bp`: their velocity rows stacked (3 bp x N), one product per block.
    const std::vector<int>* reps = mirror_ ? &mirror_->rep : nullptr;
    const auto np = static_cast<Eigen::Index>(reps ? reps->size() : static_cast<std::size_t>(n));
    constexpr Eigen::Index bp = 16;
    Eigen::ArrayXd vx, vy, vz;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows;
    MatrixXd T;
    // Single precision: the velocity rows, circulations and products in floats.
    const bool single = options_.single_precision;
    Eigen::ArrayXf fx, fy, fz;
    Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows_f;
    Eigen::MatrixXf T_f;
    Eigen::MatrixXf GG_f;
    if (single) {
        GG_f = GG.cast<float>();
        rows_f.resize(3 * bp, n);
    } else {
        rows.resize(3 * bp, n);
    }
    for (Eigen::Index q0 = 0; q0 < np; q0 += bp) {
        const Eigen::Index m = std::min(bp, np - q0);
        auto point = [&](Eigen::Index q) {
            return reps ? (*reps)[static_cast<std::size_t>(q0 + q)] : static_cast<int>(q0 + q);
        };
        for (Eigen::Index q = 0; q < m; ++q) {
            const int i = point(q);
            const Vector3d p = stretch(mid_[static_cast<std::size_t>(i)], beta_pg_);
            const int comp = component_of(model_, lattice_, static_cast<std::size_t>(i));
            if (single) {
                st.row_f(p, comp, fx, fy, fz);
                rows_f.row(3 * q) = fx.head(n).matrix().transpose();
                rows_f.row(3 * q + 1) = fy.head(n).matrix().transpose();
                rows_f.row(3 * q + 2) = fz.head(n).matrix().transpose();
                continue;
            }
            st.row(p, comp, vx, vy, vz);
            rows.row(3 * q) = vx.head(n).matrix().transpose();
            rows.row(3 * q + 1) = vy.head(n).matrix().transpose();
            rows.row(3 * q + 2) = vz.head(n).matrix().transpose();
        }
        // T = rows * GG; the row-major rows are the column-major (N x 3 bp) rows^T.
        if (single) {
            T_f.resize(3 * m, GG_f.cols());
            detail::kernels().gemm_tn_f(rows_f.data(), n, 3 * m, GG_f.data(), GG_f.cols(),
                                        T_f.data());
            T = T_f.cast<double>();
        } else {
            T.resize(3 * m, GG.cols());
            detail::kernels().gemm_tn(rows.data(), n, 3 * m, GG.data(), GG.cols(), T.data());
        }
        for (Eigen::Index q = 0; q < m; ++q) {
            const int i = point(q);
            U.middleRows(3 * i, 3) = T.middleRows(3 * q, 3).leftCols(K);
            if (!reps) continue;
            const int mi = mirror_->image[static_cast<std::size_t>(i)];
            if (mi == i) continue;
            U.row(3 * mi) = T.row(3 * q).tail(K);
            U.row(3 * mi + 1) = -T.row(3 * q + 1).tail(K);
            U.row(3 * mi + 2) = T.row(3 * q + 2).tail(K);
        }
    }
    return U;
}

Vector3d SteadySolver::wake_direction(const FlowState& state) const {
    if (options_.trailing_legs == TrailingLegs::body_axis || model_.z_symmetry != 0 ||
        (model_.y_symmetry != 0 && state.beta != 0.0))
        return Vector3d::UnitX();
    return core::free_stream_geometry(state.alpha, state.beta);
}

SteadySolver::Trefftz SteadySolver::trefftz_plane(const Vector3d& d) const {
    // The far wake of strip t is a pair of infinite 2-D vortices through its trailing-edge
    // points, in the plane normal to the legs (basis e1, e2, e1 x e2 = d; y, z for legs along x);
    // wash at the centre of strip s per unit circulation of t.
    Trefftz tp;
    tp.d = d;
    tp.e1 = (Vector3d::UnitY() - d.y() * d).normalized();
    tp.e2 = d.cross(tp.e1);
    const auto ns = lattice_.strips.size();
    const std::vector<Vector3d>& ta = kernel_->te_a;
    const std::vector<Vector3d>& tb = kernel_->te_b;
    auto plane = [&](const Vector3d& q) { return Eigen::Vector2d(q.dot(tp.e1), q.dot(tp.e2)); };
    tp.wash.setZero(static_cast<Eigen::Index>(2 * ns), static_cast<Eigen::Index>(ns));
    tp.l.resize(ns);
    for (std::size_t t = 0; t < ns; ++t) {
        const Vector3d e = tb[t] - ta[t];
        tp.l[t] = e.dot(tp.e1) * tp.e1 + e.dot(tp.e2) * tp.e2;
    }
    const double fy = model_.y_symmetry, fz = model_.z_symmetry;
    const double zp = model_.z_symmetry_plane;
    auto my = [](const Vector3d& q) { return Vector3d(q.x(), -q.y(), q.z()); };
    auto mz = [&](const Vector3d& q) { return Vector3d(q.x(), q.y(), 2.0 * zp - q.z()); };
    for (std::size_t s = 0; s < ns; ++s) {
        const Strip& S = lattice_.strips[s];
        const Eigen::Vector2d c = plane(S.le_mid + S.chord * Vector3d::UnitX());
        for (std::size_t t = 0; t < ns; ++t) {
            const Strip& T = lattice_.strips[t];
            if (!T.sheds_wake) continue;
            auto point_vortex = [&](const Vector3d& q3, double sign) {
                // Vortex along d through q: v = G/(2 pi) d x (P - q) / |P - q|^2.
                const Eigen::Vector2d q = plane(q3);
                const double dy = c.x() - q.x(), dz = c.y() - q.y();
                const double r2 = dy * dy + dz * dz;
                if (r2 <= 1e-24) return;
                const double k = sign / (2.0 * std::numbers::pi * r2);
                tp.wash(static_cast<Eigen::Index>(2 * s), static_cast<Eigen::Index>(t)) += -k * dz;
                tp.wash(static_cast<Eigen::Index>(2 * s + 1), static_cast<Eigen::Index>(t)) +=
                    k * dy;
            };
            // Legs: b -> infinity (+d) and infinity -> a (-d); images of the symmetry planes
            // with their sense reversed by each reflection (legs along x, or y images with d in
            // the x-z plane: wake_direction).
            point_vortex(tb[t], 1.0);
            point_vortex(ta[t], -1.0);
            if (fy != 0.0) {
                point_vortex(my(ta[t]), fy);
                point_vortex(my(tb[t]), -fy);
            }
            if (fz != 0.0) {
                point_vortex(mz(ta[t]), fz);
                point_vortex(mz(tb[t]), -fz);
                if (fy != 0.0) {
                    point_vortex(my(mz(tb[t])), fy * fz);
                    point_vortex(my(mz(ta[t])), -fy * fz);
                }
            }
        }
    }
    return tp;
}

SteadySolver::LegBend SteadySolver::leg_bend(const Vector3d& d) const {
    // The legs of strip s behind its trailing edge along d instead of x: the trailing-edge
    // horseshoe with legs along d less the one with legs along x (their bound segments cancel).
    // Legs along d are legs along x in the stretched frame rotated by R (rows d_s, e1, e2,
    // d_s = the stretched direction): the kernel runs there, the velocity is rotated back. A y
    // image commutes with R (d in the x-z plane, wake_direction); with beta = 1 in the kernel,
    // x is divided by the Prandtl-Glauert factor here.
    const Stretched& te = kernel_->te;
    const Vector3d ds = stretch(d, beta_pg_).normalized();
    Eigen::Matrix3d R;
    const Vector3d e1 = (Vector3d::UnitY() - ds.y() * ds).normalized();
    R.row(0) = ds.transpose();
    R.row(1) = e1.transpose();
    R.row(2) = ds.cross(e1).transpose();
    Stretched rot;
    rot.beta = 1.0;
    rot.fy = te.fy;
    rot.fz = 0.0;  // wake_direction: no z image with bent legs
    rot.z_plane = te.z_plane;
    rot.component = te.component;
    rot.core_in = te.core_in;
    rot.core_x = te.core_x;
    for (std::size_t t = 0; t < te.a.size(); ++t) {
        rot.a.push_back(R * te.a[t]);
        rot.b.push_back(R * te.b[t]);
    }
    rot.prepare_rows();
    const int n = lattice_.size();
    const auto ns = static_cast<Eigen::Index>(te.a.size());
    LegBend lb;
    lb.C.setZero(n, ns);
    lb.U.setZero(3 * n, ns);
    Eigen::ArrayXd vx, vy, vz, wx, wy, wz;
    Eigen::ArrayXf fx, fy, fz, gx, gy, gz;
    const bool single = options_.single_precision;
    auto bend = [&](const Vector3d& x, int comp, Eigen::ArrayXd& dx, Eigen::ArrayXd& dy,
                    Eigen::ArrayXd& dz) {
        const Vector3d p = stretch(x, beta_pg_);
        if (single) {
            // As the influence matrix: the velocities in single precision.
            te.row_f(p, comp, fx, fy, fz);
            rot.row_f(R * p, comp, gx, gy, gz);
            vx = fx.cast<double>();
            vy = fy.cast<double>();
            vz = fz.cast<double>();
            wx = gx.cast<double>();
            wy = gy.cast<double>();
            wz = gz.cast<double>();
        } else {
            te.row(p, comp, vx, vy, vz);
            rot.row(R * p, comp, wx, wy, wz);
        }
        // R^T w - v, x component back to physical space.
        dx = (R(0, 0) * wx.head(ns) + R(1, 0) * wy.head(ns) + R(2, 0) * wz.head(ns) - vx.head(ns)) /
             beta_pg_;
        dy = R(0, 1) * wx.head(ns) + R(1, 1) * wy.head(ns) + R(2, 1) * wz.head(ns) - vy.head(ns);
        dz = R(0, 2) * wx.head(ns) + R(1, 2) * wy.head(ns) + R(2, 2) * wz.head(ns) - vz.head(ns);
    };
    // Mirror symmetry with legs in the plane of symmetry's normal directions (d_y = 0): the
    // image strip t' of strip t (sign s_t: +1 for a mirror copy, -1 for a strip in the plane,
    // its own image reversed) has Delta_t'(S p) = s_t S Delta_t(p), so the rows of the image
    // panel m(i) follow from those of i (C(m(i), t') = s_t s_i C(i, t)): half the work, and
    // exactly symmetric (symmetric states keep zero lateral loads).
    const bool mirrored = mirror_ && d.y() == 0.0;
    std::vector<Eigen::Index> strip_image(static_cast<std::size_t>(ns));
    std::vector<double> strip_sign(static_cast<std::size_t>(ns), 1.0);
    if (mirrored)
        for (std::size_t t = 0; t < static_cast<std::size_t>(ns); ++t) {
            const auto p0 = static_cast<std::size_t>(lattice_.strips[t].first_panel);
            strip_image[t] = lattice_.strip[static_cast<std::size_t>(mirror_->image[p0])];
            strip_sign[t] = mirror_->sign[p0];
        }
    Eigen::ArrayXd dx, dy, dz;
    auto point_rows = [&](int i) {
        const auto ii = static_cast<std::size_t>(i);
        const int comp = component_of(model_, lattice_, ii);
        if (!closure_row_[ii]) {
            bend(lattice_.control_point[ii], comp, dx, dy, dz);
            const Vector3d& nrm = lattice_.normal[ii];
            lb.C.row(i) = (dx * nrm.x() + dy * nrm.y() + dz * nrm.z()).matrix().transpose();
        }
        bend(mid_[ii], comp, dx, dy, dz);
        lb.U.row(3 * i) = dx.matrix().transpose();
        lb.U.row(3 * i + 1) = dy.matrix().transpose();
        lb.U.row(3 * i + 2) = dz.matrix().transpose();
        if (!mirrored) return;
        const int mi = mirror_->image[ii];
        if (mi == i) return;
        const double si = mirror_->sign[ii];
        for (Eigen::Index t = 0; t < ns; ++t) {
            const auto tt = static_cast<std::size_t>(t);
            const Eigen::Index tm = strip_image[tt];
            const double st = strip_sign[tt];
            lb.C(mi, tm) = st * si * lb.C(i, t);
            lb.U(3 * mi, tm) = st * lb.U(3 * i, t);
            lb.U(3 * mi + 1, tm) = -st * lb.U(3 * i + 1, t);
            lb.U(3 * mi + 2, tm) = st * lb.U(3 * i + 2, t);
        }
    };
    if (mirrored)
        for (const int i : mirror_->rep) point_rows(i);
    else
        for (int i = 0; i < n; ++i) point_rows(i);
    return lb;
}

SteadySolver::Units SteadySolver::solve_units(const MatrixXd& B, const Vector3d& d) const {
    Units u;
    u.G = solve_system(B);
    if (d == Vector3d::UnitX()) {
        u.U = induced_at_bound(u.G);
        u.plane = trefftz_x_;
        return u;
    }
    // Legs bent along d: (A + C S) G = B, S the strip sums (every horseshoe of a strip bends at
    // the same trailing-edge points, so the change C S has the rank of the strip count), solved
    // by the fixed-point iteration G <- A^-1 (B - C S G) with the factorisation of A, written as
    // corrections dG_{k+1} = -A^-1 C S dG_k that shrink by the wake's influence on the lattice
    // (about 20 times per step on the Ranger 2000), to 1e-9 of the largest circulation (seven
    // corrections there). Corrections below 1e-3 of the circulations are solved without
    // refinement (their relative error, 1e-5 with single-precision factors, leaves 1e-8 in G,
    // the accuracy of the single-precision path).
    const LegBend lb = leg_bend(d);
    const auto ns = static_cast<Eigen::Index>(lattice_.strips.size());
    const int n = lattice_.size();
    auto strip_sums = [&](const MatrixXd& G) {
        MatrixXd g = MatrixXd::Zero(ns, G.cols());
        for (int i = 0; i < n; ++i) g.row(lattice_.strip[static_cast<std::size_t>(i)]) += G.row(i);
        return g;
    };
    MatrixXd dG = solve_system(-lb.C * strip_sums(u.G));
    u.G += dG;
    const double scale = std::max(u.G.cwiseAbs().maxCoeff(), 1e-300);
    const double tol = 1e-9;
    bool converged = false;
    for (int it = 0; it < 100 && !converged; ++it) {
        const double size = dG.cwiseAbs().maxCoeff();
        converged = size <= tol * scale;
        if (converged) break;
        dG = solve_system(-lb.C * strip_sums(dG), size > 1e-3 * scale);
        u.G += dG;
    }
    if (!converged)
        throw ConvergenceError(fmt::format(
            "vlm: the trailing legs along the free stream ({:.4f}, {:.4f}, {:.4f}) did not "
            "converge in 100 iterations; expected a wake clear of the lattice (or use body-axis "
            "legs)",
            d.x(), d.y(), d.z()));
    const MatrixXd g = strip_sums(u.G);
    u.U = induced_at_bound(u.G) + lb.U * g;
    // Induced drag in the Trefftz plane normal to x, as with body-axis legs (the small-angle
    // far wake): the plane normal to the bent legs put the Ranger 2000's Trefftz drag 10 to 25 %
    // off its near-field drag in sideslip (against 2 to 4 % here), docs/vlm.md.
    u.plane = trefftz_x_;
    u.plane.d = d;
    return u;
}

SteadySolver::Units SteadySolver::units(const VectorXd& deflection, const Vector3d& d) const {
    const int n = lattice_.size();
    MatrixXd B(n, 6);
    for (int k = 0; k < 3; ++k) {
        B.col(k) = rhs(deflection, Vector3d::Unit(k), Vector3d::Zero());
        B.col(k + 3) = rhs(deflection, Vector3d::Zero(), Vector3d::Unit(k));
    }
    return solve_units(B, d);
}

MatrixXd SteadySolver::unit_circulations(const VectorXd& deflection) const {
    const int n = lattice_.size();
    MatrixXd B(n, 6);
    VectorXd d = deflection.size()
                     ? deflection
                     : VectorXd::Zero(static_cast<Eigen::Index>(lattice_.control_names.size()));
    for (int k = 0; k < 3; ++k) {
        B.col(k) = rhs(d, Vector3d::Unit(k), Vector3d::Zero());
        B.col(k + 3) = rhs(d, Vector3d::Zero(), Vector3d::Unit(k));
    }
    return solve_system(B);
}

namespace {

/// Loads from circulations `g` and induced velocities `vind` (3N) at the bound midpoints.
struct RawLoads {
    Vector3d F = Vector3d::Zero();  // geometry axes, rho = 1, V = 1
    Vector3d M = Vector3d::Zero();  // about the reference point
};

}  // namespace

SteadyResult SteadySolver::loads(const Units& u, const FlowState& s, bool with_detail) const {
    const Vector3d V = core::free_stream_geometry(s.alpha, s.beta);
    const Vector3d w = omega_geometry(model_.reference, s.p_hat, s.q_hat, s.r_hat);
    Eigen::Matrix<double, 6, 1> x;
    x << V, w;
    return loads_from(u.G * x, u.U * x, s, u.plane, with_detail);
}

SteadyResult SteadySolver::loads_from(const VectorXd& g, const VectorXd& vind, const FlowState& s,
                                      const Trefftz& tp, bool with_detail) const {
    const Reference& ref = model_.reference;
    const Vector3d V = core::free_stream_geometry(s.alpha, s.beta);
    const Vector3d w = omega_geometry(ref, s.p_hat, s.q_hat, s.r_hat);
    const int n = lattice_.size();
    RawLoads raw;
    SteadyResult r;
    if (with_detail) r.strips.assign(lattice_.strips.size(), StripLoad{});
    for (int i = 0; i < n; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const Vector3d rm = mid_[ii] - ref.point;
        const Vector3d vl = V - w.cross(rm) + vind.segment<3>(3 * i);
        const Vector3d l = lattice_.b[ii] - lattice_.a[ii];
        Vector3d f = g[i] * vl.cross(l);
        raw.F += f;
        raw.M += rm.cross(f);
        // The trailing legs run over the surface from the bound vortex to the trailing edge
        // and carry a load there too: Kutta-Joukowski with the onset flow (free stream and
        // rotation; the induced velocity of the chordwise legs is neglected, as in AVL). Under
        // sideslip or rotation the two legs of a horseshoe are loaded unequally; this is the
        // chordwise-vorticity share of the rolling moment due to sideslip of swept wings.
        const Strip& st = lattice_.strips[static_cast<std::size_t>(lattice_.strip[ii])];
        const Vector3d& pa = lattice_.a[ii];
        const Vector3d& pb = lattice_.b[ii];
        const double xte_a = st.le_a.x() + st.chord_a, xte_b = st.le_b.x() + st.chord_b;
        const Vector3d ra(0.5 * (pa.x() + xte_a), pa.y(), pa.z());
        const Vector3d rb(0.5 * (pb.x() + xte_b), pb.y(), pb.z());
        const Vector3d fa =
            g[i] * (V - w.cross(ra - ref.point)).cross(Vector3d(pa.x() - xte_a, 0.0, 0.0));
        const Vector3d fb =
            g[i] * (V - w.cross(rb - ref.point)).cross(Vector3d(xte_b - pb.x(), 0.0, 0.0));
        raw.F += fa + fb;
        raw.M += (ra - ref.point).cross(fa) + (rb - ref.point).cross(fb);
        f += fa + fb;
        if (with_detail) {
            StripLoad& sl = r.strips[static_cast<std::size_t>(lattice_.strip[ii])];
            sl.force += f / 0.5;
            sl.circulation += g[i];
        }
    }
    if (model_.y_symmetry == 1) {
        // Symmetric image (AVL IYsym = 1): the lattice is one half of the aircraft; the other
        // half's loads double the symmetric ones and cancel the antisymmetric ones.
        raw.F = Vector3d(2.0 * raw.F.x(), 0.0, 2.0 * raw.F.z());
        raw.M = Vector3d(0.0, 2.0 * raw.M.y(), 0.0);
    }
    const double qS = 0.5 * ref.area;
    const Vector3d F = core::body_from_geometry(raw.F), M = core::body_from_geometry(raw.M);
    r.body.CX = F.x() / qS;
    r.body.CY = F.y() / qS;
    r.body.CZ = F.z() / qS;
    r.body.Cl = M.x() / (qS * ref.span);
    r.body.Cm = M.y() / (qS * ref.chord);
    r.body.Cn = M.z() / (qS * ref.span);
    const auto wind = aero::wind_from_body(r.body.CX, r.body.CY, r.body.CZ, s.alpha, s.beta);
    r.CL = wind.CL;
    r.CD_near_field = wind.CD;
    r.CY = wind.CY;
    // Trefftz plane.
    const auto ns = lattice_.strips.size();
    VectorXd gs = VectorXd::Zero(static_cast<Eigen::Index>(ns));
    for (int i = 0; i < n; ++i) gs[lattice_.strip[static_cast<std::size_t>(i)]] += g[i];
    const VectorXd vt = tp.wash * gs;
    Vector3d Ft = Vector3d::Zero();
    for (std::size_t t = 0; t < ns; ++t) {
        const Strip& S = lattice_.strips[t];
        if (!S.sheds_wake) continue;
        const Vector3d vw = 0.5 * vt[static_cast<Eigen::Index>(2 * t)] * tp.e1 +
                            0.5 * vt[static_cast<Eigen::Index>(2 * t + 1)] * tp.e2;
        Ft += gs[static_cast<Eigen::Index>(t)] * (V + vw).cross(tp.l[t]);
    }
    if (model_.y_symmetry == 1) Ft = Vector3d(2.0 * Ft.x(), 0.0, 2.0 * Ft.z());
    const auto wt = aero::wind_from_body(-Ft.x() / qS, Ft.y() / qS, -Ft.z() / qS, s.alpha, s.beta);
    r.CL_trefftz = wt.CL;
    r.CD_trefftz = wt.CD;
    // Induced drag from the Trefftz plane (it converges faster with refinement than the near
    // field); the body-axis forces are rebuilt from the wind-axis set so the two agree.
    r.CD_induced = r.CD_trefftz;
    r.CD = r.CD_induced;
    set_wind_forces(r, r.CL, r.CD, r.CY, s.alpha, s.beta);
    add_profile_drag(r, model_.profile_drag, s.alpha, s.beta);
    const double AR = ref.span * ref.span / ref.area;
    r.span_efficiency = r.CD_trefftz != 0.0
                            ? r.CL_trefftz * r.CL_trefftz / (std::numbers::pi * AR * r.CD_trefftz)
                            : 0.0;
    r.wake_direction = tp.d;
    if (with_detail) {
        r.gamma = g;
        for (std::size_t t = 0; t < ns; ++t) {
            const Strip& S = lattice_.strips[t];
            const Vector3d e = S.le_b - S.le_a;
            const Vector3d nrm = Vector3d::UnitX().cross(Vector3d(0.0, e.y(), e.z()).normalized());
            r.strips[t].cl = r.strips[t].force.dot(nrm) / S.area;
        }
    }
    return r;
}

namespace {
VectorXd full_deflection(const Lattice& L, const VectorXd& d) {
    const auto nc = static_cast<Eigen::Index>(L.control_names.size());
    if (d.size() == 0) return VectorXd::Zero(nc);
    if (d.size() != nc)
        throw InputError(
            fmt::format("vlm: {} control values given; the lattice has {} controls", d.size(), nc));
    return d;
}
}  // namespace

SteadyResult SteadySolver::solve(const FlowState& state) const {
    FlowState s = state;
    s.deflection = full_deflection(lattice_, state.deflection);
    return loads(units(s.deflection, wake_direction(s)), s, true);
}

Derivatives SteadySolver::derivatives(const FlowState& state) const {
    FlowState s = state;
    s.deflection = full_deflection(lattice_, state.deflection);
    // One factorised solve and one induced-velocity pass for everything: the six unit solutions
    // at the deflection, and per control the change of the circulation at this state per unit
    // deflection (the right-hand side is linear in the deflections: first-order normals).
    const auto nc = static_cast<Eigen::Index>(lattice_.control_names.size());
    const int n = lattice_.size();
    const Vector3d V = core::free_stream_geometry(s.alpha, s.beta);
    const Vector3d w = omega_geometry(model_.reference, s.p_hat, s.q_hat, s.r_hat);
    MatrixXd B(n, 6 + nc);
    for (int k = 0; k < 3; ++k) {
        B.col(k) = rhs(s.deflection, Vector3d::Unit(k), Vector3d::Zero());
        B.col(k + 3) = rhs(s.deflection, Vector3d::Zero(), Vector3d::Unit(k));
    }
    const VectorXd b0 = rhs(s.deflection, V, w);
    for (Eigen::Index k = 0; k < nc; ++k) {
        VectorXd d1 = s.deflection;
        d1[k] += 1.0;
        B.col(6 + k) = rhs(d1, V, w) - b0;
    }
    // Legs frozen at the state's direction for every derivative.
    Units all = solve_units(B, wake_direction(s));
    const MatrixXd& G_all = all.G;
    const MatrixXd& U_all = all.U;
    Units u;
    u.G = G_all.leftCols(6);
    u.U = U_all.leftCols(6);
    u.plane = all.plane;
    Derivatives d;
    d.state = loads(u, s, true);
    auto vec = [](const SteadyResult& r) {
        Eigen::Matrix<double, 6, 1> v;
        v << r.CL, r.CD_induced, r.CY, r.body.Cl, r.body.Cm, r.body.Cn;
        return v;
    };
    // Stability axes: x along the projection of the velocity on the body x-z plane. The side
    // force is the force along their y axis (the body y axis) from the near-field forces, not
    // the wind-axis CY: the beta derivatives of the two differ by the drag.
    auto stab = [](const SteadyResult& r, double alpha, double beta) {
        Eigen::Matrix<double, 6, 1> v;
        const double ca = std::cos(alpha), sa = std::sin(alpha);
        const double cy =
            aero::body_from_wind(r.CL, r.CD_near_field + r.CD_profile, r.CY, alpha, beta)[1];
        v << r.CL, r.CD_induced, cy, r.body.Cl * ca + r.body.Cn * sa, r.body.Cm,
            -r.body.Cl * sa + r.body.Cn * ca;
        return v;
    };
    const double h = 1e-4;
    for (int k = 0; k < 5; ++k) {
        FlowState sp = s, sm = s;
        double* vp[5] = {&sp.alpha, &sp.beta, &sp.p_hat, &sp.q_hat, &sp.r_hat};
        double* vm[5] = {&sm.alpha, &sm.beta, &sm.p_hat, &sm.q_hat, &sm.r_hat};
        *vp[k] += h;
        *vm[k] -= h;
        d.body.col(k) = (vec(loads(u, sp, false)) - vec(loads(u, sm, false))) / (2 * h);
    }
    // Stability-axis set: rates given about stability axes, moments resolved on them.
    {
        const double a0 = s.alpha;
        const double ca = std::cos(a0), sa = std::sin(a0);
        // Stability rates of the state.
        const double ps = s.p_hat * ca + s.r_hat * sa, rs = -s.p_hat * sa + s.r_hat * ca;
        auto eval = [&](double alpha, double beta, double p_s, double q, double r_s) {
            FlowState t = s;
            t.alpha = alpha;
            t.beta = beta;
            const double c = std::cos(alpha), si = std::sin(alpha);
            t.p_hat = p_s * c - r_s * si;
            t.r_hat = p_s * si + r_s * c;
            t.q_hat = q;
            return stab(loads(u, t, false), alpha, beta);
        };
        const double x0[5] = {a0, s.beta, ps, s.q_hat, rs};
        for (int k = 0; k < 5; ++k) {
            double xp[5], xm[5];
            for (int m = 0; m < 5; ++m) xp[m] = xm[m] = x0[m];
            xp[k] += h;
            xm[k] -= h;
            d.stability.col(k) = (eval(xp[0], xp[1], xp[2], xp[3], xp[4]) -
                                  eval(xm[0], xm[1], xm[2], xm[3], xm[4])) /
                                 (2 * h);
        }
    }
    // Controls: the loads at deflection +-h from the circulation and induced velocity changes
    // found above (the loads are quadratic in them, so the central difference is exact).
    d.control.setZero(6, nc);
    d.control_stability.setZero(6, nc);
    if (nc > 0) {
        Eigen::Matrix<double, 6, 1> x;
        x << V, w;
        const VectorXd g0 = u.G * x;
        const VectorXd v0 = u.U * x;
        for (Eigen::Index k = 0; k < nc; ++k) {
            const SteadyResult rp =
                loads_from(g0 + h * G_all.col(6 + k), v0 + h * U_all.col(6 + k), s, u.plane, false);
            const SteadyResult rm =
                loads_from(g0 - h * G_all.col(6 + k), v0 - h * U_all.col(6 + k), s, u.plane, false);
            d.control.col(k) = (vec(rp) - vec(rm)) / (2 * h);
            d.control_stability.col(k) =
                (stab(rp, s.alpha, s.beta) - stab(rm, s.alpha, s.beta)) / (2 * h);
        }
    }
    const double CLa = d.body(0, 0), Cma = d.body(4, 0);
    d.static_margin = CLa != 0.0 ? -Cma / CLa : 0.0;
    d.x_neutral_point = model_.reference.point.x() + d.static_margin * model_.reference.chord;
    return d;
}

}  // namespace manta::vlm
