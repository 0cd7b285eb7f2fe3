#include "manta/aero/source.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "manta/core/error.hpp"

namespace manta::aero {

std::unique_ptr<UnsteadyRun> AeroSource::start_unsteady(
    const Motion& /*motion*/, const UnsteadySettings& /*settings*/) const {
    throw InputError(fmt::format(
        "aero source '{}' has no unsteady (time-accurate) mode: it cannot move; expected a source "
        "that can (vlm)",
        name()));
}

CoefficientHistory AeroSource::replay(const Motion& motion,
                                      const ProgressCallback& progress) const {
    const std::unique_ptr<UnsteadyRun> run = start_unsteady(motion, {});
    CoefficientHistory out;
    out.t.reserve(static_cast<std::size_t>(run->n_steps()) + 1);
    auto record = [&](const UnsteadySample& s) {
        out.t.push_back(s.t);
        out.body.push_back(s.body);
        out.wind.push_back(s.wind);
        if (progress) progress(static_cast<double>(s.index) / std::max(1, run->n_steps()));
    };
    record(run->current());
    while (!run->finished()) record(run->step());
    return out;
}

}  // namespace manta::aero
