// `manta simulate --cases FILE --out-dir DIR`: the ensemble command end to end (the Ranger 2000
// of examples/): outputs, the --json summary's shape, a case ending on the ground, and every
// error path with its exit code and message.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "manta/core/io.hpp"

namespace fs = std::filesystem;

namespace {

const std::string ranger = std::string(MANTA_SOURCE_DIR) + "/examples/ranger2000/aircraft.yaml";

struct Outcome {
    int code = -1;
    std::string out, err;
};

/// A fresh folder for one test.
fs::path workdir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / "manta_test_cli_ensemble" / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void write(const fs::path& file, const std::string& text) {
    std::ofstream(file) << text;
}

std::string read(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// `s` in single quotes for the shell.
std::string quote(const std::string& s) {
    std::string q;
    q.reserve(s.size() + 2);
    q.push_back('\'');
    for (const char c : s) {
        if (c == '\'') {
            q.append("'\\''");
        } else {
            q.push_back(c);
        }
    }
    q.push_back('\'');
    return q;
}

/// Run `manta simulate ARGS` in `dir`; stdout and stderr captured.
Outcome simulate_with(const fs::path& dir, const std::vector<std::string>& args) {
    std::string cmd = "cd ";
    cmd.append(quote(dir.string())).append(" && ").append(quote(MANTA_EXE)).append(" simulate");
    for (const auto& a : args) cmd.append(" ").append(quote(a));
    cmd.append(" >stdout.txt 2>stderr.txt");
    const int status = std::system(cmd.c_str());
    Outcome r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read(dir / "stdout.txt");
    r.err = read(dir / "stderr.txt");
    return r;
}

/// The same with the arguments in braces.
Outcome simulate(const fs::path& dir, std::initializer_list<std::string> args) {
    return simulate_with(dir, std::vector<std::string>(args));
}

/// Run an ensemble of `cases_csv` (written to DIR/cases.csv) for 2 s, rows every 0.1 s, into
/// DIR/out, with `extra` options.
Outcome ensemble(const fs::path& dir, const std::string& cases_csv,
                 std::initializer_list<std::string> extra = {}) {
    write(dir / "cases.csv", cases_csv);
    std::vector<std::string> args = {"--aircraft",        ranger, "--cases",    "cases.csv",
                                     "--out-dir",         "out",  "--duration", "2",
                                     "--output-interval", "0.1"};
    args.insert(args.end(), extra.begin(), extra.end());
    return simulate_with(dir, args);
}

#define EXPECT_HAS(text, what) \
    EXPECT_NE((text).find(what), std::string::npos) << "'" << (what) << "' not in: " << (text)

const char* doublet =
    "t,elevator_deg\n0,-1.5\n0.5,-1.5\n0.6,-3.5\n1,-3.5\n1.1,0.5\n1.5,0.5\n1.6,-1.5\n";

}  // namespace

TEST(CliEnsemble, HelpNamesTheEnsembleOptions) {
    const auto dir = workdir("help");
    const Outcome r = simulate(dir, {"--help"});
    EXPECT_EQ(r.code, 0);
    EXPECT_HAS(r.out, "--cases");
    EXPECT_HAS(r.out, "--out-dir");
    EXPECT_HAS(r.out, "summary.json");
}

TEST(CliEnsemble, WritesATrajectoryPerCaseAndTheSummary) {
    const auto dir = workdir("run");
    fs::create_directories(dir / "inputs");
    write(dir / "inputs" / "doublet.csv", doublet);
    const Outcome r = ensemble(dir,
                               "# three cases\n"
                               "name,speed,altitude,inputs,climb_angle_deg\n"
                               "level,150,3000,,0\n"
                               "doublet,130,2000,inputs/doublet.csv,0\n"
                               "\n"
                               "climb,140,1000,,5\n");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* name : {"level", "doublet", "climb"}) {
        SCOPED_TRACE(name);
        EXPECT_HAS(r.out, name);
        const auto t = manta::core::read_csv(dir / "out" / (std::string(name) + ".csv"));
        EXPECT_EQ(t.rows.size(), 21u);  // 0, 0.1, ..., 2
        bool has_case = false;
        for (const auto& c : t.comments) has_case |= c.rfind("case: " + std::string(name), 0) == 0;
        EXPECT_TRUE(has_case);
    }
    EXPECT_HAS(r.out, "completed");
    EXPECT_HAS(r.out, "max nz");
    EXPECT_HAS(r.out, "min altitude");
    const auto j = nlohmann::json::parse(read(dir / "out" / "summary.json"));
    EXPECT_EQ(j["n_cases"], 3);
    EXPECT_EQ(j["ended"]["completed"], 3);
    // The climb is trimmed at 5 deg: it gains height, the level case keeps it.
    const auto& cases = j["cases"];
    EXPECT_GT(cases[2]["final_state"]["altitude"].get<double>(), 1000.0 + 2.0 * 140.0 * 0.08);
    EXPECT_NEAR(cases[0]["final_state"]["altitude"].get<double>(), 3000.0, 0.5);
    EXPECT_EQ(cases[1]["inputs"], "inputs/doublet.csv");
    EXPECT_EQ(cases[1]["line"], 4);
}

TEST(CliEnsemble, JsonPrintsTheSummaryWithItsShape) {
    const auto dir = workdir("json");
    write(dir / "push.csv", "t,elevator_deg\n0,0\n0.3,8\n");
    const Outcome r =
        ensemble(dir, "name,speed,altitude,inputs\nhigh,150,3000,\nlow,150,60,push.csv\n",
                 {"--json", "--form", "euler"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j, nlohmann::json::parse(read(dir / "out" / "summary.json")));
    for (const char* key : {"aircraft", "mass_case", "cases_file", "out_dir", "integrator", "form",
                            "dt", "output_interval", "duration_requested", "n_cases", "ended",
                            "wall_time", "case_seconds", "case_seconds_per_wall_second", "cases"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["form"], "euler");
    EXPECT_EQ(j["integrator"], "rk4");
    ASSERT_EQ(j["cases"].size(), 2u);
    for (const auto& c : j["cases"]) {
        for (const char* key : {"name",
                                "line",
                                "speed",
                                "altitude",
                                "climb_angle_deg",
                                "inputs",
                                "output_file",
                                "end_reason",
                                "end_message",
                                "end_time",
                                "steps",
                                "rhs_evaluations",
                                "rows",
                                "max_nz",
                                "min_nz",
                                "min_altitude",
                                "initial_state",
                                "final_state",
                                "saturation",
                                "out_of_table"})
            EXPECT_TRUE(c.contains(key)) << key;
        EXPECT_TRUE(fs::exists(dir / c["output_file"].get<std::string>()));  // relative to the run
    }
    // The pushed case from 60 m reaches the ground and stops; the other flies on.
    EXPECT_EQ(j["cases"][0]["end_reason"], "completed");
    EXPECT_EQ(j["cases"][1]["end_reason"], "ground");
    EXPECT_LT(j["cases"][1]["end_time"].get<double>(), 2.0);
    EXPECT_NEAR(j["cases"][1]["min_altitude"].get<double>(), 0.0, 1e-6);
    EXPECT_EQ(j["ended"]["ground"], 1);
}

TEST(CliEnsemble, OptionClashesAreOneLineInputErrors) {
    const auto dir = workdir("clash");
    write(dir / "in.csv", doublet);
    const std::string cases = "name,speed,altitude\na,150,3000\n";
    for (const auto& [opt, value] :
         std::vector<std::pair<std::string, std::string>>{{"--inputs", "in.csv"},
                                                          {"--out", "t.csv"},
                                                          {"--speed", "120"},
                                                          {"--altitude", "900"}}) {
        SCOPED_TRACE(opt);
        const Outcome r = ensemble(dir, cases, {opt, value});
        EXPECT_EQ(r.code, 2);
        EXPECT_HAS(r.err, opt + " cannot be used with --cases");
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
    }
    Outcome r = simulate(dir, {"--aircraft", ranger, "--cases", "cases.csv", "--duration", "1"});
    EXPECT_EQ(r.code, 2);
    EXPECT_HAS(r.err, "--cases needs --out-dir");
    r = simulate(dir, {"--aircraft", ranger, "--out-dir", "o", "--duration", "1"});
    EXPECT_EQ(r.code, 2);
    EXPECT_HAS(r.err, "--out-dir is for ensembles");
    r = simulate(
        dir, {"--aircraft", ranger, "--cases", "none.csv", "--out-dir", "o", "--duration", "1"});
    EXPECT_EQ(r.code, 2);
    EXPECT_HAS(r.err, "none.csv");
    r = ensemble(dir, cases, {"--form", "eulr"});
    EXPECT_EQ(r.code, 2);
    EXPECT_HAS(r.err, "did you mean 'euler'");
}

TEST(CliEnsemble, CasesFileErrorsNameFileLineAndColumn) {
    const auto dir = workdir("errors");
    write(dir / "bad_inputs.csv", "t,elevatr_deg\n0,1\n");
    struct Bad {
        const char* csv;
        const char* message;
    };
    const Bad bad[] = {
        {"name,speed,altitud\na,150,3000\n",
         "cases.csv:1:3: unknown column 'altitud' (did you mean 'altitude'?)"},
        {"name,altitude\na,3000\n", "cases.csv:1: missing column 'speed'"},
        {"name,speed,altitude,speed\na,1,2,3\n", "cases.csv:1:4: column 'speed' appears twice"},
        {"# only a comment\n", "no header line"},
        {"name,speed,altitude\n", "no cases after the header (line 1)"},
        {"name,speed,altitude\na,150\n", "cases.csv:2: row has 2 fields; expected 3"},
        {"name,speed,altitude\na,150,3000\n,150,3000\n", "cases.csv:3:1: empty case name"},
        {"name,speed,altitude\na/b,150,3000\n", "case name 'a/b' has a path separator '/'"},
        {"name,speed,altitude\n..,150,3000\n", "case name '..' starts with '.'"},
        {"name,speed,altitude\nx y,150,3000\n", "case name 'x y' has ' '"},
        {"name,speed,altitude\nFast,150,3000\nfast,160,3000\n",
         "cases.csv:3:1: case name 'fast' repeats 'Fast' of line 2"},
        {"name,speed,altitude\na,fast,3000\n",
         "cases.csv:2:2: column 'speed' value 'fast' is not a finite number"},
        {"name,altitude,speed\na,nan,150\n",
         "cases.csv:2:2: column 'altitude' value 'nan' is not a finite number"},
        {"name,speed,altitude\na,-150,3000\n", "cases.csv:2:2: speed -150 m/s; expected"},
        {"name,speed,altitude,climb_angle_deg\na,150,3000,95\n",
         "cases.csv:2:4: climb_angle_deg 95; expected a flight-path angle in (-90, 90) deg"},
        {"name,speed,altitude,inputs\na,150,3000,nope.csv\n",
         "cases.csv:2:4: case 'a': inputs file 'nope.csv' cannot be read"},
        {"name,speed,altitude,inputs\na,150,3000,bad_inputs.csv\n", "cases.csv:2: case 'a': "},
    };
    for (const auto& b : bad) {
        SCOPED_TRACE(b.csv);
        const Outcome r = ensemble(dir, b.csv);
        EXPECT_EQ(r.code, 2);
        EXPECT_HAS(r.err, b.message);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    // The inputs file's own error, located in it, with the closest valid column.
    const Outcome r = ensemble(dir, "name,speed,altitude,inputs\na,150,3000,bad_inputs.csv\n");
    EXPECT_HAS(r.err, "bad_inputs.csv:1:2: unknown column 'elevatr_deg'");
    EXPECT_HAS(r.err, "did you mean 'elevator_deg'");
    EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
}

TEST(CliEnsemble, ACaseWithNoTrimStopsTheRunNamingCaseAndLine) {
    const auto dir = workdir("notrim");
    const Outcome r = ensemble(dir, "name,speed,altitude\nok,150,3000\nslow,20,3000\n");
    EXPECT_EQ(r.code, 1);
    EXPECT_HAS(r.err, "cases.csv:3: case 'slow': no trim: ");
    EXPECT_FALSE(fs::exists(dir / "out"));  // nothing is flown
}
