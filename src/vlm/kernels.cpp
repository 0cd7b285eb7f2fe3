/// @file kernels.cpp
/// The vortex-lattice kernels (detail/kernels.hpp) for the baseline instruction set, and the
/// choice of the set at run time.

#include "manta/vlm/detail/kernels.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#if defined(__SSE2__)
#include <immintrin.h>
#endif
#include <cstdlib>
#include <string_view>

namespace manta::vlm::detail {

namespace avx2 {
const Kernels* table_if_built();
}
namespace avx512 {
const Kernels* table_if_built();
}

namespace base {
namespace {
constexpr const char* kernel_set_name = "baseline";
#include "kernels_impl.inc"
}  // namespace
}  // namespace base

const Kernels& baseline_kernels() {
    return base::table;
}

const Kernels* avx2_kernels() {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    static const bool cpu = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return cpu ? avx2::table_if_built() : nullptr;
#else
    return nullptr;
#endif
}

const Kernels* avx512_kernels() {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    static const bool cpu =
        __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return cpu ? avx512::table_if_built() : nullptr;
#else
    return nullptr;
#endif
}

const Kernels& kernels() {
    static const Kernels* chosen = [] {
        const char* env = std::getenv("MANTA_VLM_KERNELS");
        const std::string_view want = env != nullptr ? env : "";
        if (want == "baseline") return &base::table;
        // AVX-512 only on request: slower than AVX2 on the sandbox's AMD EPYC (docs/vlm.md).
        const Kernels* k = want == "avx512" ? avx512_kernels() : nullptr;
        if (k == nullptr) k = avx2_kernels();
        return k != nullptr ? k : &base::table;
    }();
    return *chosen;
}

}  // namespace manta::vlm::detail
