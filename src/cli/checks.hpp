#pragma once
/// @file checks.hpp
/// The checks of command-line values, one kind per kind of option, applied to every numeric and
/// path option of every subcommand: a number must be the whole text of the value, finite (no NaN,
/// no infinity), not empty, and inside a plausible range for what it is (a speed, an altitude, an
/// angle, a tolerance, a time step ...). A value that fails is bad input (exit 2) with one line
/// naming the option, the value and the range: "--alpha-deg: value 'nan' is not a finite number;
/// expected a number in [-90, 90] deg".

#include <CLI/CLI.hpp>
#include <string>

namespace manta::cli {

/// A real number in [lo, hi] (with `lo_open`: lo < value <= hi), `unit` for the message ("m/s",
/// "deg"; "" for none), `range_name` for a value outside ("the US Standard Atmosphere 1976
/// range"; default "the range").
[[nodiscard]] CLI::Validator real_in(double lo, double hi, const std::string& unit = "",
                                     bool lo_open = false, const std::string& range_name = "");
/// An altitude [m]: inside the US Standard Atmosphere 1976 range.
[[nodiscard]] CLI::Validator altitude();
/// A real number in (0, hi].
[[nodiscard]] CLI::Validator real_positive(double hi, const std::string& unit = "");
/// An integer in [lo, hi].
[[nodiscard]] CLI::Validator integer_in(long long lo, long long hi);
/// A path of an output file or folder: not empty and not only blanks.
[[nodiscard]] CLI::Validator output_path();

/// Plausible ranges shared by several commands.
namespace range {
inline constexpr double max_speed = 1000.0;      ///< true airspeed [m/s] (about Mach 3)
inline constexpr double min_altitude = -5000.0;  ///< [m], below sea level (US 1976 table)
inline constexpr double max_altitude = 86000.0;  ///< [m], top of the US Standard Atmosphere
inline constexpr double max_angle_deg = 90.0;    ///< incidence, sideslip, deflection [deg]
inline constexpr double max_duration = 86400.0;  ///< simulated or replayed time [s], a day
inline constexpr double max_time_step = 10.0;    ///< [s]
inline constexpr double max_threads = 1024.0;    ///< worker threads and jobs
}  // namespace range

}  // namespace manta::cli
