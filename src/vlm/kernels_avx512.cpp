/// @file kernels_avx512.cpp
/// The vortex-lattice kernels (detail/kernels.hpp) for AVX-512 (F, DQ, VL, BW) with AVX2 and
/// FMA. CMake compiles this unit alone with those instruction sets on x86-64
/// (src/vlm/CMakeLists.txt); `kernels()` uses it only on a processor that has them all. Eigen is
/// renamed here so that none of its inline functions compiled for AVX-512 shares a name with the
/// rest of the program's (the linker could otherwise keep the AVX-512 copy for callers anywhere).

#include "manta/vlm/detail/kernels.hpp"

#if defined(__AVX512F__) && defined(__AVX512DQ__) && defined(__AVX512VL__) && \
    defined(__AVX512BW__) && defined(__FMA__)

// GCC 12 reports the deliberately undefined first operands of its own AVX-512 intrinsics
// (_mm512_undefined_ps and the like, inlined into Eigen's packet code) as maybe uninitialised,
// and at -O1 (the sanitizer build) as uninitialised.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

// Eigen's AVX-512 square roots under EIGEN_FAST_MATH (its default) are a reciprocal-square-root
// estimate with Newton steps, not correctly rounded, while the elements that a loop peels off for
// alignment take the exact scalar root: results would depend on the data's address. Exact roots
// (the other sets' double-precision roots are exact too).
#define EIGEN_FAST_MATH 0
#define Eigen manta_vlm_eigen_avx512
#include <immintrin.h>
#include <Eigen/Core>
#include <Eigen/LU>

namespace manta::vlm::detail::avx512 {

namespace {
constexpr const char* kernel_set_name = "avx512";
#include "kernels_impl.inc"
}  // namespace

const Kernels* table_if_built() {
    return &table;
}

}  // namespace manta::vlm::detail::avx512

#else

namespace manta::vlm::detail::avx512 {

const Kernels* table_if_built() {
    return nullptr;
}

}  // namespace manta::vlm::detail::avx512

#endif
