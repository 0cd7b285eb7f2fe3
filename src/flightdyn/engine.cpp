#include "manta/flightdyn/engine.hpp"

#include <fmt/format.h>

#include <cmath>

#include "manta/core/error.hpp"

namespace manta::flightdyn {

namespace {
void check_axis(const std::vector<double>& a, const std::string& where, const char* name) {
    if (a.empty())
        throw InputError(fmt::format(
            "{}: thrust table axis '{}' is empty; expected at least one value", where, name));
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (!std::isfinite(a[i]))
            throw InputError(fmt::format("{}: thrust table axis '{}' value {} is not finite", where,
                                         name, a[i]));
        if (i > 0 && !(a[i] > a[i - 1]))
            throw InputError(fmt::format(
                "{}: thrust table axis '{}' is not strictly increasing at entry {} ({} after {})",
                where, name, i, a[i], a[i - 1]));
    }
}
}  // namespace

void EngineModel::validate(const std::string& where) const {
    if (!std::isfinite(thrust_angle))
        throw InputError(fmt::format("{}: thrust angle is not finite", where));
    if (type == Type::lapse) {
        if (!(static_thrust_sl >= 0.0 && std::isfinite(static_thrust_sl)))
            throw InputError(fmt::format("{}: static thrust {} N; expected a finite number >= 0",
                                         where, static_thrust_sl));
        if (!std::isfinite(density_exponent) || !std::isfinite(mach_a1) || !std::isfinite(mach_a2))
            throw InputError(fmt::format("{}: lapse coefficients must be finite", where));
        return;
    }
    check_axis(altitude, where, "altitude");
    check_axis(mach, where, "mach");
    check_axis(throttle, where, "throttle");
    const std::size_t n = altitude.size() * mach.size() * throttle.size();
    if (thrust.size() != n)
        throw InputError(
            fmt::format("{}: thrust table has {} values; expected {} (altitude x mach x throttle = "
                        "{} x {} x {})",
                        where, thrust.size(), n, altitude.size(), mach.size(), throttle.size()));
    for (double t : thrust)
        if (!std::isfinite(t))
            throw InputError(fmt::format("{}: thrust table value {} is not finite", where, t));
}

}  // namespace manta::flightdyn
