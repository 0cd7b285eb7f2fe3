/// @file mpi_test_unsteady_processes.cpp
/// `manta cfd --motion` (CfdCase with a motion) on 1 and on 2 MPI processes, run by ctest under
/// `mpirun -np 2` (tests/euler/CMakeLists.txt): the meshmotion tests' flat-plate flap box, 6 x 4
/// x 8 cells (315 nodes; the flap a wall, the rest of the plane z = 0 a sliding symmetry plane),
/// 8 steps of 5 inner iterations (1 to 3.3 orders of inner drop) along
/// - a rigid pitching motion,
/// - the same with the flap deflecting (the control surface's mode),
/// - the same in the deforming mesh motion.
/// Rank 0 runs the case alone (a SerialCommunicator), then both processes run it together, and
/// rank 0 compares the two coefficients.csv files.
/// With `solver.preconditioner_blocks: 2` the single process preconditions with the two parts
/// the two processes own (docs/parallel.md, "The same history on 1 and N processes"): the same
/// inner iterations and drops, the coefficients the same to 1e-9 of their largest value
/// (measured 5e-12 to 4e-11: the residuals' sums run in another order at the parts' border).
/// With the
/// default (one block per process) the block-Jacobi preconditioner of two processes is another
/// preconditioner than one process's: the histories differ by the inner tolerance, 1e-4 to 1e-2
/// of the coefficients here; no other difference remains once the inner iterations converge
/// (docs/parallel.md). Started without an MPI launcher, the comparisons are skipped.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "flap_meshes.hpp"
#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/case.hpp"
#include "manta/parallel/mpi.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
namespace fs = std::filesystem;
constexpr double deg = 3.14159265358979323846 / 180.0;

const parallel::Communicator* world = nullptr;

/// theta = 1 deg + 2 deg sin(50 t), elevator = flap sin(80 t), t = 0 ... 0.04 s in 8 steps of
/// 0.005 s, v0 170 m/s, Mach 0.5 (test_unsteady_source_deforming.cpp's motion).
aero::Motion plate_motion(double flap) {
    aero::Motion m;
    for (int i = 0; i <= 8; ++i) m.t.push_back(0.005 * i);
    for (auto& p : m.position) p.assign(m.t.size(), 0.0);
    for (auto& a : m.angles) a.assign(m.t.size(), 0.0);
    std::vector<double> e(m.t.size());
    for (std::size_t i = 0; i < m.t.size(); ++i) {
        m.angles[1][i] = 1 * deg + 2 * deg * std::sin(50.0 * m.t[i]);
        e[i] = flap * std::sin(80.0 * m.t[i]);
    }
    m.add_mode("elevator", e);
    m.add_mode("aileron", std::vector<double>(m.t.size(), 0.0));
    m.add_mode("rudder", std::vector<double>(m.t.size(), 0.0));
    m.metadata.v0 = 170.0;
    m.metadata.mach = 0.5;
    return m;
}

const fs::path& folder() {
    static const fs::path dir = fs::temp_directory_path() / "manta_euler_mpi_unsteady_processes";
    return dir;
}

/// The run's coefficients.csv as numbers, one row per line after the header.
std::vector<std::vector<double>> read_csv(const fs::path& file) {
    std::ifstream in(file);
    std::vector<std::vector<double>> rows;
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        std::vector<double> v;
        std::stringstream ls(line);
        for (std::string cell; std::getline(ls, cell, ',');) v.push_back(std::stod(cell));
        rows.push_back(v);
    }
    return rows;
}

/// Largest difference of a coefficient column between the runs, over its largest magnitude.
struct Comparison {
    double CL = 0, CD = 0, Cm = 0;
    bool same_iterations = true;
    bool same_drops = true;  ///< inner residual drops within 1e-6 orders
    std::size_t rows = 0;
};

Comparison compare(const fs::path& a, const fs::path& b) {
    const auto x = read_csv(a), y = read_csv(b);
    Comparison c;
    c.rows = std::min(x.size(), y.size());
    if (x.size() != y.size()) c.same_iterations = false;
    // Columns: t,CL,CD,CY,Cl,Cm,Cn,CX,CZ,alpha,beta,airspeed,inner_iterations,residual_drop.
    auto rel = [&](int k) {
        double d = 0.0, m = 0.0;
        for (std::size_t i = 0; i < c.rows; ++i) {
            d = std::max(d, std::abs(x[i][k] - y[i][k]));
            m = std::max(m, std::abs(x[i][k]));
        }
        return m > 0 ? d / m : d;
    };
    c.CL = rel(1);
    c.CD = rel(2);
    c.Cm = rel(5);
    for (std::size_t i = 0; i < c.rows; ++i) {
        c.same_iterations = c.same_iterations && x[i][12] == y[i][12];
        c.same_drops = c.same_drops && std::abs(x[i][13] - y[i][13]) < 1e-6;
    }
    return c;
}

/// The case's folder (written by rank 0; every process returns after it is there).
fs::path write_case(const std::string& name, double flap, const std::string& mesh_motion,
                    int blocks) {
    const parallel::Communicator& comm = *world;
    const fs::path dir = folder() / name;
    if (comm.rank() == 0) {
        fs::remove_all(dir);
        fs::create_directories(dir);
        test::write_su2(test::flap_plate(6, 4, 8), dir / "plate.su2");
        std::ofstream(dir / "case.yaml")
            << "markers: {flap: wall, wall: symmetry, farfield: farfield}\n"
               "reference: {area: 1, chord: 1, span: 1, moment_point: [1, 0.5, 0]}\n"
               "unsteady: {max_inner: 5, mesh_motion: "
            << mesh_motion
            << (mesh_motion == "deforming" ? ", rigid_radius: 0.1, fixed_radius: 0.2" : "")
            << "}\nsolver: {preconditioner_blocks: " << blocks
            << "}\noutput: {checkpoint_interval_s: 0, volume: false, surface: false}\n"
               "control_surfaces:\n  - {mode: elevator, marker: flap, hinge: [[1, 0.25, 0], [1, "
               "0.75, 0]]}\n";
        aero::write_motion(dir / "m.csv", plate_motion(flap));
    }
    comm.barrier();
    return dir;
}

/// Writes the case, runs it on rank 0 alone and on both processes, and compares (rank 0).
Comparison one_and_two(const std::string& name, double flap, const std::string& mesh_motion,
                       int blocks) {
    const parallel::Communicator& comm = *world;
    const fs::path dir = write_case(name, flap, mesh_motion, blocks);
    euler::CaseInputs in;
    in.mesh = dir / "plate.su2";
    in.config = dir / "case.yaml";
    in.motion = dir / "m.csv";
    if (comm.rank() == 0) {
        const parallel::SerialCommunicator serial;
        in.out = dir / "p1";
        euler::CfdCase one(in, serial);
        (void)one.run();
    }
    comm.barrier();
    in.out = dir / "p2";
    {
        euler::CfdCase two(in, comm);
        (void)two.run();
    }
    comm.barrier();
    Comparison c;
    if (comm.rank() == 0)
        c = compare(dir / "p1" / "coefficients.csv", dir / "p2" / "coefficients.csv");
    if (comm.rank() == 0)
        std::printf(
            "%s, preconditioner_blocks %d, %d processes: max |d| / max |.|: CL %.1e, CD %.1e, "
            "Cm %.1e; inner iterations %s\n",
            name.c_str(), blocks, comm.size(), c.CL, c.CD, c.Cm,
            c.same_iterations ? "the same" : "differ");
    return c;
}

void expect_same_history(const Comparison& c) {
    if (world->rank() != 0) return;
    EXPECT_EQ(c.rows, 9u);
    EXPECT_TRUE(c.same_iterations);
    EXPECT_TRUE(c.same_drops);
    EXPECT_LT(c.CL, 1e-9);
    EXPECT_LT(c.CD, 1e-9);
    EXPECT_LT(c.Cm, 1e-9);
}

class UnsteadyProcesses : public ::testing::Test {
protected:
    void SetUp() override {
        if (world->size() != 2) GTEST_SKIP() << "needs mpirun -np 2";
    }
};

TEST_F(UnsteadyProcesses, RigidPitchingTheSameHistory) {
    expect_same_history(one_and_two("rigid", 0.0, "rigid", 2));
}

TEST_F(UnsteadyProcesses, RigidPitchingWithTheFlapDeflectingTheSameHistory) {
    expect_same_history(one_and_two("flap", 3 * deg, "rigid", 2));
}

TEST_F(UnsteadyProcesses, DeformingWithTheFlapDeflectingTheSameHistory) {
    expect_same_history(one_and_two("deforming", 3 * deg, "deforming", 2));
}

TEST_F(UnsteadyProcesses, OneBlockPerProcessDiffersByTheInnerTolerance) {
    // The default: each process preconditions its own nodes; 5 inner iterations leave the
    // difference of the two preconditioners' iterates.
    const Comparison c = one_and_two("default", 3 * deg, "rigid", 0);
    if (world->rank() != 0) return;
    EXPECT_GT(std::max({c.CL, c.CD, c.Cm}), 1e-5);
    EXPECT_LT(std::max({c.CL, c.CD, c.Cm}), 1e-1);
}

TEST_F(UnsteadyProcesses, BlocksForAnotherProcessCountAreRefused) {
    const fs::path dir = write_case("refused", 0.0, "rigid", 3);
    euler::CaseInputs in;
    in.mesh = dir / "plate.su2";
    in.config = dir / "case.yaml";
    in.motion = dir / "m.csv";
    in.out = dir / "p2";
    std::string what;
    try {
        euler::CfdCase c(in, *world);
        (void)c.run();
    } catch (const InputError& e) {
        what = e.what();
    }
    EXPECT_NE(what.find("solver.preconditioner_blocks = 3 on 2 processes; expected 1 or 3 "
                        "processes"),
              std::string::npos)
        << what;
}

}  // namespace

/// MPI is started before the tests and stopped after them; the exit status is the worst of all
/// processes, so a failure on any rank fails the ctest test.
int main(int argc, char** argv) {
    const manta::parallel::MpiEnvironment env;
    world = &env.communicator();
    ::testing::InitGoogleTest(&argc, argv);
    const int rc = RUN_ALL_TESTS();
    return static_cast<int>(env.communicator().max(static_cast<double>(rc)));
}
