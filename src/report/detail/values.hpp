#pragma once
/// @file values.hpp
/// Small helpers on breakpoint values shared by the report's content and comparison code.

#include <algorithm>
#include <cmath>
#include <vector>

namespace manta::report::detail {

/// Equal to a relative 1e-9 (absolute below 1): breakpoints read back from CSV text.
inline bool near(double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b));
}

/// Sorted distinct values (values within `near` of each other count once).
inline std::vector<double> distinct(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    std::vector<double> out;
    for (const double x : v)
        if (out.empty() || !near(x, out.back())) out.push_back(x);
    return out;
}

}  // namespace manta::report::detail
