/// @file fuzz_cfd_config.cpp
/// libFuzzer target for the CFD configuration YAML reader (`euler::parse_cfd_config`) (issue 16;
/// docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. A configuration read must hold the ranges
/// of docs/formats.md#cfd-configuration and src/euler/config.cpp (else `abort`, a finding).

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string_view>

#include "fuzz_check.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/config.hpp"

namespace {

using manta::fuzz::check;
using manta::fuzz::finite;

bool within(double v, double lo, double hi) {
    return v >= lo && v <= hi;
}

void check_config(const manta::euler::CfdConfig& c) {
    constexpr double half_pi = std::numbers::pi / 2;
    check(!c.mach || within(*c.mach, 0.0, 10.0), "cfd config: mach in [0, 10]");
    check(!c.alpha || within(*c.alpha, -half_pi, half_pi), "cfd config: |alpha| <= 90 deg");
    check(!c.beta || within(*c.beta, -half_pi, half_pi), "cfd config: |beta| <= 90 deg");
    check(c.gamma > 1.0 && c.gamma <= 2.0, "cfd config: gamma in (1, 2]");
    const auto& r = c.reference;
    check(finite(r.area) && r.area >= 0.0, "cfd config: reference area finite, >= 0");
    check(finite(r.chord) && r.chord > 0.0, "cfd config: reference chord finite, > 0");
    check(finite(r.span) && r.span > 0.0, "cfd config: reference span finite, > 0");
    check(finite(r.moment_point[0]) && finite(r.moment_point[1]) && finite(r.moment_point[2]),
          "cfd config: moment point finite");
    const auto& f = c.spatial.flux;
    check(within(f.jst_k2, 0.0, 2.0) && within(f.jst_k4, 0.0, 0.5), "cfd config: JST constants");
    check(within(f.entropy_fix, 0.0, 1.0), "cfd config: entropy fix in [0, 1]");
    check(c.spatial.order == 1 || c.spatial.order == 2, "cfd config: order 1 or 2");
    check(finite(c.spatial.venkatakrishnan_k) && c.spatial.venkatakrishnan_k > 0.0,
          "cfd config: Venkatakrishnan K finite, > 0");
    const auto& s = c.solver;
    check(finite(s.cfl_initial) && s.cfl_initial > 0.0, "cfd config: cfl finite, > 0");
    check(finite(s.cfl_max) && s.cfl_max >= s.cfl_initial, "cfd config: cfl_max >= cfl");
    check(within(s.cfl_growth, 1.0, 10.0), "cfd config: cfl_growth in [1, 10]");
    check(s.max_iterations >= 1, "cfd config: max_iterations >= 1");
    check(within(s.residual_drop, 0.1, 16.0), "cfd config: residual_drop in [0.1, 16]");
    check(finite(s.coefficient_tolerance) && s.coefficient_tolerance > 0.0,
          "cfd config: coefficient_tolerance finite, > 0");
    check(s.coefficient_window >= 2, "cfd config: coefficient_window >= 2");
    check(within(s.freeze_limiter_drop, 0.0, 16.0), "cfd config: freeze_limiter_drop");
    check(s.freeze_limiter_stall >= 0 && s.first_order_iterations >= 0,
          "cfd config: iteration counts >= 0");
    check(s.linear.max_iterations >= 1 && s.linear.max_iterations <= 1000 &&
              s.linear.restart >= 1 && s.linear.restart <= 1000,
          "cfd config: linear iterations and restart in [1, 1000]");
    check(within(s.linear.relative_tolerance, 0.0, 1.0), "cfd config: linear tolerance");
    check(s.max_backoffs >= 0 && s.max_backoffs <= 100, "cfd config: max_backoffs in [0, 100]");
    check(finite(c.output.checkpoint_interval_s) && c.output.checkpoint_interval_s >= 0.0,
          "cfd config: checkpoint interval finite, >= 0");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        check_config(manta::euler::parse_cfd_config(text, "fuzz.yaml"));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
