/// @file test_readers.cpp
/// The report's readers: text CSV with quotes, JSON with located errors, run directories of every
/// layout, and malformed parts reported with file, line and column.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "manta/core/error.hpp"
#include "manta/report/run_data.hpp"
#include "manta/report/text_csv.hpp"

namespace fs = std::filesystem;
using namespace manta::report;

namespace {

const fs::path fixture = fs::path(MANTA_SOURCE_DIR) / "tests/data/report/run";

/// A scratch copy of the fixture run directory (or an empty folder).
fs::path scratch(const std::string& name, bool copy_fixture = true) {
    const fs::path d = fs::temp_directory_path() /
                       ("manta_report_readers_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(d);
    if (copy_fixture)
        fs::copy(fixture, d, fs::copy_options::recursive);
    else
        fs::create_directories(d);
    return d;
}

void write(const fs::path& f, const std::string& text) {
    std::ofstream(f) << text;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const manta::Error& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST(TextCsv, QuotedFieldsCommasQuotesAndNewlines) {
    const TextCsv t = parse_text_csv(
        "# comment\nid,name,note\n1,\"a, b\",\"say \"\"hi\"\"\"\n2,plain,\"two\nlines\"\n3, x ,\n",
        "mem.csv");
    ASSERT_EQ(t.rows.size(), 3u);
    EXPECT_EQ(t.comments.at(0), "comment");
    EXPECT_EQ(t.rows[0][1], "a, b");
    EXPECT_EQ(t.rows[0][2], "say \"hi\"");
    EXPECT_EQ(t.rows[1][2], "two\nlines");
    EXPECT_EQ(t.rows[2][1], "x");
    EXPECT_EQ(t.rows[2][2], "");
    EXPECT_EQ(t.row_lines, (std::vector<int>{3, 4, 6}));
    EXPECT_EQ(t.number(2, 0), 3.0);
    const TextCsv crlf = parse_text_csv("a,b\r\n1,\"x\"\r\n", "crlf.csv");
    EXPECT_EQ(crlf.columns.back(), "b");
    EXPECT_EQ(crlf.rows.at(0).at(1), "x");
}

TEST(TextCsv, ErrorsNameFileLineAndColumn) {
    EXPECT_EQ(error_of([] { (void)parse_text_csv("a,b\n1,2\n3,x7\n", "f.csv").number(1, 1); }),
              "f.csv:3: column 2 'b' value 'x7' is not a number");
    EXPECT_EQ(error_of([] { (void)parse_text_csv("a,b\n1,2,3\n", "f.csv"); }),
              "f.csv:2: row has 3 fields; expected 2 as in the header");
    EXPECT_EQ(error_of([] { (void)parse_text_csv("a,b\n1,\"open\n", "f.csv"); }),
              "f.csv:2: column 2: quoted field is not closed");
    EXPECT_EQ(error_of([] { (void)parse_text_csv("a,a\n", "f.csv"); }),
              "f.csv:1: column 2 'a' appears twice in the header");
    EXPECT_EQ(error_of([] { (void)parse_text_csv("a\n1\n", "f.csv").require("b"); }),
              "f.csv: missing column 'b'; columns present: a");
    EXPECT_EQ(error_of([] { (void)parse_text_csv("a\nnan\n", "f.csv").number(0, 0); }),
              "f.csv:2: column 1 'a' value 'nan' is not finite");
}

TEST(Json, SyntaxErrorNamesLineAndColumn) {
    const std::string e =
        error_of([] { (void)parse_json("{\n  \"a\": 1,\n  \"b\": tru\n}", "s.json"); });
    EXPECT_EQ(e.rfind("s.json:3:", 0), 0u) << e;
    EXPECT_NE(e.find("invalid JSON"), std::string::npos) << e;
    EXPECT_EQ(parse_json("{\"a\": [1, 2]}", "s.json")["a"][1], 2);
}

TEST(RunData, FixtureRunDirectoryHasEveryPart) {
    const RunData r = read_run(fixture);
    EXPECT_EQ(r.layout, "run");
    EXPECT_TRUE(r.missing.empty());
    ASSERT_TRUE(r.aircraft);
    EXPECT_EQ(r.aircraft->name, "Ranger 2000");
    EXPECT_DOUBLE_EQ(r.aircraft->area, 15.5);
    EXPECT_FALSE(r.aircraft->top.empty());
    EXPECT_FALSE(r.aircraft->body_segments.empty());
    ASSERT_TRUE(r.tables);
    EXPECT_EQ(r.tables->tables.at("static").size(), 9u * 2 * 2);  // alpha x Mach x beta
    EXPECT_EQ(r.tables->tables.count("elevator"), 1u);
    EXPECT_FALSE(r.tables->samples.empty());  // the failed sample is skipped, not an error
    EXPECT_EQ(r.tables->plot_slices.size(), 4u);
    ASSERT_EQ(r.manoeuvres.size(), 1u);
    EXPECT_EQ(r.manoeuvres[0].name, "immelmann");
    EXPECT_EQ(r.manoeuvres[0].phases, (std::vector<std::string>{"pull-up", "roll-out"}));
    ASSERT_TRUE(r.manoeuvres[0].dense);
    EXPECT_GT(r.manoeuvres[0].dense->n_rows(), r.manoeuvres[0].nodes->n_rows());
    ASSERT_EQ(r.replays.size(), 1u);
    ASSERT_TRUE(r.replays[0].comparison);
    EXPECT_TRUE(r.replays[0].summary["flags"].is_array());
    EXPECT_EQ(r.run["manta_version"], "0.1.0");
}

TEST(RunData, SingleOutputDirectoriesAreRecognised) {
    EXPECT_EQ(read_run(fixture / "tables").layout, "tables");
    const RunData m = read_run(fixture / "manoeuvres/immelmann");
    EXPECT_EQ(m.layout, "optimise");
    EXPECT_EQ(m.manoeuvres.at(0).name, "immelmann");
    EXPECT_EQ(read_run(fixture / "replay/immelmann").layout, "replay");
}

TEST(RunData, MissingPartsAreListedNotErrors) {
    const fs::path d = scratch("missing");
    fs::remove_all(d / "replay");
    fs::remove(d / "run.json");
    fs::remove(d / "manoeuvres/immelmann/trajectory_dense.csv");
    fs::remove(d / "tables/samples.csv");
    const RunData r = read_run(d);
    EXPECT_EQ(r.missing, (std::vector<std::string>{"run.json", "replay/"}));
    EXPECT_TRUE(r.replays.empty());
    EXPECT_FALSE(r.manoeuvres.at(0).dense);
    EXPECT_EQ(r.manoeuvres.at(0).missing, (std::vector<std::string>{"trajectory_dense.csv"}));
    EXPECT_EQ(r.tables->missing, (std::vector<std::string>{"samples.csv"}));
    fs::remove_all(d);
}

TEST(RunData, MalformedPartsAreLocatedErrors) {
    const fs::path d = scratch("malformed");
    // A non-number in the comparison CSV, line 5.
    {
        std::ifstream in(d / "replay/immelmann/comparison.csv");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::size_t pos = 0;
        for (int i = 0; i < 4; ++i) pos = text.find('\n', pos) + 1;
        text.replace(pos, text.find(',', pos) - pos, "oops");
        write(d / "replay/immelmann/comparison.csv", text);
    }
    EXPECT_EQ(error_of([&] { (void)read_run(d); }),
              (d / "replay/immelmann/comparison.csv").string() +
                  ":5: column 't' value 'oops' is not a number");
    fs::remove_all(d / "replay");
    write(d / "run.json", "{\"manta_version\": \"0.1.0\",\n \"command\": }\n");
    const std::string e = error_of([&] { (void)read_run(d); });
    EXPECT_EQ(e.rfind((d / "run.json").string() + ":2:", 0), 0u) << e;
    fs::remove(d / "run.json");
    write(d / "tables/tables.csv", "table,alpha_deg\nstatic,1\n");
    EXPECT_EQ(error_of([&] { (void)read_run(d); }),
              (d / "tables/tables.csv").string() +
                  ": missing column 'mach'; columns present: table,alpha_deg");
    fs::remove_all(d);
}

TEST(RunData, TrajectoryNeedsTheAgreedColumnsAndIncreasingTime) {
    const fs::path d = scratch("trajectory", false);
    write(d / "trajectory.csv", "t,x,y\n0,0,0\n1,1,1\n");
    std::string e = error_of([&] { (void)read_trajectory(d / "trajectory.csv"); });
    EXPECT_NE(e.find("missing column 'z'"), std::string::npos) << e;
    write(d / "trajectory.csv",
          "t,x,y,z,phi,theta,psi,V,alpha,beta,p,q,r,elevator,aileron,rudder\n"
          "0,0,0,0,0,0,0,100,0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,100,0,0,0,0,0,0,0,0\n"
          "1,0,0,0,0,0,0,100,0,0,0,0,0,0,0,0\n");
    e = error_of([&] { (void)read_trajectory(d / "trajectory.csv"); });
    EXPECT_EQ(e, (d / "trajectory.csv").string() +
                     ":4: column 't' value 1 does not increase (previous row 1); expected strictly "
                     "increasing times");
    fs::remove_all(d);
}

TEST(RunData, NothingToReportIsAnError) {
    const fs::path d = scratch("empty", false);
    const std::string e = error_of([&] { (void)read_run(d); });
    EXPECT_NE(e.find("nothing to report"), std::string::npos) << e;
    EXPECT_NE(error_of([&] { (void)read_run(d / "absent"); }).find("not a directory"),
              std::string::npos);
    fs::remove_all(d);
}
