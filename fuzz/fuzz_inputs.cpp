/// @file fuzz_inputs.cpp
/// libFuzzer target for the control-input CSV reader (`flightdyn::InputHistory::parse`) (issue
/// 16; docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. A history read must hold what
/// docs/flight-dynamics.md#control-inputs-csv promises (else `abort`, a finding): at least one
/// row, finite times strictly increasing, finite samples, deflections within 90 deg, and the
/// commands at the sample times equal to the samples.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string_view>

#include "fuzz_check.hpp"
#include "manta/core/error.hpp"
#include "manta/flightdyn/simulate.hpp"

namespace {

using manta::flightdyn::Channel;
using manta::fuzz::check;

double channel(const manta::flightdyn::Controls<double>& u, int c) {
    switch (c) {
        case 0:
            return u.elevator;
        case 1:
            return u.aileron;
        case 2:
            return u.rudder;
        default:
            return u.throttle;
    }
}

void check_history(const manta::flightdyn::InputHistory& h) {
    const auto& t = h.times();
    check(!t.empty(), "inputs: no rows");
    check(manta::fuzz::strictly_increasing(t), "inputs: times finite and strictly increasing");
    check(h.lines().size() == t.size(), "inputs: one line number per row");
    for (int c = 0; c < manta::flightdyn::n_channels; ++c) {
        const auto& v = h.samples(static_cast<Channel>(c));
        if (!h.has(static_cast<Channel>(c))) {
            check(v.empty(), "inputs: an absent channel has no samples");
            continue;
        }
        check(v.size() == t.size(), "inputs: one sample per row");
        check(manta::fuzz::all_finite(v), "inputs: samples finite");
        if (c != 3)
            check(manta::fuzz::all_within(v, -std::numbers::pi / 2, std::numbers::pi / 2),
                  "inputs: deflections within [-90, 90] deg");
    }
    for (std::size_t i = 0; i < t.size(); ++i) {
        const auto u = h.at(t[i]);
        for (int c = 0; c < manta::flightdyn::n_channels; ++c) {
            if (!h.has(static_cast<Channel>(c))) continue;
            check(channel(u, c) == h.samples(static_cast<Channel>(c))[i],
                  "inputs: the command at a sample time is the sample");
        }
        if (i + 1 < t.size()) {
            const auto m = h.at(0.5 * t[i] + 0.5 * t[i + 1]);
            for (int c = 0; c < manta::flightdyn::n_channels; ++c)
                check(std::isfinite(channel(m, c)), "inputs: interpolated command finite");
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        check_history(manta::flightdyn::InputHistory::parse(text, "fuzz.csv",
                                                            manta::flightdyn::Controls<double>{}));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
