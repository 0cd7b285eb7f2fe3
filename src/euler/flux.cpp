/// @file flux.cpp
/// Point-wise numerics of the Euler solver (flux.hpp): physical flux, Roe and HLLC numerical
/// fluxes, their first-order Jacobians, slip-wall and characteristic far-field fluxes.
///
/// Everything here runs once per edge or boundary node per iteration: fixed-size Eigen and
/// scalars only, no heap allocation, no virtual calls.

#include "manta/euler/flux.hpp"

#include <algorithm>
#include <cmath>

namespace manta::euler {

namespace {

/// Harten's entropy fix (Harten 1983, J. Comput. Phys. 49; Harten & Hyman 1983, J. Comput.
/// Phys. 50): |l| below the width d is replaced by the
/// parabola (l^2 + d^2) / (2 d), which keeps the modulus continuous and bounded away from 0.
/// Written as a select so that it compiles without a branch (the test is data-dependent).
inline double harten(double l, double d, double half_inv_d) noexcept {
    const double a = std::abs(l);
    const double smoothed = (a * a + d * d) * half_inv_d;
    return a < d ? smoothed : a;
}

/// Physical flux of one state through a face moving with grid flux g, given its normal velocity
/// u.n (area-weighted) and total enthalpy, written into `F`: F.n - g U = (rho (V - g),
/// rho u (V - g) + p n, rho H (V - g) + p g).
inline void flux_of(double rho, const Vec3& u, double p, double H, double Vn, double g,
                    const Vec3& n, Vec5& F) noexcept {
    const double m = rho * (Vn - g);
    F[0] = m;
    F.segment<3>(1) = m * u + p * n;
    F[4] = m * H + p * g;
}

/// Roe-averaged state and its (entropy-fixed) eigenvalue moduli through `n`.
struct RoeAverage {
    double rho;  ///< Roe-averaged density sqrt(rhoL rhoR)
    Vec3 u;      ///< velocity
    double H;    ///< total enthalpy
    double q2;   ///< |u|^2
    double c;    ///< speed of sound
    double Vn;   ///< u . n_hat
    Vec3 nh;     ///< unit normal
    double l1;   ///< |u.n - g - c |n||, entropy-fixed
    double l2;   ///< |u.n - g|, entropy-fixed (entropy and shear waves)
    double l5;   ///< |u.n - g + c |n||, entropy-fixed
};

/// Roe average (Roe 1981) of two primitive states, with the eigenvalue moduli of A - g I (times
/// the face area) after Harten's entropy fix of width fix (|u.n - g/|n|| + c) |n|; `gh` is
/// g / |n|, the face's normal speed.
inline RoeAverage roe_average(const Vec5& WL, const Vec5& WR, double HL, double HR, const Vec3& n,
                              double area, double gh, double gamma, double fix) noexcept {
    RoeAverage r;
    // Two independent square roots and one division keep the dependency chain short.
    const double sL = std::sqrt(WL[0]), sR = std::sqrt(WR[0]);
    const double inv = 1.0 / (sL + sR);
    const double wl = sL * inv, wr = sR * inv;
    r.rho = sL * sR;
    r.u = wl * WL.segment<3>(1) + wr * WR.segment<3>(1);
    r.H = wl * HL + wr * HR;
    r.q2 = r.u.squaredNorm();
    r.c = std::sqrt((gamma - 1.0) * (r.H - 0.5 * r.q2));
    r.nh = n * (1.0 / area);
    r.Vn = r.u.dot(r.nh);
    // The eigenvalues relative to the moving face (g = 0: exactly those of a fixed one).
    const double Vr = r.Vn - gh;
    const double d = fix * (std::abs(Vr) + r.c) * area;
    const double h = 0.5 / d;  // inf when the fix is off: then never selected
    r.l1 = harten((Vr - r.c) * area, d, h);
    r.l2 = harten(Vr * area, d, h);
    r.l5 = harten((Vr + r.c) * area, d, h);
    return r;
}

/// Total enthalpy of a primitive state; gg = gamma / (gamma - 1).
inline double enthalpy(const Vec5& W, double gg) noexcept {
    return gg * W[4] / W[0] + 0.5 * W.segment<3>(1).squaredNorm();
}

/// Rieper's factor z = min(1, max(M_L, M_R)) of two primitive states.
inline double low_mach_factor(const Vec5& WL, const Vec5& WR, double gamma) noexcept {
    const double m2L = WL.segment<3>(1).squaredNorm() * WL[0] / (gamma * WL[4]);
    const double m2R = WR.segment<3>(1).squaredNorm() * WR[0] / (gamma * WR[4]);
    return std::min(1.0, std::sqrt(std::max(m2L, m2R)));
}

/// Roe's flux (Roe 1981, J. Comput. Phys. 43) through a face moving with grid flux g, with
/// Harten's entropy fix of width `fix` and, if `low_mach`, Rieper's low-Mach fix:
/// (F(WL).n + F(WR).n - g (UL + UR) - |A_roe - g I| dU) / 2.
Vec5 roe_flux(const Vec5& WL, const Vec5& WR, const Vec3& n, double g, double gamma, double fix,
              bool low_mach) noexcept {
    const double area = n.norm();
    const double ig = 1.0 / (gamma - 1.0), gg = gamma * ig;
    const Vec3 uL = WL.segment<3>(1), uR = WR.segment<3>(1);
    const double HL = enthalpy(WL, gg), HR = enthalpy(WR, gg);
    const RoeAverage r = roe_average(WL, WR, HL, HR, n, area, g / area, gamma, fix);

    // Dissipation |A_roe| dU in wave-strength form: the acoustic waves carry
    // a1,5 = (dp -+ rho c d(u.n)) / (2 c^2) along r1,5 = (1, u -+ c n, H -+ c u.n); the entropy
    // and shear waves together are dU minus the two acoustic waves, so
    // |A| dU = l2 dU + (l1 - l2) a1 r1 + (l5 - l2) a5 r5 (Blazek 2015, sec. 4.3.3).
    const double dp = WR[4] - WL[4];
    const double dVn = (uR - uL).dot(r.nh);
    const double inv2c2 = 0.5 / (r.c * r.c);
    const double rc = r.rho * r.c;
    double a1 = (dp - rc * dVn) * inv2c2 * (r.l1 - r.l2);
    double a5 = (dp + rc * dVn) * inv2c2 * (r.l5 - r.l2);
    if (low_mach) {
        // Acoustic strengths with z d(u.n) in place of d(u.n): with the entropy and shear waves
        // still dU minus the unmodified acoustic waves, |A| dU gains l1 (1 - z) s r1 and loses
        // l5 (1 - z) s r5, s = rho c d(u.n) / (2 c^2).
        const double sv = (1.0 - low_mach_factor(WL, WR, gamma)) * rc * dVn * inv2c2;
        a1 += r.l1 * sv;
        a5 -= r.l5 * sv;
    }
    const Vec3 mL = WL[0] * uL, mR = WR[0] * uR;
    const double EL = WL[4] * ig + 0.5 * mL.dot(uL);
    const double ER = WR[4] * ig + 0.5 * mR.dot(uR);
    // Normal velocities relative to the face (area-weighted).
    const double VL = uL.dot(n) - g, VR = uR.dot(n) - g;
    const double sa = a1 + a5, da = (a5 - a1) * r.c;

    // F = (F(WL) + F(WR) - g (UL + UR) - |A - g I| dU) / 2.
    Vec5 F;
    F[0] = 0.5 * (WL[0] * VL + WR[0] * VR - r.l2 * (WR[0] - WL[0]) - sa);
    F.segment<3>(1) =
        0.5 * (mL * VL + mR * VR + (WL[4] + WR[4]) * n - r.l2 * (mR - mL) - sa * r.u - da * r.nh);
    F[4] = 0.5 * (WL[0] * HL * VL + WR[0] * HR * VR + (WL[4] + WR[4]) * g - r.l2 * (ER - EL) -
                  sa * r.H - da * r.Vn);
    return F;
}

/// HLLC flux (Toro, Spruce & Speares 1994, Shock Waves 4; Toro 2009, ch. 10) with Einfeldt's
/// wave-speed estimates, through a face moving with grid flux g: the Riemann fan is sampled at
/// the face's normal speed s = g / |n|, F - s U of the state there (F*K - s U*K = F_K - s U_K +
/// (S_K - s)(U*K - U_K)).
Vec5 hllc_flux(const Vec5& WL, const Vec5& WR, const Vec3& n, double g, double gamma) noexcept {
    const double area = n.norm();
    const Vec3 nh = n * (1.0 / area);
    const Vec3 uL = WL.segment<3>(1), uR = WR.segment<3>(1);
    const double rhoL = WL[0], rhoR = WR[0], pL = WL[4], pR = WR[4];
    const double gg = gamma / (gamma - 1.0);
    const double prL = pL / rhoL, prR = pR / rhoR;
    const double HL = gg * prL + 0.5 * uL.squaredNorm(), HR = gg * prR + 0.5 * uR.squaredNorm();
    const double qL = uL.dot(nh), qR = uR.dot(nh);
    const double cL = std::sqrt(gamma * prL), cR = std::sqrt(gamma * prR);

    // Einfeldt's wave-speed estimates from the Roe average (Toro 2009, eq. 10.52).
    const double sL = std::sqrt(rhoL), sR = std::sqrt(rhoR);
    const double inv = 1.0 / (sL + sR);
    const double wl = sL * inv, wr = sR * inv;
    const Vec3 u = wl * uL + wr * uR;
    const double H = wl * HL + wr * HR;
    const double c = std::sqrt((gamma - 1.0) * (H - 0.5 * u.squaredNorm()));
    const double q = u.dot(nh);
    const double SL = std::min(qL - cL, q - c);
    const double SR = std::max(qR + cR, q + c);
    const double s = g / area;  // the face's normal speed

    Vec5 F;
    if (SL >= s) {
        flux_of(rhoL, uL, pL, HL, qL * area, g, n, F);
        return F;
    }
    if (SR <= s) {
        flux_of(rhoR, uR, pR, HR, qR * area, g, n, F);
        return F;
    }
    // Contact speed (Toro 2009, eq. 10.37).
    const double mL = rhoL * (SL - qL), mR = rhoR * (SR - qR);
    const double Ss = (pR - pL + mL * qL - mR * qR) / (mL - mR);
    // Star state of the upwind side K of the contact (Toro 2009, eq. 10.39),
    // U*K = rho_K f (1, u_K + (S* - q_K) n, E_K / rho_K + (S* - q_K) (S* + p_K / m_K)) with
    // f = (S_K - q_K) / (S_K - S*) and m_K = rho_K (S_K - q_K), and F*K = F_K + S_K (U*K - U_K).
    const bool left = Ss >= s;
    const double rho = left ? rhoL : rhoR, p = left ? pL : pR, qK = left ? qL : qR;
    const double SK = left ? SL : SR, HK = left ? HL : HR;
    const Vec3& uK = left ? uL : uR;
    const double E = rho * HK - p;  // rho E
    const double i = 1.0 / (SK - Ss);
    const double f = (SK - qK) * i, dq = Ss - qK;
    // (S_K - s) (U*K - U_K), per unit area.
    const double Sr = SK - s;
    const double w = Sr * rho * (f - 1.0);
    Vec5 dF;
    dF[0] = w;
    dF.segment<3>(1) = w * uK + (Sr * rho * f * dq) * nh;
    dF[4] = Sr * ((f - 1.0) * E + dq * (f * rho * Ss + p * i));
    flux_of(rho, uK, p, HK, qK * area, g, n, F);
    return F + area * dF;
}

/// dU/dW: Jacobian of the conservative state with respect to the primitive one.
inline Mat5 dU_dW(const Vec5& W, double gamma) noexcept {
    const double rho = W[0];
    const Vec3 u = W.segment<3>(1);
    Mat5 M = Mat5::Zero();
    M(0, 0) = 1.0;
    M.block<3, 1>(1, 0) = u;
    M.block<3, 3>(1, 1).diagonal().setConstant(rho);
    M(4, 0) = 0.5 * u.squaredNorm();
    M.block<1, 3>(4, 1) = rho * u.transpose();
    M(4, 4) = 1.0 / (gamma - 1.0);
    return M;
}

/// dW/dU: Jacobian of the primitive state with respect to the conservative one.
inline Mat5 dW_dU(const Vec5& W, double gamma) noexcept {
    const double rho = W[0], ir = 1.0 / rho, g1 = gamma - 1.0;
    const Vec3 u = W.segment<3>(1);
    Mat5 M = Mat5::Zero();
    M(0, 0) = 1.0;
    M.block<3, 1>(1, 0) = -ir * u;
    M.block<3, 3>(1, 1).diagonal().setConstant(ir);
    M(4, 0) = 0.5 * g1 * u.squaredNorm();
    M.block<1, 3>(4, 1) = -g1 * u.transpose();
    M(4, 4) = g1;
    return M;
}

}  // namespace

Vec5 physical_flux(const Vec5& W, const Vec3& n, double g, double gamma) noexcept {
    const Vec3 u = W.segment<3>(1);
    Vec5 F;
    flux_of(W[0], u, W[4], enthalpy(W, gamma / (gamma - 1.0)), u.dot(n), g, n, F);
    return F;
}

Vec5 numerical_flux(const Vec5& WL, const Vec5& WR, const Vec3& n, double g, double gamma,
                    const FluxOptions& options) noexcept {
    if (options.scheme == FluxScheme::hllc) return hllc_flux(WL, WR, n, g, gamma);
    return roe_flux(WL, WR, n, g, gamma, options.entropy_fix, options.low_mach_fix);
}

Mat5 physical_flux_jacobian(const Vec5& W, const Vec3& n, double g, double gamma) noexcept {
    const double g1 = gamma - 1.0;
    const Vec3 u = W.segment<3>(1);
    const double V = u.dot(n);
    const double phi = 0.5 * g1 * u.squaredNorm();
    const double H = enthalpy(W, gamma / (gamma - 1.0));
    Mat5 A;
    A(0, 0) = 0.0;
    A.block<1, 3>(0, 1) = n.transpose();
    A(0, 4) = 0.0;
    A.block<3, 1>(1, 0) = phi * n - V * u;
    A.block<3, 3>(1, 1) = u * n.transpose() - g1 * n * u.transpose();
    A.block<3, 3>(1, 1).diagonal().array() += V;
    A.block<3, 1>(1, 4) = g1 * n;
    A(4, 0) = V * (phi - H);
    A.block<1, 3>(4, 1) = H * n.transpose() - g1 * V * u.transpose();
    A(4, 4) = gamma * V;
    A.diagonal().array() -= g;  // - g I (g = 0: unchanged)
    return A;
}

void flux_jacobians(const Vec5& WL, const Vec5& WR, const Vec3& n, double g, double gamma,
                    const FluxOptions& options, Mat5& dF_dUL, Mat5& dF_dUR) noexcept {
    const double area = n.norm();
    const double gg = gamma / (gamma - 1.0);
    const double HL = enthalpy(WL, gg), HR = enthalpy(WR, gg);
    const RoeAverage r = roe_average(WL, WR, HL, HR, n, area, g / area, gamma, options.entropy_fix);
    // |A_roe| = R |Lambda| L = l2 I + (l1 - l2) r1 L1 + (l5 - l2) r5 L5 with the left
    // eigenvectors of the acoustic waves L1,5 = ((g-1) (q^2/2, -u, 1) -+ c (-u.n, n, 0)) / (2c^2)
    // (the rows giving the wave strengths a1,5 from dU).
    const double g1 = gamma - 1.0;
    const double inv2c2 = 0.5 / (r.c * r.c);
    Eigen::Matrix<double, 1, 5> Lp, Lc;
    Lp << 0.5 * g1 * r.q2, -g1 * r.u.x(), -g1 * r.u.y(), -g1 * r.u.z(), g1;
    Lc << -r.c * r.Vn, r.c * r.nh.x(), r.c * r.nh.y(), r.c * r.nh.z(), 0.0;
    Vec5 R1, R5;
    R1 << 1.0, r.u - r.c * r.nh, r.H - r.c * r.Vn;
    R5 << 1.0, r.u + r.c * r.nh, r.H + r.c * r.Vn;
    Mat5 D = ((r.l1 - r.l2) * inv2c2) * R1 * (Lp - Lc) + ((r.l5 - r.l2) * inv2c2) * R5 * (Lp + Lc);
    if (options.low_mach_fix && options.scheme == FluxScheme::roe) {
        // Rieper's fix with z frozen: + (1 - z) (l1 R1 - l5 R5) Lc / (2 c^2).
        const double w = (1.0 - low_mach_factor(WL, WR, gamma)) * inv2c2;
        D += (w * r.l1) * R1 * Lc - (w * r.l5) * R5 * Lc;
    }
    D.diagonal().array() += r.l2;
    dF_dUL = 0.5 * (physical_flux_jacobian(WL, n, g, gamma) + D);
    dF_dUR = 0.5 * (physical_flux_jacobian(WR, n, g, gamma) - D);
}

double spectral_radius(const Vec5& W, const Vec3& n, double g, double gamma) noexcept {
    return std::abs(W.segment<3>(1).dot(n) - g) + sound_speed(W, gamma) * n.norm();
}

Vec5 wall_flux(const Vec5& W, const Vec3& n, double g, double /*gamma*/) noexcept {
    Vec5 F;
    F << 0.0, W[4] * n, W[4] * g;
    return F;
}

Mat5 wall_flux_jacobian(const Vec5& W, const Vec3& n, double g, double gamma) noexcept {
    // dp/dU = (g-1) (|u|^2/2, -u, 1).
    const double g1 = gamma - 1.0;
    const Vec3 u = W.segment<3>(1);
    Eigen::Matrix<double, 1, 5> dp;
    dp << 0.5 * g1 * u.squaredNorm(), -g1 * u.transpose(), g1;
    Mat5 J = Mat5::Zero();
    J.block<3, 5>(1, 0) = n * dp;
    if (g != 0.0) J.row(4) = g * dp;  // the pressure work p g (skipped at g = 0: no -0 entries)
    return J;
}

Vec5 farfield_flux(const Vec5& W, const Vec5& W_inf, const Vec3& n, double g, double gamma,
                   Mat5* dF_dU) noexcept {
    const double area = n.norm();
    const Vec3 nh = n / area;
    const double g1 = gamma - 1.0;
    const Vec3 ui = W.segment<3>(1);
    const double ci = sound_speed(W, gamma);
    const double Vi = ui.dot(nh);
    const double s = g / area;  // the face's normal speed

    // Supersonic relative to the face: every characteristic comes from the upwind side.
    if (Vi - s <= -ci) {
        if (dF_dU) dF_dU->setZero();
        return physical_flux(W_inf, n, g, gamma);
    }
    if (Vi - s >= ci) {
        if (dF_dU) *dF_dU = physical_flux_jacobian(W, n, g, gamma);
        return physical_flux(W, n, g, gamma);
    }

    // Subsonic: R+ = u.n + 2c/(g-1) leaves the domain (interior), R- = u.n - 2c/(g-1) enters
    // it (free stream).
    const Vec3 uo = W_inf.segment<3>(1);
    const double co = sound_speed(W_inf, gamma);
    const double Rp = Vi + 2.0 * ci / g1;
    const double Rm = uo.dot(nh) - 2.0 * co / g1;
    const double Vb = 0.5 * (Rp + Rm);
    const double cb = 0.25 * g1 * (Rp - Rm);
    // Entropy p / rho^g and tangential velocity from the upwind side (relative to the face).
    const bool out = Vb - s >= 0.0;
    const Vec5& Wu = out ? W : W_inf;
    const double cu = out ? ci : co;
    const Vec3 uu = Wu.segment<3>(1);
    Vec5 Wb;
    // Same entropy as the upwind state: c^2 ~ rho^(g-1), so rho_b = rho_u (c_b / c_u)^(2/(g-1)).
    Wb[0] = Wu[0] * std::pow(cb / cu, 2.0 / g1);
    Wb.segment<3>(1) = uu + (Vb - uu.dot(nh)) * nh;
    Wb[4] = Wb[0] * cb * cb / gamma;
    const Vec5 F = physical_flux(Wb, n, g, gamma);
    if (!dF_dU) return F;

    // Chain rule dF/dU = dF/dWb dWb/dWi dWi/dUi. With dR+ = n.du + 2/(g-1) dc and
    // dc = c/2 (dp/p - drho/rho): dVb = dR+/2, dcb = (g-1)/4 dR+; drho_b/rho_b =
    // (2 dcb/cb - ds/s)/(g-1), dp_b/p_b = drho_b/rho_b + 2 dcb/cb, ds/s = dp/p - g drho/rho
    // (outflow only); du_b = (I - n n^T) du (outflow only) + n dVb.
    Eigen::Matrix<double, 1, 5> dRp;
    dRp << -ci / (g1 * W[0]), nh.transpose(), ci / (g1 * W[4]);
    const Eigen::Matrix<double, 1, 5> dcb_cb = (0.25 * g1 / cb) * dRp;
    Eigen::Matrix<double, 1, 5> dlnrho = (2.0 / g1) * dcb_cb;
    if (out) {
        Eigen::Matrix<double, 1, 5> dlns;
        dlns << -gamma / W[0], 0.0, 0.0, 0.0, 1.0 / W[4];
        dlnrho -= dlns / g1;
    }
    Mat5 dWb;
    dWb.row(0) = Wb[0] * dlnrho;
    dWb.block<3, 5>(1, 0) = 0.5 * nh * dRp;
    if (out) dWb.block<3, 3>(1, 1) += Eigen::Matrix3d::Identity() - nh * nh.transpose();
    dWb.row(4) = Wb[4] * (dlnrho + 2.0 * dcb_cb);
    *dF_dU = physical_flux_jacobian(Wb, n, g, gamma) * dU_dW(Wb, gamma) * dWb * dW_dU(W, gamma);
    return F;
}

}  // namespace manta::euler
