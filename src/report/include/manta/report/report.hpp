#pragma once
/// @file report.hpp
/// `manta report`: the self-contained HTML report of a run directory (docs/report.md), its
/// figures as SVG, CSV and PNG.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manta/report/compare.hpp"
#include "manta/report/figure.hpp"
#include "manta/report/run_data.hpp"

namespace manta::report {

/// A figure chosen from several (e.g. the static table at each Mach and sideslip) by a menu.
struct FigureGroup {
    std::string id;                   ///< element id
    std::string label;                ///< menu label
    std::vector<std::string> labels;  ///< one per choice
    std::vector<std::string> figure_ids;
    std::size_t initial = 0;  ///< the choice shown first
};

/// A picture drawn in C++ (inline SVG): a replay's surface Cp at a snapshot.
struct Picture {
    std::string id;          ///< unique; the file stem of --figures
    std::size_t replay = 0;  ///< index into RunData::replays
    std::string caption;     ///< what it shows (HTML-escaped when written)
    std::string svg;         ///< the SVG element
};

/// The Cp range of a replay's pictures: the 1st and 99th percentiles of the nodes' Cp.
struct CpRange {
    double lo = -1.0, hi = 1.0;
};
[[nodiscard]] CpRange cp_range(const std::vector<const SurfaceSnapshot*>& snapshots);
/// Plan views (from above and below, one scale) of a snapshot's wall coloured by Cp in `levels`
/// bands of `range`, the triangles of a band merged into polygons, with a colour bar.
[[nodiscard]] std::string cp_picture_svg(const SurfaceSnapshot& s, const CpRange& range,
                                         const std::string& title, int levels = 16);

/// Everything drawn in the report, built from the run data.
struct ReportContent {
    std::vector<Picture> pictures;         ///< surface Cp pictures, by replay
    std::vector<Figure> figures;           ///< every x-y figure (ids unique)
    std::vector<FlightPath> paths;         ///< one per manoeuvre
    std::vector<FigureGroup> groups;       ///< menus over figures
    std::vector<std::string> exported;     ///< ids written by --figures (every path too)
    std::optional<Comparison> comparison;  ///< with a second table set (--compare-tables)
};

/// Build the figures of a run (pure; no files touched).
[[nodiscard]] ReportContent build_content(const RunData& run);

/// Three-view drawing of the aircraft (side, top, front; one scale, metres) as SVG.
[[nodiscard]] std::string three_view_svg(const AircraftInfo& aircraft);

/// The whole HTML page (CSS, JavaScript and data inline; no external reference).
[[nodiscard]] std::string render_html(const RunData& run, const ReportContent& content);

/// What to do.
struct ReportOptions {
    std::filesystem::path run_dir;                     ///< RUN_DIR
    std::filesystem::path html;                        ///< --html FILE
    std::optional<std::filesystem::path> figures_dir;  ///< --figures DIR
    bool png = false;      ///< also render PNGs with headless chromium (a note if it is absent)
    std::string chromium;  ///< browser executable ("" = search PATH for chromium)
    /// --compare-tables DIR: a second `manta tables --out` directory drawn beside the tables.
    std::optional<std::filesystem::path> compare_tables;
    std::string compare_label;  ///< --compare-label ("" = from DIR's summary.json source)
};

/// What was done.
struct ReportResult {
    std::string layout;                ///< "run", "tables", "optimise", "replay"
    std::vector<std::string> parts;    ///< parts shown ("aircraft", "tables", "manoeuvre:x"...)
    std::vector<std::string> missing;  ///< parts or files absent
    std::size_t n_figures = 0;         ///< plots in the page
    std::size_t n_pictures = 0;        ///< surface Cp pictures (inline SVG) in the page
    std::vector<std::string> files;    ///< files written (the page last)
    std::string png_note;              ///< why PNGs were not written ("" if they were / not asked)
    std::size_t html_bytes = 0;
    nlohmann::json comparison;  ///< Comparison::to_json() (null without --compare-tables)
    /// As JSON (the --json output).
    [[nodiscard]] nlohmann::json to_json() const;
};

/// Read the run directory, build the report and write it (atomically; figures first, the page
/// last). Nothing is written when reading fails.
[[nodiscard]] ReportResult make_report(const ReportOptions& options);

/// Path of a headless-capable chromium ("chromium", "chromium-browser", "google-chrome" on PATH),
/// or "" if none.
[[nodiscard]] std::string find_chromium();

}  // namespace manta::report
