#include "manta/aero/source.hpp"

#include <fmt/format.h>

#include "manta/core/error.hpp"

namespace manta::aero {

CoefficientHistory AeroSource::replay(const Motion& /*motion*/,
                                      const ProgressCallback& /*progress*/) const {
    throw InputError(fmt::format("aero source '{}' has no unsteady (time-accurate) mode", name()));
}

}  // namespace manta::aero
