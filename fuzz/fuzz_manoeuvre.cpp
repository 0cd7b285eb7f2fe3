/// @file fuzz_manoeuvre.cpp
/// libFuzzer target for the manoeuvre YAML reader (`manoeuvres::parse_manoeuvre`) (issue 16;
/// docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. A manoeuvre read must hold what
/// docs/manoeuvres.md#file-format and src/manoeuvres/manoeuvre.cpp promise (else `abort`, a
/// finding): finite numbers, every [lower, upper] ordered, the entry speed, altitude and throttle,
/// the mesh sizes and the solver settings in range, the duration guess strictly inside its bounds.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "manta/core/error.hpp"
#include "manta/manoeuvres/manoeuvre.hpp"

namespace {

using manta::fuzz::check;
using manta::fuzz::finite;
using manta::manoeuvres::Target;

void check_target(const Target& t, const char* what) {
    if (!t.active()) return;
    check(finite(t.lower) && finite(t.upper) && t.lower <= t.upper, what);
}

void check_pair(const std::array<double, 2>& p, const char* what) {
    check(finite(p[0]) && finite(p[1]) && p[0] <= p[1], what);
}

bool within(double v, double lo, double hi) {
    return v >= lo && v <= hi;
}

void check_manoeuvre(const manta::manoeuvres::ManoeuvreSpec& s) {
    check(within(s.entry_speed, 10.0, 1000.0), "manoeuvre: entry speed in [10, 1000] m/s");
    check(within(s.entry_altitude, 0.0, 30000.0), "manoeuvre: entry altitude in [0, 30000] m");
    check(finite(s.entry_heading) && finite(s.entry_climb) && finite(s.entry_alpha) &&
              finite(s.entry_beta) && finite(s.entry_bank) && finite(s.entry_pitch) &&
              finite(s.entry_p) && finite(s.entry_q) && finite(s.entry_r),
          "manoeuvre: entry state finite");
    check(manta::fuzz::all_finite(s.entry_controls) && within(s.entry_controls[3], 0.0, 1.0),
          "manoeuvre: entry controls finite, throttle in [0, 1]");
    for (const Target* t :
         {&s.speed, &s.altitude, &s.heading_change, &s.bank, &s.pitch, &s.flight_path_angle,
          &s.sideslip, &s.north_change, &s.east_change, &s.roll_angle})
        check_target(*t, "manoeuvre: final condition finite, lower <= upper");
    const auto& im = s.intermediate;
    if (im.present) {
        check(within(im.fraction, 0.01, 0.99), "manoeuvre: intermediate fraction in [0.01, 0.99]");
        for (const Target* t : {&im.speed, &im.altitude, &im.heading_change, &im.bank, &im.pitch,
                                &im.flight_path_angle})
            check_target(*t, "manoeuvre: intermediate condition finite, lower <= upper");
    }
    check_pair(s.alpha, "manoeuvre: path alpha range ordered");
    check_pair(s.beta, "manoeuvre: path beta range ordered");
    check_pair(s.load_factor, "manoeuvre: load factor range ordered");
    check_pair(s.throttle, "manoeuvre: throttle range ordered");
    check(within(s.throttle[0], 0.0, 1.0) && within(s.throttle[1], 0.0, 1.0),
          "manoeuvre: throttle range within [0, 1]");
    check_pair(s.altitude_range, "manoeuvre: altitude range ordered");
    check_pair(s.speed_range, "manoeuvre: speed range ordered");
    check(s.speed_range[0] > 0.0, "manoeuvre: speed range positive");
    check(within(s.mach_max, 0.0, 5.0), "manoeuvre: mach_max in [0, 5]");
    if (s.bank_range) check_pair(*s.bank_range, "manoeuvre: bank range ordered");
    check_pair(s.east_range, "manoeuvre: east range ordered");
    check(finite(s.control_rate) && s.control_rate > 0.0, "manoeuvre: control rate > 0");
    check(finite(s.throttle_rate) && s.throttle_rate > 0.0, "manoeuvre: throttle rate > 0");
    for (const double r : s.body_rate_max)
        check(finite(r) && r > 0.0, "manoeuvre: body rate limits > 0");
    check(!s.mass || (finite(*s.mass) && *s.mass > 0.0), "manoeuvre: mass override > 0");
    check(!s.cg_mac_fraction || within(*s.cg_mac_fraction, -0.5, 1.5),
          "manoeuvre: cg override in [-0.5, 1.5]");
    check(within(s.nodes, 4, 300) && within(s.segments, 1, 50) && within(s.coarse_nodes, 0, 300),
          "manoeuvre: mesh sizes in range");
    check(finite(s.rate_weight) && s.rate_weight >= 0.0, "manoeuvre: rate weight >= 0");
    check_pair(s.duration, "manoeuvre: duration bounds ordered");
    check(s.duration[0] > 0.0, "manoeuvre: duration bounds positive");
    check(s.duration_guess > s.duration[0] && s.duration_guess < s.duration[1],
          "manoeuvre: duration guess strictly inside the bounds");
    for (const auto& w : s.guess)
        check(within(w.fraction, 0.0, 1.0) && finite(w.bank) && finite(w.pitch) &&
                  finite(w.heading) && finite(w.speed) && w.speed >= 0.0,
              "manoeuvre: guess waypoint finite, fraction in [0, 1]");
    check(finite(s.tolerance) && s.tolerance > 0.0, "manoeuvre: tolerance > 0");
    check(s.max_iterations >= 1, "manoeuvre: max_iterations >= 1");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        check_manoeuvre(manta::manoeuvres::parse_manoeuvre(text, std::string("fuzz.yaml")));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
