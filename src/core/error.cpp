#include "manta/core/error.hpp"

#include <fmt/format.h>

namespace manta::detail {

void require_failed(const char* expr, const char* file, int line, const std::string& msg) {
    throw InputError(fmt::format("{} (requirement '{}' failed at {}:{})", msg, expr, file, line));
}

}  // namespace manta::detail
