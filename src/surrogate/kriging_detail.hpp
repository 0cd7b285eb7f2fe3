#pragma once
/// @file kriging_detail.hpp
/// Private helpers of the surrogate module: a small deterministic random generator whose output
/// does not depend on the standard library's distribution implementations (so designs and
/// likelihood starts are the same on every platform for a given seed).

#include <cstdint>

namespace manta::surrogate::detail {

/// SplitMix64 (Steele, Lea & Flood 2014): 64-bit state, full period, good enough for designs and
/// optimiser starts.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}

    /// Next 64 random bits.
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1) with 53 random bits.
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    /// Uniform integer in [0, m), m >= 1 (the modulo bias is below 2^-40 for m < 2^24).
    int index(int m) { return static_cast<int>(next() % static_cast<std::uint64_t>(m)); }

private:
    std::uint64_t state_;
};

}  // namespace manta::surrogate::detail
