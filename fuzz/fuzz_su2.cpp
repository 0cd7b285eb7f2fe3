/// @file fuzz_su2.cpp
/// libFuzzer target for the SU2 native reader: any bytes given to `mesh::parse_su2` must either
/// give a finalized mesh or a `manta::Error` (docs/fuzzing.md). Any other exception, a crash or
/// a sanitizer report is a finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_mesh_check.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        manta::fuzz::check_mesh(manta::mesh::parse_su2(text, "fuzz.su2"));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
