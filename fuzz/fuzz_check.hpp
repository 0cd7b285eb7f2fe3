#pragma once
/// @file fuzz_check.hpp
/// Invariant checks of the fuzz targets (issue 16, "silently accepted nonsense"; docs/fuzzing.md):
/// after a reader returns, its result must hold what the reader's documentation promises (finite
/// numbers, the documented ranges and orderings). A violation prints the broken rule and aborts,
/// which libFuzzer reports as a crash and saves the input.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace manta::fuzz {

/// Abort with `what` when `ok` is false.
inline void check(bool ok, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
    std::abort();
}

inline bool finite(double v) {
    return std::isfinite(v);
}

/// Every element finite.
template <class Range>
bool all_finite(const Range& r) {
    for (const auto& v : r)
        if (!std::isfinite(static_cast<double>(v))) return false;
    return true;
}

/// Every element finite and in [lo, hi].
template <class Range>
bool all_within(const Range& r, double lo, double hi) {
    for (const auto& v : r)
        if (!(static_cast<double>(v) >= lo && static_cast<double>(v) <= hi)) return false;
    return true;
}

/// Finite and strictly increasing.
inline bool strictly_increasing(const std::vector<double>& v) {
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!std::isfinite(v[i])) return false;
        if (i > 0 && !(v[i] > v[i - 1])) return false;
    }
    return true;
}

}  // namespace manta::fuzz
