#include "manta/vlm/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"

namespace manta::vlm {

namespace {
void check_parameter(double parameter) {
    if (!(std::abs(parameter) <= 3.0))
        throw InputError(
            fmt::format("lattice spacing parameter {}; expected a number in [-3, 3]", parameter));
}
}  // namespace

double spacing_law(double s, double parameter) {
    check_parameter(parameter);
    const double p = std::abs(parameter);
    const double equal = s;
    const double cosine = 0.5 * (1.0 - std::cos(std::numbers::pi * s));
    // Sine: fine at the start; mirrored for a negative parameter (fine at the end).
    const double sine = parameter < 0.0 ? std::sin(0.5 * std::numbers::pi * s)
                                        : 1.0 - std::cos(0.5 * std::numbers::pi * s);
    if (p <= 1.0) return (1.0 - p) * equal + p * cosine;
    if (p <= 2.0) return (2.0 - p) * cosine + (p - 1.0) * sine;
    return (3.0 - p) * sine + (p - 2.0) * equal;
}

double spacing_parameter_of(double f, double parameter) {
    check_parameter(parameter);
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (spacing_law(mid, parameter) < f ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

std::vector<double> spacing_fractions(int n, double parameter) {
    if (n < 1) throw InputError(fmt::format("lattice spacing: {} intervals; expected >= 1", n));
    check_parameter(parameter);
    std::vector<double> f(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i)
        f[static_cast<std::size_t>(i)] = spacing_law(static_cast<double>(i) / n, parameter);
    f.front() = 0.0;
    f.back() = 1.0;
    return f;
}

ChordStations chord_stations(int n, double parameter, double lift_slope_factor) {
    if (n < 1) throw InputError(fmt::format("lattice spacing: {} intervals; expected >= 1", n));
    check_parameter(parameter);
    // Weights of the equal, cosine and sine laws (blended positions, as spacing_law does).
    const double p = std::abs(parameter);
    double we = 0.0, wc = 0.0, ws = 0.0;
    if (p <= 1.0) {
        we = 1.0 - p;
        wc = p;
    } else if (p <= 2.0) {
        wc = 2.0 - p;
        ws = p - 1.0;
    } else {
        ws = 3.0 - p;
        we = p - 2.0;
    }
    const double pi = std::numbers::pi;
    const double k = lift_slope_factor;
    // Each law places panel i's edge, vortex and control point at successive steps of its own
    // parameter: equal steps of 1/(4n) in x; cosine steps of pi/(4n + 2) in angle, starting one
    // step in, so vortex and control point fall at the quarter and three-quarter points of the
    // semicircle's intervals; sine steps of (pi/2)/(4n + 1).
    auto at = [&](double steps_equal, double steps_cos, double steps_sin) {
        const double e = steps_equal / (4.0 * n);
        const double c = 0.5 * (1.0 - std::cos(steps_cos * pi / (4.0 * n + 2.0)));
        const double sd = 0.5 * pi / (4.0 * n + 1.0);
        const double sn =
            parameter >= 0.0 ? 1.0 - std::cos(steps_sin * sd) : std::sin((steps_sin - 1.0) * sd);
        return we * e + wc * c + ws * sn;
    };
    ChordStations st;
    st.edge.resize(static_cast<std::size_t>(n) + 1);
    st.vortex.resize(static_cast<std::size_t>(n));
    st.control.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const double b = 4.0 * i;
        st.edge[static_cast<std::size_t>(i)] = at(b, b + 1.0, b + 1.0);
        st.vortex[static_cast<std::size_t>(i)] = at(b + 1.0, b + 2.0, b + 2.0);
        st.control[static_cast<std::size_t>(i)] =
            at(b + 1.0 + 2.0 * k, b + 2.0 + 2.0 * k, b + 2.0 + 2.0 * k);
    }
    st.edge.front() = 0.0;
    st.edge.back() = 1.0;
    return st;
}

std::vector<std::string> Model::control_names() const {
    std::vector<std::string> names;
    for (const auto& s : surfaces)
        for (const auto& sec : s.sections)
            for (const auto& c : sec.controls)
                if (std::find(names.begin(), names.end(), c.name) == names.end())
                    names.push_back(c.name);
    return names;
}

}  // namespace manta::vlm
