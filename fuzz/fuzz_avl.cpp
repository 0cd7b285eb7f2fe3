/// @file fuzz_avl.cpp
/// libFuzzer target for the AVL geometry reader (`vlm::parse_avl`) (issue 16; docs/fuzzing.md): any bytes must give a
/// result or a `manta::Error`; any other exception, a crash, a hang or a sanitizer report is a
/// finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "manta/core/error.hpp"
#include <string>
#include <vector>

#include "manta/vlm/avl_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        std::vector<std::string> warnings;
        (void)manta::vlm::parse_avl(text, "fuzz.avl", "/nonexistent-fuzz-dir", warnings);
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
