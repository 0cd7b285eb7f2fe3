/// `manta vlm-unsteady`: the unsteady vortex lattice along a motion file (`manta vlm-oscillation`
/// is in cmd_oscillation.cpp).

#include <fmt/format.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aero/motion.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/vlm/unsteady.hpp"

namespace manta::cli {

namespace {

struct UnsteadyArgs {
    std::string aircraft, motion, out;
    std::optional<double> dt, speed, mach;
    double wake_length = 20.0;
    bool impulsive = false;
    bool free_wake = false;
    int n_chord = vlm::LatticeDensity{}.n_chord;
    double strip_width = vlm::LatticeDensity{}.strip_width;
    bool json = false;
};

std::string history_csv(const vlm::UnsteadyHistory& h) {
    std::string s = "t,CL,CD,CY,Cl,Cm,Cn,CX,CZ,alpha,beta,airspeed,CL_added_mass,wake_rows\n";
    for (const auto& st : h.steps) {
        s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", core::format_exact(st.t),
                         core::format_exact(st.CL), core::format_exact(st.CD),
                         core::format_exact(st.CY), core::format_exact(st.body.Cl),
                         core::format_exact(st.body.Cm), core::format_exact(st.body.Cn),
                         core::format_exact(st.body.CX), core::format_exact(st.body.CZ),
                         core::format_exact(st.alpha), core::format_exact(st.beta),
                         core::format_exact(st.airspeed), core::format_exact(st.CL_added_mass),
                         st.wake_rows);
    }
    return s;
}

/// A MANTA aircraft file states its control limits (`controls:`): the motion's modes elevator,
/// aileron and rudder must stay within them (an AVL geometry file states none).
void check_motion_limits(const aero::Motion& motion, const UnsteadyArgs& a) {
    std::string ext = std::filesystem::path(a.aircraft).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".avl") return;
    const std::vector<aero::ModeLimit> limits = aircraft::load_aircraft(a.aircraft).mode_limits();
    try {
        aero::check_mode_limits(motion, limits, a.motion);
    } catch (const InputError& e) {
        throw InputError(
            fmt::format("{}; limits from the 'controls' section of {}", e.what(), a.aircraft));
    }
}

void run_unsteady(const UnsteadyArgs& a) {
    using clock = std::chrono::steady_clock;
    vlm::LatticeDensity density;
    density.n_chord = a.n_chord;
    density.strip_width = a.strip_width;
    const aero::Motion motion = aero::read_motion(a.motion);
    check_motion_limits(motion, a);  // before the lattice is built
    const VlmInput in = load_vlm_input(a.aircraft, density);
    vlm::UnsteadyOptions o;
    if (a.dt) o.dt = *a.dt;
    o.speed = a.speed;
    if (a.mach)
        o.mach = a.mach;
    else if (motion.metadata.mach)
        o.mach = motion.metadata.mach;
    o.wake_length = a.wake_length;
    o.start = a.impulsive ? vlm::StartMode::impulsive : vlm::StartMode::steady;
    o.wake = a.free_wake ? vlm::WakeModel::free : vlm::WakeModel::prescribed;
    const std::filesystem::path out(a.out);
    const core::RunFolderLock lock(out, "vlm-unsteady");
    vlm::UnsteadySolver solver(in.model, vlm::build_lattice(in.model), o);
    const auto t0 = clock::now();
    auto last = t0;
    // A live status line on a terminal; a line every 10 s otherwise (logs).
    const bool tty = isatty(fileno(stderr)) != 0;
    const auto every = tty ? std::chrono::seconds(1) : std::chrono::seconds(10);
    const vlm::UnsteadyHistory h = solver.run(motion, [&](const vlm::UnsteadySolver& s) {
        const auto now = clock::now();
        if (now - last < every) return;
        last = now;
        const double done = static_cast<double>(s.current().index) / std::max(1, s.n_steps());
        const double spent = std::chrono::duration<double>(now - t0).count();
        std::fprintf(stderr, "%sstep %d/%d  t %.3f s  CL %.4f  %.0f%%  about %.0f s left%s",
                     tty ? "\r" : "", s.current().index, s.n_steps(), s.current().t, s.current().CL,
                     100 * done, done > 0 ? spent * (1 - done) / done : 0.0, tty ? "   " : "\n");
    });
    if (tty && last != t0) std::fprintf(stderr, "\n");
    const double wall = std::chrono::duration<double>(clock::now() - t0).count();
    core::write_file_atomic(out / "coefficients.csv", history_csv(h));
    vlm::write_vtu(out / "wake.vtu", solver.lattice(), solver.wake());
    nlohmann::json j;
    j["aircraft"] = a.aircraft;
    j["motion"] = a.motion;
    j["steps"] = static_cast<int>(h.steps.size()) - 1;
    j["dt"] = h.dt;
    j["speed"] = h.speed;
    j["mach"] = h.mach;
    j["max_wake_rows"] = h.max_wake_rows;
    j["vortices"] = solver.lattice().size();
    j["wall_time_s"] = wall;
    j["files"] = {(out / "coefficients.csv").string(), (out / "wake.vtu").string()};
    const auto& e = h.steps.back();
    j["final"] = {{"t", e.t},        {"CL", e.CL},      {"CD", e.CD},     {"CY", e.CY},
                  {"Cl", e.body.Cl}, {"Cm", e.body.Cm}, {"Cn", e.body.Cn}};
    core::write_file_atomic(out / "summary.json", j.dump(2) + "\n");
    if (a.json) {
        print_json(j);
        return;
    }
    fmt::print("{} steps of {:.5f} s ({} vortices, wake up to {} rows) in {:.1f} s\n",
               h.steps.size() - 1, h.dt, solver.lattice().size(), h.max_wake_rows, wall);
    fmt::print("wrote {}, {}, {}\n", (out / "coefficients.csv").string(),
               (out / "wake.vtu").string(), (out / "summary.json").string());
}

}  // namespace

void add_vlm_unsteady(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "vlm-unsteady",
        "Unsteady vortex lattice along a motion file (docs/formats.md#motion-file): writes\n"
        "coefficients.csv (history), wake.vtu (final wake) and summary.json into --out.");
    auto a = std::make_shared<UnsteadyArgs>();
    cmd->add_option("--aircraft", a->aircraft, "Aircraft file: MANTA YAML or AVL geometry (.avl)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--motion", a->motion, "Motion file (CSV)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--out", a->out, "Output folder")->required()->check(output_path());
    cmd->add_option("--dt", a->dt, "Time step [s] (default: one chordwise panel per step)")
        ->check(real_positive(range::max_time_step, "s"));
    cmd->add_option("--speed", a->speed, "Entry free-stream speed v0 [m/s] (default: the motion's)")
        ->check(real_positive(range::max_speed, "m/s"));
    cmd->add_option("--mach", a->mach, "Mach number (default: the motion's, else 0)")
        ->check(real_in(0.0, 0.95));
    cmd->add_option("--wake-length", a->wake_length, "Wake kept [reference chords] (default 20)")
        ->check(real_positive(1000.0, "chords"));
    cmd->add_flag("--impulsive", a->impulsive,
                  "Impulsive start (default: from the steady solution)");
    cmd->add_flag("--free-wake", a->free_wake, "Force-free wake (default: convected with v0)");
    cmd->add_option("--n-chord", a->n_chord, "Chordwise vortices per strip (MANTA files)")
        ->check(integer_in(1, 100));
    cmd->add_option("--strip-width", a->strip_width, "Strip width / span (MANTA files)")
        ->check(real_in(1e-4, 0.5));
    cmd->add_flag("--json", a->json, "Print the summary as one JSON object");
    cmd->callback([a, &action] {
        action = [a]() -> int {
            run_unsteady(*a);
            return 0;
        };
    });
}

}  // namespace manta::cli
