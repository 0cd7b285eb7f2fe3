/// @file fuzz_aircraft.cpp
/// libFuzzer target for the aircraft YAML reader (`aircraft::parse_aircraft`) (issue 16; docs/fuzzing.md): any bytes must give a
/// result or a `manta::Error`; any other exception, a crash, a hang or a sanitizer report is a
/// finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "manta/core/error.hpp"
#include "manta/aircraft/aircraft.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        // Relative file names (airfoils) resolve in a folder that does not exist.
        (void)manta::aircraft::parse_aircraft(text, "fuzz.yaml", "/nonexistent-fuzz-dir");
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
