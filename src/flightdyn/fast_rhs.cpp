/// @file fast_rhs.cpp
/// The fused double-precision right-hand side: the baseline x86-64 kernels, the choice of
/// kernel set at run time, and the per-call parameters taken from a FlightModel.

#include "fast_rhs.hpp"

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include <Eigen/LU>

#include <fmt/format.h>

#include "manta/core/error.hpp"
#include "manta/core/fastmath.hpp"
#include "manta/core/frames.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/flightdyn/eom.hpp"

namespace manta::flightdyn::detail {

namespace base {
namespace {
namespace fm = ::manta::core;
constexpr int vector_width = 2;
constexpr const char* kernel_set_name = "baseline";
#include "fast_rhs_impl.inc"
const RhsKernels table = {&euler_kernel, &quaternion_kernel, nullptr, nullptr, kernel_set_name};
}  // namespace
}  // namespace base

const RhsKernels& baseline_rhs_kernels() {
    return base::table;
}

namespace {

const RhsKernels* avx2_rhs_kernels() {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    static const bool cpu = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return cpu ? avx2::rhs_kernels_if_built() : nullptr;
#else
    return nullptr;
#endif
}

/// The kernel set of `which`; the automatic choice is AVX2 where the processor has it, unless
/// the environment variable MANTA_FLIGHTDYN_KERNELS is "baseline" (that set) or "reference"
/// (none: the templates alone, for comparisons).
const RhsKernels* kernels_of(FastKernelSet which) {
    switch (which) {
        case FastKernelSet::baseline:
            return &baseline_rhs_kernels();
        case FastKernelSet::avx2:
            return avx2_rhs_kernels();
        case FastKernelSet::automatic:
            break;
    }
    static const RhsKernels* chosen = []() -> const RhsKernels* {
        const char* env = std::getenv("MANTA_FLIGHTDYN_KERNELS");
        if (env != nullptr && std::string_view(env) == "baseline") return &baseline_rhs_kernels();
        if (env != nullptr && std::string_view(env) == "reference") return nullptr;
        const RhsKernels* k = avx2_rhs_kernels();
        return k != nullptr ? k : &baseline_rhs_kernels();
    }();
    return chosen;
}

const FastAtmosphere& fast_atmosphere() {
    static const FastAtmosphere a = [] {
        FastAtmosphere f{};
        namespace c = us1976_constants;
        static_assert(c::layers.size() == FastAtmosphere::n_layers);
        const auto& log_sigma = us1976_log_sigma_base();
        for (std::size_t i = 0; i < c::layers.size(); ++i) {
            f.h_base[i] = c::layers[i].h_base;
            f.t_base[i] = c::layers[i].t_base;
            f.lapse[i] = c::layers[i].lapse;
            f.p_base[i] = c::layers[i].p_base;
            f.log_sigma_base[i] = log_sigma[i];
        }
        f.earth_radius = c::earth_radius;
        f.gmr = c::g0 / c::gas_constant;
        f.gas_constant = c::gas_constant;
        f.gamma_r = c::gamma * c::gas_constant;
        f.h_bottom = c::h_bottom;
        f.h_top = c::h_top;
        return f;
    }();
    return a;
}

/// The parameters of `m`, or false where the fused path does not cover the model (a thrust
/// table, C1 aero interpolation, tables beyond the plain-data plan's limits). `inverse` holds
/// the inverse inertia when the one cached by finalize is stale.
bool make_params(const FlightModel& m, RhsParams& p, Eigen::Matrix3d& inverse) {
    if (m.engine.type != EngineModel::Type::lapse) return false;
    p.aero = nullptr;
    if (m.aero) {
        if (m.interpolation != aero::Interpolation::multilinear) return false;
        p.aero = m.aero->fast_plan();
        if (p.aero == nullptr) return false;
    }
    p.atmosphere = &fast_atmosphere();
    p.gravity = m.environment.gravity;
    p.inv_mass = 1.0 / m.mass.mass;
    p.inertia = m.mass.inertia.data();
    if (m.inertia_inverse_of == m.mass.inertia) [[likely]] {
        p.inv_inertia = m.inertia_inverse.data();
    } else {
        inverse = m.mass.inertia.inverse();
        p.inv_inertia = inverse.data();
    }
    p.h_engine = m.engine_angular_momentum.data();
    p.area = m.reference.area;
    p.span = m.reference.span;
    p.chord = m.reference.chord;
    const Eigen::Vector3d r_mrp =
        core::body_from_geometry(m.moment_reference_geom - m.mass.cg_geom);
    p.r_mrp[0] = r_mrp.x();
    p.r_mrp[1] = r_mrp.y();
    p.r_mrp[2] = r_mrp.z();
    p.thrust_sl = m.engine.static_thrust_sl;
    p.density_exponent = m.engine.density_exponent;
    p.mach_a1 = m.engine.mach_a1;
    p.mach_a2 = m.engine.mach_a2;
    if (m.engine.thrust_angle == 0.0) {
        p.sin_thrust_angle = 0.0;
        p.cos_thrust_angle = 1.0;
    } else {
        core::sin_cos(m.engine.thrust_angle, p.sin_thrust_angle, p.cos_thrust_angle);
    }
    p.has_engine_arm = m.engine.has_position ? 1 : 0;
    if (m.engine.has_position) {
        const auto& e = m.engine.position;
        const Eigen::Vector3d r_engine =
            core::body_from_geometry(Eigen::Vector3d(e[0], e[1], e[2]) - m.mass.cg_geom);
        p.r_engine[0] = r_engine.x();
        p.r_engine[1] = r_engine.y();
        p.r_engine[2] = r_engine.z();
    }
    p.alpha_dot_terms = m.alpha_dot_terms ? 1 : 0;
    p.beta_dot_terms = m.beta_dot_terms ? 1 : 0;
    p.angle_rate_terms = m.angle_rate_terms ? 1 : 0;
    return true;
}

}  // namespace

bool has_avx2_rhs_kernels() {
    return avx2_rhs_kernels() != nullptr;
}

const char* fast_rhs_kernel_name() {
    const RhsKernels* k = kernels_of(FastKernelSet::automatic);
    return k != nullptr ? k->name : "reference";
}

bool fast_euler_rhs(const FlightModel& m, const EulerState<double>& s, const Controls<double>& u,
                    EulerState<double>& d, FastKernelSet which) {
    const RhsKernels* k = kernels_of(which);
    RhsParams p;
    Eigen::Matrix3d inverse;
    if (k == nullptr || !make_params(m, p, inverse)) return false;
    const double uu[4] = {u.elevator, u.aileron, u.rudder, u.throttle};
    if (!k->euler(p, s.data(), uu, d.data())) return false;
    if (m.aero) m.aero->count_evaluation();
    return true;
}

bool fast_quaternion_rhs(const FlightModel& m, const QuatState<double>& s,
                         const Controls<double>& u, QuatState<double>& d, FastKernelSet which) {
    const RhsKernels* k = kernels_of(which);
    RhsParams p;
    Eigen::Matrix3d inverse;
    if (k == nullptr || !make_params(m, p, inverse)) return false;
    const double uu[4] = {u.elevator, u.aileron, u.rudder, u.throttle};
    if (!k->quaternion(p, s.data(), uu, d.data())) return false;
    if (m.aero) m.aero->count_evaluation();
    return true;
}

namespace {

/// The four-lane loop of batched_euler_rhs and batched_quaternion_rhs: `State` the state
/// vector, `kernel4` the member of RhsKernels, `one` the single-state right-hand side.
template <class State, class Kernel4, class One>
void batched_rhs(const FlightModel& m, const State* s, const Controls<double>* u, State* d,
                 std::size_t n, FastKernelSet which, std::size_t& next, Kernel4 kernel4, One one) {
    next = 0;
    const RhsKernels* k = kernels_of(which);
    if (k == nullptr || k->*kernel4 == nullptr || n < 4) return;
    RhsParams p;
    Eigen::Matrix3d inverse;
    if (!make_params(m, p, inverse)) return;
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        double uu[16];
        for (int l = 0; l < 4; ++l) {
            const Controls<double>& c = u[i + static_cast<std::size_t>(l)];
            uu[4 * l] = c.elevator;
            uu[4 * l + 1] = c.aileron;
            uu[4 * l + 2] = c.rudder;
            uu[4 * l + 3] = c.throttle;
        }
        const unsigned done = (k->*kernel4)(p, s[i].data(), uu, d[i].data());
        for (unsigned l = 0; l < 4; ++l) {
            const std::size_t j = i + l;
            if ((done >> l & 1u) != 0) {
                if (m.aero) m.aero->count_evaluation();
            } else {
                d[j] = one(m, s[j], u[j]);
            }
        }
    }
    next = i;
}

}  // namespace

void batched_euler_rhs(const FlightModel& m, const EulerState<double>* s, const Controls<double>* u,
                       EulerState<double>* d, std::size_t n, FastKernelSet which,
                       std::size_t& next) {
    static_assert(sizeof(EulerState<double>) == euler::size * sizeof(double),
                  "consecutive Euler states are consecutive records of 12 doubles");
    batched_rhs(m, s, u, d, n, which, next, &RhsKernels::euler4,
                [](const FlightModel& mm, const EulerState<double>& x, const Controls<double>& c) {
                    return euler_rhs(mm, x, c);
                });
}

void batched_quaternion_rhs(const FlightModel& m, const QuatState<double>* s,
                            const Controls<double>* u, QuatState<double>* d, std::size_t n,
                            FastKernelSet which, std::size_t& next) {
    static_assert(sizeof(QuatState<double>) == quat::size * sizeof(double),
                  "consecutive quaternion states are consecutive records of 13 doubles");
    batched_rhs(m, s, u, d, n, which, next, &RhsKernels::quaternion4,
                [](const FlightModel& mm, const QuatState<double>& x, const Controls<double>& c) {
                    return quaternion_rhs(mm, x, c);
                });
}

}  // namespace manta::flightdyn::detail

namespace manta::flightdyn {

namespace {

void check_batch_sizes(const char* what, std::size_t ns, std::size_t nu, std::size_t nd) {
    if (ns != nu || ns != nd)
        throw InputError(
            fmt::format("{}: {} states, {} controls and {} outputs; expected the same "
                        "number of each",
                        what, ns, nu, nd));
}

}  // namespace

void euler_rhs_batch(const FlightModel& m, std::span<const EulerState<double>> s,
                     std::span<const Controls<double>> u, std::span<EulerState<double>> d) {
    check_batch_sizes("euler_rhs_batch", s.size(), u.size(), d.size());
    const std::size_t n = s.size();
    std::size_t i = 0;
    detail::batched_euler_rhs(m, s.data(), u.data(), d.data(), n, detail::FastKernelSet::automatic,
                              i);
    for (; i < n; ++i) d[i] = euler_rhs(m, s[i], u[i]);
}

void quaternion_rhs_batch(const FlightModel& m, std::span<const QuatState<double>> s,
                          std::span<const Controls<double>> u, std::span<QuatState<double>> d) {
    check_batch_sizes("quaternion_rhs_batch", s.size(), u.size(), d.size());
    const std::size_t n = s.size();
    std::size_t i = 0;
    detail::batched_quaternion_rhs(m, s.data(), u.data(), d.data(), n,
                                   detail::FastKernelSet::automatic, i);
    for (; i < n; ++i) d[i] = quaternion_rhs(m, s[i], u[i]);
}

}  // namespace manta::flightdyn
