/// @file oscillation.cpp
/// Forced-oscillation analysis: whole-period window, Fourier projection with the trapezoidal
/// inner product, weighted least squares (docs/forced-oscillation.md).

#include "manta/aero/oscillation.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "manta/core/error.hpp"

namespace manta::aero {

namespace {

constexpr std::string_view who = "analyse_oscillation";

void check_spec(const OscillationSpec& s) {
    const auto positive = [](double v, std::string_view name, std::string_view unit) {
        if (!(v > 0.0) || !std::isfinite(v)) {
            throw InputError(
                fmt::format("{}: {} = {}{}; expected a finite number > 0", who, name, v, unit));
        }
    };
    positive(s.amplitude, "amplitude", " rad");
    positive(s.omega, "omega", " rad/s");
    positive(s.reduced_frequency, "reduced_frequency", "");
    if (!std::isfinite(s.x0) || !std::isfinite(s.phase)) {
        throw InputError(
            fmt::format("{}: x0 = {} and phase = {} must be finite", who, s.x0, s.phase));
    }
    if (s.n_periods < 0) {
        throw InputError(
            fmt::format("{}: n_periods = {}; expected >= 1, or 0 for every whole "
                        "period the history holds",
                        who, s.n_periods));
    }
    if (!(s.period_tolerance >= 0.0 && s.period_tolerance < 0.5)) {
        throw InputError(fmt::format("{}: period_tolerance = {}; expected 0 <= tolerance < 0.5",
                                     who, s.period_tolerance));
    }
}

void check_history(std::span<const double> t, std::span<const double> c, std::span<const double> x,
                   std::span<const double> xdot_hat, bool given_motion) {
    const std::size_t n = t.size();
    const auto same_size = [&](std::span<const double> v, std::string_view name) {
        if (v.size() != n) {
            throw InputError(fmt::format("{}: {} has {} samples but t has {}; expected the same",
                                         who, name, v.size(), n));
        }
    };
    same_size(c, "C");
    if (given_motion) {
        same_size(x, "x");
        same_size(xdot_hat, "xdot_hat");
    }
    if (n < 3) throw InputError(fmt::format("{}: {} samples; expected at least 3", who, n));
    const auto finite = [&](std::span<const double> v, std::string_view name) {
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (!std::isfinite(v[i])) {
                throw InputError(
                    fmt::format("{}: {}[{}] = {} is not finite; expected a finite "
                                "number",
                                who, name, i, v[i]));
            }
        }
    };
    finite(t, "t");
    finite(c, "C");
    if (given_motion) {
        finite(x, "x");
        finite(xdot_hat, "xdot_hat");
    }
    for (std::size_t i = 1; i < n; ++i) {
        if (!(t[i] > t[i - 1])) {
            throw InputError(
                fmt::format("{}: t[{}] = {} is not greater than t[{}] = {}; times "
                            "must increase strictly",
                            who, i, t[i], i - 1, t[i - 1]));
        }
    }
}

/// Index of the sample within `tol` of `ts`, if any.
std::optional<std::size_t> sample_near(std::span<const double> t, double ts, double tol) {
    const auto it = std::lower_bound(t.begin(), t.end(), ts - tol);
    if (it != t.end() && std::abs(*it - ts) <= tol) return static_cast<std::size_t>(it - t.begin());
    return std::nullopt;
}

struct Window {
    std::size_t first = 0;
    int n_periods = 0;
};

/// The last whole periods of the history: the window ends on the last sample and must begin on a
/// sample n T earlier.
Window find_window(std::span<const double> t, const OscillationSpec& s) {
    const double period = 2.0 * std::numbers::pi / s.omega;
    const double tol = s.period_tolerance * period;
    const double t_end = t.back();
    const double span = t_end - t.front();
    if (s.n_periods > 0) {
        const double ts = t_end - s.n_periods * period;
        if (ts < t.front() - tol) {
            throw InputError(fmt::format(
                "{}: the last {} period{} (T = {} s) would start at t = {} s, before the first "
                "sample t = {} s; the history holds {:.6g} periods",
                who, s.n_periods, s.n_periods == 1 ? "" : "s", period, ts, t.front(),
                span / period));
        }
        const auto j = sample_near(t, ts, tol);
        if (!j) {
            const auto it = std::lower_bound(t.begin(), t.end(), ts);
            throw InputError(fmt::format(
                "{}: no sample at the window start t = {} s ({} whole period{} of T = {} s before "
                "the last sample t = {} s; nearest samples t = {} s and {} s); the window must "
                "hold whole periods",
                who, ts, s.n_periods, s.n_periods == 1 ? "" : "s", period, t_end, *(it - 1), *it));
        }
        return {*j, s.n_periods};
    }
    const int n_max = static_cast<int>(std::floor((span + tol) / period));
    for (int n = n_max; n >= 1; --n) {
        if (const auto j = sample_near(t, t_end - n * period, tol)) return {*j, n};
    }
    throw InputError(fmt::format(
        "{}: the history (t = {} to {} s, {:.6g} periods of T = {} s) holds no whole period "
        "ending on its last sample that begins on a sample",
        who, t.front(), t_end, span / period, period));
}

OscillationResult analyse(std::span<const double> t, std::span<const double> c,
                          std::span<const double> x, std::span<const double> xdot_hat,
                          bool given_motion, const OscillationSpec& s) {
    check_spec(s);
    check_history(t, c, x, xdot_hat, given_motion);
    const Window win = find_window(t, s);
    const std::size_t n = t.size();
    const std::size_t j0 = win.first;
    const std::size_t m = n - j0;
    if (m < 3) {
        throw InputError(
            fmt::format("{}: {} samples in the window of {} period{}; expected at "
                        "least 3 per period",
                        who, m, win.n_periods, win.n_periods == 1 ? "" : "s"));
    }

    // Trapezoidal weights over the window: the integral of f is sum w_k f_k.
    std::vector<double> w(m, 0.0);
    for (std::size_t k = 0; k + 1 < m; ++k) {
        const double half = 0.5 * (t[j0 + k + 1] - t[j0 + k]);
        w[k] += half;
        w[k + 1] += half;
    }
    const double length = t[n - 1] - t[j0];

    OscillationResult r;
    r.n_periods = win.n_periods;
    r.first_sample = j0;
    r.n_samples = m;
    r.t_begin = t[j0];
    r.t_end = t[n - 1];

    // Fourier: project C on (1, sin, cos) with the trapezoidal inner product. On uniform samples
    // over whole periods (>= 3 per period) the Gram matrix is diag(L, L/2, L/2) and this is the
    // classical C0 = (1/L) int C, Ca = (2/L) int C sin, Cb = (2/L) int C cos; on non-uniform ones
    // it removes the quadrature error of the basis itself.
    Eigen::Matrix3d gram = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    std::vector<double> sin_k(m), cos_k(m);
    double sum_c = 0.0;
    for (std::size_t k = 0; k < m; ++k) {
        const double arg = s.omega * t[j0 + k] + s.phase;
        sin_k[k] = std::sin(arg);
        cos_k[k] = std::cos(arg);
        const Eigen::Vector3d b(1.0, sin_k[k], cos_k[k]);
        gram.noalias() += w[k] * b * b.transpose();
        rhs += w[k] * c[j0 + k] * b;
        sum_c += w[k] * c[j0 + k];
    }
    r.mean = sum_c / length;
    const Eigen::Matrix3d gram_unit = gram / length;  // diag(1, 1/2, 1/2) ideally
    const double smallest =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(gram_unit, Eigen::EigenvaluesOnly)
            .eigenvalues()
            .minCoeff();
    if (!(smallest > 1e-2)) {
        throw InputError(fmt::format(
            "{}: {} samples over {} period{} cannot separate the mean, sine and cosine parts "
            "(smallest eigenvalue {:.3g} of the normalised Gram matrix; 0.5 expected); sample "
            "each period more often",
            who, m, win.n_periods, win.n_periods == 1 ? "" : "s", smallest));
    }
    const Eigen::Vector3d fc = gram.ldlt().solve(rhs);
    r.fourier.c0 = fc[0];
    r.fourier.c_sin = fc[1];
    r.fourier.c_cos = fc[2];
    r.fourier.in_phase = fc[1] / s.amplitude;
    r.fourier.out_of_phase = fc[2] / (s.amplitude * s.reduced_frequency);

    // Regression: weighted least squares (weights = trapezoidal shares of the window, so the fit
    // is a time average and the two ends, one phase apart by whole periods, count once together).
    // Columns are scaled to unit norm before the QR so that small amplitudes or reduced
    // frequencies do not look rank-deficient.
    Eigen::MatrixXd a(m, 3);
    Eigen::VectorXd y(m);
    for (std::size_t k = 0; k < m; ++k) {
        const double sw = std::sqrt(w[k]);
        const auto row = static_cast<Eigen::Index>(k);
        const double dx = given_motion ? x[j0 + k] - s.x0 : s.amplitude * sin_k[k];
        const double xd =
            given_motion ? xdot_hat[j0 + k] : s.amplitude * s.reduced_frequency * cos_k[k];
        a(row, 0) = sw;
        a(row, 1) = sw * dx;
        a(row, 2) = sw * xd;
        y[row] = sw * c[j0 + k];
    }
    Eigen::Vector3d scale;
    for (Eigen::Index col = 0; col < 3; ++col) {
        scale[col] = a.col(col).norm();
        if (!(scale[col] > 0.0)) {
            throw InputError(fmt::format("{}: {} is zero over the window; nothing to regress on",
                                         who, col == 1 ? "x - x0" : "xdot_hat"));
        }
        a.col(col) /= scale[col];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
    qr.setThreshold(1e-10);
    if (qr.rank() < 3) {
        throw InputError(fmt::format(
            "{}: 1, x - x0 and xdot_hat are linearly dependent over the window; the regression "
            "cannot separate the in-phase and out-of-phase parts",
            who));
    }
    const Eigen::Vector3d beta = qr.solve(y).cwiseQuotient(scale);
    r.regression.c0 = beta[0];
    r.regression.in_phase = beta[1];
    r.regression.out_of_phase = beta[2];
    double ss_res = 0.0;
    double ss_tot = 0.0;
    for (std::size_t k = 0; k < m; ++k) {
        const double dx = given_motion ? x[j0 + k] - s.x0 : s.amplitude * sin_k[k];
        const double xd =
            given_motion ? xdot_hat[j0 + k] : s.amplitude * s.reduced_frequency * cos_k[k];
        const double res = c[j0 + k] - (beta[0] + beta[1] * dx + beta[2] * xd);
        const double dev = c[j0 + k] - r.mean;
        ss_res += w[k] * res * res;
        ss_tot += w[k] * dev * dev;
    }
    r.regression.residual_rms = std::sqrt(ss_res / length);
    r.regression.r_squared = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 1.0;
    return r;
}

}  // namespace

double reduced_frequency(double omega, double lref, double airspeed) {
    if (!std::isfinite(omega) || !std::isfinite(lref) || !(lref > 0.0) || !(airspeed > 0.0) ||
        !std::isfinite(airspeed)) {
        throw InputError(fmt::format(
            "reduced_frequency: omega = {} rad/s, lref = {} m, V = {} m/s; expected finite "
            "values with lref > 0 and V > 0",
            omega, lref, airspeed));
    }
    return omega * lref / (2.0 * airspeed);
}

OscillationResult analyse_oscillation(std::span<const double> t, std::span<const double> c,
                                      const OscillationSpec& spec) {
    return analyse(t, c, {}, {}, false, spec);
}

OscillationResult analyse_oscillation(std::span<const double> t, std::span<const double> c,
                                      std::span<const double> x, std::span<const double> xdot_hat,
                                      const OscillationSpec& spec) {
    return analyse(t, c, x, xdot_hat, true, spec);
}

}  // namespace manta::aero
