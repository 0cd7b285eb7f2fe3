// The cases CSV of an ensemble (flightdyn::parse_cases / read_cases, docs/formats.md#cases-csv):
// a good file, each error with its file:line:column, a file of max_cases rows (the duplicate-name
// check was quadratic: 1e5 rows took minutes), repeated names differing only in case, the cap.

#include <gtest/gtest.h>

#include <filesystem>
#include <initializer_list>
#include <string>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/flightdyn/cases.hpp"

namespace fd = manta::flightdyn;

namespace {

/// The message of the error of type E that `f` throws (fails the test if none).
template <class E = manta::InputError, class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an error";
    return {};
}

/// The InputError message of parsing `text` as "cases.csv".
std::string parse_error(const std::string& text) {
    return error_of([&] { (void)fd::parse_cases(text, "dir/cases.csv"); });
}

void expect_parts(const std::string& msg, std::initializer_list<const char*> parts) {
    for (const char* p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << msg << "\nlacks: " << p;
}

}  // namespace

TEST(CasesCsv, ReadsAGoodFile) {
    const auto rows = fd::parse_cases(
        "# sweep\n"
        "name, speed, altitude, inputs, climb_angle_deg\n"
        "\n"
        "cruise_low,150,1000,doublet.csv,0\n"
        "cruise-high.2,+180,8000,/abs/doublet.csv,-2.5\n"
        "climb,130,2000,,5\n",
        "dir/cases.csv");
    ASSERT_EQ(rows.size(), 3U);
    EXPECT_EQ(rows[0].name, "cruise_low");
    EXPECT_EQ(rows[0].line, 4);
    EXPECT_EQ(rows[0].speed, 150.0);
    EXPECT_EQ(rows[0].altitude, 1000.0);
    EXPECT_EQ(rows[0].inputs, "doublet.csv");
    EXPECT_EQ(rows[0].inputs_path, std::filesystem::path("dir/doublet.csv"));
    EXPECT_EQ(rows[0].inputs_column, 4);
    EXPECT_TRUE(rows[0].inputs_text.empty());  // no reader given: no file touched
    EXPECT_EQ(rows[1].speed, 180.0);
    EXPECT_EQ(rows[1].climb_angle_deg, -2.5);
    EXPECT_EQ(rows[1].inputs_path, std::filesystem::path("/abs/doublet.csv"));
    EXPECT_EQ(rows[2].line, 6);
    EXPECT_TRUE(rows[2].inputs.empty());
    EXPECT_EQ(rows[2].climb_angle_deg, 5.0);

    // Columns in any order; the optional ones absent.
    const auto r = fd::parse_cases("altitude,name,speed\n500,a,90\n", "c.csv");
    ASSERT_EQ(r.size(), 1U);
    EXPECT_EQ(r[0].name, "a");
    EXPECT_EQ(r[0].speed, 90.0);
    EXPECT_EQ(r[0].altitude, 500.0);
    EXPECT_EQ(r[0].climb_angle_deg, 0.0);
}

TEST(CasesCsv, ReadsTheFileAndItsInputsFiles) {
    const auto dir = std::filesystem::temp_directory_path() / "manta_test_cases_csv";
    std::filesystem::create_directories(dir);
    manta::core::write_file_atomic(dir / "in.csv", "t,throttle\n0,0.2\n");
    manta::core::write_file_atomic(dir / "cases.csv",
                                   "name,speed,altitude,inputs\nA,150,1000,in.csv\nB,150,1000,\n");
    const auto rows = fd::read_cases((dir / "cases.csv").string());
    ASSERT_EQ(rows.size(), 2U);
    EXPECT_EQ(rows[0].inputs_text, "t,throttle\n0,0.2\n");
    EXPECT_EQ(rows[0].inputs_path, dir / "in.csv");
    EXPECT_TRUE(rows[1].inputs_text.empty());

    manta::core::write_file_atomic(dir / "bad.csv",
                                   "name,speed,altitude,inputs\nA,150,1000,absent.csv\n");
    expect_parts(
        error_of<manta::IoError>([&] { (void)fd::read_cases((dir / "bad.csv").string()); }),
        {"bad.csv:2:4: case 'A': inputs file 'absent.csv' cannot be read"});
    EXPECT_THROW((void)fd::read_cases((dir / "none.csv").string()), manta::IoError);
    std::filesystem::remove_all(dir);
}

TEST(CasesCsv, HeaderErrors) {
    expect_parts(parse_error("name,speed,altitud\na,1,2\n"),
                 {"dir/cases.csv:1:3: unknown column 'altitud' (did you mean 'altitude'?)",
                  "valid columns: name, speed, altitude, inputs, climb_angle_deg"});
    expect_parts(parse_error("name,,speed,altitude\n"),
                 {"dir/cases.csv:1:2: column 2 of the header is empty"});
    expect_parts(parse_error("name,speed,speed,altitude\n"),
                 {"dir/cases.csv:1:3: column 'speed' appears twice in the header"});
    expect_parts(parse_error("# only\nname,altitude\na,1\n"),
                 {"dir/cases.csv:2: missing column 'speed' (true airspeed [m/s])",
                  "columns present: name, altitude"});
    expect_parts(parse_error("# nothing\n\n"), {"dir/cases.csv: no header line"});
    expect_parts(parse_error(""), {"dir/cases.csv: no header line"});
    expect_parts(parse_error("\nname,speed,altitude\n# none\n"),
                 {"dir/cases.csv: no cases after the header (line 2)"});
}

TEST(CasesCsv, RowErrors) {
    const std::string h = "name,speed,altitude,inputs,climb_angle_deg\n";
    expect_parts(parse_error(h + "a,1,2\n"),
                 {"dir/cases.csv:2: row has 3 fields; expected 5 as in the header"});
    expect_parts(parse_error(h + ",150,1000,,0\n"), {"dir/cases.csv:2:1: empty case name"});
    expect_parts(
        parse_error(h + "a/b,150,1000,,0\n"),
        {"dir/cases.csv:2:1: case name 'a/b' has a path separator '/'", "names become file names"});
    expect_parts(parse_error(h + ".hidden,150,1000,,0\n"), {"case name '.hidden' starts with '.'"});
    expect_parts(parse_error(h + "a b,150,1000,,0\n"), {"case name 'a b' has ' '"});
    expect_parts(parse_error(h + "caf\xC3\xA9,150,1000,,0\n"), {"has the byte 0xc3"});
    expect_parts(parse_error(h + "a,fast,1000,,0\n"),
                 {"dir/cases.csv:2:2: column 'speed' value 'fast' is not a finite number; "
                  "expected the true airspeed [m/s]"});
    expect_parts(parse_error(h + "a,inf,1000,,0\n"), {"column 'speed' value 'inf'"});
    expect_parts(parse_error(h + "a,+-1,1000,,0\n"), {"column 'speed' value '+-1'"});
    expect_parts(parse_error(h + "a,0,1000,,0\n"),
                 {"dir/cases.csv:2:2: speed 0 m/s; expected a true airspeed > 0"});
    expect_parts(parse_error(h + "a,150,1e3x,,0\n"),
                 {"dir/cases.csv:2:3: column 'altitude' value '1e3x' is not a finite number"});
    expect_parts(parse_error(h + "a,150,1000,,nan\n"),
                 {"dir/cases.csv:2:5: column 'climb_angle_deg' value 'nan'"});
    expect_parts(
        parse_error(h + "a,150,1000,,90\n"),
        {"dir/cases.csv:2:5: climb_angle_deg 90; expected a flight-path angle in (-90, 90) "
         "deg"});
    expect_parts(parse_error(h + "a,150,1000,in\xFF.csv,0\n"),
                 {"dir/cases.csv:2:4: case 'a': inputs path 'in\\xFF.csv' is not valid UTF-8",
                  "0xFF at byte offset 2", "expected a UTF-8 file name"});
    // Valid UTF-8 in a path is accepted.
    EXPECT_EQ(fd::parse_cases(h + "a,150,1000,caf\xC3\xA9.csv,0\n", "c.csv")[0].inputs,
              "caf\xC3\xA9.csv");
}

TEST(CasesCsv, RepeatedNamesIgnoringCaseNameTheFirstLine) {
    expect_parts(parse_error("name,speed,altitude\nFast,150,1000\nslow,100,1000\nfAST,200,1000\n"),
                 {"dir/cases.csv:4:1: case name 'fAST' repeats 'Fast' of line 2",
                  "ignoring upper/lower case"});
    // Names differing by more than case are distinct.
    EXPECT_EQ(fd::parse_cases("name,speed,altitude\nA.1,1,0\na_1,1,0\na-1,1,0\n", "c.csv").size(),
              3U);
}

TEST(CasesCsv, ReadsMaxCasesRowsAndRefusesOneMore) {
    // max_cases rows with distinct names: the name check is a hash look-up per row (it compared
    // every pair before, 5e9 comparisons for 1e5 rows).
    std::string text = "name,speed,altitude\n";
    for (std::size_t i = 0; i + 1 < fd::max_cases; ++i)
        text += "case_" + std::to_string(i) + ",150," + std::to_string(i % 9000) + "\n";
    // A repeat in the last row allowed is still found, naming the first line.
    expect_parts(error_of([&] { (void)fd::parse_cases(text + "CASE_17,150,0\n", "big.csv"); }),
                 {"big.csv:100001:1: case name 'CASE_17' repeats 'case_17' of line 19"});
    text += "last,150,0\n";
    const auto rows = fd::parse_cases(text, "big.csv");
    ASSERT_EQ(rows.size(), fd::max_cases);
    EXPECT_EQ(rows[fd::max_cases - 2].name, "case_" + std::to_string(fd::max_cases - 2));
    EXPECT_EQ(rows[fd::max_cases - 2].altitude, static_cast<double>((fd::max_cases - 2) % 9000));
    EXPECT_EQ(rows.back().name, "last");
    EXPECT_EQ(rows.back().line, static_cast<int>(fd::max_cases) + 1);
    // One row more than the cap.
    expect_parts(error_of([&] { (void)fd::parse_cases(text + "extra,150,0\n", "big.csv"); }),
                 {"big.csv:100002: more than 100000 cases; a cases file holds at most 100000"});
}

TEST(CasesCsv, UnsafeNameReasons) {
    EXPECT_EQ(fd::unsafe_case_name_reason("ok_name-1.2"), "");
    EXPECT_EQ(fd::unsafe_case_name_reason(""), "is empty");
    EXPECT_EQ(fd::unsafe_case_name_reason("a\\b"), "has a path separator '\\'");
    EXPECT_EQ(fd::unsafe_case_name_reason(std::string("a\0b", 3)), "has the byte 0x00");
}
