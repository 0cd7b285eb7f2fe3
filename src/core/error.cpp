#include "manta/core/error.hpp"

#include <fmt/format.h>

#include "manta/core/text.hpp"

namespace manta {

Error::Error(const std::string& message) : std::runtime_error(core::printable(message)) {}
Error::Error(const char* message) : Error(std::string(message)) {}

}  // namespace manta

namespace manta::detail {

void require_failed(const char* expr, const char* file, int line, const std::string& msg) {
    throw InputError(fmt::format("{} (requirement '{}' failed at {}:{})", msg, expr, file, line));
}

}  // namespace manta::detail
