/// @file test_cfd_deflection.cpp
/// Steady control deflections of `manta cfd` (the case driver, case.hpp: `CaseInputs::elevator`,
/// `aileron`, `rudder`; deflection.hpp) on the coarse half wing with a flap of the meshmotion
/// tests, `test::flap_wing(2)` (the aft 25 % of the chord between y = 1 and 2 m, the marker
/// `flap`, hinge along +y so that a positive deflection is trailing edge down; symmetry plane
/// y = 0 within the flap's cut-off, so the deformation slides on it), written as an SU2 file:
/// - the deflected run gives the Euler source's evaluate() for the same deflection (the same
///   deformation code; coefficients to 1e-10, the same iterations);
/// - explicit zero deflections are the undeflected run bit for bit (restart.bin, surface.csv);
/// - 5 deg of flap raise CL and lower Cm (trailing edge down, aft of the moment point), and
///   surface.csv shows the flap's trailing edge lowered by about 0.25 m sin 5 deg;
/// - a restart file of another deflection is refused (one line naming both), a warm start from
///   the undeflected solution (--initial) is taken and converges to the cold run's lift;
/// - one-line errors naming the option and value for a mode no surface has (listing the modes
///   there are), a value that is not finite, a deflection that folds the mesh (the dual volume
///   the Euler source reports) and a deflection with --motion.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "flap_meshes.hpp"
#include "manta/core/error.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/source.hpp"
#include "test_meshes.hpp"

namespace {

using namespace manta;
namespace fs = std::filesystem;
constexpr double deg = M_PI / 180.0;

constexpr const char* config_text =
    "markers: {wing: wall, flap: wall, symmetry: symmetry, farfield: farfield}\n"
    "reference: {area: 3, chord: 1, span: 3, moment_point: [0.25, 0, 0]}\n"
    "numerics: {order: 1}\n"
    "solver: {residual_drop: 4}\n"
    "output: {checkpoint_interval_s: 0, volume: false}\n"
    "control_surfaces:\n"
    "  - {mode: elevator, marker: flap, hinge: [[0.75, 1, 0], [0.75, 2, 0]]}\n";

/// The folder with flap.su2 and cfd.yaml (made once per process, named by the process id: CTest
/// runs the cases of this file as processes at the same time; removed when the process ends).
struct Scratch {
    fs::path dir =
        fs::temp_directory_path() / ("manta-euler-cfd-deflection-" + std::to_string(::getpid()));
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};
const fs::path& folder() {
    static const Scratch scratch;
    static const fs::path dir = [] {
        const fs::path d = scratch.dir;
        fs::remove_all(d);
        fs::create_directories(d);
        const mesh::Mesh m = test::flap_wing(2.0);
        std::printf("flap_wing(2): %d nodes\n", static_cast<int>(m.n_nodes()));
        test::write_su2(m, d / "flap.su2");
        std::ofstream(d / "cfd.yaml") << config_text;
        return d;
    }();
    return dir;
}

euler::CaseInputs inputs(const std::string& run, std::optional<double> elevator_deg = {}) {
    euler::CaseInputs in;
    in.mesh = folder() / "flap.su2";
    in.config = folder() / "cfd.yaml";
    in.out = folder() / run;
    in.mach = 0.3;
    in.alpha = 2.0 * deg;
    if (elevator_deg) in.elevator = *elevator_deg * deg;
    return in;
}

struct CaseRun {
    euler::SolveOutcome outcome;
    nlohmann::json summary;
};
CaseRun run_case(const euler::CaseInputs& in) {
    parallel::SerialCommunicator comm;
    euler::CfdCase c(in, comm);
    euler::CaseResult r = c.run();
    return {r.outcome, r.summary};
}

/// The undeflected and the 5 deg runs (solved once).
const CaseRun& plain() {
    static const CaseRun r = run_case(inputs("plain"));
    return r;
}
const CaseRun& deflected() {
    static const CaseRun r = run_case(inputs("deflected", 5.0));
    return r;
}

std::string file_text(const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The nodes of `marker` in a surface.csv (columns node,marker,x,y,z,...): node -> (x, y, z).
std::map<long, Eigen::Vector3d> marker_nodes(const fs::path& csv, const std::string& marker) {
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    std::map<long, Eigen::Vector3d> nodes;
    while (std::getline(in, line)) {
        std::stringstream s(line);
        std::string node, name, x, y, z;
        std::getline(s, node, ',');
        std::getline(s, name, ',');
        std::getline(s, x, ',');
        std::getline(s, y, ',');
        std::getline(s, z, ',');
        if (name == marker)
            nodes[std::stol(node)] = Eigen::Vector3d(std::stod(x), std::stod(y), std::stod(z));
    }
    return nodes;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(CfdDeflection, TheDeflectedRunIsTheEulerSourcesEvaluation) {
    const CaseRun& d = deflected();
    ASSERT_TRUE(d.outcome.converged) << d.outcome.reason;
    const auto source =
        euler::EulerSource::from_files(folder() / "flap.su2", folder() / "cfd.yaml");
    aero::AeroQuery<double> q;
    q.mach = 0.3;
    q.alpha = 2.0 * deg;
    q.elevator = 5.0 * deg;
    const aero::SourceResult r = source->evaluate(q, {});
    const euler::ForceCoefficients& f = d.outcome.forces;
    std::printf("elevator 5 deg: cfd CL %.12f Cm %.12f, source CL %.12f Cm %.12f, %d iterations\n",
                f.CL, f.Cm(), r.wind.CL, r.body.Cm, d.outcome.iterations);
    EXPECT_NEAR(r.wind.CL, f.CL, 1e-10);
    EXPECT_NEAR(r.wind.CD, f.CD, 1e-10);
    EXPECT_NEAR(r.wind.CY, f.CY, 1e-10);
    EXPECT_NEAR(r.body.Cm, f.Cm(), 1e-10);
    EXPECT_NEAR(r.body.Cl, f.Cl(), 1e-10);
    EXPECT_NEAR(r.body.Cn, f.Cn(), 1e-10);
    EXPECT_EQ(source->stats().iterations, d.outcome.iterations);

    // summary.json names the deflections and each surface's own.
    EXPECT_NEAR(d.summary["deflections_deg"]["elevator"].get<double>(), 5.0, 1e-12);
    EXPECT_EQ(d.summary["deflections_deg"]["rudder"].get<double>(), 0.0);
    ASSERT_EQ(d.summary["control_surfaces"].size(), 1u);
    EXPECT_EQ(d.summary["control_surfaces"][0]["marker"], "flap");
    EXPECT_NEAR(d.summary["control_surfaces"][0]["deflection_deg"].get<double>(), 5.0, 1e-12);
    const nlohmann::json on_disk =
        nlohmann::json::parse(file_text(folder() / "deflected" / "summary.json"));
    EXPECT_EQ(on_disk["deflections_deg"], d.summary["deflections_deg"]);
}

TEST(CfdDeflection, ZeroDeflectionIsTheUndeflectedRunBitForBit) {
    const CaseRun& p = plain();
    ASSERT_TRUE(p.outcome.converged) << p.outcome.reason;
    euler::CaseInputs in = inputs("zero", 0.0);
    in.aileron = 0.0;
    in.rudder = 0.0;
    const CaseRun z = run_case(in);
    EXPECT_EQ(z.outcome.forces.CL, p.outcome.forces.CL);
    EXPECT_EQ(z.outcome.forces.CMy, p.outcome.forces.CMy);
    EXPECT_EQ(z.outcome.iterations, p.outcome.iterations);
    EXPECT_EQ(file_text(folder() / "zero" / "restart.bin"),
              file_text(folder() / "plain" / "restart.bin"));
    EXPECT_EQ(file_text(folder() / "zero" / "surface.csv"),
              file_text(folder() / "plain" / "surface.csv"));
    EXPECT_EQ(z.summary["deflections_deg"]["elevator"].get<double>(), 0.0);
    EXPECT_FALSE(z.summary.contains("control_surfaces"));

    // Trailing edge down: more lift, nose down; the flap's trailing edge lower by about
    // 0.25 m sin 5 deg = 0.0218 m in surface.csv.
    const CaseRun& d = deflected();
    const double dCL = d.outcome.forces.CL - p.outcome.forces.CL;
    const double dCm = d.outcome.forces.Cm() - p.outcome.forces.Cm();
    // The trailing-edge nodes away from the side edges' blend bands (0.125 m wide there).
    const auto before = marker_nodes(folder() / "plain" / "surface.csv", "flap");
    const auto after = marker_nodes(folder() / "deflected" / "surface.csv", "flap");
    double drop = 0.0;
    int n_te = 0;
    for (const auto& [node, x] : before)
        if (x.x() > 0.999 && x.y() > 1.3 && x.y() < 1.7) {
            drop += x.z() - after.at(node).z();
            ++n_te;
        }
    ASSERT_GT(n_te, 0);
    drop /= n_te;
    std::printf("5 deg of flap: dCL %.5f, dCm %.5f, trailing edge %.5f m lower (%d nodes)\n", dCL,
                dCm, drop, n_te);
    EXPECT_GT(dCL, 0.0);
    EXPECT_LT(dCm, 0.0);
    EXPECT_NEAR(drop, 0.25 * std::sin(5.0 * deg), 1e-6);
}

TEST(CfdDeflection, RestartsOfAnotherDeflectionAreRefusedWarmStartsTaken) {
    const CaseRun& d = deflected();
    const CaseRun& p = plain();
    ASSERT_TRUE(d.outcome.converged);
    // The same deflection resumes from the folder's restart file (converged: no iteration).
    parallel::SerialCommunicator comm;
    {
        euler::CfdCase again(inputs("deflected", 5.0), comm);
        EXPECT_EQ(again.resumed_from(), d.outcome.iterations);
    }
    // Another deflection, or none, in that folder: refused, naming both.
    std::string e = error_of([&] { euler::CfdCase(inputs("deflected", 3.0), comm); });
    EXPECT_NE(e.find("another control deflection"), std::string::npos) << e;
    EXPECT_NE(e.find("elevator 5 deg"), std::string::npos) << e;
    EXPECT_NE(e.find("elevator 3 deg"), std::string::npos) << e;
    EXPECT_NE(e.find("--restart"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    e = error_of([&] { euler::CfdCase(inputs("plain", 5.0), comm); });
    EXPECT_NE(e.find("no deflection"), std::string::npos) << e;
    // A warm start from the undeflected solution on the same mesh.
    euler::CaseInputs warm = inputs("warm", 5.0);
    warm.initial = folder() / "plain" / "restart.bin";
    const CaseRun w = run_case(warm);
    std::printf("warm start from 0 deg: %d iterations (cold %d), CL %.6f (cold %.6f)\n",
                w.outcome.iterations, d.outcome.iterations, w.outcome.forces.CL,
                d.outcome.forces.CL);
    ASSERT_TRUE(w.outcome.converged) << w.outcome.reason;
    EXPECT_LE(w.outcome.iterations, d.outcome.iterations);
    EXPECT_NEAR(w.outcome.forces.CL, d.outcome.forces.CL,
                0.02 * std::abs(d.outcome.forces.CL - p.outcome.forces.CL));
}

TEST(CfdDeflection, BadDeflectionsAreOneLineErrors) {
    parallel::SerialCommunicator comm;
    auto expect_one_line = [](const std::string& e, const std::string& what) {
        EXPECT_NE(e.find(what), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    };
    // A mode no surface has: names the option, the value, the configuration and its modes.
    euler::CaseInputs in = inputs("bad");
    in.rudder = 3.0 * deg;
    std::string e = error_of([&] { euler::CfdCase(in, comm); });
    expect_one_line(e, "--rudder-deg 3:");
    expect_one_line(e, "cfd.yaml has no control surface of mode 'rudder'");
    expect_one_line(e, "control surfaces: elevator)");
    // Not finite.
    in = inputs("bad");
    in.aileron = std::numeric_limits<double>::quiet_NaN();
    e = error_of([&] { euler::CfdCase(in, comm); });
    expect_one_line(e, "--aileron-deg nan");
    expect_one_line(e, "finite");
    // A fold: the volume held within 2 cm of the flap, which turns its trailing edge by 18 cm.
    {
        std::string text = config_text;
        text.replace(text.rfind('}'), 1, ", cutoff: 0.02}");
        std::ofstream(folder() / "tight.yaml") << text;
    }
    in = inputs("bad", 45.0);
    in.config = folder() / "tight.yaml";
    e = error_of([&] { euler::CfdCase(in, comm); });
    expect_one_line(e, "manta cfd: --elevator-deg 45 folds the mesh at node ");
    const auto volume = e.find("(dual volume");
    ASSERT_NE(volume, std::string::npos) << e;
    const auto source =
        euler::EulerSource::from_files(folder() / "flap.su2", folder() / "tight.yaml");
    aero::AeroQuery<double> q;
    q.mach = 0.3;
    q.elevator = 45.0 * deg;
    const std::string se = error_of([&] { (void)source->evaluate(q, {}); });
    const std::string v = e.substr(volume, e.find(')', volume) - volume);
    EXPECT_NE(se.find(v), std::string::npos) << se << "\n" << e;  // the same dual volume
    // With --motion the mode columns deflect: refused.
    std::ofstream(folder() / "still.csv")
        << "# v0: 100\n# mach: 0.3\nt,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,"
           "mode_aileron,mode_rudder\n0,0,0,0,0,0,0,0,0,0\n0.01,0,0,0,0,0,0,0,0,0\n";
    in = inputs("bad", 2.0);
    in.alpha.reset();
    in.motion = folder() / "still.csv";
    e = error_of([&] { euler::CfdCase(in, comm); });
    expect_one_line(e, "--elevator-deg 2 is not taken with --motion");
}

}  // namespace
