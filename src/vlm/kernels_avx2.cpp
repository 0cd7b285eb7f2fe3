/// @file kernels_avx2.cpp
/// The vortex-lattice kernels (detail/kernels.hpp) for AVX2 with FMA. CMake compiles this unit
/// alone with -mavx2 -mfma on x86-64 (src/vlm/CMakeLists.txt); `kernels()` uses it only on a
/// processor that has both. Eigen is renamed here so that none of its inline functions compiled
/// for AVX2 shares a name with the rest of the program's (the linker could otherwise keep the
/// AVX2 copy for callers anywhere).

#include "manta/vlm/detail/kernels.hpp"

#if defined(__AVX2__) && defined(__FMA__)

#define Eigen manta_vlm_eigen_avx2
#include <immintrin.h>
#include <Eigen/Core>
#include <Eigen/LU>

namespace manta::vlm::detail::avx2 {

namespace {
constexpr const char* kernel_set_name = "avx2";
#include "kernels_impl.inc"
}  // namespace

const Kernels* table_if_built() {
    return &table;
}

}  // namespace manta::vlm::detail::avx2

#else

namespace manta::vlm::detail::avx2 {

const Kernels* table_if_built() {
    return nullptr;
}

}  // namespace manta::vlm::detail::avx2

#endif
