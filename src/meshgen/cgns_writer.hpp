#pragma once
/// @file cgns_writer.hpp
/// Internal: write a tetrahedral mesh with its marker faces as CGNS.

#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace manta::meshgen::detail {

/// `tris` holds the markers' faces one marker after the other, `markers` their names and counts
/// in that order, `roles` their boundary roles. IoError naming the file on failure.
void write_cgns(const std::filesystem::path& file, const std::vector<double>& xyz,
                const std::vector<std::array<long long, 4>>& tets,
                const std::vector<std::array<long long, 3>>& tris,
                const std::vector<std::pair<std::string, long long>>& markers,
                const std::vector<std::string>& roles);

}  // namespace manta::meshgen::detail
