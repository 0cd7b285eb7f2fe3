#pragma once
/// @file motion_builder.hpp
/// The motion file of a replay, after Ghoreyshi et al. (AIAA 2010), sec. II.D: the flow solution
/// keeps the entry free stream v0; the moment reference point moves with the air-relative
/// velocity minus v0; the body turns by the Euler angles relative to the motion frame; one mode
/// per control surface carries its deflection. Theory and accuracy: docs/replay.md.

#include <Eigen/Core>
#include <array>
#include <string>

#include "manta/aero/motion.hpp"
#include "manta/replay/trajectory.hpp"

namespace manta::replay {

/// The time step a replay takes and why (docs/replay.md, "Time step").
struct TimeStepChoice {
    double dt = 0.0;             ///< [s]
    double rate_scale = 0.0;     ///< 1 / max |omega| [s] (inf when the body does not turn)
    double control_scale = 0.0;  ///< min over controls of range / max |rate| [s] (inf if still)
    std::string reason;          ///< which bound decided
};

/// Bounds of the automatic time step.
struct TimeStepRule {
    double fraction = 0.1;  ///< dt = fraction x the shortest time scale ...
    double min_dt = 0.005;  ///< ... bounded below [s] ...
    double max_dt = 0.05;   ///< ... and above [s] ...
    /// ... and by the convective time: the air crosses at most this many reference chords per
    /// step, dt <= max_chords c_ref / V_max (when a chord is given).
    double max_chords = 1.0;
};

/// The automatic replay time step of `trajectory`: a fraction of the shortest time scale of the
/// body rates (1 / max |omega|) and of the control motion (the largest deflection change over
/// the manoeuvre divided by the largest deflection rate, per control), within [min_dt, max_dt]
/// and, with a reference `chord` > 0, at most max_chords c_ref / max V.
[[nodiscard]] TimeStepChoice choose_time_step(const Trajectory& trajectory,
                                              const TimeStepRule& rule = {}, double chord = 0.0);

/// A replay motion and the frame it lives in.
struct ReplayMotion {
    aero::Motion motion;  ///< sampled every `sample_dt`, metadata v0, mach, altitude
    double sample_dt = 0.0;
    double v0 = 0.0;         ///< entry airspeed [m/s]
    double mach0 = 0.0;      ///< entry Mach number
    double altitude0 = 0.0;  ///< entry altitude [m]
    /// Direction cosines from earth to motion axes: x along the entry air velocity, y
    /// horizontal to the right, z down (the earth axes turned by the entry track angle chi0
    /// about z, then by the flight-path angle gamma0 about y).
    Eigen::Matrix3d earth_to_motion = Eigen::Matrix3d::Identity();
    Eigen::Vector3d entry_position = Eigen::Vector3d::Zero();  ///< earth axes [m]
    double chi0 = 0.0, gamma0 = 0.0;                           ///< [rad]
};

/// The motion of `trajectory` sampled every `sample_dt` (the last sample at its final time).
/// The air velocity is C_earth_from_body (V cos a cos b, V sin b, V sin a cos b), integrated
/// (Simpson per sample interval, the trajectory interpolated by the C1 cubic of aero::Motion)
/// minus v0 t along the motion x axis. The Euler angles relative to the motion frame are kept
/// continuous: of the two 3-2-1 triples of each attitude, (phi, theta, psi) and
/// (phi + pi, pi - theta, psi + pi), each modulo 2 pi, the one nearest the previous sample, so a
/// loop passes through theta = 90 deg smoothly. Mach: the trajectory's `mach` column, else V
/// over the US 1976 speed of sound at altitude -z. InputError if sample_dt is not positive.
[[nodiscard]] ReplayMotion build_motion(const Trajectory& trajectory, double sample_dt);

/// The trajectory as an interpolant (aero::Motion with position x y z earth, the Euler angles
/// made continuous as above, and modes elevator aileron rudder V alpha beta mach p q r).
[[nodiscard]] aero::Motion trajectory_interpolant(const Trajectory& trajectory);

/// The first `duration` seconds of `trajectory` (from its first time t0), as if the file ended
/// there: its rows before t0 + duration and a last row at exactly t0 + duration (a row within
/// 1e-9 s of it is kept as it is). The last row's columns are those of trajectory_interpolant
/// there (the C1 cubic the replay motion follows): position, airspeed, air angles, body rates,
/// deflections and, when the trajectory has one, Mach; its Euler angles the principal triple
/// (|theta| <= 90 deg) of the interpolated attitude, phi and psi shifted by whole turns to the row
/// before; the throttle linear between the neighbouring rows; the phase and file line those of
/// the row before. A duration that reaches the last row gives the whole trajectory. InputError
/// unless duration is finite and at least 1e-6 s.
[[nodiscard]] Trajectory first_seconds(const Trajectory& trajectory, double duration);

/// Euler angles of a direction-cosine matrix body-from-frame, continuous with `previous` (see
/// build_motion); with no previous the principal triple of core::euler_from_dcm, |theta| <= pi/2.
/// (The matrix of a triple is core::dcm_body_from_earth, manta/core/frames.hpp.)
[[nodiscard]] std::array<double, 3> continuous_euler(const Eigen::Matrix3d& body_from_frame,
                                                     const std::array<double, 3>* previous);

/// Air state of the reference point at time t along a motion (as the unsteady sources compute
/// it): angle of attack, sideslip [rad] and airspeed [m/s].
struct AirState {
    double alpha = 0.0, beta = 0.0, airspeed = 0.0;
};
[[nodiscard]] AirState motion_air_state(const aero::Motion& motion, double v0, double t);

/// Earth position [m] and earth Euler angles [rad] of the reference point at time t
/// re-integrated from the motion (the inverse of build_motion, for checks and plots).
struct EarthPose {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    std::array<double, 3> euler{};
};
[[nodiscard]] EarthPose earth_pose(const ReplayMotion& replay_motion, double t);

}  // namespace manta::replay
