/// @file fuzz_trajectory.cpp
/// libFuzzer target for the trajectory CSV reader (`replay::parse_trajectory`) (issue 16; docs/fuzzing.md): any bytes must give a
/// result or a `manta::Error`; any other exception, a crash, a hang or a sanitizer report is a
/// finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "manta/core/error.hpp"
#include "manta/replay/trajectory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        (void)manta::replay::parse_trajectory(text, "fuzz.csv");
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
