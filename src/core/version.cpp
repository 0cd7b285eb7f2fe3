#include "manta/core/version.hpp"

#include <fmt/format.h>
#include <Eigen/Core>

namespace manta::core {

std::string version() {
    return MANTA_VERSION_STRING;
}

std::string dependency_versions() {
    return fmt::format("eigen {}.{}.{}; fmt {}; compiler {}", EIGEN_WORLD_VERSION,
                       EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION, FMT_VERSION, __VERSION__);
}

}  // namespace manta::core
