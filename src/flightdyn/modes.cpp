/// Modal analysis about a trim point (modes.hpp).

#include "manta/flightdyn/modes.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "manta/core/error.hpp"

namespace manta::flightdyn {

namespace {

using cd = std::complex<double>;

bool is_complex(const cd& l) {
    return std::abs(l.imag()) > 1e-9 * std::abs(l) && std::abs(l.imag()) > 1e-14;
}

/// Complex pairs (each by its member with Im > 0) and real roots of four eigenvalues.
void split(const Eigen::Vector4cd& ev, std::vector<cd>& pairs, std::vector<cd>& reals) {
    for (int i = 0; i < 4; ++i) {
        const cd l = ev[i];
        if (is_complex(l)) {
            if (l.imag() > 0.0) pairs.push_back(l);
        } else {
            reals.emplace_back(l.real(), 0.0);
        }
    }
    // A real matrix has conjugate pairs; guard against a numerically unpaired root.
    if (pairs.size() * 2 + reals.size() != 4) {
        throw NumericalError(
            "modes: eigenvalues of a real 4x4 matrix did not come in conjugate pairs");
    }
    auto by_magnitude_desc = [](const cd& a, const cd& b) { return std::abs(a) > std::abs(b); };
    std::sort(pairs.begin(), pairs.end(), by_magnitude_desc);
    std::sort(reals.begin(), reals.end(), by_magnitude_desc);
}

Mode named(const cd& l, std::string name) {
    Mode m = make_mode(l);
    m.name = std::move(name);
    return m;
}

Eigen::Vector4cd eigenvalues_of(const Eigen::Matrix4d& A, const char* which) {
    if (!A.allFinite())
        throw NumericalError(fmt::format("modes: the {} matrix is not finite", which));
    Eigen::EigenSolver<Eigen::Matrix4d> es(A, false);
    if (es.info() != Eigen::Success)
        throw NumericalError(fmt::format("modes: eigenvalues of the {} matrix failed", which));
    return es.eigenvalues();
}

}  // namespace

Mode make_mode(std::complex<double> lambda) {
    Mode m;
    constexpr double inf = std::numeric_limits<double>::infinity();
    m.oscillatory = is_complex(lambda);
    if (m.oscillatory && lambda.imag() < 0.0) lambda = std::conj(lambda);
    if (!m.oscillatory) lambda = {lambda.real(), 0.0};
    m.eigenvalue = lambda;
    const double sigma = lambda.real();
    m.natural_frequency = std::abs(lambda);
    m.damping_ratio = m.natural_frequency > 0.0 ? -sigma / m.natural_frequency : 0.0;
    m.period = m.oscillatory ? 2.0 * std::numbers::pi / lambda.imag() : inf;
    m.time_to_half = sigma < 0.0 ? std::numbers::ln2 / -sigma : inf;
    m.time_to_double = sigma > 0.0 ? std::numbers::ln2 / sigma : inf;
    return m;
}

Eigen::Matrix4d subsystem(const Eigen::Matrix<double, 12, 12>& A, const int (&idx)[4]) {
    Eigen::Matrix4d s;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) s(i, j) = A(idx[i], idx[j]);
    return s;
}

std::vector<Mode> classify_longitudinal(const Eigen::Vector4cd& eigenvalues) {
    std::vector<cd> pairs, reals;
    split(eigenvalues, pairs, reals);
    std::vector<Mode> modes;
    if (pairs.size() == 2) {
        modes.push_back(named(pairs[0], "short period"));
        modes.push_back(named(pairs[1], "phugoid"));
    } else if (pairs.size() == 1) {
        // The pair is the short period when it is faster than the real roots (geometric mean):
        // the phugoid has split; otherwise the short period has split into two real roots.
        const double scale = std::sqrt(std::abs(reals[0]) * std::abs(reals[1]));
        if (std::abs(pairs[0]) >= scale) {
            modes.push_back(named(pairs[0], "short period"));
            modes.push_back(named(reals[0], "phugoid (real)"));
            modes.push_back(named(reals[1], "phugoid (real)"));
        } else {
            modes.push_back(named(reals[0], "short period (real)"));
            modes.push_back(named(reals[1], "short period (real)"));
            modes.push_back(named(pairs[0], "phugoid"));
        }
    } else {
        modes.push_back(named(reals[0], "short period (real)"));
        modes.push_back(named(reals[1], "short period (real)"));
        modes.push_back(named(reals[2], "phugoid (real)"));
        modes.push_back(named(reals[3], "phugoid (real)"));
    }
    return modes;
}

std::vector<Mode> classify_lateral(const Eigen::Vector4cd& eigenvalues) {
    std::vector<cd> pairs, reals;
    split(eigenvalues, pairs, reals);
    std::vector<Mode> modes;
    if (pairs.size() == 1) {
        modes.push_back(named(pairs[0], "Dutch roll"));
        modes.push_back(named(reals[0], "roll"));
        modes.push_back(named(reals[1], "spiral"));
    } else if (pairs.size() == 2) {
        // Roll and spiral coupled into an oscillation (the "lateral phugoid"): the Dutch roll is
        // the pair of higher damped frequency.
        const bool first_is_dutch = pairs[0].imag() >= pairs[1].imag();
        modes.push_back(named(first_is_dutch ? pairs[0] : pairs[1], "Dutch roll"));
        modes.push_back(named(first_is_dutch ? pairs[1] : pairs[0], "roll-spiral (coupled)"));
    } else {
        modes.push_back(named(reals[1], "Dutch roll (real)"));
        modes.push_back(named(reals[2], "Dutch roll (real)"));
        modes.push_back(named(reals[0], "roll"));
        modes.push_back(named(reals[3], "spiral"));
    }
    return modes;
}

ModesResult analyse_modes(const LinearModel& linear) {
    ModesResult r;
    r.A_longitudinal = subsystem(linear.A, longitudinal_states);
    r.A_lateral = subsystem(linear.A, lateral_states);
    r.eigenvalues_longitudinal = eigenvalues_of(r.A_longitudinal, "longitudinal");
    r.eigenvalues_lateral = eigenvalues_of(r.A_lateral, "lateral-directional");
    if (!linear.A.allFinite()) throw NumericalError("modes: the state matrix A is not finite");
    Eigen::EigenSolver<Eigen::Matrix<double, 12, 12>> es(linear.A, false);
    if (es.info() != Eigen::Success)
        throw NumericalError("modes: eigenvalues of the 12-state matrix failed");
    std::vector<cd> all(es.eigenvalues().data(), es.eigenvalues().data() + 12);
    std::sort(all.begin(), all.end(), [](const cd& a, const cd& b) {
        return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
    });
    for (int i = 0; i < 12; ++i) r.eigenvalues_full[i] = all[static_cast<std::size_t>(i)];
    r.longitudinal = classify_longitudinal(r.eigenvalues_longitudinal);
    r.lateral = classify_lateral(r.eigenvalues_lateral);
    return r;
}

}  // namespace manta::flightdyn
