#pragma once
/// @file manoeuvre.hpp
/// The manoeuvre file (docs/manoeuvres.md#file-format): entry condition, final conditions, path
/// constraints, mass case, mesh, cost and initial-guess hints of a time-optimal aircraft
/// manoeuvre, read through the validated configuration layer. SI units and radians inside;
/// angles are written with `_deg` keys in the file.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace manta::manoeuvres {

/// A condition on one quantity at the end of the manoeuvre: none, an interval [lower, upper]
/// (lower == upper for an equality), or equal to its entry value plus [lower, upper].
struct Target {
    enum class Kind { none, range, entry };
    Kind kind = Kind::none;
    double lower = 0.0;  ///< SI / radians (for `entry`: offset from the entry value)
    double upper = 0.0;  ///< SI / radians (for `entry`: offset from the entry value)
    [[nodiscard]] bool active() const { return kind != Kind::none; }
};

/// One attitude waypoint of the initial guess (3-2-1 Euler angles, radians).
struct GuessWaypoint {
    double fraction = 0.0;  ///< fraction of the guessed duration, 0..1
    double bank = 0.0;      ///< phi
    double pitch = 0.0;     ///< theta
    double heading = 0.0;   ///< psi, relative to the entry heading
    double speed = 0.0;     ///< [m/s]; 0: the entry speed
};

/// Conditions at an intermediate point of the manoeuvre (an interior event whose time is free),
/// splitting it into two phases: e.g. the Lazy Eight's 90 deg of bank at the top of the climb.
struct IntermediateSpec {
    bool present = false;      ///< an `intermediate` section was given
    double fraction = 0.5;     ///< guessed time of the event as a fraction of the duration
    Target speed;              ///< true airspeed [m/s]
    Target altitude;           ///< [m]
    Target heading_change;     ///< psi - psi(t0) [rad], modulo 2 pi
    Target bank;               ///< phi [rad], modulo 2 pi
    Target pitch;              ///< theta [rad]
    Target flight_path_angle;  ///< gamma [rad]
    [[nodiscard]] bool active() const { return present; }
};

/// A manoeuvre definition (see the file format in docs/manoeuvres.md).
struct ManoeuvreSpec {
    std::filesystem::path file;  ///< where it was read from
    std::string name;            ///< `name`
    std::string description;     ///< `description` ("" if absent)

    // --- entry -----------------------------------------------------------------------------
    double entry_speed = 0.0;     ///< true airspeed [m/s]
    double entry_altitude = 0.0;  ///< [m]
    double entry_heading = 0.0;   ///< psi [rad]
    double entry_climb = 0.0;     ///< flight-path angle of the trimmed entry [rad]
    /// True: the entry is the trimmed steady flight at (speed, altitude, climb, heading).
    /// False: the state given by the angles, rates and controls below.
    bool entry_trimmed = true;
    double entry_alpha = 0.0, entry_beta = 0.0;                ///< [rad] (given state)
    double entry_bank = 0.0, entry_pitch = 0.0;                ///< [rad] (given state)
    double entry_p = 0.0, entry_q = 0.0, entry_r = 0.0;        ///< [rad/s] (given state)
    std::array<double, 4> entry_controls{0.0, 0.0, 0.0, 0.0};  ///< de, da, dr [rad], throttle

    // --- final conditions ------------------------------------------------------------------
    Target speed;                  ///< true airspeed [m/s]
    Target altitude;               ///< [m]
    Target heading_change;         ///< psi(tf) - psi(t0) [rad], modulo 2 pi
    Target bank;                   ///< phi(tf) [rad], modulo 2 pi
    Target pitch;                  ///< theta(tf) [rad]
    Target flight_path_angle;      ///< gamma(tf) [rad]
    Target sideslip;               ///< beta(tf) [rad]
    Target north_change;           ///< x(tf) - x(t0) [m]
    Target east_change;            ///< y(tf) - y(t0) [m]
    Target roll_angle;             ///< integral of the body roll rate p over the manoeuvre [rad]
    bool final_rates_zero = true;  ///< p = q = r = 0 at the end (steady exit)

    // --- intermediate condition and phases --------------------------------------------------
    IntermediateSpec intermediate;         ///< `intermediate` (absent: one phase)
    std::vector<std::string> phase_names;  ///< `phases` (default: "manoeuvre", or two names)

    // --- path constraints ------------------------------------------------------------------
    std::array<double, 2> alpha{-0.10471975511965977, 0.20943951023931953};  ///< [rad]
    std::array<double, 2> beta{-0.17453292519943295, 0.17453292519943295};   ///< [rad]
    std::array<double, 2> load_factor{-3.0, 6.0};          ///< nz range (CS-23.337 aerobatic)
    std::array<double, 2> throttle{0.0, 1.0};              ///< within the aircraft's range
    std::array<double, 2> altitude_range{100.0, 15000.0};  ///< [m]
    std::array<double, 2> speed_range{40.0, 300.0};        ///< [m/s]
    /// `path.speed` was given: the true airspeed is a path constraint within speed_range at
    /// every node (else speed_range only bounds the body velocity u).
    bool speed_path = false;
    /// Largest Mach number (a path constraint at every node; 0: none).
    double mach_max = 0.0;
    /// Bank angle phi range [rad] (a path constraint at every node; none when not given).
    std::optional<std::array<double, 2>> bank_range;
    std::array<double, 2> east_range{-1e5, 1e5};  ///< east position y relative to the entry [m]
    double control_rate = 1.0471975511965976;     ///< |deflection rate| limit [rad/s] (60 deg/s)
    double throttle_rate = 0.5;                   ///< |throttle rate| limit [1/s]
    std::array<double, 3> body_rate_max{5.0, 3.0, 3.0};  ///< |p|, |q|, |r| limits [rad/s]
    /// Sign of the body roll rate p at every node (`path.roll_direction`): 0 either way, -1 to
    /// the left only (p <= 0, a barrel roll to the left), +1 to the right only (p >= 0).
    int roll_direction = 0;

    // --- mass -------------------------------------------------------------------------------
    std::string mass_case;                  ///< aircraft mass case ("" = the default)
    std::optional<double> mass;             ///< override [kg]
    std::optional<double> cg_mac_fraction;  ///< override, fraction of the MAC

    // --- mesh, cost, solver ----------------------------------------------------------------
    int nodes = 40;         ///< LGL points per segment
    int segments = 1;       ///< hp segments
    int coarse_nodes = 20;  ///< points per segment of a first coarse solve (0: none)
    /// With an intermediate condition: only the junction of the phases is a free break, the
    /// segments of each phase share its length equally (`mesh.breaks: junction`); false: every
    /// interior break is free (`mesh.breaks: free`).
    bool tie_breaks = true;
    std::string cost = "minimum_time";  ///< minimum_time (only form)
    /// Weight [s] of the integral of the squared control rates, each over its limit, added to tf.
    double rate_weight = 0.01;
    double duration_guess = 20.0;                ///< [s]
    std::array<double, 2> duration{1.0, 200.0};  ///< bounds on tf [s]
    std::vector<GuessWaypoint> guess;  ///< attitude waypoints (empty: entry attitude held)
    std::string hessian = "exact";     ///< exact or limited-memory
    double tolerance = 1e-7;           ///< IPOPT tol
    int max_iterations = 1000;         ///< IPOPT max_iter
};

/// Read and validate a manoeuvre file. ConfigError/IoError naming file, line and key.
[[nodiscard]] ManoeuvreSpec load_manoeuvre(const std::filesystem::path& file);
/// Same for YAML text; `source` names it in messages.
[[nodiscard]] ManoeuvreSpec parse_manoeuvre(std::string_view yaml_text, const std::string& source);

}  // namespace manta::manoeuvres
