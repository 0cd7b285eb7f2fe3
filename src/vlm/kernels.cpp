/// @file kernels.cpp
/// The vortex-lattice kernels (detail/kernels.hpp) for the baseline instruction set, and the
/// choice of the set at run time.

#include "manta/vlm/detail/kernels.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#include <cstdlib>
#include <string_view>

namespace manta::vlm::detail {

namespace avx2 {
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

const Kernels& kernels() {
    static const Kernels* chosen = [] {
        const char* env = std::getenv("MANTA_VLM_KERNELS");
        if (env != nullptr && std::string_view(env) == "baseline") return &base::table;
        const Kernels* k = avx2_kernels();
        return k != nullptr ? k : &base::table;
    }();
    return *chosen;
}

}  // namespace manta::vlm::detail
