#pragma once
/// @file ranger_text.hpp
/// The Ranger 2000's aircraft file for the meshgen tests, as text to be edited into bad variants.

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace manta::test {

inline const std::string ranger_file =
    std::string(MANTA_SOURCE_DIR) + "/examples/ranger2000/aircraft.yaml";

inline std::string ranger_text() {
    std::ifstream in(ranger_file);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// `text` with the first occurrence of `from` replaced by `to` (std::logic_error if absent).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto p = text.find(from);
    if (p == std::string::npos) throw std::logic_error("ranger_text: no '" + from + "'");
    return text.replace(p, from.size(), to);
}

}  // namespace manta::test
