// The solver around the validation problems: exact and limited-memory Hessians, costates,
// guesses (linear, time history, previous solution), interpolation, re-simulation, the failure
// report of infeasible problems, the progress callback and input checks.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "manta/core/error.hpp"
#include "manta/optimal/problems.hpp"

namespace {

using namespace manta::optimal;
namespace fs = std::filesystem;

TEST(Solver, BrachistochroneLimitedMemoryMatchesExactHessian) {
    const Brachistochrone p;
    const auto m = make_model(p);
    SolverOptions o;
    const Solution exact = solve(*m, Mesh::uniform(1, 20), p.guess(), o);
    o.hessian = HessianMode::limited_memory;
    const Solution lbfgs = solve(*m, Mesh::uniform(1, 20), p.guess(), o);
    ASSERT_TRUE(exact.converged()) << exact.status_text;
    ASSERT_TRUE(lbfgs.converged()) << lbfgs.status_text;
    EXPECT_NEAR(lbfgs.final_time, exact.final_time, 1e-7);
    EXPECT_GT(exact.n_hessian_nonzeros, 0);
    EXPECT_EQ(lbfgs.n_hessian_nonzeros, 0);
}

TEST(Solver, CostatesGiveConstantHamiltonian) {
    // min t_f with autonomous dynamics: H = lambda . f = -1 along the optimum, and lambda_x is
    // constant since x does not appear in f (free-final-time transversality condition; Bryson &
    // Ho, Applied Optimal Control, 1975)
    const Brachistochrone p;
    const auto m = make_model(p);
    const Solution s = solve(*m, Mesh::uniform(1, 30), p.guess());
    ASSERT_TRUE(s.converged());
    const SegmentSolution& g = s.segments[0];
    for (Eigen::Index i = 0; i < g.time.size(); ++i) {
        std::vector<double> x(3), u(1), xd(3), none;
        for (int r = 0; r < 3; ++r) x[r] = g.states(i, r);
        u[0] = g.controls(i, 0);
        m->dynamics(x, u, none, g.time(i), xd);
        const double H =
            g.costates(i, 0) * xd[0] + g.costates(i, 1) * xd[1] + g.costates(i, 2) * xd[2];
        EXPECT_NEAR(H, -1.0, 1e-7) << "node " << i;
        EXPECT_NEAR(g.costates(i, 0), g.costates(0, 0), 1e-6) << "node " << i;
    }
    // interpolated costate between nodes
    const double tm = 0.37 * s.final_time;
    EXPECT_NEAR(s.costate(tm)(0), g.costates(0, 0), 1e-6);
}

TEST(Solver, InterpolationFollowsTheCycloid) {
    const Brachistochrone p;
    const auto m = make_model(p);
    const Solution s = solve(*m, Mesh::uniform(1, 30), p.guess());
    ASSERT_TRUE(s.converged());
    const CycloidSolution c = brachistochrone_cycloid(p.x_final, p.y_final, p.gravity);
    const double w = std::sqrt(p.gravity / c.radius);  // phi = w t on the cycloid
    for (const double f : {0.1, 0.333, 0.5, 0.77, 0.95}) {
        const double t = f * s.final_time;
        const double phi = w * t;
        const Eigen::VectorXd x = s.state(t);
        EXPECT_NEAR(x(0), c.radius * (phi - std::sin(phi)), 1e-7) << t;
        EXPECT_NEAR(x(1), c.radius * (1.0 - std::cos(phi)), 1e-7) << t;
        EXPECT_NEAR(s.control(t)(0), 0.5 * phi, 1e-6) << t;
    }
    EXPECT_TRUE(s.resimulation.done);
    EXPECT_LT(s.resimulation.max_scaled_error, 1e-7);
}

TEST(Solver, GuessFromPreviousSolutionAndFromHistory) {
    const Brachistochrone p;
    const auto m = make_model(p);
    const Solution coarse = solve(*m, Mesh::uniform(1, 10), p.guess());
    ASSERT_TRUE(coarse.converged());
    const Solution fine = solve(*m, Mesh::uniform(2, 16), Guess::from_solution(coarse));
    ASSERT_TRUE(fine.converged());
    EXPECT_LE(fine.iterations, 8);
    EXPECT_NEAR(fine.final_time, brachistochrone_cycloid(10.0, 5.0, p.gravity).final_time, 1e-8);

    // a sampled history (e.g. from a simulation), linearly interpolated onto the nodes
    std::vector<double> t;
    Eigen::MatrixXd x(11, 3), u(11, 1);
    for (int i = 0; i <= 10; ++i) {
        const double ti = 0.2 * i;
        t.push_back(ti);
        const Eigen::VectorXd xi = coarse.state(std::min(ti, coarse.final_time));
        x.row(i) = xi.transpose();
        u(i, 0) = 0.5;
    }
    const Solution h = solve(*m, Mesh::uniform(1, 20), Guess::from_history(t, x, u));
    ASSERT_TRUE(h.converged()) << h.status_text;
    EXPECT_NEAR(h.final_time, fine.final_time, 1e-8);
}

TEST(Solver, InfeasibleProblemReportsTheViolatedConstraintByName) {
    // v(0) = 1 is fixed but the path constraint speed_limit demands |v| <= 0.1 everywhere
    DoubleIntegrator p;
    p.max_speed = 0.1;
    const auto m = make_model(p);
    SolverOptions o;
    const fs::path csv = fs::temp_directory_path() / "manta_optimal_infeasible_best.csv";
    fs::remove(csv);
    o.failure_csv = csv;
    const Solution s = solve(*m, Mesh::uniform(1, 15), p.guess(), o);
    EXPECT_FALSE(s.converged());
    EXPECT_EQ(s.status, SolveStatus::infeasible) << s.status_text;
    ASSERT_FALSE(s.violations.empty());
    EXPECT_EQ(s.violations.front().name, "speed_limit");
    EXPECT_EQ(s.violations.front().node, 0);
    EXPECT_NEAR(s.violations.front().value, 1.0, 1e-6);
    EXPECT_GT(s.max_violation, 0.5);
    const std::string r = failure_report(s, csv);
    EXPECT_NE(r.find("Infeasible_Problem_Detected"), std::string::npos) << r;
    EXPECT_NE(r.find("speed_limit"), std::string::npos) << r;
    EXPECT_NE(r.find("segment 0 node 0"), std::string::npos) << r;
    ASSERT_TRUE(fs::exists(csv));
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, "t,segment,node,x,v,u,lambda_x,lambda_v,speed_limit");
    fs::remove(csv);
}

TEST(Solver, ProgressCallbackSeesEveryIterationAndCanStop) {
    const MinTimeToClimb p;
    const auto m = make_model(p);
    SolverOptions o;
    int calls = 0;
    o.progress = [&](const IterationInfo& it) {
        EXPECT_EQ(it.iteration, calls);
        ++calls;
        return it.iteration < 3;
    };
    const Solution s = solve(*m, Mesh::uniform(1, 20), p.guess(), o);
    EXPECT_EQ(s.status, SolveStatus::stopped);
    EXPECT_EQ(calls, 4);
}

TEST(Solver, RejectsBadMeshAndGuess) {
    Mesh m = Mesh::uniform(2, 5);
    m.breaks = {0.0, 1.2, 1.0};
    EXPECT_THROW(m.validate(), manta::InputError);
    EXPECT_THROW((void)Mesh::uniform(0, 5), manta::InputError);
    EXPECT_THROW((void)Mesh::uniform(1, 1), manta::InputError);
    const Brachistochrone p;
    const auto model = make_model(p);
    const Guess bad = Guess::linear(0.0, 1.0, Eigen::Vector2d::Zero(), Eigen::Vector2d::Ones(),
                                    Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
    EXPECT_THROW((void)solve(*model, Mesh::uniform(1, 5), bad), manta::InputError);
    EXPECT_THROW((void)Guess::from_history({0.0, 0.0}, Eigen::MatrixXd::Zero(2, 3),
                                           Eigen::MatrixXd::Zero(2, 1)),
                 manta::InputError);
}

struct DuplicateNames {
    ProblemInfo info() const {
        ProblemInfo p;
        p.name = "dup";
        p.states = {{"x", -1, 1, 0}, {"x", -1, 1, 0}};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T>, std::span<const T>, std::span<const T>, const T&,
                  std::span<T> xd) const {
        xd[0] = 0.0;
        xd[1] = 0.0;
    }
};

TEST(Solver, ProblemInfoIsValidated) {
    try {
        (void)make_model(DuplicateNames{});
        FAIL() << "no error";
    } catch (const manta::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("'x' used twice"), std::string::npos) << e.what();
    }
}

TEST(Solver, CsvHasOneRowPerNode) {
    const DoubleIntegrator p;
    const auto m = make_model(p);
    const Solution s = solve(*m, Mesh::uniform(2, 8), p.guess());
    const fs::path f = fs::temp_directory_path() / "manta_optimal_di.csv";
    write_csv(s, f);
    std::ifstream in(f);
    int lines = 0;
    for (std::string l; std::getline(in, l);) ++lines;
    EXPECT_EQ(lines, 1 + s.n_nodes());
    EXPECT_EQ(s.n_nodes(), 16);
    fs::remove(f);
}

/// A fixed initial state outside the state's own bounds is rejected up front (naming the state
/// and both intervals), not left to fail inside IPOPT.
struct InitialOutsideBounds {
    ProblemInfo info() const {
        ProblemInfo p;
        p.name = "outside";
        p.states = {{"x", 0.0, 1.0, 0}};
        p.controls = {{"u", -1.0, 1.0, 0}};
        p.initial_states = {fixed(2.0)};
        return p;
    }
    template <class T>
    void dynamics(std::span<const T>, std::span<const T> u, std::span<const T>, const T&,
                  std::span<T> xd) const {
        xd[0] = u[0];
    }
};

TEST(Solver, AnInitialStateOutsideTheStateBoundsIsRejected) {
    try {
        (void)make_model(InitialOutsideBounds{});
        FAIL() << "no error";
    } catch (const manta::InputError& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("initial x in [2, 2] lies outside the state's bounds [0, 1]"),
                  std::string::npos)
            << w;
    }
}

TEST(Solver, AnUnresolvedOptimumIsReportedAsSuch) {
    // The minimum time to climb (Bryson, Desai & Hoffman 1969; optimum 321.11 s, see
    // test_problems_validation.cpp) on one segment of 10 points from the crude linear guess:
    // IPOPT converges to a badly resolved point whose controls, integrated a posteriori, depart
    // from the collocated states by about 0.9 (scaled); 40 points resolve it (resimulation
    // below 1e-2 there).
    const MinTimeToClimb p;
    const auto m = make_model(p);
    const Solution coarse = solve(*m, Mesh::uniform(1, 10), p.guess());
    ASSERT_TRUE(coarse.converged()) << coarse.status_text;
    ASSERT_TRUE(coarse.resimulation.done);
    EXPECT_GT(coarse.resimulation.max_scaled_error, 0.1);
    EXPECT_EQ(coarse.status, SolveStatus::solved_unresolved);
    EXPECT_FALSE(coarse.resolved());
    EXPECT_EQ(to_string(coarse.status), "solved_unresolved");
    EXPECT_NE(coarse.status_text.find("refine the mesh"), std::string::npos) << coarse.status_text;
    // Without a limit the same solve is reported solved.
    SolverOptions o;
    o.resolution_limit = 0.0;
    EXPECT_EQ(solve(*m, Mesh::uniform(1, 10), p.guess(), o).status, SolveStatus::solved);
    // Resolved on 40 points.
    const Solution fine = solve(*m, Mesh::uniform(1, 40), p.guess());
    EXPECT_TRUE(fine.resolved()) << fine.status_text;
}

}  // namespace
