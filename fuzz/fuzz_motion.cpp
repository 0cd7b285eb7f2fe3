/// @file fuzz_motion.cpp
/// libFuzzer target for the motion CSV reader (`aero::parse_motion`); a motion read must also validate and write back (issue 16; docs/fuzzing.md): any bytes must give a
/// result or a `manta::Error`; any other exception, a crash, a hang or a sanitizer report is a
/// finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "manta/core/error.hpp"
#include "manta/aero/motion.hpp"
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const manta::aero::Motion m = manta::aero::parse_motion(text, "fuzz.csv");
        // Read back what it writes: a motion that does not round-trip is silently altered input.
        const manta::aero::Motion back =
            manta::aero::parse_motion(manta::aero::motion_to_text(m), "fuzz-back.csv");
        if (back.t != m.t || back.angles != m.angles || back.modes != m.modes) std::abort();
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
