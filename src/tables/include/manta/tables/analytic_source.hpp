#pragma once
/// @file analytic_source.hpp
/// An analytic aerodynamic test function with a known closed form: smooth, nonlinear and
/// aerodynamic-like in every input (lift with a soft stall and the Prandtl–Glauert factor, a drag
/// polar with a Mach drag rise, lateral coefficients linear in beta with alpha coupling, control
/// effectiveness that fades with alpha, rate damping). The fast tests and the CLI checks of
/// `manta tables` sample it in place of a flow solver; it is not a model of any aircraft.
///
/// With k = 1 / sqrt(1 - M^2) (Prandtl–Glauert), s(x) = w ln(1 + exp((x - alpha_s) / w)) (a
/// softplus: 0 well below the stall angle alpha_s, x - alpha_s well above it), the control
/// effectiveness e(alpha) = 1 - e_loss (alpha / alpha_s)^2 and sin of each deflection:
///
///     CL = (1 - 0.5 sin^2 beta) [k CL_alpha (alpha - alpha_0) - stall_lift s(alpha)
///          + k CL_de e sin(de)] + CL_q q_hat
///     CD = CD_0 + CD_k CL^2 + CD_wave (M / M_crit)^8 + CD_beta sin^2 beta
///          + CD_de de^2 + CD_da da^2 + CD_dr dr^2
///     CY = k (CY_beta beta + CY_dr sin dr) + CY_p p_hat + CY_r r_hat
///     Cl = k (Cl_beta (1 + Cl_beta_alpha alpha) beta + Cl_da e sin da + Cl_dr sin dr)
///          + Cl_p p_hat + (Cl_r + Cl_r_CL CL) r_hat
///     Cm = Cm_0 + k Cm_alpha alpha + stall_pitch s(alpha) + Cm_beta2 sin^2 beta
///          + k Cm_de e sin(de) + Cm_q q_hat
///     Cn = k (Cn_beta beta + Cn_da sin da + Cn_dr sin dr) + (Cn_p + Cn_p_CL CL) p_hat + Cn_r r_hat
///
/// Angles in radians, deflections with the paper's signs; forces wind-axis, moments body-axis.
/// CD_induced is CD_k CL^2, CD_profile the rest.

#include <string>

#include "manta/aero/source.hpp"

namespace manta::tables {

/// Parameters of the analytic source (per radian; defaults: a jet-trainer-like aircraft).
struct AnalyticParameters {
    double CL_alpha = 5.0, alpha_0 = -0.03, stall_alpha = 0.17, stall_width = 0.035,
           stall_lift = 4.5, CL_q = 4.5, CL_de = 0.45, effectiveness_loss = 0.3;
    double CD_0 = 0.022, CD_k = 0.056, CD_wave = 0.02, mach_crit = 0.72, CD_beta = 0.15,
           CD_de = 0.05, CD_da = 0.02, CD_dr = 0.03;
    double CY_beta = -0.6, CY_dr = 0.15, CY_p = -0.05, CY_r = 0.3;
    double Cl_beta = -0.08, Cl_beta_alpha = 2.0, Cl_da = 0.1, Cl_dr = 0.012, Cl_p = -0.45,
           Cl_r = 0.05, Cl_r_CL = 0.2;
    double Cm_0 = 0.02, Cm_alpha = -0.8, stall_pitch = 1.2, Cm_beta2 = -0.05, Cm_de = -1.2,
           Cm_q = -14.0;
    double Cn_beta = 0.1, Cn_da = -0.008, Cn_dr = -0.07, Cn_p = -0.01, Cn_p_CL = -0.06,
           Cn_r = -0.18;
    /// Evaluations at alpha above this angle throw NumericalError (to exercise failed samples);
    /// +infinity: never. Part of the fingerprint.
    double fail_above_alpha = 1e300;
    /// Wall-clock delay of each evaluation [s] (to imitate an expensive solver in tests of
    /// interruption and concurrency). Not part of the fingerprint: it changes no result.
    double delay_s = 0.0;
};

/// The analytic test function as an `aero::AeroSource` (thread-safe, deterministic).
class AnalyticSource : public aero::AeroSource {
public:
    explicit AnalyticSource(AnalyticParameters p = {});
    [[nodiscard]] std::string name() const override { return "analytic"; }
    /// "analytic:<hash of every parameter except delay_s>".
    [[nodiscard]] std::string fingerprint() const override { return fingerprint_; }
    /// The closed form above (sleeps delay_s first). NumericalError above fail_above_alpha.
    [[nodiscard]] aero::SourceResult evaluate(const aero::AeroQuery<double>& q,
                                              const aero::FlowConditions& c) const override;
    [[nodiscard]] const AnalyticParameters& parameters() const { return p_; }

private:
    AnalyticParameters p_;
    std::string fingerprint_;
};

}  // namespace manta::tables
