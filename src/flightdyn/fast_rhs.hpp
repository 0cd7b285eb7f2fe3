#pragma once
/// @file fast_rhs.hpp
/// Private: the plain data of the fused double-precision right-hand side (fast_rhs_impl.inc),
/// compiled once for baseline x86-64 (fast_rhs.cpp) and once for AVX2 with FMA
/// (fast_rhs_avx2.cpp). Plain structs only: the AVX2 unit includes this header and nothing that
/// defines inline code shared with the rest of the program.

#include "manta/aero/detail/fast_plan.hpp"

namespace manta::flightdyn::detail {

/// US Standard Atmosphere 1976 constants as atmosphere.hpp has them (filled from there once).
struct FastAtmosphere {
    static constexpr int n_layers = 7;
    double h_base[n_layers];          ///< geopotential altitude of each layer base [m']
    double t_base[n_layers];          ///< [K]
    double lapse[n_layers];           ///< [K/m']
    double p_base[n_layers];          ///< [Pa]
    double log_sigma_base[n_layers];  ///< ln(rho_base / rho_ref)
    double earth_radius;              ///< r0 [m]
    double gmr;                       ///< g0 M0 / R* [K/m']
    double gas_constant;              ///< R [J/(kg K)]
    double gamma_r;                   ///< gamma R
    double h_bottom;                  ///< lowest geopotential altitude [m']
    double h_top;                     ///< highest [m']
};

/// What the fused right-hand side needs of a FlightModel, taken per call (so a model changed
/// after finalize is never paired with stale data): scalars copied, the matrices pointed to.
struct RhsParams {
    const aero::detail::FastPlan* aero;  ///< nullptr: no aero tables
    const FastAtmosphere* atmosphere;
    double gravity;             ///< [m/s^2]
    double inv_mass;            ///< [1/kg]
    const double* inertia;      ///< 3x3, body axes, column major [kg m^2]
    const double* inv_inertia;  ///< its inverse, column major
    const double* h_engine;     ///< engine angular momentum, body axes [kg m^2/s]
    double area, span, chord;
    double r_mrp[3];   ///< CG to moment reference point, body axes [m]
    double thrust_sl;  ///< lapse law: T_sl [N], exponent n, Mach coefficients a1 a2
    double density_exponent;
    double mach_a1, mach_a2;
    double sin_thrust_angle, cos_thrust_angle;
    double r_engine[3];  ///< CG to the engine, body axes [m] (used when has_engine_arm)
    int has_engine_arm;
    int alpha_dot_terms;
    int beta_dot_terms;
    int angle_rate_terms;
};

/// One instruction set's kernels. Each returns false, having written nothing, where the fused
/// path does not apply (an out-of-table query, altitude outside the atmosphere, V near zero,
/// non-principal Euler air data); the caller then takes the reference templates.
struct RhsKernels {
    /// s: the 12 Euler states, u: elevator aileron rudder throttle; d: the 12 rates.
    bool (*euler)(const RhsParams& p, const double* s, const double* u, double* d);
    /// s: the 13 quaternion states; d: the 13 rates.
    bool (*quaternion)(const RhsParams& p, const double* s, const double* u, double* d);
    /// Four Euler states at once (s, u, d: four consecutive records of 12, 4 and 12 doubles);
    /// returns the bit set of the lanes written, the others being left to `euler`. nullptr in a
    /// set without a batched kernel.
    unsigned (*euler4)(const RhsParams& p, const double* s, const double* u, double* d);
    /// The same for four quaternion states (records of 13, 4 and 13 doubles).
    unsigned (*quaternion4)(const RhsParams& p, const double* s, const double* u, double* d);
    const char* name;
};

[[nodiscard]] const RhsKernels& baseline_rhs_kernels();
namespace avx2 {
/// The AVX2 set if this build compiled it (the processor is not checked here).
[[nodiscard]] const RhsKernels* rhs_kernels_if_built();
}  // namespace avx2

}  // namespace manta::flightdyn::detail
