#pragma once
/// @file flux.hpp
/// Point-wise numerics of the Euler solver: the physical flux, the approximate Riemann solvers
/// (Roe with Harten's entropy fix, HLLC) and their first-order Jacobians, and the boundary
/// fluxes (slip wall / symmetry plane, characteristic far field) (docs/euler.md).
///
/// Every flux is the flux through an area vector `n` (its length is the face area, m^2), in
/// the solver's non-dimensional variables (gas.hpp); states are primitive (rho, u, v, w, p).
/// Jacobians are with respect to the conservative states.

#include "manta/euler/gas.hpp"

namespace manta::euler {

/// Approximate Riemann solver of the interior (edge) fluxes.
enum class FluxScheme {
    roe,   ///< Roe's flux difference splitting, Harten's entropy fix on all waves
    hllc,  ///< Toro's HLLC, wave speeds from Roe averages (Einfeldt estimates)
    /// Jameson-Schmidt-Turkel central scheme with blended second- and fourth-difference scalar
    /// dissipation (Jameson, Schmidt & Turkel, AIAA 81-1259, 1981; edge form of Mavriplis &
    /// Jameson, AIAA J. 28, 1990). Not a point-wise flux: it needs the neighbourhood (undivided
    /// Laplacians, pressure sensor), so SpatialOperator evaluates it (spatial.hpp);
    /// `numerical_flux` and `flux_jacobians` treat it as Roe.
    jst,
};

/// Options of the interior flux.
struct FluxOptions {
    FluxScheme scheme = FluxScheme::roe;
    /// Harten's entropy-fix width as a fraction of the Roe-averaged spectral radius
    /// |u.n| + c |n|: eigenvalue moduli below it are smoothed to (l^2 + d^2) / (2 d), on all
    /// waves (acoustic, entropy, shear). 0 switches it off. Roe only (HLLC needs none). With the
    /// fix on, stationary contacts and shocks get a dissipation of order d; without it Roe
    /// resolves them exactly but forms expansion shocks at sonic points (docs/euler.md).
    double entropy_fix = 0.05;
    /// Rieper's low-Mach fix of Roe's flux (J. Comput. Phys. 230, 5263-5287, 2011): the normal
    /// velocity jump in the acoustic waves' strengths is scaled by z = min(1, max(M_L, M_R)),
    /// the local Mach numbers of the two states, which removes the O(1/M) excess dissipation
    /// of the pressure field at low Mach numbers (spurious drag). Roe only; its Jacobian (frozen
    /// z) is part of `flux_jacobians`.
    bool low_mach_fix = false;
    /// JST second-difference coefficient k2 (shock capturing, scaled by the pressure sensor);
    /// SU2's default 0.5. JST only.
    double jst_k2 = 0.5;
    /// JST fourth-difference coefficient k4 (background dissipation in smooth regions, switched
    /// off where k2 times the sensor exceeds it); SU2's default 0.02. JST only.
    double jst_k4 = 0.02;
};

/// Physical Euler flux through a moving face, F(W).n - g U(W): `g` is the face's grid flux, the
/// integral of the grid velocity's component along the area vector over the face (m^3/s in the
/// solver's units; the face's swept volume per time step, so that the geometric conservation law
/// holds, docs/euler.md "Moving meshes"). Written (rho (V - g), rho u (V - g) + p n,
/// rho H (V - g) + p g) with V = u.n; g = 0 gives the fixed-face flux bit for bit.
[[nodiscard]] Vec5 physical_flux(const Vec5& W, const Vec3& n, double g, double gamma) noexcept;
/// Physical Euler flux F(W).n of a fixed face.
[[nodiscard]] inline Vec5 physical_flux(const Vec5& W, const Vec3& n, double gamma) noexcept {
    return physical_flux(W, n, 0.0, gamma);
}

/// Numerical flux from the left state WL (the edge's first node) to the right state WR through
/// `n` (pointing from left to right) moving with grid flux `g` (arbitrary Lagrangian-Eulerian
/// form: the upwind dissipation is |A - g I| with the eigenvalues u.n - g, u.n - g +- c |n|, the
/// entropy fix relative to |u.n - g| + c |n|, HLLC's waves sampled at the face's speed g / |n|).
/// Consistent: numerical_flux(W, W, n, g) = physical_flux(W, n, g). g = 0: bit for bit the
/// fixed-face flux.
[[nodiscard]] Vec5 numerical_flux(const Vec5& WL, const Vec5& WR, const Vec3& n, double g,
                                  double gamma, const FluxOptions& options) noexcept;
/// Numerical flux through a fixed face (g = 0).
[[nodiscard]] inline Vec5 numerical_flux(const Vec5& WL, const Vec5& WR, const Vec3& n,
                                         double gamma, const FluxOptions& options) noexcept {
    return numerical_flux(WL, WR, n, 0.0, gamma, options);
}

/// First-order Jacobians of `numerical_flux` with respect to the conservative left and right
/// states, for the implicit operator: for Roe, dF/dUL = (A(UL) - g I + |A_roe - g I|) / 2 and
/// dF/dUR = (A(UR) - g I - |A_roe - g I|) / 2 with the dissipation matrix frozen; HLLC uses the
/// same (a documented approximation: it only steers the implicit iteration).
void flux_jacobians(const Vec5& WL, const Vec5& WR, const Vec3& n, double g, double gamma,
                    const FluxOptions& options, Mat5& dF_dUL, Mat5& dF_dUR) noexcept;
/// `flux_jacobians` of a fixed face (g = 0).
inline void flux_jacobians(const Vec5& WL, const Vec5& WR, const Vec3& n, double gamma,
                           const FluxOptions& options, Mat5& dF_dUL, Mat5& dF_dUR) noexcept {
    flux_jacobians(WL, WR, n, 0.0, gamma, options, dF_dUL, dF_dUR);
}

/// Exact Jacobian d(F(W).n - g U)/dU of the physical flux through a moving face, A(U) n - g I.
[[nodiscard]] Mat5 physical_flux_jacobian(const Vec5& W, const Vec3& n, double g,
                                          double gamma) noexcept;
/// Exact Jacobian A(U) n of the physical flux through a fixed face.
[[nodiscard]] inline Mat5 physical_flux_jacobian(const Vec5& W, const Vec3& n,
                                                 double gamma) noexcept {
    return physical_flux_jacobian(W, n, 0.0, gamma);
}

/// Largest wave speed relative to the face times area, |u.n - g| + c |n| (local time steps).
[[nodiscard]] double spectral_radius(const Vec5& W, const Vec3& n, double g, double gamma) noexcept;
/// |u.n| + c |n| of a fixed face.
[[nodiscard]] inline double spectral_radius(const Vec5& W, const Vec3& n, double gamma) noexcept {
    return spectral_radius(W, n, 0.0, gamma);
}

/// Slip-wall / symmetry-plane flux through the outward boundary area vector `n` of a wall face
/// moving with grid flux `g`: the wall moves with the fluid's normal velocity, (u - v_grid).n = 0,
/// so no mass crosses it and the flux is (0, p n, p g), the pressure force and its work on the
/// moving wall, with the wall pressure taken from the node's state.
[[nodiscard]] Vec5 wall_flux(const Vec5& W, const Vec3& n, double g, double gamma) noexcept;
/// Wall flux (0, p n, 0) of a fixed wall.
[[nodiscard]] inline Vec5 wall_flux(const Vec5& W, const Vec3& n, double gamma) noexcept {
    return wall_flux(W, n, 0.0, gamma);
}
/// Jacobian of `wall_flux` with respect to the node's conservative state.
[[nodiscard]] Mat5 wall_flux_jacobian(const Vec5& W, const Vec3& n, double g,
                                      double gamma) noexcept;
/// Jacobian of the fixed wall's flux.
[[nodiscard]] inline Mat5 wall_flux_jacobian(const Vec5& W, const Vec3& n, double gamma) noexcept {
    return wall_flux_jacobian(W, n, 0.0, gamma);
}

/// Characteristic far-field flux through the outward area vector `n` (moving with grid flux `g`)
/// between the interior state W and the free stream W_inf: the boundary state from the locally
/// one-dimensional Riemann invariants (incoming ones from the free stream, outgoing ones from the
/// interior; entropy and tangential velocity from the upwind side), then the physical flux of that
/// state through the moving face, F(W_b).n - g U(W_b). The interior's normal Mach number relative
/// to the face, (u.n - s) / c with s = g / |n| the face's normal speed, picks the case: <= -1
/// supersonic inflow (free stream only), >= 1 supersonic outflow (interior only), else subsonic,
/// where R+ = u.n + 2c/(gamma-1) comes from the interior, R- = u.n - 2c/(gamma-1) from the free
/// stream, and the sign of the boundary normal velocity relative to the face, (R+ + R-)/2 - s,
/// says which side is upwind. `dF_dU`, when not null, receives the exact (analytic) Jacobian
/// with respect to the interior conservative state; it is undefined only on the switches between
/// the cases.
[[nodiscard]] Vec5 farfield_flux(const Vec5& W, const Vec5& W_inf, const Vec3& n, double g,
                                 double gamma, Mat5* dF_dU = nullptr) noexcept;
/// Far-field flux through a fixed face (g = 0).
[[nodiscard]] inline Vec5 farfield_flux(const Vec5& W, const Vec5& W_inf, const Vec3& n,
                                        double gamma, Mat5* dF_dU = nullptr) noexcept {
    return farfield_flux(W, W_inf, n, 0.0, gamma, dF_dU);
}

}  // namespace manta::euler
