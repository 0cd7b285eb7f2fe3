/// @file fuzz_aero_database.cpp
/// libFuzzer target for the aero database YAML reader (`aero::AeroDatabase::from_text`) (issue
/// 16; docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other exception, a
/// crash, a hang or a sanitizer report is a finding. A database read must hold what
/// docs/aero-database.md promises (else `abort`, a finding): one static table, axes finite and
/// strictly increasing, angles within 2 pi rad, Mach in [0, 10], values sized, finite and within
/// 100 (static and control tables) or 1000 (dynamic derivatives), the text written back read back
/// to the same text (exact round trip), and finite coefficients at the first breakpoints and at
/// the middle of every axis, with both interpolations.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/error.hpp"

namespace {

using manta::aero::Axis;
using manta::aero::TableKind;
using manta::fuzz::check;

void set_axis(manta::aero::AeroQuery<double>& q, Axis a, double v) {
    switch (a) {
        case Axis::alpha:
            q.alpha = v;
            break;
        case Axis::beta:
            q.beta = v;
            break;
        case Axis::mach:
            q.mach = v;
            break;
        case Axis::elevator:
            q.elevator = v;
            break;
        case Axis::aileron:
            q.aileron = v;
            break;
        case Axis::rudder:
            q.rudder = v;
            break;
    }
}

bool finite(const manta::aero::BodyCoefficients<double>& c) {
    return std::isfinite(c.CX) && std::isfinite(c.CY) && std::isfinite(c.CZ) &&
           std::isfinite(c.Cl) && std::isfinite(c.Cm) && std::isfinite(c.Cn);
}

void check_database(const manta::aero::AeroDatabase& db) {
    int n_static = 0;
    // Per axis, the range every table with that axis covers (a query inside it extrapolates
    // nowhere).
    std::array<double, 6> lo, hi;
    lo.fill(-std::numeric_limits<double>::infinity());
    hi.fill(std::numeric_limits<double>::infinity());
    for (const auto& t : db.tables()) {
        if (t.kind == TableKind::static_table) ++n_static;
        std::size_t points = 1;
        for (const auto& a : t.axes) {
            check(!a.breakpoints.empty(), "aero database: an axis has breakpoints");
            check(manta::fuzz::strictly_increasing(a.breakpoints),
                  "aero database: breakpoints finite and strictly increasing");
            if (manta::aero::is_angle(a.axis))
                check(manta::fuzz::all_within(a.breakpoints, -2 * std::numbers::pi,
                                              2 * std::numbers::pi),
                      "aero database: angles within 2 pi rad");
            if (a.axis == Axis::mach)
                check(manta::fuzz::all_within(a.breakpoints, 0.0, 10.0),
                      "aero database: Mach in [0, 10]");
            points *= a.breakpoints.size();
            const auto k = static_cast<std::size_t>(a.axis);
            lo[k] = std::max(lo[k], a.breakpoints.front());
            hi[k] = std::min(hi[k], a.breakpoints.back());
        }
        check(t.n_points() == points, "aero database: n_points is the product of the axis sizes");
        check(t.values.size() == points * t.columns.size(), "aero database: values sized");
        const double limit = t.kind == TableKind::dynamic ? 1000.0 : 100.0;
        check(manta::fuzz::all_within(t.values, -limit, limit),
              "aero database: values finite and within the plausible magnitude");
    }
    check(n_static == 1, "aero database: exactly one static table");
    const std::string text = db.to_text();
    const auto back = manta::aero::AeroDatabase::from_text(text, "fuzz-back.madb.yaml");
    check(back.to_text() == text, "aero database: written text reads back to the same text");
    manta::aero::AeroQuery<double> first, middle;
    for (std::size_t k = 0; k < 6; ++k) {
        if (lo[k] > hi[k]) return;            // no query inside every table: evaluation not checked
        if (!std::isfinite(lo[k])) continue;  // no table has this axis: 0
        set_axis(first, static_cast<Axis>(k), lo[k]);
        set_axis(middle, static_cast<Axis>(k), 0.5 * lo[k] + 0.5 * hi[k]);
    }
    for (const auto method :
         {manta::aero::Interpolation::multilinear, manta::aero::Interpolation::c1}) {
        check(finite(db.evaluate(first, method)), "aero database: coefficients finite (first)");
        check(finite(db.evaluate(middle, method)), "aero database: coefficients finite (middle)");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const auto db = manta::aero::AeroDatabase::from_text(text, "fuzz.madb.yaml");
        try {
            check_database(db);
        } catch (const manta::Error& e) {
            // The database's own text must read back: an error here is a finding.
            std::fprintf(stderr, "fuzz invariant violated: %s\n", e.what());
            std::abort();
        }
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
