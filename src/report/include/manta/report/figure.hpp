#pragma once
/// @file figure.hpp
/// The report's figures as data: panels of x-y series (lines, markers, bands) and shaded
/// intervals, and the 3-D flight path. One model, three outputs: JSON for the page's renderer,
/// a standalone SVG and the CSV of every curve (`manta report --figures`).

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace manta::report {

/// How a series is drawn.
enum class SeriesStyle {
    line,     ///< solid polyline
    dashed,   ///< dashed polyline (reference levels, tolerances)
    markers,  ///< open circles (samples, collocation nodes)
    squares,  ///< open squares (the samples of a second table set)
    band,     ///< filled band between y (lower) and y_upper (e.g. +-2 sigma)
};

/// One series of a panel, in display units (degrees for angles).
struct Series {
    std::string name;    ///< legend text
    std::string colour;  ///< CSS colour, from `colour_of`
    SeriesStyle style = SeriesStyle::line;
    std::vector<double> x, y;
    std::vector<double> y_upper;  ///< band only: upper edge (y is the lower edge)
    bool legend = true;           ///< listed in the figure's legend
    double opacity = 0.2;         ///< band only: fill opacity (a second table set's: lighter)
};

/// A shaded x interval (e.g. a flagged part of a replay) with its label.
struct Shade {
    double x0 = 0.0, x1 = 0.0;
    std::string label;
};

/// One axes: labels carry the unit ("alpha [deg]").
struct Panel {
    std::string title;
    std::string x_label, y_label;
    std::vector<Series> series;
    std::vector<Shade> shades;
};

/// A grid of panels.
struct Figure {
    std::string id;  ///< unique in the report; file stem of --figures outputs
    std::string title;
    int columns = 3;  ///< panels per row
    std::vector<Panel> panels;
};

/// A flight path in earth axes with attitude glyphs (the paper's Fig. 9).
struct FlightPath {
    std::string id;
    std::string title;
    std::vector<double> t, north, east, altitude;      ///< [s], [m]
    std::vector<double> phi, theta, psi;               ///< [rad], at the same times
    std::vector<std::size_t> glyphs;                   ///< indices drawn with the aircraft glyph
    std::vector<std::array<double, 6>> body_segments;  ///< glyph in body axes [m]
    double glyph_scale = 1.0;                          ///< glyph magnification (drawing : aircraft)
};

/// The colour of a quantity or source, the same in every figure: "table", "replay", "samples",
/// "difference", "flag", "nodes" and the state and control names of the trajectory ("V",
/// "altitude", "alpha", "beta", "phi", "theta", "psi", "p", "q", "r", "nz", "elevator",
/// "aileron", "rudder", "throttle"), the control deflections "delta_min", "delta_max" and the
/// second table set of a comparison "compare" (its deflections "compare_min", "compare_max").
/// Unknown keys get a neutral grey.
[[nodiscard]] std::string colour_of(const std::string& key);

/// JSON of a figure for the page's renderer (numbers rounded to 7 significant digits).
[[nodiscard]] nlohmann::json to_json(const Figure& f);
/// JSON of a flight path for the page's renderer.
[[nodiscard]] nlohmann::json to_json(const FlightPath& p);

/// Standalone SVG of a figure: the same layout, axes, ticks and legend as the page.
[[nodiscard]] std::string to_svg(const Figure& f);
/// Standalone SVG of a flight path seen from a fixed direction (azimuth -60 deg, elevation
/// 25 deg), with axes in metres and the attitude glyphs.
[[nodiscard]] std::string to_svg(const FlightPath& p);

/// CSV of every curve of a figure, long format: `panel,series,x,y,y_upper` with '#' lines giving
/// the figure title and each panel's axis labels.
[[nodiscard]] std::string to_csv(const Figure& f);
/// CSV of a flight path: t, north, east, altitude, phi, theta, psi (SI, radians).
[[nodiscard]] std::string to_csv(const FlightPath& p);

/// "Nice" axis ticks covering [lo, hi] (about `target` of them, steps 1, 2 or 5 x 10^k).
[[nodiscard]] std::vector<double> nice_ticks(double lo, double hi, int target = 5);

}  // namespace manta::report
