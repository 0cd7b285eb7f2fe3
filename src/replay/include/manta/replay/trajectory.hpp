#pragma once
/// @file trajectory.hpp
/// The trajectory a replay starts from: the trajectory CSV of docs/formats.md#trajectory-csv
/// (written by `manta simulate` and `manta optimise --aircraft`, or a flight-test-like file with
/// the same columns), read and validated with one-line errors naming file, line and column.
///
/// Required columns (any order, unknown extra columns ignored): t, x y z (earth axes, z down),
/// phi theta psi (3-2-1 Euler angles earth to body), V, alpha beta, p q r, elevator aileron
/// rudder. Optional: throttle, mach, phase. Metadata lines `# key: value` before the header.
/// Physical ranges (docs/replay.md): 0 < V <= 1000 m/s, |alpha| and |beta| <= 90 deg,
/// |theta| <= 90 deg, phi and psi any finite value (unwrapped histories are allowed), |p|, |q|,
/// |r| <= 20 rad/s, |deflection| <= 90 deg, throttle in [-0.05, 1.05], 0 <= mach <= 5, phase >= 0
/// and integer; times strictly increasing; at least two rows.

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace manta::replay {

/// A validated trajectory, SI units and radians, one entry per row.
struct Trajectory {
    std::string source;                           ///< file name (messages)
    std::vector<double> t;                        ///< [s], strictly increasing
    std::array<std::vector<double>, 3> position;  ///< x y z earth axes [m] (z down)
    std::array<std::vector<double>, 3> euler;     ///< phi theta psi [rad], as in the file
    std::vector<double> V;                        ///< true airspeed [m/s]
    std::vector<double> alpha, beta;              ///< [rad]
    std::array<std::vector<double>, 3> rates;     ///< p q r [rad/s]
    std::array<std::vector<double>, 3> controls;  ///< elevator aileron rudder [rad]
    std::vector<double> throttle;                 ///< empty if absent
    std::vector<double> mach;                     ///< empty if absent
    std::vector<int> phase;                       ///< empty if absent
    std::vector<std::string> phase_names;         ///< `# phases:` (empty if absent)
    std::map<std::string, std::string> metadata;  ///< every `# key: value` line
    std::vector<int> line;                        ///< 1-based file line of each row

    [[nodiscard]] std::size_t size() const { return t.size(); }
    /// Metadata value or `fallback`.
    [[nodiscard]] std::string meta(const std::string& key, const std::string& fallback = {}) const;
};

/// Parse trajectory CSV text; `source` names it in messages. InputError, one line naming
/// source:line and the column, for a missing column (all missing ones named), a field that is
/// not a number, NaN or infinity, a time not after the one before, a value outside its physical
/// range, a short row, or fewer than two rows.
[[nodiscard]] Trajectory parse_trajectory(std::string_view text, std::string source);
/// Read a trajectory file: IoError if unreadable, else as `parse_trajectory`.
[[nodiscard]] Trajectory read_trajectory(const std::filesystem::path& file);

}  // namespace manta::replay
