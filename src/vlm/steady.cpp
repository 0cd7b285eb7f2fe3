#include "manta/vlm/steady.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"
#include "manta/vlm/detail/biot_savart.hpp"

namespace manta::vlm {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

Vector3d freestream_geometry(double alpha, double beta) {
    // Aircraft velocity in body axes (V cos a cos b, V sin b, V sin a cos b); the air moves the
    // opposite way, and geometry axes are body axes with x and z reversed.
    return {std::cos(alpha) * std::cos(beta), -std::sin(beta), std::sin(alpha) * std::cos(beta)};
}

Vector3d omega_geometry(const Reference& ref, double p_hat, double q_hat, double r_hat) {
    // p = 2 V p_hat / b with V = 1; body (p, q, r) -> geometry (-p, q, -r).
    return {-2.0 * p_hat / ref.span, 2.0 * q_hat / ref.chord, -2.0 * r_hat / ref.span};
}

namespace {

/// Velocity at p (stretched coordinates) of horseshoe j of the lattice (stretched ends), with
/// the x component returned to physical space (divided by beta).
struct Stretched {
    std::vector<Vector3d> a, b, ta, tb;  // bound ends, trailing-edge ends (no-wake surfaces)
    std::vector<char> wake;
    double beta = 1.0;
    double core2 = 0.0;  // squared core radius of trailing legs [m^2], stretched

    [[nodiscard]] Vector3d at(const Vector3d& p, std::size_t j) const {
        Vector3d v = detail::segment(p, a[j], b[j]);
        if (wake[j]) {
            const Vector3d x = Vector3d::UnitX();
            v +=
                detail::semi_infinite(p, b[j], x, core2) - detail::semi_infinite(p, a[j], x, core2);
        } else {
            // No wake: a closed ring through the trailing edge, so the surface sheds no net
            // circulation (its strips carry no Kutta condition and almost no net lift).
            v += detail::segment(p, b[j], tb[j]) + detail::segment(p, tb[j], ta[j]) +
                 detail::segment(p, ta[j], a[j]);
        }
        v.x() /= beta;
        return v;
    }
};

Vector3d stretch(const Vector3d& p, double beta) {
    return {p.x() / beta, p.y(), p.z()};
}

Stretched make_stretched(const Lattice& L, double beta, double lref) {
    Stretched s;
    s.beta = beta;
    s.core2 = std::pow(1e-6 * lref, 2);
    const auto n = static_cast<std::size_t>(L.size());
    s.a.resize(n);
    s.b.resize(n);
    s.ta.resize(n);
    s.tb.resize(n);
    s.wake.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
        s.a[j] = stretch(L.a[j], beta);
        s.b[j] = stretch(L.b[j], beta);
        const Strip& st = L.strips[static_cast<std::size_t>(L.strip[j])];
        s.ta[j] = stretch(Vector3d(st.le_a.x() + st.chord_a, L.a[j].y(), L.a[j].z()), beta);
        s.tb[j] = stretch(Vector3d(st.le_b.x() + st.chord_b, L.b[j].y(), L.b[j].z()), beta);
        s.wake[j] = L.wake[j] ? 1 : 0;
    }
    return s;
}

}  // namespace

struct SteadySolver::Units {
    MatrixXd G;  // N x K circulations
    MatrixXd U;  // 3N x K induced velocity at bound midpoints
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

SteadySolver::SteadySolver(const Model& model, Lattice lattice, double mach)
    : model_(model), lattice_(std::move(lattice)), mach_(mach) {
    if (!(mach >= 0.0 && mach < 0.95))
        throw InputError(fmt::format(
            "vlm: Mach {}; expected 0 <= M < 0.95 (Prandtl-Glauert is subsonic)", mach));
    check_lattice(model_, lattice_);
    beta_pg_ = std::sqrt(1.0 - mach * mach);
    const int n = lattice_.size();
    const Stretched st = make_stretched(lattice_, beta_pg_, model_.reference.chord);
    MatrixXd A(n, n);
    for (int i = 0; i < n; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const Vector3d p = stretch(lattice_.control_point[ii], beta_pg_);
        const Vector3d& nrm = lattice_.normal[ii];
        for (int j = 0; j < n; ++j) A(i, j) = st.at(p, static_cast<std::size_t>(j)).dot(nrm);
    }
    lu_.compute(A);
    mid_.resize(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < mid_.size(); ++i) mid_[i] = 0.5 * (lattice_.a[i] + lattice_.b[i]);
    // Trefftz plane: the wake of strip t is a pair of infinite 2-D vortices at its edges (the
    // trailing legs far downstream); wash at the centre of strip s per unit circulation of t.
    const auto ns = lattice_.strips.size();
    trefftz_.setZero(static_cast<Eigen::Index>(2 * ns), static_cast<Eigen::Index>(ns));
    for (std::size_t s = 0; s < ns; ++s) {
        const Strip& S = lattice_.strips[s];
        const Eigen::Vector2d c(S.le_mid.y(), S.le_mid.z());
        for (std::size_t t = 0; t < ns; ++t) {
            const Strip& T = lattice_.strips[t];
            if (!T.sheds_wake) continue;
            auto point_vortex = [&](const Vector3d& q, double sign) {
                // Vortex along +x through q: v = G/(2 pi) x-hat x (P - q) / |P - q|^2.
                const double dy = c.x() - q.y(), dz = c.y() - q.z();
                const double r2 = dy * dy + dz * dz;
                if (r2 <= 1e-24) return;
                const double k = sign / (2.0 * std::numbers::pi * r2);
                trefftz_(static_cast<Eigen::Index>(2 * s), static_cast<Eigen::Index>(t)) += -k * dz;
                trefftz_(static_cast<Eigen::Index>(2 * s + 1), static_cast<Eigen::Index>(t)) +=
                    k * dy;
            };
            // Legs: b -> infinity (+x) and infinity -> a (-x).
            point_vortex(T.le_b, 1.0);
            point_vortex(T.le_a, -1.0);
        }
    }
}

VectorXd SteadySolver::rhs(const VectorXd& deflection, const Vector3d& v, const Vector3d& w) const {
    const int n = lattice_.size();
    VectorXd b(n);
    for (int i = 0; i < n; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const Vector3d r = lattice_.control_point[ii] - model_.reference.point;
        const Vector3d nrm = lattice_.deflected_normal(i, deflection);
        b[i] = -(v - w.cross(r)).dot(nrm);
    }
    return b;
}

MatrixXd SteadySolver::induced_at_bound(const MatrixXd& gamma) const {
    const int n = lattice_.size();
    const auto K = gamma.cols();
    const Stretched st = make_stretched(lattice_, beta_pg_, model_.reference.chord);
    MatrixXd U = MatrixXd::Zero(3 * n, K);
    const MatrixXd gt = gamma.transpose();  // K x N: column j holds horseshoe j's strengths
    for (int i = 0; i < n; ++i) {
        const Vector3d p = stretch(mid_[static_cast<std::size_t>(i)], beta_pg_);
        Eigen::Matrix<double, 3, Eigen::Dynamic> acc =
            Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, K);
        for (int j = 0; j < n; ++j) {
            const Vector3d v = st.at(p, static_cast<std::size_t>(j));
            acc.noalias() += v * gt.col(j).transpose();
        }
        U.middleRows(3 * i, 3) = acc;
    }
    return U;
}

SteadySolver::Units SteadySolver::units(const VectorXd& deflection) const {
    const int n = lattice_.size();
    MatrixXd B(n, 6);
    for (int k = 0; k < 3; ++k) {
        B.col(k) = rhs(deflection, Vector3d::Unit(k), Vector3d::Zero());
        B.col(k + 3) = rhs(deflection, Vector3d::Zero(), Vector3d::Unit(k));
    }
    Units u;
    u.G = lu_.solve(B);
    u.U = induced_at_bound(u.G);
    return u;
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
    return lu_.solve(B);
}

namespace {

/// Loads from circulations `g` and induced velocities `vind` (3N) at the bound midpoints.
struct RawLoads {
    Vector3d F = Vector3d::Zero();  // geometry axes, rho = 1, V = 1
    Vector3d M = Vector3d::Zero();  // about the reference point
};

}  // namespace

SteadyResult SteadySolver::loads(const Units& u, const FlowState& s, bool with_detail) const {
    const Vector3d V = freestream_geometry(s.alpha, s.beta);
    const Vector3d w = omega_geometry(model_.reference, s.p_hat, s.q_hat, s.r_hat);
    Eigen::Matrix<double, 6, 1> x;
    x << V, w;
    return loads_from(u.G * x, u.U * x, s, with_detail);
}

SteadyResult SteadySolver::loads_from(const VectorXd& g, const VectorXd& vind, const FlowState& s,
                                      bool with_detail) const {
    const Reference& ref = model_.reference;
    const Vector3d V = freestream_geometry(s.alpha, s.beta);
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
        const Vector3d f = g[i] * vl.cross(l);
        raw.F += f;
        raw.M += rm.cross(f);
        if (with_detail) {
            StripLoad& sl = r.strips[static_cast<std::size_t>(lattice_.strip[ii])];
            sl.force += f / 0.5;
            sl.circulation += g[i];
        }
    }
    const double qS = 0.5 * ref.area;
    r.body.CX = -raw.F.x() / qS;
    r.body.CY = raw.F.y() / qS;
    r.body.CZ = -raw.F.z() / qS;
    r.body.Cl = -raw.M.x() / (qS * ref.span);
    r.body.Cm = raw.M.y() / (qS * ref.chord);
    r.body.Cn = -raw.M.z() / (qS * ref.span);
    const auto wind = aero::wind_from_body(r.body.CX, r.body.CY, r.body.CZ, s.alpha, s.beta);
    r.CL = wind.CL;
    r.CD_near_field = wind.CD;
    r.CY = wind.CY;
    // Trefftz plane.
    const auto ns = lattice_.strips.size();
    VectorXd gs = VectorXd::Zero(static_cast<Eigen::Index>(ns));
    for (int i = 0; i < n; ++i) gs[lattice_.strip[static_cast<std::size_t>(i)]] += g[i];
    const VectorXd vt = trefftz_ * gs;
    Vector3d Ft = Vector3d::Zero();
    for (std::size_t t = 0; t < ns; ++t) {
        const Strip& S = lattice_.strips[t];
        if (!S.sheds_wake) continue;
        const Vector3d l(0.0, S.le_b.y() - S.le_a.y(), S.le_b.z() - S.le_a.z());
        const Vector3d vw(0.0, 0.5 * vt[static_cast<Eigen::Index>(2 * t)],
                          0.5 * vt[static_cast<Eigen::Index>(2 * t + 1)]);
        Ft += gs[static_cast<Eigen::Index>(t)] * (V + vw).cross(l);
    }
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
    return loads(units(s.deflection), s, true);
}

Derivatives SteadySolver::derivatives(const FlowState& state) const {
    FlowState s = state;
    s.deflection = full_deflection(lattice_, state.deflection);
    const Units u = units(s.deflection);
    Derivatives d;
    d.state = loads(u, s, true);
    auto vec = [](const SteadyResult& r) {
        Eigen::Matrix<double, 6, 1> v;
        v << r.CL, r.CD_induced, r.CY, r.body.Cl, r.body.Cm, r.body.Cn;
        return v;
    };
    // Stability axes: x along the projection of the velocity on the body x-z plane.
    auto stab = [](const SteadyResult& r, double alpha) {
        Eigen::Matrix<double, 6, 1> v;
        const double ca = std::cos(alpha), sa = std::sin(alpha);
        v << r.CL, r.CD_induced, r.CY, r.body.Cl * ca + r.body.Cn * sa, r.body.Cm,
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
            return stab(loads(u, t, false), alpha);
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
    // Controls: the circulation at deflection +-h of each control, one back substitution each,
    // and one pass for all the induced velocities.
    const auto nc = static_cast<Eigen::Index>(lattice_.control_names.size());
    d.control.setZero(6, nc);
    d.control_stability.setZero(6, nc);
    if (nc > 0) {
        const Vector3d V = freestream_geometry(s.alpha, s.beta);
        const Vector3d w = omega_geometry(model_.reference, s.p_hat, s.q_hat, s.r_hat);
        const int n = lattice_.size();
        MatrixXd B(n, 2 * nc);
        for (Eigen::Index k = 0; k < nc; ++k) {
            VectorXd dp = s.deflection, dm = s.deflection;
            dp[k] += h;
            dm[k] -= h;
            B.col(2 * k) = rhs(dp, V, w);
            B.col(2 * k + 1) = rhs(dm, V, w);
        }
        const MatrixXd G = lu_.solve(B);
        const MatrixXd U = induced_at_bound(G);
        for (Eigen::Index k = 0; k < nc; ++k) {
            const SteadyResult rp = loads_from(G.col(2 * k), U.col(2 * k), s, false);
            const SteadyResult rm = loads_from(G.col(2 * k + 1), U.col(2 * k + 1), s, false);
            d.control.col(k) = (vec(rp) - vec(rm)) / (2 * h);
            d.control_stability.col(k) = (stab(rp, s.alpha) - stab(rm, s.alpha)) / (2 * h);
        }
    }
    const double CLa = d.body(0, 0), Cma = d.body(4, 0);
    d.static_margin = CLa != 0.0 ? -Cma / CLa : 0.0;
    d.x_neutral_point = model_.reference.point.x() + d.static_margin * model_.reference.chord;
    return d;
}

}  // namespace manta::vlm
