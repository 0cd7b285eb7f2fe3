/// @file memory.cpp
#include "manta/core/memory.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace manta::core {

void keep_large_allocations() noexcept {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace manta::core
