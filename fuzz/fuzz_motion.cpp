/// @file fuzz_motion.cpp
/// libFuzzer target for the motion CSV reader (`aero::parse_motion`) (issue 16;
/// docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. A motion read must hold what
/// aero/motion.hpp promises (else `abort`, a finding): it validates, it writes back and reads
/// back equal, and the interpolated state (`Motion::at`) at each sample and between samples is
/// finite.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fuzz_check.hpp"
#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"

namespace {

using manta::fuzz::all_finite;
using manta::fuzz::check;

void check_state(const manta::aero::MotionState& s) {
    check(std::isfinite(s.t) && all_finite(s.position) && all_finite(s.velocity) &&
              all_finite(s.euler) && all_finite(s.euler_rates) && all_finite(s.omega_body) &&
              all_finite(s.modes) && all_finite(s.mode_rates),
          "motion: interpolated state finite");
}

void check_motion(const manta::aero::Motion& m) {
    m.validate("fuzz.csv");
    // Read back what it writes: a motion that does not round-trip is silently altered input.
    const manta::aero::Motion back =
        manta::aero::parse_motion(manta::aero::motion_to_text(m), "fuzz-back.csv");
    check(back.t == m.t && back.position == m.position && back.angles == m.angles &&
              back.mode_names == m.mode_names && back.modes == m.modes,
          "motion: written text reads back equal");
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        check_state(m.at(m.t[i]));
        if (i + 1 < m.t.size()) check_state(m.at(0.5 * m.t[i] + 0.5 * m.t[i + 1]));
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    manta::aero::Motion m;
    try {
        m = manta::aero::parse_motion(text, "fuzz.csv");
    } catch (const manta::Error&) {
        return 0;  // a one-line input error: the expected outcome for malformed input
    }
    try {
        check_motion(m);
    } catch (const manta::Error& e) {
        // A motion the reader accepted must validate, write, read back and interpolate.
        std::fprintf(stderr, "fuzz invariant violated: %s\n", e.what());
        std::abort();
    }
    return 0;
}
