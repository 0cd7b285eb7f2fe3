/// @file fuzz_cases.cpp
/// libFuzzer target for the cases CSV of `manta simulate --cases` (`flightdyn::parse_cases`, no
/// inputs files read) (issue 16; docs/fuzzing.md): any bytes must give cases or a
/// `manta::Error`; any other exception, a crash, a hang or a sanitizer report is a finding. Cases
/// read must hold what docs/formats.md#cases-csv promises (else `abort`, a finding): 1 to
/// max_cases rows on increasing lines, each name safe as a file name and unique ignoring case,
/// speed finite and > 0, altitude finite, climb angle in (-90, 90) deg, an inputs path in UTF-8.

#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>

#include "manta/core/error.hpp"
#include "manta/core/utf8.hpp"
#include "manta/flightdyn/cases.hpp"

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

void check_cases(const std::vector<manta::flightdyn::CaseRow>& rows) {
    check(!rows.empty() && rows.size() <= manta::flightdyn::max_cases);
    std::set<std::string> names;
    int line = 0;
    for (const auto& c : rows) {
        check(c.line > line);
        line = c.line;
        check(manta::flightdyn::unsafe_case_name_reason(c.name).empty());
        std::string low = c.name;
        for (char& ch : low) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        check(names.insert(low).second);
        check(std::isfinite(c.speed) && c.speed > 0.0);
        check(std::isfinite(c.altitude));
        check(std::isfinite(c.climb_angle_deg) && std::abs(c.climb_angle_deg) < 90.0);
        check(manta::core::is_utf8(c.inputs));
        check(c.inputs.empty() == (c.inputs_column == 0));
        check(c.inputs.empty() == c.inputs_path.empty());
        check(c.inputs_text.empty());
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        check_cases(manta::flightdyn::parse_cases(text, "fuzz/cases.csv"));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
