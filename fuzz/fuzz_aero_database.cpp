/// @file fuzz_aero_database.cpp
/// libFuzzer target for the aero database YAML reader (`aero::AeroDatabase::from_text`) (issue 16; docs/fuzzing.md): any bytes must give a
/// result or a `manta::Error`; any other exception, a crash, a hang or a sanitizer report is a
/// finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "manta/core/error.hpp"
#include "manta/aero/database.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        (void)manta::aero::AeroDatabase::from_text(text, "fuzz.madb.yaml");
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
