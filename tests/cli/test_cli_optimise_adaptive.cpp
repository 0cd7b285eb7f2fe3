// `manta optimise --adaptive`: error-driven ph mesh refinement (optimal::solve_adaptive) from the
// command line, on the double integrator (analytic optimum) and on the quick level-turn manoeuvre;
// its report in the text output and in --json; option errors.
//
// Minimum-time double integrator x'' = u, |u| <= 1 from (1, 1) to rest at the origin:
// bang-bang, t_f = v0 + 2 sqrt(v0^2/2 + x0) = 3.4494897 s (Kirk, Optimal Control Theory, 1970,
// ch. 5, minimum-time problems).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string source = MANTA_SOURCE_DIR;

struct Outcome {
    int code = -1;
    std::string out, err;
};

std::string read(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string quote(const std::string& s) {
    std::string q = "'";
    for (const char c : s) {
        if (c == '\'')
            q.append("'\\''");
        else
            q.push_back(c);
    }
    return q + "'";
}

fs::path work_dir() {
    const fs::path dir = fs::temp_directory_path() / "manta_test_cli_optimise_adaptive";
    fs::create_directories(dir);
    return dir;
}

Outcome optimise(const std::vector<std::string>& args) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string stem = (work_dir() / info->name()).string();
    std::string cmd = quote(MANTA_EXE) + " optimise";
    for (const auto& a : args) cmd.append(" ").append(quote(a));
    cmd.append(" >" + quote(stem + ".out") + " 2>" + quote(stem + ".err"));
    const int status = std::system(cmd.c_str());
    Outcome r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read(stem + ".out");
    r.err = read(stem + ".err");
    return r;
}

TEST(CliOptimiseAdaptive, DoubleIntegratorFromSixPointsReachesTheBangBangOptimum) {
    const Outcome r =
        optimise({"--problem", "double-integrator", "--nodes", "6", "--adaptive", "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const auto& ref = j.at("refinement");
    EXPECT_EQ(ref.at("status"), "tolerance_met");
    EXPECT_DOUBLE_EQ(ref.at("tolerance").get<double>(), 1e-6);
    const auto& passes = ref.at("passes");
    ASSERT_GE(passes.size(), 2U);
    // the user's mesh does not resolve the switch, the last one meets the tolerance
    EXPECT_EQ(passes.front().at("total_nodes"), 6);
    EXPECT_GT(passes.front().at("max_error").get<double>(), 1e-6);
    EXPECT_LE(passes.back().at("max_error").get<double>(), 1e-6);
    EXPECT_GT(passes.back().at("segments").get<int>(), 1);
    int iterations = 0;
    for (const auto& p : passes) iterations += p.at("iterations").get<int>();
    EXPECT_EQ(j.at("iterations").get<int>(), iterations);  // every pass counted
    EXPECT_EQ(j.at("segments"), passes.back().at("segments"));
    EXPECT_EQ(j.at("nodes_per_segment"), passes.back().at("nodes_per_segment"));
    EXPECT_TRUE(j.at("resolved").get<bool>());
    const double t_f = 1.0 + 2.0 * std::sqrt(1.5);  // 3.4494897 s, Kirk (1970)
    EXPECT_NEAR(j.at("final_time").get<double>(), t_f, 1e-6);
    EXPECT_NEAR(j.at("final_time_error").get<double>(), 0.0, 1e-6);
}

TEST(CliOptimiseAdaptive, TextOutputPrintsTheReportPerPass) {
    const Outcome r = optimise({"--problem", "double-integrator", "--nodes", "6", "--adaptive",
                                "--adaptive-tol", "1e-4", "--max-passes", "3"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("error-driven mesh refinement (tolerance 0.0001)"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("pass segments points  max error"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("tolerance_met: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("   1        1      6 "), std::string::npos) << r.out;
}

TEST(CliOptimiseAdaptive, PassLimitIsReportedWithAWarning) {
    // one solve only: the user's mesh, its error above the tolerance
    const Outcome r = optimise({"--problem", "double-integrator", "--nodes", "6", "--adaptive",
                                "--max-passes", "1", "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("refinement").at("status"), "pass_limit");
    EXPECT_EQ(j.at("refinement").at("passes").size(), 1U);
    EXPECT_NE(r.err.find("warning: mesh refinement pass_limit: "), std::string::npos) << r.err;
}

TEST(CliOptimiseAdaptive, LevelTurnRefinesFromTheManoeuvresMesh) {
    // two passes with splits into 10-point segments (the default 4-point pieces stall IPOPT on
    // this problem: docs/manoeuvres.md#error-driven-mesh-refinement); about 10 s CPU
    const fs::path out = work_dir() / "level_turn";
    fs::remove_all(out);
    const Outcome r =
        optimise({"--aircraft", source + "/examples/ranger2000/aircraft.yaml", "--manoeuvre",
                  source + "/examples/ranger2000/manoeuvres/level_turn.yaml", "--adaptive",
                  "--adaptive-tol", "1e-3", "--max-passes", "2", "--min-nodes", "10", "--max-nodes",
                  "20", "--out", out.string(), "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const auto& ref = j.at("refinement");
    const auto& passes = ref.at("passes");
    ASSERT_EQ(passes.size(), 2U) << ref.at("report").get<std::string>();
    // the first pass is the manoeuvre file's mesh (one segment of 20 points), solved again
    // from the manoeuvre's solution: few iterations, the same optimum (5.98 s, not resolved:
    // re-simulation error 0.19 scaled)
    EXPECT_EQ(passes[0].at("segments"), 1);
    EXPECT_EQ(passes[0].at("total_nodes"), 20);
    EXPECT_LT(passes[0].at("iterations").get<int>(), 60);
    EXPECT_NEAR(passes[0].at("final_time").get<double>(), 5.98, 0.05);
    EXPECT_EQ(passes[0].at("status"), "solved_unresolved");
    // the second: more segments and points, a smaller error estimate, never coarser
    EXPECT_GT(passes[1].at("segments").get<int>(), 1);
    EXPECT_GT(passes[1].at("total_nodes").get<int>(), 20);
    EXPECT_LT(passes[1].at("max_error").get<double>(), passes[0].at("max_error").get<double>());
    for (const auto& n : passes[1].at("nodes_per_segment")) EXPECT_GE(n.get<int>(), 10);
    EXPECT_EQ(ref.at("status"), "pass_limit");
    EXPECT_NE(r.err.find("warning: level_turn_90: mesh refinement pass_limit"), std::string::npos)
        << r.err;
    EXPECT_EQ(j.at("segments"), passes[1].at("segments"));
    EXPECT_NEAR(j.at("final_time").get<double>(), passes[1].at("final_time").get<double>(), 1e-9);
    EXPECT_NEAR(j.at("checks").at("final_heading_change_deg").get<double>(), 90.0, 1e-3);
    // the manoeuvre's own solve and both passes counted
    EXPECT_GT(j.at("iterations").get<int>(),
              passes[0].at("iterations").get<int>() + passes[1].at("iterations").get<int>());
    const auto summary = nlohmann::json::parse(read(out / "summary.json"));
    EXPECT_EQ(summary.at("refinement").at("passes").size(), 2U);
    EXPECT_TRUE(fs::exists(out / "trajectory.csv"));
    EXPECT_TRUE(fs::exists(out / "solution.csv"));
}

TEST(CliOptimiseAdaptive, OptionErrorsExitTwo) {
    Outcome r = optimise({"--problem", "double-integrator", "--adaptive-tol", "1e-4"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--adaptive-tol requires --adaptive"), std::string::npos) << r.err;
    r = optimise({"--problem", "double-integrator", "--adaptive", "--refine"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("excludes"), std::string::npos) << r.err;
    r = optimise(
        {"--problem", "double-integrator", "--adaptive", "--min-nodes", "8", "--max-nodes", "6"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--max-nodes 6 is below --min-nodes 8"), std::string::npos) << r.err;
    r = optimise({"--problem", "double-integrator", "--adaptive", "--adaptive-tol", "0"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--adaptive-tol"), std::string::npos) << r.err;
}

}  // namespace
