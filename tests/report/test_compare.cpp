/// @file test_compare.cpp
/// A second table set beside the first (`manta report --compare-tables`): the summary numbers
/// on synthetic pairs made from the fixture's tables (CL scaled by 1.1: every CL ratio 1.1;
/// the tables moved to other Mach and sideslip breakpoints by bilinear extension: the
/// interpolated curves reproduce the fixture's), both tables' series in every static figure, the
/// figures and JSON written, and bad input rejected in one line.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/report/compare.hpp"
#include "manta/report/report.hpp"
#include "manta/report/text_csv.hpp"
#include "table_copies.hpp"

namespace fs = std::filesystem;
using namespace manta::report;

namespace {

using namespace manta::report::test_data;
constexpr double deg = 3.14159265358979323846 / 180.0;

RunData with_compare(const fs::path& other) {
    RunData run = read_run(fixture_tables);
    run.compare = read_compare_tables(other);
    return run;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const manta::Error& e) {
        return e.what();
    }
    return "no error";
}

const Series* find_series(const Panel& p, const std::string& name) {
    for (const auto& s : p.series)
        if (s.name == name) return &s;
    return nullptr;
}

}  // namespace

TEST(Compare, LeastSquaresSlopeAndFitPoints) {
    EXPECT_DOUBLE_EQ(least_squares_slope({0, 1, 2, 3}, {1, 3, 5, 7}), 2.0);
    EXPECT_TRUE(std::isnan(least_squares_slope({1}, {1})));
    const std::vector<double> a{-4, -2, 0, 2, 4, 6, 8};
    EXPECT_EQ(fit_points(a, -2, 4, {-4, 8}, 3), (std::vector<double>{-2, 0, 2, 4}));
    // The window outside the common range: the three points nearest its centre inside it.
    EXPECT_EQ(fit_points(a, -2, 4, {4, 8}, 3), (std::vector<double>{4, 6, 8}));
    EXPECT_EQ(fit_points({-25, 0, 15}, -10, 10, {-25, 15}, 3), (std::vector<double>{-25, 0, 15}));
}

TEST(Compare, InterpolantReproducesTheEntriesAndInterpolatesBetween) {
    const TablesData t = read_tables(fixture_tables);
    const TablesInterpolant in(t);
    ASSERT_NE(in.grid("static"), nullptr);
    EXPECT_EQ(in.grid("static")->mach.size(), 2u);
    for (const auto& e : t.tables.at("static")) {
        const auto v = in.value("static", e.alpha, e.mach, e.beta);
        const auto s = in.sigma("static", e.alpha, e.mach, e.beta);
        for (std::size_t k = 0; k < 6; ++k) {
            EXPECT_NEAR(v[k], e.c[k], 1e-12) << k;
            EXPECT_NEAR(s[k], e.sigma[k], 1e-12) << k;
        }
    }
    for (const auto& e : t.tables.at("elevator")) {
        const auto v = in.value("elevator", e.alpha, e.mach, e.beta, e.delta);
        for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(v[k], e.c[k], 1e-12) << k;
    }
    // Half way in Mach: the mean of the two Mach numbers' entries.
    double a = 0, b = 0;
    for (const auto& e : t.tables.at("static"))
        if (e.alpha == 0.0 && e.beta == 0.0) (e.mach < 0.3 ? a : b) = e.c[0];
    EXPECT_NEAR(in.value("static", 0.0, 0.35, 0.0)[0], (a + b) / 2, 1e-12);
    EXPECT_TRUE(in.inside("static", 0.0, 0.35, 0.0));
    EXPECT_FALSE(in.inside("static", 0.0, 0.6, 0.0));
    EXPECT_FALSE(in.inside("rudder", 0.0, 0.2, 0.0, 30 * deg));
    // The dynamic derivatives at an entry and between.
    const auto& d = *t.dynamic;
    EXPECT_NEAR(*in.dynamic("Cm_q", d.at("alpha_deg")[0] * deg, d.at("mach")[0]), d.at("Cm_q")[0],
                1e-12);
    EXPECT_NEAR(*in.dynamic("CL_q", d.at("alpha_deg")[0] * deg, d.at("mach")[0]), d.at("CL_q")[0],
                1e-12);
    EXPECT_FALSE(in.dynamic("Cm_x", 0.0, 0.35).has_value());
}

TEST(Compare, CopyWithCLScaledByOnePointOneHasRatioOnePointOne) {
    const RunData run = with_compare(scaled_copy("scaled", {"CL", "sigma_CL"}, 1.1));
    const ReportContent c = build_content(run);
    ASSERT_TRUE(c.comparison.has_value());
    const Comparison& cmp = *c.comparison;
    EXPECT_EQ(cmp.main_label, "vlm");
    EXPECT_EQ(cmp.other_label, "scaled");
    ASSERT_EQ(cmp.machs.size(), 2u);
    const auto& entries = run.tables->tables.at("static");
    for (const auto& m : cmp.machs) {
        EXPECT_EQ(m.beta, 0.0);
        // The fit points: the table's alphas in [-2, 4] deg.
        ASSERT_EQ(m.fit_alpha.size(), 4u);
        EXPECT_NEAR(m.fit_alpha.front(), -2 * deg, 1e-12);
        EXPECT_NEAR(m.fit_alpha.back(), 4 * deg, 1e-12);
        // The main table's numbers, computed here from its entries.
        std::vector<double> x, cl, cm;
        double cl0 = 0, cm0 = 0, cd0 = 0;
        for (const auto& e : entries) {
            if (std::abs(e.mach - m.mach) > 1e-12 || e.beta != 0.0) continue;
            if (e.alpha > -2.5 * deg && e.alpha < 4.5 * deg) {
                x.push_back(e.alpha);
                cl.push_back(e.c[0]);
                cm.push_back(e.c[4]);
            }
            if (e.alpha == 0.0) {
                cl0 = e.c[0];
                cm0 = e.c[4];
                cd0 = e.c[1];
            }
        }
        EXPECT_NEAR(m.main[0], least_squares_slope(x, cl), 1e-10);
        EXPECT_NEAR(m.main[1], least_squares_slope(x, cm), 1e-10);
        EXPECT_GT(m.main[0], 3.0) << "a lift slope per radian";
        EXPECT_NEAR(m.main[2], cl0, 1e-12);
        EXPECT_NEAR(m.main[3], cm0, 1e-12);
        EXPECT_NEAR(m.main[4], cd0, 1e-12);
        EXPECT_NEAR(m.ratio(0), 1.1, 1e-9) << "CL_alpha";
        EXPECT_NEAR(m.ratio(2), 1.1, 1e-9) << "CL_0";
        EXPECT_NEAR(m.ratio(1), 1.0, 1e-9) << "Cm_alpha";
        EXPECT_NEAR(m.ratio(3), 1.0, 1e-9) << "Cm_0";
        EXPECT_NEAR(m.ratio(4), 1.0, 1e-9) << "CD_0";
    }
    // Control power at alpha 0 and the middle Mach (0.5), deflections -25, 0, 15 deg.
    ASSERT_EQ(cmp.controls.size(), 3u);
    for (const auto& cs : cmp.controls) {
        EXPECT_NEAR(cs.mach, 0.5, 1e-12);
        ASSERT_EQ(cs.fit_delta.size(), 3u) << cs.control;
        std::vector<double> x, y;
        for (const auto& e : run.tables->tables.at(cs.control))
            if (std::abs(e.mach - 0.5) < 1e-12 && e.alpha == 0.0) {
                x.push_back(e.delta);
                y.push_back(e.c[cs.control == "elevator" ? 4 : cs.control == "aileron" ? 3 : 5]);
            }
        const std::size_t k = cs.control == "elevator" ? 4 : cs.control == "aileron" ? 3 : 5;
        EXPECT_NEAR(cs.main[k], least_squares_slope(x, y), 1e-10) << cs.control;
        EXPECT_NEAR(cs.ratio(k), 1.0, 1e-9) << cs.control;
        if (cs.control == "elevator") {
            EXPECT_LT(cs.main[4], 0.0) << "Cm_de of a tail aft";
            EXPECT_NEAR(cs.ratio(0), 1.1, 1e-9) << "CL_de";
        }
    }
    // Every slice exact; both table sets' static curves, bands and samples on each figure.
    for (const auto& [mb, mode] : cmp.slices) EXPECT_EQ(mode, SliceMode::exact);
    std::size_t n_static = 0;
    for (const auto& f : c.figures) {
        if (f.id.rfind("tables-static-", 0) != 0) continue;
        ++n_static;
        for (const auto& p : f.panels) {
            const Series* a = find_series(p, "vlm");
            const Series* b = find_series(p, "scaled");
            ASSERT_TRUE(a && b) << f.id << " " << p.title;
            EXPECT_NE(a->colour, b->colour);
            ASSERT_EQ(a->x, b->x);
            for (std::size_t i = 0; i < a->y.size(); ++i)
                EXPECT_NEAR(b->y[i], a->y[i] * (p.title == "CL" ? 1.1 : 1.0), 1e-12);
            const Series* band = find_series(p, "scaled +-2 sigma");
            ASSERT_TRUE(band);
            EXPECT_LT(band->opacity, find_series(p, "vlm +-2 sigma")->opacity);
        }
        // Samples of both where the slice has some: circles and squares.
        const Series* sa = find_series(f.panels[0], "vlm samples");
        const Series* sb = find_series(f.panels[0], "scaled samples");
        EXPECT_EQ(sa != nullptr, sb != nullptr) << f.id;
        if (sa && sb) {
            EXPECT_EQ(sa->style, SeriesStyle::markers);
            EXPECT_EQ(sb->style, SeriesStyle::squares);
            ASSERT_EQ(sa->y.size(), sb->y.size());
            for (std::size_t i = 0; i < sa->y.size(); ++i)
                EXPECT_NEAR(sb->y[i], sa->y[i] * 1.1, 1e-12);
        }
    }
    EXPECT_EQ(n_static, 4u);
    // Control figures: both tables at both deflections; the dynamic and summary figures.
    bool control = false, dynamic = false, summary = false;
    for (const auto& f : c.figures) {
        if (f.id == "tables-elevator-M1") {
            control = true;
            EXPECT_TRUE(find_series(f.panels[0], "vlm elevator -25 deg"));
            const Series* s = find_series(f.panels[0], "scaled elevator -25 deg");
            ASSERT_TRUE(s);
            EXPECT_EQ(s->style, SeriesStyle::dashed);
            EXPECT_TRUE(find_series(f.panels[0], "scaled elevator 15 deg"));
        }
        if (f.id == "tables-dynamic-compare-M1") {
            dynamic = true;
            EXPECT_TRUE(find_series(f.panels[0], "vlm") && find_series(f.panels[0], "scaled"));
        }
        if (f.id == "tables-compare-summary") {
            summary = true;
            ASSERT_EQ(f.panels.size(), 5u);
            const Series* a = find_series(f.panels[0], "vlm");
            ASSERT_TRUE(a);
            ASSERT_EQ(a->y.size(), 2u);
            EXPECT_NEAR(a->y[0], cmp.machs[0].main[0], 1e-12);
        }
    }
    EXPECT_TRUE(control && dynamic && summary);
    // The page: the summary table, the comparison data embedded, the ratio 1.1 shown.
    const std::string page = render_html(run, c);
    for (const char* s :
         {"id=\"tables-compare\"", "id=\"compare-summary\"", "id=\"compare-controls\"",
          "data-figure=\"tables-compare-summary\"", "Comparison: vlm and scaled", "<td>1.1</td>",
          "data-group=\"tables-dynamic-compare\""})
        EXPECT_NE(page.find(s), std::string::npos) << s;
}

TEST(Compare, SecondTableAtOtherBreakpointsIsInterpolatedAtTheSlices) {
    const RunData run = with_compare(moved_copy());
    const ReportContent c = build_content(run);
    ASSERT_TRUE(c.comparison.has_value());
    for (const auto& [mb, mode] : c.comparison->slices) EXPECT_EQ(mode, SliceMode::interpolated);
    std::size_t n = 0;
    for (const auto& f : c.figures) {
        if (f.id.rfind("tables-static-", 0) != 0) continue;
        for (const auto& p : f.panels) {
            const Series* a = find_series(p, "vlm");
            const Series* b = find_series(p, "moved (interpolated)");
            ASSERT_TRUE(a && b) << f.id << " " << p.title;
            // At the main table's alphas inside the second's range [-2, 8] deg only.
            ASSERT_EQ(b->x.size(), 6u);
            for (std::size_t i = 0; i < b->x.size(); ++i) {
                EXPECT_NEAR(b->x[i], -2.0 + 2.0 * static_cast<double>(i), 1e-12);
                const std::size_t j = static_cast<std::size_t>(
                    std::find(a->x.begin(), a->x.end(), b->x[i]) - a->x.begin());
                ASSERT_LT(j, a->x.size());
                EXPECT_NEAR(b->y[i], a->y[j], 1e-12) << f.id << " " << p.title;
            }
            EXPECT_FALSE(find_series(p, "moved samples"));
            ++n;
        }
    }
    EXPECT_EQ(n, 24u);
    for (const auto& m : c.comparison->machs)
        for (std::size_t k = 0; k < summary_names.size(); ++k)
            EXPECT_NEAR(m.ratio(k), 1.0, 1e-9) << summary_names[k];
    for (const auto& cs : c.comparison->controls)
        for (const std::size_t k : {std::size_t{0}, std::size_t{4}})
            EXPECT_NEAR(cs.other[k], cs.main[k], 1e-10) << cs.control;
    // The moved copy has no dynamic table: no dynamic comparison.
    for (const auto& g : c.groups) EXPECT_NE(g.id, "tables-dynamic-compare");
}

TEST(Compare, SlicesOutsideTheSecondTableAreLeftOutAndSaid) {
    // The moved copy, the other way round: the fixture is the second table; Mach 0.1 and 0.6
    // and sideslip -4 and 10 deg lie outside it.
    RunData run = read_run(moved_copy());
    run.compare = read_tables(fixture_tables);
    const ReportContent c = build_content(run);
    ASSERT_TRUE(c.comparison.has_value());
    for (const auto& [mb, mode] : c.comparison->slices) EXPECT_EQ(mode, SliceMode::outside);
    for (const auto& m : c.comparison->machs) EXPECT_TRUE(std::isnan(m.other[0]));
    const std::string page = render_html(run, c);
    EXPECT_NE(page.find("Static slices outside the Mach or sideslip range of vlm"),
              std::string::npos);
    EXPECT_NE(page.find("&ndash;"), std::string::npos);
}

TEST(Compare, ReportWritesComparisonFiguresAndJson) {
    const fs::path out = scratch("report");
    ReportOptions o;
    o.run_dir = fixture;
    o.html = out / "report.html";
    o.figures_dir = out / "figures";
    o.compare_tables = scaled_copy("scaled_report", {"CL"}, 1.1);
    o.compare_label = "VLM x 1.1";
    const ReportResult r = make_report(o);
    const nlohmann::json j = r.to_json();
    ASSERT_TRUE(j.contains("comparison"));
    EXPECT_EQ(j["comparison"]["main"]["label"], "vlm");
    EXPECT_EQ(j["comparison"]["compare"]["label"], "VLM x 1.1");
    EXPECT_NEAR(j["comparison"]["summary"][0]["ratio"]["CL_alpha"].get<double>(), 1.1, 1e-9);
    EXPECT_NEAR(j["comparison"]["controls"][0]["ratio"]["dCl_daileron"].get<double>(), 1.0, 1e-9);
    EXPECT_EQ(j["comparison"]["slices"]["exact"], 4);
    EXPECT_EQ(j["parts"][1], "tables");
    EXPECT_EQ(j["parts"][2], "compare-tables");
    for (const char* f :
         {"tables-compare-summary.svg", "tables-compare-summary.csv", "tables-static-M0-b0.svg",
          "tables-static-M1-b0.csv", "tables-elevator-M1.svg", "tables-dynamic-compare-M0.svg",
          "tables-dynamic-compare-M2.csv"})
        EXPECT_TRUE(fs::exists(*o.figures_dir / f)) << f;
    const std::string csv = manta::core::read_file(*o.figures_dir / "tables-static-M0-b0.csv");
    EXPECT_NE(csv.find("0,vlm,"), std::string::npos);
    EXPECT_NE(csv.find("0,VLM x 1.1,"), std::string::npos);
    EXPECT_NE(csv.find("0,VLM x 1.1 samples,"), std::string::npos);
    const std::string svg = manta::core::read_file(*o.figures_dir / "tables-static-M0-b0.svg");
    EXPECT_NE(svg.find(colour_of("compare")), std::string::npos);
    EXPECT_NE(svg.find("width=\"6\" height=\"6\""), std::string::npos) << "square markers";
    // Without a comparison the JSON has no comparison object.
    o.compare_tables.reset();
    o.figures_dir.reset();
    EXPECT_FALSE(make_report(o).to_json().contains("comparison"));
    fs::remove_all(out);
}

TEST(Compare, BadSecondTablesAreOneLineErrorsAndNothingIsWritten) {
    const fs::path out = scratch("bad");
    ReportOptions o;
    o.run_dir = fixture;
    o.html = out / "page.html";
    auto fails = [&](const fs::path& dir) {
        o.compare_tables = dir;
        const std::string e = error_of([&] { (void)make_report(o); });
        EXPECT_FALSE(fs::exists(o.html)) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        return e;
    };
    EXPECT_NE(fails(out / "nowhere").find("not a directory"), std::string::npos);
    // A run directory: not a tables directory, with a hint at its tables/.
    const std::string run_dir = fails(fixture);
    EXPECT_NE(run_dir.find("no tables.csv"), std::string::npos) << run_dir;
    EXPECT_NE(run_dir.find("(such as " + (fixture / "tables").string() + ")"), std::string::npos)
        << run_dir;
    // Mismatched coefficient sets.
    const fs::path extra = scaled_copy("extra", {}, 1.0);
    {
        TextCsv t = read_text_csv(extra / "tables.csv");
        t.columns.push_back("CX");
        for (auto& r : t.rows) r.push_back("0");
        write_csv(extra / "tables.csv", t.columns, t.rows);
    }
    const std::string mismatch = fails(extra);
    EXPECT_NE(mismatch.find("coefficient columns CL,CD,CY,Cl,Cm,Cn,CX differ"), std::string::npos)
        << mismatch;
    // A table with a row missing is not a grid the database can hold.
    const fs::path holed = scaled_copy("holed", {}, 1.0);
    {
        TextCsv t = read_text_csv(holed / "tables.csv");
        t.rows.erase(t.rows.begin() + 3);
        write_csv(holed / "tables.csv", t.columns, t.rows);
    }
    const std::string hole = fails(holed);
    EXPECT_NE(hole.find("table 'static' is not a full grid: 35 rows"), std::string::npos) << hole;
    // No static table.
    const fs::path nostatic = scaled_copy("nostatic", {}, 1.0);
    {
        TextCsv t = read_text_csv(nostatic / "tables.csv");
        std::erase_if(t.rows, [](const auto& r) { return r[0] == "static"; });
        write_csv(nostatic / "tables.csv", t.columns, t.rows);
    }
    EXPECT_NE(fails(nostatic).find("no static table"), std::string::npos);
    // A RUN_DIR without tables has nothing to compare with.
    o.run_dir = fixture / "replay/immelmann";
    const std::string none = fails(fixture_tables);
    EXPECT_NE(none.find("--compare-tables: "), std::string::npos) << none;
    fs::remove_all(out);
    for (const char* d : {"extra", "holed", "nostatic"}) fs::remove_all(scratch(d));
}
