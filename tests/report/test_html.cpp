/// @file test_html.cpp
/// The page and the figures: escaping of text and embedded JSON ("</script>" in a name must not
/// end the data element), the content of the page, the figure SVG and CSV, and that a failed
/// report writes nothing.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "manta/core/error.hpp"
#include "manta/report/html.hpp"
#include "manta/report/report.hpp"

namespace fs = std::filesystem;
using namespace manta::report;

namespace {

const fs::path fixture = fs::path(MANTA_SOURCE_DIR) / "tests/data/report/run";

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto k = text.find(what); k != std::string::npos; k = text.find(what, k + 1)) ++n;
    return n;
}

/// The JSON text inside <script type="application/json" id="manta-data">.
std::string data_json(const std::string& page) {
    const std::string open = "<script type=\"application/json\" id=\"manta-data\">";
    const auto a = page.find(open) + open.size();
    return page.substr(a, page.find("</script>", a) - a);
}

}  // namespace

TEST(Html, EscapeText) {
    EXPECT_EQ(escape_html("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
    EXPECT_EQ(escape_html("plain"), "plain");
}

TEST(Html, ScriptJsonCannotCloseTheElementAndRoundTrips) {
    const nlohmann::json j{{"name", "</script><script>alert(1)</script> <!-- & \u2028"}};
    const std::string s = script_json(j);
    EXPECT_EQ(s.find('<'), std::string::npos);
    EXPECT_EQ(s.find('>'), std::string::npos);
    EXPECT_EQ(s.find('&'), std::string::npos);
    EXPECT_EQ(s.find("\xE2\x80\xA8"), std::string::npos);
    EXPECT_EQ(nlohmann::json::parse(s), j);
    // Invalid UTF-8 is replaced, not thrown.
    EXPECT_NO_THROW((void)script_json(nlohmann::json{{"bad", std::string("a\xff")}}));
}

TEST(Html, HostileManoeuvreNameStaysText) {
    RunData run = read_run(fixture);
    const std::string evil = "</script><script>window.pwned=1</script><b>x";
    run.manoeuvres[0].name = evil;
    run.replays[0].name = evil;
    const ReportContent c = build_content(run);
    const std::string page = render_html(run, c);
    EXPECT_EQ(page.find(evil), std::string::npos);
    // Exactly the two script elements of the page close.
    EXPECT_EQ(count(page, "</script>"), 2u);
    EXPECT_NE(page.find("&lt;/script&gt;&lt;script&gt;window.pwned=1"), std::string::npos);
    const auto data = nlohmann::json::parse(data_json(page));
    EXPECT_EQ(data["figures"]["manoeuvre-0-histories"]["title"], evil + ": states and controls");
}

TEST(Html, PageOfTheFixtureShowsEveryPart) {
    const RunData run = read_run(fixture);
    const ReportContent c = build_content(run);
    const std::string page = render_html(run, c);
    for (const char* s :
         {"id=\"overview\"", "id=\"aircraft\"", "id=\"tables\"", "id=\"manoeuvre-0\"",
          "id=\"replay-0\"", "id=\"provenance\"", "Ranger 2000", "Three-view",
          "data-path=\"manoeuvre-0-path\"", "fast elevator motion", "Solve_Succeeded",
          "timings_s.optimise.immelmann"})
        EXPECT_NE(page.find(s), std::string::npos) << s;
    // Self-contained: no external resource.
    for (const char* s : {"src=\"http", "href=\"http", "<link", "src=\"//", "@import"})
        EXPECT_EQ(page.find(s), std::string::npos) << s;
    // Every plot placeholder has its data.
    const auto data = nlohmann::json::parse(data_json(page));
    std::size_t pos = 0, n = 0;
    while ((pos = page.find("data-figure=\"", pos)) != std::string::npos) {
        pos += 13;
        const std::string id = page.substr(pos, page.find('"', pos) - pos);
        EXPECT_TRUE(data["figures"].contains(id)) << id;
        ++n;
    }
    EXPECT_EQ(n, 1u + 3u + 1u + 1u + 3u);  // static, 3 controls, dynamic, histories, replay x3
    // Static slices: one per Mach and sideslip of the table; the first plotted one shown first.
    EXPECT_EQ(c.groups.at(0).figure_ids.size(), 4u);
}

TEST(Html, MissingPartsAreSaidInThePage) {
    RunData run = read_run(fixture);
    run.replays.clear();
    run.missing = {"replay/"};
    run.manoeuvres[0].dense.reset();
    run.manoeuvres[0].missing = {"trajectory_dense.csv"};
    const std::string page = render_html(run, build_content(run));
    EXPECT_NE(page.find("Not in the run directory: replay/"), std::string::npos);
    EXPECT_NE(page.find("Not in the manoeuvre directory: trajectory_dense.csv"), std::string::npos);
    EXPECT_EQ(page.find("id=\"replay-0\""), std::string::npos);
}

TEST(Figure, SvgAndCsvOfAFigure) {
    Figure f;
    f.id = "f";
    f.title = "T <1>";
    Panel p;
    p.title = "CL";
    p.x_label = "alpha [deg]";
    p.y_label = "CL [-]";
    p.series.push_back(
        {"table", colour_of("table"), SeriesStyle::line, {0, 1, 2}, {0, 0.1, 0.2}, {}});
    p.series.push_back(
        {"band, 2 sigma", colour_of("table"), SeriesStyle::band, {0, 2}, {-1, 0}, {1, 2}});
    p.shades.push_back({0.5, 1.0, "flagged"});
    f.panels.push_back(p);
    const std::string svg = to_svg(f);
    EXPECT_NE(svg.find("T &lt;1&gt;"), std::string::npos);
    EXPECT_NE(svg.find("alpha [deg]"), std::string::npos);
    EXPECT_NE(svg.find("<polyline"), std::string::npos);
    EXPECT_NE(svg.find("<polygon"), std::string::npos);
    const std::string csv = to_csv(f);
    EXPECT_NE(csv.find("panel,series,x,y,y_upper\n0,table,0,0,\n0,table,1,0.1,\n"),
              std::string::npos);
    EXPECT_NE(csv.find("0,\"band, 2 sigma\",2,0,2\n"), std::string::npos);
    EXPECT_EQ(colour_of("replay"), colour_of("replay"));
    EXPECT_NE(colour_of("replay"), colour_of("table"));
}

TEST(Figure, NiceTicks) {
    EXPECT_EQ(nice_ticks(0, 10, 5), (std::vector<double>{0, 2, 4, 6, 8, 10}));
    EXPECT_EQ(nice_ticks(-0.013, 0.012, 5), (std::vector<double>{-0.01, -0.005, 0, 0.005, 0.01}));
    EXPECT_TRUE(nice_ticks(1, 1).empty());
}

TEST(Report, WritesFiguresAndPageAtomically) {
    const fs::path out =
        fs::temp_directory_path() / ("manta_report_html_" + std::to_string(::getpid()));
    fs::remove_all(out);
    ReportOptions o;
    o.run_dir = fixture;
    o.html = out / "report.html";
    o.figures_dir = out / "figures";
    o.png = false;
    const ReportResult r = make_report(o);
    EXPECT_TRUE(fs::exists(o.html));
    EXPECT_EQ(r.files.back(), o.html.string());
    for (const char* f :
         {"manoeuvre-0-histories.svg", "manoeuvre-0-histories.csv", "manoeuvre-0-path.svg",
          "manoeuvre-0-path.csv", "replay-0-coefficients.svg", "replay-0-differences.csv",
          "tables-dynamic.svg", "aircraft-three-view.svg"})
        EXPECT_TRUE(fs::exists(*o.figures_dir / f)) << f;
    EXPECT_EQ(r.layout, "run");
    EXPECT_EQ(r.to_json()["parts"].size(), 5u);
    // A malformed part: an error, and neither page nor figures are written.
    const fs::path bad = out / "bad";
    fs::copy(fixture, bad, fs::copy_options::recursive);
    std::ofstream(bad / "replay/immelmann/summary.json") << "{\"steps\": 3,";
    o.run_dir = bad;
    o.html = out / "bad.html";
    o.figures_dir = out / "bad_figures";
    EXPECT_THROW((void)make_report(o), manta::InputError);
    EXPECT_FALSE(fs::exists(o.html));
    EXPECT_FALSE(fs::exists(*o.figures_dir));
    fs::remove_all(out);
}
