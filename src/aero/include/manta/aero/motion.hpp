#pragma once
/// @file motion.hpp
/// `Motion`: the prescribed rigid-body and control-surface history that drives every unsteady
/// aerodynamic source (the unsteady vortex-lattice solver now, the CFD replay later), its text
/// file (docs/formats.md, "Motion file") and the forced-oscillation histories used to extract
/// dynamic derivatives (docs/forced-oscillation.md).
///
/// Frame (the *motion frame*): it translates, without rotating, at the entry free-stream speed v0
/// along its own x axis, so that in it the undisturbed air moves at (-v0, 0, 0). Its axes are the
/// flight-mechanics ones, x forward (along the entry air velocity), y right, z down (y horizontal);
/// for level entry flight heading north they are the earth axes of docs/conventions.md. `x_ref
/// y_ref z_ref` is the position of the moment reference point in this frame [m], and `phi theta
/// psi` are the 3-2-1 Euler angles [rad] from the motion frame to the body axes (x forward, y right
/// wing, z down). A motion of all zeros is steady flight at alpha = beta = 0 at speed v0; the
/// air-relative velocity of the reference point is (v0, 0, 0) + d(x_ref, y_ref, z_ref)/dt.
///
/// Control modes are deflections [rad] with the signs of docs/conventions.md, one per named mode
/// (`elevator`, `aileron`, `rudder` always; others such as `flap` may be added).

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace manta::aero {

/// Metadata of a motion file, written as `# key: value` lines before the header.
struct MotionMetadata {
    std::optional<double> v0;        ///< entry free-stream speed [m/s], > 0 (`# v0: 150.0`)
    std::optional<double> mach;      ///< entry Mach number, >= 0 (`# mach: 0.45`)
    std::optional<double> altitude;  ///< entry altitude [m] (`# altitude: 3000`)
    /// Any other `#` line, without the `#` and trimmed (written back as `# <text>`). A comment
    /// may not contain a line break nor start with `v0:`, `mach:` or `altitude:`.
    std::vector<std::string> comments;
};

/// The state of a motion at one instant, interpolated by `Motion::at`.
struct MotionState {
    double t = 0.0;                       ///< time evaluated [s] (after clamping)
    bool clamped = false;                 ///< true if the requested time lay outside [t0, tN]
    std::array<double, 3> position{};     ///< x_ref, y_ref, z_ref [m], motion frame
    std::array<double, 3> velocity{};     ///< their time derivatives [m/s], motion frame
    std::array<double, 3> euler{};        ///< phi, theta, psi [rad]
    std::array<double, 3> euler_rates{};  ///< phi_dot, theta_dot, psi_dot [rad/s]
    std::array<double, 3> omega_body{};   ///< p, q, r [rad/s], body axes
    std::vector<double> modes;            ///< deflections [rad], in `Motion::mode_names` order
    std::vector<double> mode_rates;       ///< their time derivatives [rad/s]
};

/// A sampled motion history: columns of equal length over strictly increasing times.
///
/// Interpolation (`at`): each column is a C1 piecewise cubic Hermite in time whose node slopes are
/// finite differences of fourth order, the derivative at t_i of the polynomial through the five
/// nearest samples (fewer when the motion has fewer than five): exact for quartics, hence for
/// cubics, error O(h^4) in values and O(h^3) in rates for smooth histories. The slopes are not
/// limited, so a step in a column overshoots (motions are meant to be smooth).
struct Motion {
    std::vector<double> t;                        ///< times [s], strictly increasing, >= 2 samples
    std::array<std::vector<double>, 3> position;  ///< x_ref, y_ref, z_ref [m], motion frame
    std::array<std::vector<double>, 3> angles;    ///< phi, theta, psi [rad]
    std::vector<std::string> mode_names;          ///< mode names without the `mode_` prefix
    std::vector<std::vector<double>> modes;       ///< modes[k][i]: mode k at sample i [rad]
    MotionMetadata metadata;

    /// Number of samples.
    [[nodiscard]] std::size_t n_samples() const { return t.size(); }
    /// Index of mode `name` (without prefix), or -1.
    [[nodiscard]] int find_mode(std::string_view name) const;
    /// Add a mode column (`values.size()` must equal `n_samples()` when validated).
    void add_mode(std::string name, std::vector<double> values);

    /// Check the invariants (the same as for a file): >= 2 samples, strictly increasing finite
    /// times, columns of the same length, finite values, modes elevator, aileron and rudder
    /// present, mode names unique and made of letters, digits and '_', metadata in range, and
    /// plausible values: |t| <= 10^6 s, |x_ref|, |y_ref|, |z_ref| <= 10^5 m, |phi|, |theta|,
    /// |psi| <= 100 rad (unwrapped angles may accumulate turns), |mode| <= pi/2 rad (a larger
    /// deflection is reported as degrees typed as radians).
    /// InputError in one line naming `source`, the row and the column.
    void validate(std::string_view source = "motion") const;

    /// Default clamping tolerance of `at`: 1e-6 of the duration.
    [[nodiscard]] double default_clamp_tolerance() const;
    /// The state at time `t`. A time outside [t0, tN] by at most `default_clamp_tolerance()` is
    /// clamped to the nearest end (the state there, rates included, `clamped` set); further out is
    /// an InputError. Requires a valid motion (see `validate`).
    [[nodiscard]] MotionState at(double time) const;
    /// As `at(time)` with an explicit clamping tolerance [s] (>= 0).
    [[nodiscard]] MotionState at(double time, double clamp_tolerance) const;
};

/// Parse motion-file text (docs/formats.md). `source` names the text in messages. InputError
/// (one line: source:line, the column and what was expected) for a missing column (all missing
/// ones named), an unknown column, a non-numeric or non-finite value, non-increasing time, fewer
/// than two rows or bad metadata.
[[nodiscard]] Motion parse_motion(std::string_view text, std::string source);
/// Read a motion file. IoError if it cannot be read; InputError as `parse_motion`.
[[nodiscard]] Motion read_motion(const std::filesystem::path& file);
/// Motion-file text of `motion` (validated first); numbers written exactly, so that
/// `parse_motion(motion_to_text(m))` equals `m` bit for bit.
[[nodiscard]] std::string motion_to_text(const Motion& motion);
/// Write a motion file atomically (a reader never sees half a file). InputError if the motion is
/// invalid, IoError if the file cannot be written.
void write_motion(const std::filesystem::path& file, const Motion& motion);

/// Deflection limits of one control mode of an aircraft [rad].
struct ModeLimit {
    std::string name;  ///< mode name without the `mode_` prefix ("elevator")
    double lower = 0.0;
    double upper = 0.0;
};

/// InputError naming `source`, the mode, the value, the time and the limits (in rad and deg)
/// when a mode of `motion` leaves its aircraft's limits; a value far beyond them is reported as a
/// likely unit slip (degrees typed as radians). Modes without a limit are not checked.
void check_mode_limits(const Motion& motion, const std::vector<ModeLimit>& limits,
                       std::string_view source);

/// The axis of a forced oscillation.
enum class OscillationAxis {
    roll,    ///< phi = mean + A sin(omega t): p = phi_dot
    pitch,   ///< theta = mean + A sin(omega t): alpha = theta, q = alpha_dot = theta_dot
    yaw,     ///< psi = mean + A sin(omega t): beta = -psi, r = psi_dot
    plunge,  ///< z_ref = mean + A sin(omega t) [m], z down: alpha ~ z_dot / v0, q = 0
};

[[nodiscard]] std::string_view to_string(OscillationAxis axis);

/// A forced harmonic oscillation about the reference point: on `axis`, mean + amplitude
/// sin(omega t) (amplitude and mean in rad, or m for plunge), every other column zero, modes
/// elevator, aileron and rudder zero. Samples t_i = i T / samples_per_period, i = 0 ...
/// n_periods * samples_per_period (T = 2 pi / omega, both ends included); the phase is reduced
/// to one period before the sine is taken, so every period holds the same values.
/// InputError unless omega > 0, n_periods >= 1, samples_per_period >= 4 and the values are finite.
[[nodiscard]] Motion harmonic_motion(OscillationAxis axis, double amplitude, double omega,
                                     int n_periods, int samples_per_period, double mean = 0.0,
                                     MotionMetadata metadata = {});

}  // namespace manta::aero
