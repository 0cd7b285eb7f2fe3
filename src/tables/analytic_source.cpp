/// @file analytic_source.cpp
/// The analytic aerodynamic test function (closed form in analytic_source.hpp).

#include "manta/tables/analytic_source.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <thread>

#include "manta/core/error.hpp"

namespace manta::tables {

namespace {

/// FNV-1a over the bytes of the parameters that change results.
std::uint64_t hash_parameters(const AnalyticParameters& p) {
    const double values[] = {p.CL_alpha,   p.alpha_0,       p.stall_alpha, p.stall_width,
                             p.stall_lift, p.CL_q,          p.CL_de,       p.effectiveness_loss,
                             p.CD_0,       p.CD_k,          p.CD_wave,     p.mach_crit,
                             p.CD_beta,    p.CD_de,         p.CD_da,       p.CD_dr,
                             p.CY_beta,    p.CY_dr,         p.CY_p,        p.CY_r,
                             p.Cl_beta,    p.Cl_beta_alpha, p.Cl_da,       p.Cl_dr,
                             p.Cl_p,       p.Cl_r,          p.Cl_r_CL,     p.Cm_0,
                             p.Cm_alpha,   p.stall_pitch,   p.Cm_beta2,    p.Cm_de,
                             p.Cm_q,       p.Cn_beta,       p.Cn_da,       p.Cn_dr,
                             p.Cn_p,       p.Cn_p_CL,       p.Cn_r,        p.fail_above_alpha};
    std::uint64_t h = 1469598103934665603ULL;
    for (const double v : values) {
        unsigned char b[sizeof(double)];
        std::memcpy(b, &v, sizeof v);
        for (const unsigned char c : b) {
            h ^= c;
            h *= 1099511628211ULL;
        }
    }
    return h;
}

}  // namespace

AnalyticSource::AnalyticSource(AnalyticParameters p)
    : p_(p), fingerprint_(fmt::format("analytic:{:016x}", hash_parameters(p))) {}

aero::SourceResult AnalyticSource::evaluate(const aero::AeroQuery<double>& q,
                                            const aero::FlowConditions& /*c*/) const {
    if (p_.delay_s > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(p_.delay_s));
    if (!(q.mach >= 0.0 && q.mach < 1.0))
        throw InputError(fmt::format("analytic source: Mach {} is outside [0, 1)", q.mach));
    if (q.alpha > p_.fail_above_alpha)
        throw NumericalError(
            fmt::format("analytic source: alpha {:.4f} rad is above fail_above_alpha {:.4f} rad (a "
                        "deliberate failure)",
                        q.alpha, p_.fail_above_alpha));
    const double a = q.alpha, b = q.beta, m = q.mach;
    const double k = 1.0 / std::sqrt(1.0 - m * m);
    const double x = (a - p_.stall_alpha) / p_.stall_width;
    // Softplus written to stay finite for large arguments.
    const double soft = p_.stall_width * (x > 30.0 ? x : std::log1p(std::exp(x)));
    const double e = 1.0 - p_.effectiveness_loss * (a / p_.stall_alpha) * (a / p_.stall_alpha);
    const double sb2 = std::sin(b) * std::sin(b);
    const double sde = std::sin(q.elevator), sda = std::sin(q.aileron), sdr = std::sin(q.rudder);

    const double CL = (1.0 - 0.5 * sb2) * (k * p_.CL_alpha * (a - p_.alpha_0) -
                                           p_.stall_lift * soft + k * p_.CL_de * e * sde) +
                      p_.CL_q * q.q_hat;
    const double CD_induced = p_.CD_k * CL * CL;
    const double CD_profile = p_.CD_0 + p_.CD_wave * std::pow(m / p_.mach_crit, 8) +
                              p_.CD_beta * sb2 + p_.CD_de * q.elevator * q.elevator +
                              p_.CD_da * q.aileron * q.aileron + p_.CD_dr * q.rudder * q.rudder;
    const double CY = k * (p_.CY_beta * b + p_.CY_dr * sdr) + p_.CY_p * q.p_hat + p_.CY_r * q.r_hat;
    const double Cl =
        k * (p_.Cl_beta * (1.0 + p_.Cl_beta_alpha * a) * b + p_.Cl_da * e * sda + p_.Cl_dr * sdr) +
        p_.Cl_p * q.p_hat + (p_.Cl_r + p_.Cl_r_CL * CL) * q.r_hat;
    const double Cm = p_.Cm_0 + k * p_.Cm_alpha * a + p_.stall_pitch * soft + p_.Cm_beta2 * sb2 +
                      k * p_.Cm_de * e * sde + p_.Cm_q * q.q_hat;
    const double Cn = k * (p_.Cn_beta * b + p_.Cn_da * sda + p_.Cn_dr * sdr) +
                      (p_.Cn_p + p_.Cn_p_CL * CL) * q.p_hat + p_.Cn_r * q.r_hat;

    aero::SourceResult r;
    r.wind = {CL, CD_induced + CD_profile, CY};
    r.CD_induced = CD_induced;
    r.CD_profile = CD_profile;
    const auto f = aero::body_from_wind(CL, r.wind.CD, CY, a, b);
    r.body = {f[0], f[1], f[2], Cl, Cm, Cn};
    return r;
}

}  // namespace manta::tables
