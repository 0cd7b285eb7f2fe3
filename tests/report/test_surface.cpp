/// @file test_surface.cpp
/// Surface snapshots and replays of other sources in the report (docs/report.md, "Sources on the
/// same axes", "Surface Cp"): the snapshot files read and their errors located, the snapshots
/// picked for the flagged intervals and the reference, the Cp plan views (bands merged into
/// polygons), and the page of the fixture with a lattice replay beside its replay and snapshots.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "manta/core/error.hpp"
#include "manta/report/report.hpp"

namespace fs = std::filesystem;
using namespace manta::report;

namespace {

const fs::path fixture = fs::path(MANTA_SOURCE_DIR) / "tests/data/report/run";

fs::path scratch(const std::string& name) {
    const fs::path d =
        fs::temp_directory_path() / ("manta_report_surface_" + std::to_string(getpid())) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string fmt_node(double x, double y, double z) {
    char b[96];
    std::snprintf(b, sizeof b, "%.9g,%.9g,%.9g\n", x, y, z);
    return b;
}

void write(const fs::path& f, const std::string& text) {
    std::ofstream(f) << text;
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto k = text.find(what); k != std::string::npos; k = text.find(what, k + 1)) ++n;
    return n;
}

/// A wall of two plates of nx x ny squares (two triangles each), 1 m x 0.5 m: the upper one at
/// z = 0 facing up (+z), the lower one at z = -0.1 facing down, nodes numbered per plate.
std::string plates_wall(int nx, int ny) {
    std::string nodes, tris;
    int n_nodes = 0, n_tri = 0;
    for (int plate = 0; plate < 2; ++plate) {
        const int base = n_nodes;
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i, ++n_nodes)
                nodes += fmt_node(static_cast<double>(i) / nx, 0.5 * j / ny, plate ? -0.1 : 0.0);
        auto id = [&](int i, int j) { return base + i + (nx + 1) * j; };
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                // Counter-clockwise seen from +z: normal up; reversed for the lower plate.
                const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
                if (plate == 0)
                    tris += std::to_string(a) + "," + std::to_string(b) + "," + std::to_string(c) +
                            ",0\n" + std::to_string(a) + "," + std::to_string(c) + "," +
                            std::to_string(d) + ",0\n";
                else
                    tris += std::to_string(a) + "," + std::to_string(c) + "," + std::to_string(b) +
                            ",1\n" + std::to_string(a) + "," + std::to_string(d) + "," +
                            std::to_string(c) + ",1\n";
                n_tri += 2;
            }
    }
    return "# MANTA surface wall 1\n# coordinates: test\n# markers: upper,lower\n# nodes: " +
           std::to_string(n_nodes) + "\n# triangles: " + std::to_string(n_tri) + "\nx,y,z\n" +
           nodes + "a,b,c,marker\n" + tris;
}

/// One snapshot of `n` nodes with Cp = f(node index).
template <class F>
std::string snapshot(double t, int step, int n, F f) {
    std::string s = "# MANTA surface snapshot 1\n# wall: wall.csv\n# t: " + std::to_string(t) +
                    "\n# step: " + std::to_string(step) + "\n# nodes: " + std::to_string(n) +
                    "\nCp\n";
    for (int i = 0; i < n; ++i) s += std::to_string(f(i)) + "\n";
    return s;
}

}  // namespace

TEST(Surface, ReadsTheWallAndASnapshot) {
    const fs::path d = scratch("read");
    write(d / "wall.csv", plates_wall(3, 2));
    write(d / "step-000004.csv", snapshot(0.5, 4, 24, [](int i) { return 0.1 * i; }));
    const auto wall = std::make_shared<const SurfaceWall>(read_surface_wall(d / "wall.csv"));
    EXPECT_EQ(wall->x.size(), 24u);
    EXPECT_EQ(wall->triangles.size(), 24u);
    EXPECT_EQ(wall->markers, (std::vector<std::string>{"upper", "lower"}));
    EXPECT_NEAR(wall->x[5][0], 1.0 / 3.0, 1e-9);  // node (1, 1) of the upper plate
    EXPECT_NEAR(wall->x[5][1], 0.25, 1e-9);
    const SurfaceSnapshot s = read_surface_snapshot(d / "step-000004.csv", wall);
    EXPECT_DOUBLE_EQ(s.t, 0.5);
    EXPECT_EQ(s.step, 4);
    ASSERT_EQ(s.cp.size(), 24u);
    EXPECT_DOUBLE_EQ(s.cp[10], 1.0);
    EXPECT_EQ(s.meta.at("wall"), "wall.csv");
}

TEST(Surface, MalformedFilesAreOneLineErrorsWithTheLine) {
    const fs::path d = scratch("bad");
    auto message = [&](const std::string& wall_text, const std::string& snap_text) {
        write(d / "wall.csv", wall_text);
        write(d / "s.csv", snap_text);
        try {
            const auto w = std::make_shared<const SurfaceWall>(read_surface_wall(d / "wall.csv"));
            (void)read_surface_snapshot(d / "s.csv", w);
        } catch (const manta::InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string good = plates_wall(2, 1);
    const std::string snap = snapshot(1.0, 2, 12, [](int) { return 0.0; });
    EXPECT_EQ(message(good, snap), "no error");
    // The format line.
    EXPECT_NE(message("x,y,z\n", snap).find("wall.csv:1: no '# MANTA surface wall 1' line"),
              std::string::npos);
    // A node that is not a number (line 7 is the first node).
    std::string w = good;
    w.replace(w.find("x,y,z\n") + 6, w.find('\n', w.find("x,y,z\n") + 6) - w.find("x,y,z\n") - 6,
              "0,oops,0");
    EXPECT_NE(message(w, snap).find("wall.csv:7: node row '0,oops,0' is not three numbers"),
              std::string::npos)
        << message(w, snap);
    // A triangle naming a node that does not exist.
    w = good;
    w.replace(w.rfind("a,b,c,marker\n") + 13, 6, "0,1,99");
    EXPECT_NE(message(w, snap).find("triangle row '0,1,99"), std::string::npos) << message(w, snap);
    // A snapshot of another wall, and a Cp that is not a number.
    EXPECT_NE(message(good, snapshot(1.0, 2, 11, [](int) { return 0.0; }))
                  .find("s.csv:6: 11 nodes; its wall"),
              std::string::npos);
    std::string bad = snap;
    bad.replace(bad.find("Cp\n") + 3, 8, "nan\n");
    EXPECT_NE(message(good, bad).find("s.csv:7: Cp 'nan' is not a number"), std::string::npos)
        << message(good, bad);
    for (const std::string& m : {message("x\n", snap), message(good, bad)})
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(Surface, PicksTheSnapshotNearestEachFlagsLargestDifferenceAndAReference) {
    ReplayData r;
    for (int k = 0; k <= 10; ++k)
        r.snapshot_index.emplace_back(10 * k, 1.0 * k, "step-" + std::to_string(k) + ".csv");
    Columns c;
    c.names = {"t", "CL_diff", "Cm_diff"};
    for (int i = 0; i <= 100; ++i) {
        const double t = 0.1 * i;
        c.values["t"].push_back(t);
        // CL: largest at t = 2.3 (in the first interval); Cm: largest at 6.6 relative to its
        // tolerance (in the second).
        c.values["CL_diff"].push_back(0.1 * std::exp(-std::pow(t - 2.3, 2)));
        c.values["Cm_diff"].push_back(-0.05 * std::exp(-std::pow(t - 6.6, 2)));
    }
    r.comparison = c;
    r.summary = nlohmann::json::parse(R"({"tolerances": {"CL": 0.05, "Cm": 0.01},
        "flags": [{"t_start": 1.5, "t_end": 3.0, "coefficients": ["CL"]},
                  {"t_start": 5.8, "t_end": 7.4, "coefficients": ["CL", "Cm"]}]})");
    const auto picks = pick_snapshots(r);
    ASSERT_EQ(picks.size(), 3u);
    // Sorted by time: flag 1 at t = 2 (nearest 2.3), flag 2 at 7 (nearest 6.6), the reference at
    // t = 10 (the farthest from both intervals).
    EXPECT_EQ(picks[0].flag, 0);
    EXPECT_EQ(picks[0].snapshot, 2u);
    EXPECT_NEAR(picks[0].t_wanted, 2.3, 1e-9);
    EXPECT_NE(picks[0].why.find("largest difference at t = 2.3 s (CL +0.1)"), std::string::npos)
        << picks[0].why;
    EXPECT_EQ(picks[1].flag, 1);
    EXPECT_EQ(picks[1].snapshot, 7u);
    EXPECT_NEAR(picks[1].t_wanted, 6.6, 1e-9);
    EXPECT_EQ(picks[2].flag, -1);
    EXPECT_EQ(picks[2].snapshot, 10u);
    // At most one flagged pick: the first interval's.
    const auto one = pick_snapshots(r, 1);
    ASSERT_EQ(one.size(), 2u);
    EXPECT_EQ(one[0].flag, 0);
    EXPECT_EQ(one[1].flag, -1);
    // Flags over the whole replay: no reference; no flags: the middle snapshot for reference.
    r.summary["flags"] =
        nlohmann::json::parse(R"([{"t_start": 0, "t_end": 10, "coefficients": ["CL"]}])");
    const auto all = pick_snapshots(r);
    ASSERT_EQ(all.size(), 1u);
    EXPECT_EQ(all[0].flag, 0);
    r.summary["flags"] = nlohmann::json::array();
    const auto none = pick_snapshots(r);
    ASSERT_EQ(none.size(), 1u);
    EXPECT_EQ(none[0].flag, -1);
    EXPECT_EQ(none[0].snapshot, 5u);
    // No snapshots: nothing.
    r.snapshot_index.clear();
    EXPECT_TRUE(pick_snapshots(r).empty());
}

TEST(Surface, PlanViewsMergeEachBandsTrianglesIntoPolygons) {
    const fs::path d = scratch("svg");
    write(d / "wall.csv", plates_wall(20, 10));
    const auto wall = std::make_shared<const SurfaceWall>(read_surface_wall(d / "wall.csv"));
    const int n = static_cast<int>(wall->x.size());
    // Uniform Cp: each view is one polygon (400 triangles merged) with the plate's 4 corners.
    write(d / "u.csv", snapshot(0.0, 0, n, [](int) { return 0.3; }));
    const SurfaceSnapshot u = read_surface_snapshot(d / "u.csv", wall);
    const std::string svg = cp_picture_svg(u, {-1.0, 1.0}, "uniform", 8);
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    EXPECT_EQ(count(svg, "<path fill=\"#"), 2u) << svg;  // one band in each view
    EXPECT_EQ(count(svg, "M"), 4u);                      // and an outline of each
    const std::regex path(R"(<path fill="#[0-9a-f]{6}" d="M[-0-9]+ [-0-9]+l([^"]*)z"/>)");
    for (std::sregex_iterator it(svg.begin(), svg.end(), path), end; it != end; ++it)
        EXPECT_EQ(count((*it)[1].str(), " ") + 1, 2u * 3u) << (*it)[0];  // 3 moves, 6 numbers
    EXPECT_NE(svg.find("from above"), std::string::npos);
    EXPECT_NE(svg.find("from below"), std::string::npos);
    // Cp linear in x over the range: every band drawn in both views, the bands nested (each one
    // the union of it and those above), the colour bar with all 8 bands.
    write(d / "x.csv", snapshot(0.0, 0, n, [&](int i) {
              return -1.0 + 2.0 * wall->x[static_cast<std::size_t>(i)][0];
          }));
    const SurfaceSnapshot x = read_surface_snapshot(d / "x.csv", wall);
    const std::string sx = cp_picture_svg(x, {-1.0, 1.0}, "linear", 8);
    EXPECT_EQ(count(sx, "<path fill=\"#"), 16u);
    EXPECT_EQ(count(sx, "<rect "), 8u);
    EXPECT_NE(sx.find(">-1.00<"), std::string::npos);
    EXPECT_NE(sx.find(">1.00<"), std::string::npos);
    // The range of a replay's pictures: its nodes' 1st and 99th percentiles.
    const CpRange r = cp_range({&x});
    EXPECT_NEAR(r.lo, -1.0, 0.05);
    EXPECT_NEAR(r.hi, 1.0, 0.05);
}

TEST(Surface, PageShowsBothReplaysTheTableAndTheCpPictures) {
    // The fixture with a lattice replay beside its replay (CL + 0.01) and snapshots of a plate.
    const fs::path run = scratch("run") / "run";
    fs::copy(fixture, run, fs::copy_options::recursive);
    const fs::path rep = run / "replay" / "immelmann";
    const fs::path other = run / "replay-vlm" / "immelmann";
    fs::create_directories(other);
    {
        std::ifstream in(rep / "comparison.csv");
        std::ofstream out(other / "comparison.csv");
        std::string line;
        std::getline(in, line);
        out << line << "\n";
        while (std::getline(in, line)) out << line << "\n";  // same rows: zero difference
    }
    write(other / "summary.json", R"({"source": "vlm-copy", "dt": 0.25, "steps": 97})");
    fs::create_directories(rep / "surface");
    write(rep / "surface" / "wall.csv", plates_wall(8, 4));
    std::string index = "step,t,file\n";
    for (int k = 0; k <= 24; k += 2) {
        const std::string f = "step-" + std::to_string(k) + ".csv";
        write(rep / "surface" / f,
              snapshot(k, k, 90, [&](int i) { return 0.01 * i * std::cos(0.3 * k); }));
        index += std::to_string(k) + "," + std::to_string(k) + "," + f + "\n";
    }
    write(rep / "surface" / "index.csv", index);

    const RunData data = read_run(run);
    ASSERT_EQ(data.replays.size(), 1u);
    ASSERT_EQ(data.replays[0].others.size(), 1u);
    EXPECT_EQ(data.replays[0].others[0].label, "vlm-copy");
    EXPECT_EQ(data.replays[0].snapshot_index.size(), 13u);
    const ReportContent c = build_content(data);
    const auto f = std::find_if(c.figures.begin(), c.figures.end(),
                                [](const Figure& g) { return g.id == "replay-0-sources"; });
    ASSERT_NE(f, c.figures.end());
    ASSERT_EQ(f->panels.size(), 6u);
    for (const auto& p : f->panels) {
        ASSERT_EQ(p.series.size(), 3u);
        EXPECT_EQ(p.series[0].name, "table");
        EXPECT_EQ(p.series[1].name, "vlm replay");  // the fixture's own source
        EXPECT_EQ(p.series[2].name, "vlm-copy replay");
        EXPECT_EQ(p.series[2].style, SeriesStyle::dashed);
        EXPECT_FALSE(p.shades.empty());
    }
    // The fixture's 9 flagged intervals, at most 6 distinct pictures, and a reference.
    EXPECT_GE(c.pictures.size(), 2u);
    EXPECT_LE(c.pictures.size(), 7u);
    const std::string page = render_html(data, c);
    EXPECT_NE(page.find("Sources on the same axes: vlm replay, table, vlm-copy replay"),
              std::string::npos);
    EXPECT_NE(page.find("vlm replay − vlm-copy replay</td><td>0 / 0</td>"), std::string::npos);
    EXPECT_EQ(count(page, "class=\"cp-picture\""), c.pictures.size());
    EXPECT_NE(page.find("the snapshot nearest"), std::string::npos);
    EXPECT_NE(page.find("reference"), std::string::npos);
    EXPECT_NE(page.find("13 snapshot(s)"), std::string::npos);
    // --figures writes the pictures and the sources figure.
    ReportOptions o;
    o.run_dir = run;
    o.html = run.parent_path() / "page.html";
    o.figures_dir = run.parent_path() / "fig";
    const ReportResult res = make_report(o);
    EXPECT_EQ(res.n_pictures, c.pictures.size());
    EXPECT_TRUE(fs::exists(*o.figures_dir / "replay-0-cp-0.svg"));
    EXPECT_TRUE(fs::exists(*o.figures_dir / "replay-0-sources.svg"));
    EXPECT_EQ(res.to_json()["parts"][4], "replay:immelmann:vlm-copy") << res.to_json().dump();
}
