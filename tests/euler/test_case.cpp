/// @file test_case.cpp
/// The CFD case driver (case.hpp): on the bump channel written as an SU2 file, a run stopped at
/// its iteration limit and run again continues from its restart file to the uninterrupted run's
/// result bit for bit, with its history and outputs in the folder; a warm start from another
/// run's restart file converges in fewer iterations; no Mach number, a foreign restart file and
/// a locked folder are one-line errors; the table campaign's source built from the same files
/// (`EulerSource::from_files`) gives the driver's coefficients exactly; the mesh's companion
/// file (`X.mesh.yaml`, written by `manta mesh`) stands in for the configuration's markers,
/// reference values and control surfaces where the configuration is silent.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "manta/core/error.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/source.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
namespace fs = std::filesystem;

using test::write_su2;

/// A folder with the channel's mesh and configuration (walls lower and upper, area 0.1,
/// checkpoints only at the end).
struct Folder {
    fs::path dir;
    explicit Folder(const std::string& name) : dir(fs::temp_directory_path() / name) {
        fs::remove_all(dir);
        fs::create_directories(dir);
        write_su2(test::bump_channel(0, 0.1), dir / "channel.su2");
        std::ofstream(dir / "case.yaml")
            << "markers: {lower: wall, upper: wall}\nreference: {area: 0.1}\n"
               "output: {checkpoint_interval_s: 0}\n";
    }
    [[nodiscard]] euler::CaseInputs inputs(const std::string& run, double alpha_deg) const {
        euler::CaseInputs in;
        in.mesh = dir / "channel.su2";
        in.config = dir / "case.yaml";
        in.out = dir / run;
        in.mach = 0.5;
        in.alpha = alpha_deg * M_PI / 180.0;
        return in;
    }
};

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

int rows(const fs::path& csv) {
    std::ifstream in(csv);
    std::string line;
    int n = -1;  // the header
    while (std::getline(in, line)) ++n;
    return n;
}

TEST(CfdCase, AStoppedRunContinuesToTheUninterruptedResultBitForBit) {
    const Folder f("manta-euler-case");
    parallel::SerialCommunicator comm;
    euler::CaseResult whole;
    {
        euler::CfdCase c(f.inputs("whole", 1.0), comm);
        EXPECT_EQ(c.resumed_from(), -1);
        int calls = 0, last = -1;
        whole = c.run([&](const euler::CaseProgress& p) {
            ++calls;
            EXPECT_GT(p.iteration, last);
            last = p.iteration;
            EXPECT_EQ(p.target, 6.0);
            if (p.seconds_left) {
                EXPECT_GT(*p.seconds_left, 0.0);
            }
        });
        ASSERT_TRUE(whole.outcome.converged) << whole.outcome.reason;
        EXPECT_EQ(calls, whole.outcome.iterations + 1);  // iterations 0..n
    }
    for (const char* file :
         {"summary.json", "history.csv", "surface.csv", "surface.vtu", "flow.vtu", "restart.bin"})
        EXPECT_TRUE(fs::exists(f.dir / "whole" / file)) << file;
    EXPECT_EQ(rows(f.dir / "whole" / "history.csv"), whole.outcome.iterations + 1);
    EXPECT_EQ(whole.summary["iterations"].get<int>(), whole.outcome.iterations);
    EXPECT_EQ(whole.summary["coefficients"]["CL"].get<double>(), whole.outcome.forces.CL);
    EXPECT_EQ(whole.summary["processes"].get<int>(), 1);

    // Stopped after 12 iterations, then the same inputs without the limit.
    euler::CaseInputs in = f.inputs("parts", 1.0);
    in.max_iterations = 12;
    {
        euler::CfdCase c(in, comm);
        const euler::CaseResult r = c.run();
        EXPECT_FALSE(r.outcome.converged);
        EXPECT_EQ(r.outcome.iterations, 12);
    }
    in.max_iterations.reset();
    euler::CfdCase c(in, comm);
    EXPECT_EQ(c.resumed_from(), 12);
    const euler::CaseResult r = c.run();
    ASSERT_TRUE(r.outcome.converged) << r.outcome.reason;
    EXPECT_EQ(r.outcome.iterations, whole.outcome.iterations);
    EXPECT_EQ(r.outcome.forces.CL, whole.outcome.forces.CL);
    EXPECT_EQ(r.outcome.forces.CD, whole.outcome.forces.CD);
    EXPECT_EQ(r.summary["resumed_from"].get<int>(), 12);
    EXPECT_EQ(rows(f.dir / "parts" / "history.csv"), whole.outcome.iterations + 1);

    // The folder is locked while its case exists.
    const std::string locked = error_of([&] { euler::CfdCase again(in, comm); });
    EXPECT_NE(locked.find("in use"), std::string::npos) << locked;
}

TEST(CfdCase, WarmStartAndBadInput) {
    const Folder f("manta-euler-case-warm");
    parallel::SerialCommunicator comm;
    euler::SolveOutcome cold;
    {
        euler::CfdCase c(f.inputs("cold", 1.5), comm);
        cold = c.run().outcome;
        ASSERT_TRUE(cold.converged) << cold.reason;
    }
    {
        euler::CfdCase c(f.inputs("near", 1.0), comm);
        ASSERT_TRUE(c.run().outcome.converged);
    }
    euler::CaseInputs warm = f.inputs("warm", 1.5);
    warm.initial = f.dir / "near" / "restart.bin";
    {
        euler::CfdCase c(warm, comm);
        const euler::SolveOutcome w = c.run().outcome;
        ASSERT_TRUE(w.converged) << w.reason;
        std::printf("iterations: cold %d, warm from 1 deg %d\n", cold.iterations, w.iterations);
        EXPECT_LT(w.iterations, cold.iterations);
        EXPECT_NEAR(w.forces.CL, cold.forces.CL, 1e-4);
    }
    // No Mach number.
    euler::CaseInputs none = f.inputs("none", 0.0);
    none.mach.reset();
    const std::string mach = error_of([&] { euler::CfdCase c(none, comm); });
    EXPECT_NE(mach.find("--mach"), std::string::npos) << mach;
    // The cold run's folder at another angle of attack.
    const std::string foreign = error_of([&] { euler::CfdCase c(f.inputs("cold", 2.0), comm); });
    EXPECT_NE(foreign.find("another mesh or flow condition"), std::string::npos) << foreign;
    EXPECT_NE(foreign.find("--restart"), std::string::npos) << foreign;
    EXPECT_EQ(foreign.find('\n'), std::string::npos) << foreign;
    euler::CaseInputs over = f.inputs("cold", 2.0);
    over.restart = true;
    over.max_iterations = 2;
    EXPECT_EQ(error_of([&] { euler::CfdCase(over, comm).run(); }), "");
}

TEST(CfdCase, TheTableSourceFromTheSameFilesGivesTheDriversCoefficients) {
    const Folder f("manta-euler-case-source");
    parallel::SerialCommunicator comm;
    euler::CfdCase c(f.inputs("run", 1.0), comm);
    const euler::SolveOutcome oc = c.run().outcome;
    ASSERT_TRUE(oc.converged) << oc.reason;
    const auto source = euler::EulerSource::from_files(f.dir / "channel.su2", f.dir / "case.yaml");
    aero::AeroQuery<double> q;
    q.mach = 0.5;
    q.alpha = 1.0 * M_PI / 180.0;
    const aero::SourceResult r = source->evaluate(q, {});
    EXPECT_EQ(r.wind.CL, oc.forces.CL);
    EXPECT_EQ(r.wind.CD, oc.forces.CD);
    EXPECT_EQ(r.body.Cm, oc.forces.Cm());
    EXPECT_EQ(source->stats().iterations, oc.iterations);
}

/// A companion file for the channel: the walls and reference values of case.yaml, with a
/// moment point and chord of its own.
void write_channel_companion(const fs::path& file, double area) {
    std::ofstream(file) << "schema_version: 1\nmesh: channel.su2\nmodel: half\nlevel: coarse\n"
                           "markers: {lower: wall, upper: wall}\n"
                           "reference: {area: "
                        << area
                        << ", chord: 0.5, span: 2, moment_point: [0.25, 0, 0]}\n"
                           "control_surfaces: []\n";
}

TEST(CfdCase, TheMeshCompanionFileStandsInWhereTheConfigurationIsSilent) {
    const Folder f("manta-euler-case-companion");
    parallel::SerialCommunicator comm;
    // The reference run: everything from the configuration file.
    std::ofstream(f.dir / "full.yaml")
        << "markers: {lower: wall, upper: wall}\n"
           "reference: {area: 0.1, chord: 0.5, span: 2, moment_point: [0.25, 0, 0]}\n"
           "output: {checkpoint_interval_s: 0}\n";
    euler::CaseInputs in = f.inputs("full", 1.0);
    in.config = f.dir / "full.yaml";
    const euler::CaseResult full = euler::CfdCase(in, comm).run();
    ASSERT_TRUE(full.outcome.converged) << full.outcome.reason;
    EXPECT_FALSE(full.summary.contains("companion"));

    // No configuration at all: markers and reference values from the companion.
    write_channel_companion(f.dir / "channel.mesh.yaml", 0.1);
    in = f.inputs("companion", 1.0);
    in.config.clear();
    const euler::CaseResult comp = euler::CfdCase(in, comm).run();
    EXPECT_EQ(comp.outcome.forces.CL, full.outcome.forces.CL);
    EXPECT_EQ(comp.outcome.forces.CMy, full.outcome.forces.CMy);
    EXPECT_EQ(comp.summary.at("companion").get<std::string>(),
              (f.dir / "channel.mesh.yaml").string());
    EXPECT_EQ(comp.summary.at("reference").at("chord").get<double>(), 0.5);

    // The configuration wins: its reference section (area 0.1, chord 1, moment point 0) is
    // taken whole over the companion's.
    write_channel_companion(f.dir / "channel.mesh.yaml", 0.05);
    in = f.inputs("config-wins", 1.0);
    const euler::CaseResult wins = euler::CfdCase(in, comm).run();
    EXPECT_EQ(wins.summary.at("reference").at("area").get<double>(), 0.1);
    EXPECT_EQ(wins.summary.at("reference").at("chord").get<double>(), 1.0);

    // The table source reads the companion too.
    aero::AeroQuery<double> q;
    q.mach = 0.5;
    q.alpha = 1.0 * M_PI / 180.0;
    write_channel_companion(f.dir / "channel.mesh.yaml", 0.1);
    const auto source = euler::EulerSource::from_files(f.dir / "channel.su2", {});
    EXPECT_EQ(source->evaluate(q, {}).wind.CL, full.outcome.forces.CL);

    // A malformed companion is a one-line error naming it.
    std::ofstream(f.dir / "channel.mesh.yaml") << "schema_version: 1\nmesh: channel.su2\n"
                                                  "model: quarter\n";
    const std::string e = error_of([&] { euler::CfdCase(f.inputs("bad", 1.0), comm); });
    EXPECT_NE(e.find("channel.mesh.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("quarter"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

}  // namespace
