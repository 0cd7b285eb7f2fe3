/// @file companion.cpp
/// Names of the mesh models and levels.

#include <fmt/format.h>

#include <string>

#include "manta/core/error.hpp"
#include "manta/meshgen/meshgen.hpp"

namespace manta::meshgen {

std::string_view to_string(Model m) {
    return m == Model::half ? "half" : "full";
}
std::string_view to_string(Level l) {
    switch (l) {
        case Level::coarse:
            return "coarse";
        case Level::medium:
            return "medium";
        case Level::fine:
            return "fine";
    }
    return "coarse";
}
Model parse_model(std::string_view text, std::string_view what) {
    if (text == "half") return Model::half;
    if (text == "full") return Model::full;
    throw InputError(
        fmt::format("{}: value '{}' is not a model; expected half or full", what, text));
}
Level parse_level(std::string_view text, std::string_view what) {
    if (text == "coarse") return Level::coarse;
    if (text == "medium") return Level::medium;
    if (text == "fine") return Level::fine;
    throw InputError(
        fmt::format("{}: value '{}' is not a level; expected coarse, medium or fine", what, text));
}

}  // namespace manta::meshgen
