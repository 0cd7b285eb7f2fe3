#pragma once
/// @file version.hpp
/// MANTA's version and the versions of the libraries it was built with.

#include <string>

namespace manta::core {

/// "0.1.0"
[[nodiscard]] std::string version();
/// One line per dependency: "eigen 3.4.0", "yaml-cpp", ...
[[nodiscard]] std::string dependency_versions();

}  // namespace manta::core
