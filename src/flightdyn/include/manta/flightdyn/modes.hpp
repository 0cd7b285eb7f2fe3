#pragma once
/// @file modes.hpp
/// Dynamic modes of the aircraft about a trim point: eigenvalues of the linear model of
/// `linearise` (trim.hpp), split into the longitudinal subsystem (V, alpha, q, theta) and the
/// lateral-directional subsystem (beta, p, r, phi), each classified into the classical modes
/// (Etkin & Reid, *Dynamics of Flight: Stability and Control*, 3rd ed., Wiley 1996, ch. 6,
/// "Stability of uncontrolled motion"; the same modes in Stevens, Lewis & Johnson, *Aircraft
/// Control and Simulation*, 3rd ed., Wiley 2015):
///  - longitudinal: two complex pairs, the higher-frequency one the short period, the other the
///    phugoid; a pair that has split into two real roots is reported as two real modes labelled
///    "short period (real)" or "phugoid (real)";
///  - lateral-directional: a complex pair, the Dutch roll, and two real roots, the roll
///    subsidence (larger |lambda|) and the spiral (smaller); a split Dutch roll is labelled
///    "Dutch roll (real)", a second complex pair (coupled roll-spiral) "roll-spiral (coupled)".
/// The split is exact only for symmetric flight (wings level, no sideslip, no rates), where the
/// two subsystems decouple; elsewhere the full 12-state eigenvalues are the ones to trust.

#include <Eigen/Core>
#include <complex>
#include <string>
#include <vector>

#include "manta/flightdyn/trim.hpp"

namespace manta::flightdyn {

/// One mode: a complex-conjugate pair (reported by its eigenvalue with Im > 0) or a real root.
struct Mode {
    std::string name;  ///< "short period", "phugoid", "Dutch roll", "roll", "spiral", ...
    std::complex<double> eigenvalue;  ///< lambda [1/s]; Im >= 0 for a pair
    bool oscillatory = false;         ///< true for a complex pair
    double natural_frequency = 0.0;   ///< omega_n = |lambda| [rad/s]
    /// zeta = -Re(lambda) / |lambda| (1 or -1 for a real root, 0 at lambda = 0).
    double damping_ratio = 0.0;
    /// Damped period 2 pi / Im(lambda) [s]; +infinity for a real root.
    double period = 0.0;
    /// ln 2 / -Re(lambda) [s] for a decaying mode; +infinity otherwise.
    double time_to_half = 0.0;
    /// ln 2 / Re(lambda) [s] for a growing mode; +infinity otherwise.
    double time_to_double = 0.0;
    /// Re(lambda) < 0: the mode decays.
    [[nodiscard]] bool is_stable() const { return eigenvalue.real() < 0.0; }
};

/// Properties of the mode of eigenvalue `lambda` (name left empty).
[[nodiscard]] Mode make_mode(std::complex<double> lambda);

/// Modal analysis of a linear model.
struct ModesResult {
    /// Longitudinal subsystem of A, states (V, alpha, q, theta) in this order [SI, rad].
    Eigen::Matrix4d A_longitudinal;
    /// Lateral-directional subsystem of A, states (beta, p, r, phi) in this order.
    Eigen::Matrix4d A_lateral;
    Eigen::Vector4cd eigenvalues_longitudinal;  ///< of A_longitudinal, in Eigen's order
    Eigen::Vector4cd eigenvalues_lateral;       ///< of A_lateral, in Eigen's order
    /// Eigenvalues of the whole 12-state A (Euler-angle state of eom.hpp), sorted by real part
    /// then imaginary part. Includes the zero roots of x, y, psi and the slow altitude root.
    Eigen::Matrix<std::complex<double>, 12, 1> eigenvalues_full;
    std::vector<Mode> longitudinal;  ///< short period first, then phugoid
    std::vector<Mode> lateral;       ///< Dutch roll, roll, spiral
};

/// State indices (eom.hpp euler::Index) of the longitudinal subsystem: V, alpha, q, theta.
inline constexpr int longitudinal_states[4] = {euler::V, euler::alpha, euler::q, euler::theta};
/// State indices of the lateral-directional subsystem: beta, p, r, phi.
inline constexpr int lateral_states[4] = {euler::beta, euler::p, euler::r, euler::phi};

/// The 4x4 block of `A` over the states `idx`.
[[nodiscard]] Eigen::Matrix4d subsystem(const Eigen::Matrix<double, 12, 12>& A,
                                        const int (&idx)[4]);

/// Classify four longitudinal eigenvalues (see the file comment). Pairs are detected with a
/// relative imaginary-part tolerance of 1e-9.
[[nodiscard]] std::vector<Mode> classify_longitudinal(const Eigen::Vector4cd& eigenvalues);
/// Classify four lateral-directional eigenvalues (see the file comment).
[[nodiscard]] std::vector<Mode> classify_lateral(const Eigen::Vector4cd& eigenvalues);

/// Eigenvalues of both subsystems and of the full A, and the classified modes.
[[nodiscard]] ModesResult analyse_modes(const LinearModel& linear);

}  // namespace manta::flightdyn
