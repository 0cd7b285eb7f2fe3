/// @file replay_60s.cpp
/// Wall time of a 60-second manoeuvre replayed through the unsteady vortex lattice of the Ranger
/// 2000 (default lattice density, ~2 000 panels), the second speed target of issue 3 (under five
/// minutes on two cores). Not a Google benchmark (one run takes minutes): `make bench` does not
/// run it.
///
///   build/bench/vlm/vlm_replay_60s [--threads N] [--steps N] [--motion FILE]
///
/// The manoeuvre (written to FILE if given, docs/formats.md): 150 m/s at 3000 m (Mach 0.45) on a
/// straight path, pitching up and down (theta = 2 deg + 3 deg sin(2 pi t / 12 s)) while rolling
/// to +-30 deg (phi = 30 deg sin(2 pi t / 20 s)), with elevator, aileron and rudder histories
/// (2, 3 and 1 deg amplitudes, periods 12, 20 and 15 s) through the motion file's control modes;
/// sampled every 0.05 s. Time step c_ref / v0 (the air crosses one reference chord per step: 5 825
/// steps), wake 20 reference chords (20 rows), prescribed wake, span loading recorded. `--steps N`
/// stops after N steps (the time per step is printed either way).

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>

#include "manta/aero/motion.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/vlm/unsteady.hpp"

namespace {

namespace fs = std::filesystem;
using namespace manta;

aero::Motion manoeuvre() {
    aero::Motion m;
    const double deg = std::numbers::pi / 180.0;
    const double two_pi = 2.0 * std::numbers::pi;
    std::vector<double> de, da, dr;
    for (int i = 0; i <= 1200; ++i) {
        const double t = 0.05 * i;
        m.t.push_back(t);
        m.position[0].push_back(0.0);
        m.position[1].push_back(0.0);
        m.position[2].push_back(0.0);
        m.angles[0].push_back(30.0 * deg * std::sin(two_pi * t / 20.0));
        m.angles[1].push_back(2.0 * deg + 3.0 * deg * std::sin(two_pi * t / 12.0));
        m.angles[2].push_back(0.0);
        de.push_back(-2.0 * deg * std::sin(two_pi * t / 12.0));
        da.push_back(3.0 * deg * std::cos(two_pi * t / 20.0));
        dr.push_back(1.0 * deg * std::sin(two_pi * t / 15.0));
    }
    m.add_mode("elevator", de);
    m.add_mode("aileron", da);
    m.add_mode("rudder", dr);
    m.metadata.v0 = 150.0;
    m.metadata.mach = 0.45;
    m.metadata.altitude = 3000.0;
    m.metadata.comments.push_back("Ranger 2000 60-s replay benchmark (bench/vlm/replay_60s.cpp)");
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    int threads = 2;
    int max_steps = -1;
    std::string motion_file;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        if (k == "--threads") {
            threads = std::atoi(argv[i + 1]);
        } else if (k == "--steps") {
            max_steps = std::atoi(argv[i + 1]);
        } else if (k == "--motion") {
            motion_file = argv[i + 1];
        } else {
            std::fprintf(stderr, "unknown option %s\n", k.c_str());
            return 2;
        }
    }
    const auto def = aircraft::load_aircraft(fs::path(MANTA_SOURCE_DIR) / "examples" /
                                             "ranger2000" / "aircraft.yaml");
    const vlm::Reference ref{def.reference.area, def.reference.span, def.reference.chord,
                             def.moment_reference_geom};
    const vlm::Model model = vlm::from_geometry(def.geometry, ref, {}, def.name);
    const aero::Motion motion = manoeuvre();
    if (!motion_file.empty()) aero::write_motion(motion_file, motion);

    vlm::UnsteadyOptions o;
    o.dt = ref.chord / *motion.metadata.v0;
    o.wake_length = 20.0;
    o.threads = threads;
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    vlm::UnsteadySolver solver(model, vlm::build_lattice(model), o);
    solver.start(motion);
    const auto t1 = clock::now();
    int steps = 0;
    double cl_min = 1e9, cl_max = -1e9;
    while (!solver.finished() && (max_steps < 0 || steps < max_steps)) {
        const vlm::UnsteadyStep& s = solver.step();
        cl_min = std::min(cl_min, s.CL);
        cl_max = std::max(cl_max, s.CL);
        ++steps;
    }
    const auto t2 = clock::now();
    const double setup = std::chrono::duration<double>(t1 - t0).count();
    const double run = std::chrono::duration<double>(t2 - t1).count();
    std::printf(
        "Ranger 2000: %d panels, %d steps of %.5f s (of %d), %d wake rows, %d threads\n"
        "setup (lattice, influence matrix, steady start) %.2f s\n"
        "steps %.2f s wall (%.2f ms per step); whole replay %.1f s wall "
        "(estimated for all %d steps: %.1f s)\nCL range %.4f .. %.4f\n",
        solver.lattice().size(), steps, solver.dt(), solver.n_steps(), solver.max_wake_rows(),
        threads, setup, run, 1e3 * run / std::max(1, steps), setup + run, solver.n_steps(),
        setup + run / std::max(1, steps) * solver.n_steps(), cl_min, cl_max);
    return 0;
}
