#pragma once
/// @file memory.hpp
/// Process-wide allocator settings for MANTA's programs (the `manta` CLI and the benchmarks that
/// measure what it does).

namespace manta::core {

/// Keep freed blocks of up to 64 MiB in the heap for reuse (glibc `mallopt`: mmap threshold
/// 64 MiB, trim threshold 256 MiB) instead of returning each to the system. A solver that builds
/// and frees matrices of a few MiB per evaluation (the vortex lattice's influence matrices, 15 MiB
/// for the Ranger) otherwise pays the page faults of fresh memory every time: 4-6 ms of a 50 ms
/// steady solve with all derivatives (docs/vlm.md). The process may then hold up to 256 MiB of
/// freed memory. Call once, first thing in main(); no effect on other C libraries.
void keep_large_allocations() noexcept;

}  // namespace manta::core
