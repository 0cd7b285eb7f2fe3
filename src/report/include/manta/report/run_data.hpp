#pragma once
/// @file run_data.hpp
/// The content of a run directory (docs/report.md#run-directory), read and validated: the
/// provenance, the aircraft, the tables of `manta tables`, the manoeuvres of `manta optimise` and
/// the replays of `manta replay`. Every part is optional; a part that is present must be well
/// formed, or reading fails with a one-line error naming the file, line and column.

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace manta::report {

/// The six coefficients in the shared vocabulary's order (CL CD CY wind axes, Cl Cm Cn body).
inline constexpr std::array<const char*, 6> coefficient_names{"CL", "CD", "CY", "Cl", "Cm", "Cn"};

/// A polyline of a view of the aircraft drawing, in the view's plane [m].
struct Outline {
    std::string part;                           ///< "wing", "fuselage", ...
    std::vector<std::array<double, 2>> points;  ///< closed if first == last
};

/// The aircraft as the report shows it (from `aircraft.yaml` through the aircraft module).
struct AircraftInfo {
    std::string file;                            ///< the file read
    std::string name;                            ///< `name`
    std::string description;                     ///< `description`
    double area = 0.0, span = 0.0, chord = 0.0;  ///< reference S [m^2], b [m], c-bar [m]
    std::array<double, 3> moment_reference{};    ///< geometry axes [m]
    double length = 0.0;                         ///< overall length [m]
    /// Loading cases: name, mass [kg], CG (geometry axes) [m], Ixx Iyy Izz Ixz [kg m^2].
    struct MassCase {
        std::string name;
        double mass = 0.0;
        std::array<double, 3> cg{};
        std::array<double, 4> inertia{};
    };
    std::vector<MassCase> mass_cases;
    std::string default_mass_case;
    /// Control limits [rad]: elevator, aileron, rudder (lower, upper).
    std::array<std::array<double, 2>, 3> control_limits{};
    std::string aero_label;  ///< how the aero model was obtained
    /// Three-view outlines: top (x aft, y right), side (x aft, z up), front (y right, z up).
    std::vector<Outline> top, side, front;
    /// Line segments of the aircraft in body axes about the default CG (x fwd, y right, z down)
    /// [m], for the attitude glyphs of the flight path: {x0, y0, z0, x1, y1, z1}.
    std::vector<std::array<double, 6>> body_segments;
};

/// A numeric table with named columns (CSV content or derived curves).
struct Columns {
    std::string source;                                 ///< file it came from
    std::vector<std::string> names;                     ///< column names in file order
    std::map<std::string, std::vector<double>> values;  ///< each of size n_rows()
    std::vector<std::string> comments;                  ///< '#' lines
    /// Number of rows.
    [[nodiscard]] std::size_t n_rows() const {
        return values.empty() ? 0 : values.begin()->second.size();
    }
    /// True if column `name` exists.
    [[nodiscard]] bool has(const std::string& name) const { return values.count(name) > 0; }
    /// Column `name` (std::out_of_range if absent: check `has` first).
    [[nodiscard]] const std::vector<double>& at(const std::string& name) const {
        return values.at(name);
    }
    /// Value of `# key: value` metadata, or "".
    [[nodiscard]] std::string meta(const std::string& key) const;
};

/// One entry of the static or a control table (tables.csv) [angles in rad].
struct TableEntry {
    double alpha = 0.0, mach = 0.0, beta = 0.0, delta = 0.0;
    std::array<double, 6> c{};      ///< coefficients (control tables: increments)
    std::array<double, 6> sigma{};  ///< Kriging standard deviations
};

/// A sample of the campaign (samples.csv, status done) [angles in rad].
struct Sample {
    std::string scenario;  ///< "static", "control:elevator", ...
    double alpha = 0.0, mach = 0.0, beta = 0.0;
    double elevator = 0.0, aileron = 0.0, rudder = 0.0;
    bool has_rates = false;  ///< p_hat, q_hat or r_hat non-zero
    std::array<double, 6> c{};
};

/// A `manta tables --out` directory.
struct TablesData {
    std::filesystem::path dir;
    /// Name in the page and the legends: summary.json's source name ("vlm", "euler"), else the
    /// directory's name; `--compare-label` replaces it for the second table.
    std::string label;
    std::vector<std::string> coefficient_columns;           ///< tables.csv's coefficient columns
    nlohmann::json summary;                                 ///< summary.json (null if absent)
    std::map<std::string, std::vector<TableEntry>> tables;  ///< "static", "elevator", ...
    std::vector<Sample> samples;                            ///< done samples (empty if absent)
    std::optional<Columns> dynamic;                         ///< dynamic.csv
    /// (Mach, beta [rad]) slices to show first: from the plot_static_M*_beta*.svg outputs named
    /// in summary.json, else the middle Mach at the beta nearest 0.
    std::vector<std::array<double, 2>> plot_slices;
    std::vector<std::string> missing;  ///< files of the layout that were absent
};

/// A `manta optimise --aircraft --out` directory.
struct ManoeuvreData {
    std::string name;  ///< folder name (or the trajectory's `manoeuvre` metadata)
    std::filesystem::path dir;
    nlohmann::json summary;            ///< summary.json (null if absent)
    std::optional<Columns> nodes;      ///< trajectory.csv (the LGL nodes)
    std::optional<Columns> dense;      ///< trajectory_dense.csv
    std::vector<std::string> phases;   ///< phase names from the metadata
    std::vector<std::string> missing;  ///< files of the layout that were absent
    /// The trajectory to draw: dense if present, else the nodes.
    [[nodiscard]] const Columns& curve() const { return dense ? *dense : *nodes; }
};

/// The wall of an Euler replay's surface snapshots (surface/wall.csv,
/// docs/formats.md#surface-snapshot): nodes and triangles (normals into the flow).
struct SurfaceWall {
    std::filesystem::path file;
    std::map<std::string, std::string> meta;             ///< every `# key: value` line
    std::vector<std::string> markers;                    ///< the wall markers
    std::vector<std::array<double, 3>> x;                ///< node coordinates (geometry axes) [m]
    std::vector<std::array<std::int32_t, 4>> triangles;  ///< a b c (node indices), marker index
};

/// One surface snapshot: Cp of every wall node at one instant.
struct SurfaceSnapshot {
    std::filesystem::path file;
    double t = 0.0;  ///< flight time [s]
    int step = 0;
    std::map<std::string, std::string> meta;  ///< every `# key: value` line
    std::shared_ptr<const SurfaceWall> wall;  ///< its wall.csv
    std::vector<double> cp;                   ///< one per wall node
};

/// A snapshot the report shows: at a flagged interval's largest difference, or for reference.
struct SnapshotPick {
    std::size_t snapshot = 0;  ///< into ReplayData::snapshots
    int flag = -1;             ///< index of the flagged interval in summary.json, -1: reference
    double t_wanted = 0.0;     ///< the instant it stands for [s]
    std::string why;           ///< the caption's reason
};

/// A `manta replay --out` directory.
struct ReplayData {
    std::string name;
    std::filesystem::path dir;
    /// The source in the page and the legends: summary.json's `source` (`euler`, `vlm`), else the
    /// name of the folder above (`replay-vlm` gives `vlm`).
    std::string label;
    nlohmann::json summary;             ///< summary.json (null if absent)
    std::optional<Columns> comparison;  ///< comparison.csv
    std::vector<std::string> missing;
    /// Replays of the same manoeuvre by other sources (RUN_DIR/replay-<source>/<name>/), drawn
    /// on the same axes.
    std::vector<ReplayData> others;
    /// surface/index.csv: every snapshot (step, t [s], file); empty without one.
    std::vector<std::tuple<int, double, std::string>> snapshot_index;
    std::vector<SurfaceSnapshot> snapshots;  ///< the ones picked (read)
    std::vector<SnapshotPick> picks;
};

/// Everything the report shows.
struct RunData {
    std::filesystem::path dir;              ///< the directory given
    std::string layout;                     ///< "run", "tables", "optimise" or "replay"
    nlohmann::json run;                     ///< run.json (null if absent)
    std::optional<AircraftInfo> aircraft;   ///< aircraft.yaml
    std::optional<TablesData> tables;       ///< tables/
    std::optional<TablesData> compare;      ///< --compare-tables: a second table set
    std::vector<ManoeuvreData> manoeuvres;  ///< manoeuvres/<name>/, sorted by name
    std::vector<ReplayData> replays;        ///< replay/<name>/, sorted by name
    std::vector<std::string> missing;       ///< parts of the layout that were absent
};

/// Read a run directory, or a single tables, optimise or replay output directory (recognised by
/// the files present). InputError/ConfigError/IoError with file, line and column on the first
/// malformed file; IoError if `dir` is not a directory or holds nothing a report could show.
[[nodiscard]] RunData read_run(const std::filesystem::path& dir);

/// Read an aircraft file into the report's summary (AircraftInfo).
[[nodiscard]] AircraftInfo read_aircraft_info(const std::filesystem::path& file);
/// Read a `manta tables --out` directory.
[[nodiscard]] TablesData read_tables(const std::filesystem::path& dir);
/// Read a `manta optimise --out` directory; `name` is the fallback name.
[[nodiscard]] ManoeuvreData read_manoeuvre(const std::filesystem::path& dir,
                                           const std::string& name);
/// Read a `manta replay --out` directory.
[[nodiscard]] ReplayData read_replay(const std::filesystem::path& dir, const std::string& name);
/// Read a snapshot's wall (surface/wall.csv) and a snapshot of it
/// (docs/formats.md#surface-snapshot). InputError naming the file and line when one is malformed
/// or the snapshot does not fit the wall.
[[nodiscard]] SurfaceWall read_surface_wall(const std::filesystem::path& file);
[[nodiscard]] SurfaceSnapshot read_surface_snapshot(const std::filesystem::path& file,
                                                    std::shared_ptr<const SurfaceWall> wall);
/// The snapshots a replay's page shows (docs/report.md): for each flagged interval the snapshot
/// nearest its time of largest |difference| / tolerance (at most `max_flagged` distinct ones),
/// and one reference snapshot outside every flagged interval (the one farthest from them; with
/// no flags the middle one). Uses the replay's summary, comparison and snapshot index.
[[nodiscard]] std::vector<SnapshotPick> pick_snapshots(const ReplayData& r,
                                                       std::size_t max_flagged = 6);
/// Read a trajectory CSV (docs/formats.md#trajectory-csv): the required columns t x y z phi
/// theta psi V alpha beta p q r elevator aileron rudder, times strictly increasing.
[[nodiscard]] Columns read_trajectory(const std::filesystem::path& file);
/// Read a replay comparison CSV: t, and C_replay, C_table, C_diff for the six coefficients.
[[nodiscard]] Columns read_comparison(const std::filesystem::path& file);

}  // namespace manta::report
