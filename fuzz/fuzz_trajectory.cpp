/// @file fuzz_trajectory.cpp
/// libFuzzer target for the trajectory CSV reader (`replay::parse_trajectory`) (issue 16;
/// docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. A trajectory read must hold the physical
/// ranges of replay/trajectory.hpp and docs/replay.md (else `abort`, a finding).

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string_view>

#include "fuzz_check.hpp"
#include "manta/core/error.hpp"
#include "manta/replay/trajectory.hpp"

namespace {

using manta::fuzz::all_finite;
using manta::fuzz::all_within;
using manta::fuzz::check;

void check_trajectory(const manta::replay::Trajectory& tr) {
    constexpr double half_pi = std::numbers::pi / 2;
    const std::size_t n = tr.size();
    check(n >= 2, "trajectory: at least two rows");
    check(manta::fuzz::strictly_increasing(tr.t), "trajectory: t finite, strictly increasing");
    check(tr.line.size() == n, "trajectory: one line number per row");
    for (int k = 0; k < 3; ++k) {
        check(tr.position[k].size() == n && all_finite(tr.position[k]),
              "trajectory: x y z finite, one per row");
        check(tr.euler[k].size() == n && all_finite(tr.euler[k]),
              "trajectory: phi theta psi finite, one per row");
        check(tr.rates[k].size() == n && all_within(tr.rates[k], -20.0, 20.0),
              "trajectory: |p|, |q|, |r| <= 20 rad/s");
        check(tr.controls[k].size() == n && all_within(tr.controls[k], -half_pi, half_pi),
              "trajectory: |deflection| <= 90 deg");
    }
    check(all_within(tr.euler[1], -half_pi, half_pi), "trajectory: |theta| <= 90 deg");
    check(tr.V.size() == n && all_within(tr.V, 0.0, 1000.0), "trajectory: 0 < V <= 1000 m/s");
    for (const double v : tr.V) check(v > 0.0, "trajectory: V > 0");
    check(tr.alpha.size() == n && all_within(tr.alpha, -half_pi, half_pi),
          "trajectory: |alpha| <= 90 deg");
    check(tr.beta.size() == n && all_within(tr.beta, -half_pi, half_pi),
          "trajectory: |beta| <= 90 deg");
    check(tr.throttle.empty() || (tr.throttle.size() == n && all_within(tr.throttle, -0.05, 1.05)),
          "trajectory: throttle in [-0.05, 1.05]");
    check(tr.mach.empty() || (tr.mach.size() == n && all_within(tr.mach, 0.0, 5.0)),
          "trajectory: mach in [0, 5]");
    check(tr.phase.empty() || tr.phase.size() == n, "trajectory: one phase per row");
    for (const int p : tr.phase) check(p >= 0, "trajectory: phase >= 0");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        check_trajectory(manta::replay::parse_trajectory(text, "fuzz.csv"));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
