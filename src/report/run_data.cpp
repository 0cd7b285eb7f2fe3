/// @file run_data.cpp
/// Reading and validating a run directory for the report.

#include "manta/report/run_data.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/frames.hpp"
#include "manta/core/io.hpp"
#include "manta/report/text_csv.hpp"

namespace manta::report {

namespace fs = std::filesystem;

namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;

Columns to_columns(const core::CsvTable& t) {
    Columns c;
    c.source = t.source;
    c.names = t.columns;
    c.comments = t.comments;
    for (std::size_t j = 0; j < t.columns.size(); ++j) c.values[t.columns[j]] = t.column(j);
    return c;
}

/// Times must increase strictly; the message names the file and the line of the offending row.
void require_increasing(const core::CsvTable& t, std::size_t col) {
    for (std::size_t i = 1; i < t.rows.size(); ++i)
        if (!(t.rows[i][col] > t.rows[i - 1][col]))
            throw InputError(fmt::format(
                "{}:{}: column '{}' value {} does not increase (previous row {}); expected "
                "strictly increasing times",
                t.source, t.row_lines[i], t.columns[col], t.rows[i][col], t.rows[i - 1][col]));
}

std::vector<std::string> split_list(const std::string& s) {
    std::vector<std::string> out;
    std::size_t pos = 0;
    while (pos <= s.size()) {
        const auto k = s.find(',', pos);
        std::string item = s.substr(pos, k == std::string::npos ? std::string::npos : k - pos);
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t") + 1);
        if (!item.empty()) out.push_back(item);
        if (k == std::string::npos) break;
        pos = k + 1;
    }
    return out;
}

/// Outlines of a lifting surface in the three views, and its body-axis segments.
void add_surface(const geometry::LiftingSurface& s, AircraftInfo& a, const Eigen::Vector3d& cg) {
    const int copies = s.n_copies();
    for (int copy = 0; copy < copies; ++copy) {
        const double m = copy == 0 ? 1.0 : -1.0;  // mirror y for the second copy
        std::vector<Eigen::Vector3d> ring;        // LE root..tip, then TE tip..root
        for (const auto& sec : s.sections) ring.push_back(sec.leading_edge);
        for (auto it = s.sections.rbegin(); it != s.sections.rend(); ++it)
            ring.push_back(it->leading_edge + Eigen::Vector3d(it->chord, 0.0, 0.0));
        ring.push_back(ring.front());
        Outline top{s.name, {}}, side{s.name, {}}, front{s.name, {}};
        for (const auto& p : ring) {
            top.points.push_back({p.x(), m * p.y()});
            side.points.push_back({p.x(), p.z()});
            front.points.push_back({m * p.y(), p.z()});
        }
        a.top.push_back(top);
        if (copy == 0) a.side.push_back(side);
        a.front.push_back(front);
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
            auto body = [&](const Eigen::Vector3d& g) {
                const Eigen::Vector3d b = core::body_from_geometry(
                    Eigen::Vector3d(g.x() - cg.x(), m * g.y(), g.z() - cg.z()));
                return std::array<double, 3>{b.x(), b.y(), b.z()};
            };
            const auto p0 = body(ring[i]);
            const auto p1 = body(ring[i + 1]);
            a.body_segments.push_back({p0[0], p0[1], p0[2], p1[0], p1[1], p1[2]});
        }
    }
}

void add_fuselage(const geometry::Fuselage& f, AircraftInfo& a, const Eigen::Vector3d& cg) {
    if (f.empty()) return;
    Outline top{"fuselage", {}}, side{"fuselage", {}}, front{"fuselage", {}};
    for (const auto& st : f.stations) top.points.push_back({st.x, st.width / 2});
    for (auto it = f.stations.rbegin(); it != f.stations.rend(); ++it)
        top.points.push_back({it->x, -it->width / 2});
    top.points.push_back(top.points.front());
    for (const auto& st : f.stations) side.points.push_back({st.x, st.z_centre + st.height / 2});
    for (auto it = f.stations.rbegin(); it != f.stations.rend(); ++it)
        side.points.push_back({it->x, it->z_centre - it->height / 2});
    side.points.push_back(side.points.front());
    const auto widest = std::max_element(
        f.stations.begin(), f.stations.end(),
        [](const auto& p, const auto& q) { return p.width * p.height < q.width * q.height; });
    for (int k = 0; k <= 48; ++k) {
        const double t = 2 * 3.14159265358979323846 * k / 48;
        front.points.push_back(
            {widest->width / 2 * std::cos(t), widest->z_centre + widest->height / 2 * std::sin(t)});
    }
    a.top.push_back(top);
    a.side.push_back(side);
    a.front.push_back(front);
    // Body glyph: the side outline's top and bottom lines in the plane of symmetry.
    for (std::size_t i = 0; i + 1 < side.points.size(); ++i) {
        const auto& p = side.points[i];
        const auto& q = side.points[i + 1];
        a.body_segments.push_back(
            {-(p[0] - cg.x()), 0.0, -(p[1] - cg.z()), -(q[0] - cg.x()), 0.0, -(q[1] - cg.z())});
    }
}

std::optional<Columns> optional_trajectory(const fs::path& file,
                                           std::vector<std::string>& missing) {
    if (!fs::exists(file)) {
        missing.push_back(file.filename().string());
        return std::nullopt;
    }
    return read_trajectory(file);
}

nlohmann::json optional_json(const fs::path& file, std::vector<std::string>& missing) {
    if (!fs::exists(file)) {
        missing.push_back(file.filename().string());
        return nullptr;
    }
    nlohmann::json j = read_json(file);
    if (!j.is_object())
        throw InputError(fmt::format("{}:1:1: expected a JSON object, found a {}", file.string(),
                                     j.type_name()));
    return j;
}

/// Sub-directories of `dir`, sorted by name.
std::vector<fs::path> subdirs(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_directory()) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

std::string Columns::meta(const std::string& key) const {
    for (const auto& c : comments) {
        if (c.size() > key.size() && c.compare(0, key.size(), key) == 0 && c[key.size()] == ':') {
            std::string v = c.substr(key.size() + 1);
            v.erase(0, v.find_first_not_of(" \t"));
            v.erase(v.find_last_not_of(" \t\r") + 1);
            return v;
        }
    }
    return {};
}

AircraftInfo read_aircraft_info(const fs::path& file) {
    const aircraft::AircraftDefinition d = aircraft::load_aircraft(file);
    AircraftInfo a;
    a.file = file.string();
    a.name = d.name;
    a.description = d.description;
    a.area = d.reference.area;
    a.span = d.reference.span;
    a.chord = d.reference.chord;
    a.moment_reference = {d.moment_reference_geom.x(), d.moment_reference_geom.y(),
                          d.moment_reference_geom.z()};
    a.length = d.geometry.length;
    for (const auto& m : d.mass_cases)
        a.mass_cases.push_back(
            {m.name,
             m.mass,
             {m.cg_geom.x(), m.cg_geom.y(), m.cg_geom.z()},
             {m.inertia(0, 0), m.inertia(1, 1), m.inertia(2, 2), -m.inertia(0, 2)}});
    a.default_mass_case = d.default_mass_case;
    a.control_limits = {d.limits.elevator, d.limits.aileron, d.limits.rudder};
    a.aero_label = d.aero_label;
    const Eigen::Vector3d cg = d.mass_case().cg_geom;
    for (const auto& s : d.geometry.surfaces) add_surface(s, a, cg);
    add_fuselage(d.geometry.fuselage, a, cg);
    return a;
}

Columns read_trajectory(const fs::path& file) {
    const core::CsvTable t = core::read_csv(file);
    for (const char* c : {"t", "x", "y", "z", "phi", "theta", "psi", "V", "alpha", "beta", "p", "q",
                          "r", "elevator", "aileron", "rudder"})
        (void)t.require(c);
    if (t.rows.size() < 2)
        throw InputError(
            fmt::format("{}: {} data rows; expected at least 2", file.string(), t.rows.size()));
    require_increasing(t, t.require("t"));
    return to_columns(t);
}

Columns read_comparison(const fs::path& file) {
    const core::CsvTable t = core::read_csv(file);
    (void)t.require("t");
    for (const char* c : coefficient_names)
        for (const char* suffix : {"_replay", "_table", "_diff"})
            (void)t.require(std::string(c) + suffix);
    if (t.rows.empty())
        throw InputError(
            fmt::format("{}: no data rows; expected one row per replay step", file.string()));
    require_increasing(t, t.require("t"));
    return to_columns(t);
}

TablesData read_tables(const fs::path& dir) {
    TablesData d;
    d.dir = dir;
    d.summary = optional_json(dir / "summary.json", d.missing);
    const fs::path norm = fs::absolute(dir).lexically_normal();
    d.label = (norm.has_filename() ? norm : norm.parent_path()).filename().string();
    if (d.summary.is_object() && d.summary.contains("source") && d.summary["source"].is_object() &&
        d.summary["source"].contains("name") && d.summary["source"]["name"].is_string() &&
        !d.summary["source"]["name"].get<std::string>().empty())
        d.label = d.summary["source"]["name"].get<std::string>();
    if (fs::exists(dir / "tables.csv")) {
        const TextCsv t = read_text_csv(dir / "tables.csv");
        const std::size_t ct = t.require("table"), ca = t.require("alpha_deg"),
                          cm = t.require("mach"), cb = t.require("beta_deg"),
                          cd = t.require("delta_deg");
        for (const auto& c : t.columns)
            if (c != "table" && c != "alpha_deg" && c != "mach" && c != "beta_deg" &&
                c != "delta_deg" && c.rfind("sigma_", 0) != 0)
                d.coefficient_columns.push_back(c);
        std::array<std::size_t, 6> cc{}, cs{};
        for (std::size_t k = 0; k < 6; ++k) {
            cc[k] = t.require(coefficient_names[k]);
            cs[k] = t.require(std::string("sigma_") + coefficient_names[k]);
        }
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
            TableEntry e;
            e.alpha = t.number(i, ca) * deg;
            e.mach = t.number(i, cm);
            e.beta = t.number(i, cb) * deg;
            e.delta = t.number(i, cd) * deg;
            for (std::size_t k = 0; k < 6; ++k) {
                e.c[k] = t.number(i, cc[k]);
                e.sigma[k] = t.number(i, cs[k]);
            }
            const std::string& name = t.rows[i][ct];
            if (name.empty())
                throw InputError(
                    fmt::format("{}:{}: column {} 'table' is empty; expected "
                                "'static' or a control name",
                                t.source, t.row_lines[i], ct + 1));
            d.tables[name].push_back(e);
        }
    } else {
        d.missing.push_back("tables.csv");
    }
    if (fs::exists(dir / "samples.csv")) {
        const TextCsv t = read_text_csv(dir / "samples.csv");
        const std::size_t cscen = t.require("scenario"), cstat = t.require("status"),
                          ca = t.require("alpha_deg"), cb = t.require("beta_deg"),
                          cm = t.require("mach");
        std::array<std::size_t, 6> cc{};
        for (std::size_t k = 0; k < 6; ++k) cc[k] = t.require(coefficient_names[k]);
        auto optional_number = [&](std::size_t row, const char* name) {
            const int j = t.find(name);
            return j < 0 ? 0.0 : t.number(row, static_cast<std::size_t>(j));
        };
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
            if (t.rows[i][cstat] != "done") continue;
            Sample s;
            s.scenario = t.rows[i][cscen];
            s.alpha = t.number(i, ca) * deg;
            s.beta = t.number(i, cb) * deg;
            s.mach = t.number(i, cm);
            s.elevator = optional_number(i, "elevator_deg") * deg;
            s.aileron = optional_number(i, "aileron_deg") * deg;
            s.rudder = optional_number(i, "rudder_deg") * deg;
            s.has_rates = optional_number(i, "p_hat") != 0.0 ||
                          optional_number(i, "q_hat") != 0.0 || optional_number(i, "r_hat") != 0.0;
            for (std::size_t k = 0; k < 6; ++k) s.c[k] = t.number(i, cc[k]);
            d.samples.push_back(s);
        }
    } else {
        d.missing.push_back("samples.csv");
    }
    if (fs::exists(dir / "dynamic.csv")) {
        const core::CsvTable t = core::read_csv(dir / "dynamic.csv");
        (void)t.require("alpha_deg");
        (void)t.require("mach");
        d.dynamic = to_columns(t);
    } else {
        d.missing.push_back("dynamic.csv");
    }
    // The slices `manta tables` plotted (plot_static_M<M>_beta<b>.svg in summary.outputs).
    if (d.summary.is_object() && d.summary.contains("outputs") && d.summary["outputs"].is_array()) {
        const std::regex re(R"(plot_static_M([-0-9.eE+]+)_beta([-0-9.eE+]+)\.svg)");
        for (const auto& o : d.summary["outputs"]) {
            std::smatch m;
            const std::string s = o.is_string() ? o.get<std::string>() : std::string();
            if (std::regex_match(s, m, re)) {
                try {
                    d.plot_slices.push_back({std::stod(m[1].str()), std::stod(m[2].str()) * deg});
                } catch (const std::exception&) {  // a name we cannot read: not plotted first
                }
            }
        }
    }
    if (d.plot_slices.empty() && d.tables.count("static")) {
        std::vector<double> machs, betas;
        for (const auto& e : d.tables["static"]) {
            machs.push_back(e.mach);
            betas.push_back(e.beta);
        }
        std::sort(machs.begin(), machs.end());
        machs.erase(std::unique(machs.begin(), machs.end()), machs.end());
        const double b0 = *std::min_element(betas.begin(), betas.end(), [](double p, double q) {
            return std::abs(p) < std::abs(q);
        });
        d.plot_slices.push_back({machs[machs.size() / 2], b0});
    }
    return d;
}

ManoeuvreData read_manoeuvre(const fs::path& dir, const std::string& name) {
    ManoeuvreData m;
    m.dir = dir;
    m.name = name;
    m.summary = optional_json(dir / "summary.json", m.missing);
    m.nodes = optional_trajectory(dir / "trajectory.csv", m.missing);
    m.dense = optional_trajectory(dir / "trajectory_dense.csv", m.missing);
    const Columns* c = m.dense ? &*m.dense : m.nodes ? &*m.nodes : nullptr;
    if (c) {
        if (const std::string n = c->meta("manoeuvre"); !n.empty()) m.name = n;
        m.phases = split_list(c->meta("phases"));
    } else if (m.summary.is_object() && m.summary.contains("manoeuvre") &&
               m.summary["manoeuvre"].is_string()) {
        m.name = m.summary["manoeuvre"].get<std::string>();
    }
    return m;
}

ReplayData read_replay(const fs::path& dir, const std::string& name) {
    ReplayData r;
    r.dir = dir;
    r.name = name;
    r.summary = optional_json(dir / "summary.json", r.missing);
    if (fs::exists(dir / "comparison.csv"))
        r.comparison = read_comparison(dir / "comparison.csv");
    else
        r.missing.push_back("comparison.csv");
    if (r.summary.is_object() && r.summary.contains("manoeuvre") &&
        r.summary["manoeuvre"].is_string() && !r.summary["manoeuvre"].get<std::string>().empty())
        r.name = r.summary["manoeuvre"].get<std::string>();
    if (r.summary.is_object() && r.summary.contains("source") && r.summary["source"].is_string())
        r.label = r.summary["source"].get<std::string>();
    if (r.label.empty()) {
        const std::string up =
            fs::absolute(dir).lexically_normal().parent_path().filename().string();
        r.label = up.starts_with("replay-") ? up.substr(7) : std::string("replay");
    }
    // Surface snapshots (manta replay --source euler): the index, then the ones the page shows.
    if (fs::exists(dir / "surface" / "index.csv")) {
        const TextCsv t = read_text_csv(dir / "surface" / "index.csv");
        const std::size_t cs = t.require("step"), ct = t.require("t"), cf = t.require("file");
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
            const double step = t.number(i, cs);
            r.snapshot_index.emplace_back(static_cast<int>(step), t.number(i, ct), t.rows[i][cf]);
        }
        r.picks = pick_snapshots(r);
        std::vector<std::size_t> read;  // index rows read, in r.snapshots order
        std::shared_ptr<const SurfaceWall> wall;
        if (!r.picks.empty())
            wall = std::make_shared<const SurfaceWall>(
                read_surface_wall(dir / "surface" / "wall.csv"));
        for (auto& p : r.picks) {
            const auto at = std::find(read.begin(), read.end(), p.snapshot);
            if (at == read.end()) {
                r.snapshots.push_back(read_surface_snapshot(
                    dir / "surface" / std::get<2>(r.snapshot_index[p.snapshot]), wall));
                read.push_back(p.snapshot);
                p.snapshot = r.snapshots.size() - 1;
            } else {
                p.snapshot = static_cast<std::size_t>(at - read.begin());
            }
        }
    }
    return r;
}

RunData read_run(const fs::path& dir) {
    if (!fs::is_directory(dir))
        throw IoError(fmt::format("{}: not a directory; expected a run directory", dir.string()));
    RunData run;
    run.dir = dir;
    auto has = [&](const char* f) { return fs::exists(dir / f); };
    // The folder's own name (a trailing '/' leaves an empty filename).
    const fs::path norm = fs::absolute(dir).lexically_normal();
    const std::string leaf = (norm.has_filename() ? norm : norm.parent_path()).filename().string();
    if (has("run.json") || has("aircraft.yaml") || has("tables") || has("manoeuvres") ||
        has("replay")) {
        run.layout = "run";
        run.run = optional_json(dir / "run.json", run.missing);
        if (has("aircraft.yaml"))
            run.aircraft = read_aircraft_info(dir / "aircraft.yaml");
        else
            run.missing.push_back("aircraft.yaml");
        if (fs::is_directory(dir / "tables"))
            run.tables = read_tables(dir / "tables");
        else
            run.missing.push_back("tables/");
        if (fs::is_directory(dir / "manoeuvres")) {
            for (const auto& d : subdirs(dir / "manoeuvres"))
                run.manoeuvres.push_back(read_manoeuvre(d, d.filename().string()));
        } else {
            run.missing.push_back("manoeuvres/");
        }
        if (fs::is_directory(dir / "replay")) {
            for (const auto& d : subdirs(dir / "replay"))
                run.replays.push_back(read_replay(d, d.filename().string()));
        } else {
            run.missing.push_back("replay/");
        }
        // Replays of the same manoeuvres by other sources: RUN_DIR/replay-<source>/<name>/,
        // beside the replay of replay/<name>/ (alone when there is none).
        for (const auto& other : subdirs(dir)) {
            const std::string top = other.filename().string();
            if (!top.starts_with("replay-") || top.size() <= 7) continue;
            for (const auto& d : subdirs(other)) {
                ReplayData o = read_replay(d, d.filename().string());
                auto it = std::find_if(run.replays.begin(), run.replays.end(), [&](const auto& r) {
                    return r.dir.filename() == d.filename();
                });
                if (it != run.replays.end()) {
                    it->others.push_back(std::move(o));
                } else {
                    o.name += " (" + o.label + ")";
                    run.replays.push_back(std::move(o));
                }
            }
        }
    } else if (has("tables.csv") || has("samples.csv")) {
        run.layout = "tables";
        run.tables = read_tables(dir);
    } else if (has("trajectory.csv") || has("trajectory_dense.csv")) {
        run.layout = "optimise";
        run.manoeuvres.push_back(read_manoeuvre(dir, leaf));
    } else if (has("comparison.csv")) {
        run.layout = "replay";
        run.replays.push_back(read_replay(dir, leaf));
    } else {
        throw IoError(fmt::format(
            "{}: holds no run.json, aircraft.yaml, tables/, manoeuvres/ or replay/ (a run "
            "directory), no tables.csv (manta tables), no trajectory.csv (manta optimise) and no "
            "comparison.csv (manta replay); nothing to report",
            dir.string()));
    }
    return run;
}

}  // namespace manta::report
