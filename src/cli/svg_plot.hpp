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

/// A curve of an x-y panel, optionally with a shaded band [band_lo, band_hi] (e.g. +-2 sigma).
struct XyCurve {
    std::string label;  ///< legend text
    std::vector<double> x, y;
    std::vector<double> band_lo, band_hi;  ///< empty: no band; else sized as x
    std::string colour = "#1f77b4";
};

/// Scattered points (markers) of an x-y panel.
struct XyPoints {
    std::string label;
    std::vector<double> x, y;
    std::string colour = "#d62728";
};

/// One x-y panel: curves with optional bands and marker sets.
struct XyPanel {
    std::string y_label;  ///< with unit
    std::vector<XyCurve> curves;
    std::vector<XyPoints> points;
};

/// SVG text of x-y panels sharing the x label, in a grid of `columns`, with a legend of the
/// first panel's curves and point sets under the title.
[[nodiscard]] std::string svg_xy_panels(const std::string& title, const std::string& x_label,
                                        const std::vector<XyPanel>& panels, int columns = 3);

/// A flight path for `svg_flight_path_3d`: positions in earth axes (x north, y east, altitude up)
/// [m] and 3-2-1 Euler angles [rad] at each sample.
struct FlightPath3d {
    std::vector<double> north, east, altitude;  ///< [m]
    std::vector<double> phi, theta, psi;        ///< [rad]
    std::vector<double> time;                   ///< [s], for the glyph labels (may be empty)
    int glyphs = 10;                            ///< number of attitude glyphs along the path
};

/// SVG text of a 3-D flight path like Fig. 9 of Ghoreyshi et al.: an oblique (axonometric, equal
/// scale on the three axes) projection of the path in a box with axes in metres, its ground
/// track, and aircraft glyphs (wings, nose, fin) drawn at the attitude of evenly spaced samples.
[[nodiscard]] std::string svg_flight_path_3d(const std::string& title, const FlightPath3d& path);

}  // namespace manta::cli
