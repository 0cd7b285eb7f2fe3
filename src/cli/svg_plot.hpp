#pragma once
/// @file svg_plot.hpp
/// Minimal stacked time-history plots as a standalone SVG (labelled axes with units, ticks,
/// one curve per panel). Used by `manta demo` for a first look; the report module of a later
/// issue supersedes it.

#include <string>
#include <vector>

namespace manta::cli {

struct Panel {
    std::string label;  ///< y-axis label with unit, e.g. "alpha [deg]"
    std::vector<double> y;
    std::string colour = "#1f77b4";
};

/// SVG text of panels sharing the x axis `t` (label `x_label`), in a grid of `columns`.
[[nodiscard]] std::string svg_time_histories(const std::string& title, const std::string& x_label,
                                             const std::vector<double>& t,
                                             const std::vector<Panel>& panels, int columns = 2);

}  // namespace manta::cli
