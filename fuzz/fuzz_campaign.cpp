/// @file fuzz_campaign.cpp
/// libFuzzer target for the campaign YAML reader (`tables::parse_campaign`) (issue 16;
/// docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. A campaign read must hold what
/// docs/formats.md#campaign-file promises (else `abort`, a finding): axes finite and strictly
/// increasing, angles within 90 deg, Mach in [0, 0.95], 2 <= initial size <= budget <= table
/// entries, deflection axes holding 0, rate step and thresholds in range.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string_view>
#include <vector>

#include "fuzz_check.hpp"
#include "manta/core/error.hpp"
#include "manta/tables/campaign.hpp"

namespace {

using manta::fuzz::check;

// Degrees are converted after the range check, so allow the rounding of deg -> rad.
constexpr double max_angle = std::numbers::pi / 2 * (1 + 1e-12);

void check_axis(const std::vector<double>& v, bool angle, const char* what) {
    check(!v.empty() && manta::fuzz::strictly_increasing(v), what);
    if (angle)
        check(manta::fuzz::all_within(v, -max_angle, max_angle), what);
    else
        check(manta::fuzz::all_within(v, 0.0, 0.95), what);
}

void check_campaign(const manta::tables::Campaign& c) {
    const auto& s = c.static_table;
    check_axis(s.alpha, true, "campaign: static alpha axis increasing, within 90 deg");
    check_axis(s.mach, false, "campaign: static Mach axis increasing, in [0, 0.95]");
    check_axis(s.beta, true, "campaign: static beta axis increasing, within 90 deg");
    const std::size_t entries = s.alpha.size() * s.mach.size() * s.beta.size();
    check(s.initial_size >= 2 && s.initial_size <= s.budget &&
              static_cast<std::size_t>(s.budget) <= entries,
          "campaign: 2 <= initial size <= budget <= table entries");
    check(s.batch >= 0, "campaign: batch >= 0");
    check(s.cv_threshold >= 0.0 && s.cv_threshold <= 1.0, "campaign: cv_threshold in [0, 1]");
    check(s.kriging.nugget >= 0.0 && s.kriging.nugget <= 0.1, "campaign: nugget in [0, 0.1]");
    check(s.kriging.restarts >= 1, "campaign: kriging restarts >= 1");
    check(c.altitude >= -5000.0 && c.altitude <= 86000.0, "campaign: altitude in range");
    check(c.source.n_chord >= 1 && c.source.strip_width > 0.0 && c.source.strip_width <= 0.5,
          "campaign: lattice density in range");
    for (const auto& p : c.controls) {
        check_axis(p.deflection, true, "campaign: deflection axis increasing, within 90 deg");
        check(std::find(p.deflection.begin(), p.deflection.end(), 0.0) != p.deflection.end(),
              "campaign: deflection axis holds 0");
        check_axis(p.alpha, true, "campaign: control alpha axis increasing, within 90 deg");
        check_axis(p.mach, false, "campaign: control Mach axis increasing, in [0, 0.95]");
        check(p.samples >= 2 && static_cast<std::size_t>(p.samples) <=
                                    (p.deflection.size() - 1) * p.alpha.size() * p.mach.size(),
              "campaign: control samples no more than the deflected entries");
    }
    if (c.dynamic) {
        check_axis(c.dynamic->alpha, true, "campaign: dynamic alpha axis increasing, 90 deg");
        check_axis(c.dynamic->mach, false, "campaign: dynamic Mach axis increasing, [0, 0.95]");
        check(c.dynamic->rate_step >= 1e-6 && c.dynamic->rate_step <= 0.2,
              "campaign: rate step in [1e-6, 0.2]");
    }
    check(manta::fuzz::all_within(c.output.plot_mach, 0.0, 0.95), "campaign: plot Mach range");
    check(manta::fuzz::all_within(c.output.plot_beta, -max_angle, max_angle),
          "campaign: plot beta range");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        check_campaign(manta::tables::parse_campaign(text, "fuzz.yaml", "/nonexistent-fuzz-dir"));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
