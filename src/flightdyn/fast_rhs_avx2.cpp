/// @file fast_rhs_avx2.cpp
/// The fused right-hand side (fast_rhs_impl.inc) for AVX2 with FMA. CMake compiles this unit
/// alone with -mavx2 -mfma on x86-64 (src/flightdyn/CMakeLists.txt); it is used only on a
/// processor that has both (fast_rhs.cpp). It includes no header that defines inline code
/// shared with the rest of the program except core/fastmath.hpp and core/frames_scalar.hpp,
/// whose namespace is renamed here, so the linker cannot pick an AVX2 copy of any function for
/// other callers.

#include "fast_rhs.hpp"

#if defined(__AVX2__) && defined(__FMA__)

#include <cmath>
#include <cstddef>
#include <cstring>

#include <immintrin.h>

#define manta manta_flightdyn_avx2
#include "manta/core/fastmath.hpp"
#include "manta/core/frames_scalar.hpp"
#undef manta

namespace manta::flightdyn::detail::avx2 {

namespace {
namespace fm = ::manta_flightdyn_avx2::core;
constexpr int vector_width = 4;
constexpr const char* kernel_set_name = "avx2";
#include "fast_rhs_impl.inc"
// The batched kernel uses the table code above.
#include "fast_rhs_batch_impl.inc"
const RhsKernels table = {&euler_kernel, &quaternion_kernel, &euler_kernel4, &quaternion_kernel4,
                          kernel_set_name};
}  // namespace

const RhsKernels* rhs_kernels_if_built() {
    return &table;
}

}  // namespace manta::flightdyn::detail::avx2

#else

namespace manta::flightdyn::detail::avx2 {

const RhsKernels* rhs_kernels_if_built() {
    return nullptr;
}

}  // namespace manta::flightdyn::detail::avx2

#endif
