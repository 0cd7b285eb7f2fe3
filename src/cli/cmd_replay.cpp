/// @file cmd_replay.cpp
/// `manta replay`: a trajectory replayed through a time-accurate aero source and compared with
/// the tables (docs/replay.md): motion.csv, comparison.csv, summary.json in --out, checkpoints
/// in --out/checkpoint while it runs.

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aero/database.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/source.hpp"
#include "manta/euler/surface_snapshot.hpp"
#include "manta/mesh/companion.hpp"
#include "manta/replay/input_checks.hpp"
#include "manta/replay/motion_builder.hpp"
#include "manta/replay/replay.hpp"
#include "manta/replay/trajectory.hpp"
#include "manta/vlm/source.hpp"

namespace manta::cli {

namespace {

namespace fs = std::filesystem;

/// Lattice of a replay: coarser than the steady default, chosen for speed (docs/replay.md).
constexpr int replay_n_chord = 8;
constexpr double replay_strip_width = 0.02;

struct ReplayArgs {
    std::string trajectory, source = "vlm", aircraft, out, tables;
    std::string mesh, cfd_config, cfd_start = "steady";  // --source euler
    double dt = 0.0;
    double until = 0.0;           // 0: the whole trajectory
    double snapshot_every = 1.0;  // --source euler: surface snapshots [s of flight]; 0: none
    bool snapshot_given = false;
    int n_chord = replay_n_chord;
    double strip_width = replay_strip_width;
    double wake_length = 10.0;
    int threads = 0;
    std::vector<std::string> tolerances;  // NAME=VALUE
    int checkpoint_steps = 0;
    double checkpoint_seconds = 30.0;
    bool restart = false, keep_checkpoint = false, no_viscous = false, json = false;
};

replay::ReferenceFacts reference_facts(double area, double chord, double span,
                                       const Eigen::Vector3d& moment_point) {
    return {area, chord, span, {moment_point.x(), moment_point.y(), moment_point.z()}};
}

replay::CompanionFacts companion_facts(const mesh::Companion& c, const fs::path& file) {
    replay::CompanionFacts f;
    f.file = file.string();
    f.aircraft_name = c.aircraft_name;
    f.half_model = c.model == "half";
    f.reference = reference_facts(c.reference.aircraft_area, c.reference.chord, c.reference.span,
                                  c.reference.moment_point);
    for (const auto& s : c.control_surfaces) f.control_modes.push_back(s.mode);
    return f;
}

/// The Euler source's set-up as `EulerSource::from_files` will make it (the configuration with
/// the mesh companion's defaults), read without the mesh: the facts replay::check_euler_setup
/// compares before the mesh is read and the CFD starts.
replay::EulerFacts euler_facts(const std::string& mesh_file, const std::string& config_file) {
    euler::CfdConfig cfg =
        config_file.empty() ? euler::CfdConfig{} : euler::read_cfd_config(config_file);
    const auto companion = mesh::find_companion(mesh_file);
    euler::apply_mesh_companion(cfg, mesh_file);
    replay::EulerFacts f;
    f.mesh = mesh_file;
    f.config = config_file.empty() ? std::string("the default CFD configuration") : config_file;
    if (companion) f.companion = companion_facts(*companion, mesh::companion_path(mesh_file));
    f.mach = cfg.mach;
    if (cfg.alpha) f.ignored_flow_keys.push_back("alpha");
    if (cfg.beta) f.ignored_flow_keys.push_back("beta");
    if (cfg.p_hat) f.ignored_flow_keys.push_back("p_hat");
    if (cfg.q_hat) f.ignored_flow_keys.push_back("q_hat");
    if (cfg.r_hat) f.ignored_flow_keys.push_back("r_hat");
    f.reference_given = cfg.reference_given;
    f.reference = reference_facts(cfg.reference.area, cfg.reference.chord, cfg.reference.span,
                                  cfg.reference.moment_point);
    f.half_model = cfg.reference.half_model;
    for (const auto& [name, role] : cfg.markers)
        if (role == euler::BoundaryKind::symmetry) f.half_model = true;
    for (const auto& c : cfg.control_surfaces) f.control_modes.push_back(c.mode);
    return f;
}

/// The companions of the meshes a `manta tables` folder's Euler campaign made (DIR/mesh/).
std::vector<replay::CompanionFacts> tables_mesh_companions(const std::string& tables) {
    std::vector<replay::CompanionFacts> out;
    if (tables.empty()) return out;
    // The folder, or the folder of its database.yaml.
    fs::path dir = fs::path(tables) / "mesh";
    if (!fs::is_directory(tables)) {
        if (fs::path(tables).filename() != "database.yaml") return out;
        dir = fs::path(tables).parent_path() / "mesh";
    }
    if (!fs::is_directory(dir)) return out;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n.size() > 10 && n.compare(n.size() - 10, 10, ".mesh.yaml") == 0)
            files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& p : files) out.push_back(companion_facts(mesh::read_companion(p), p));
    return out;
}

int run_replay_command(const ReplayArgs& a) {
    const bool euler = a.source == "euler";
    if (euler && a.mesh.empty())
        throw InputError(
            "--source euler needs --mesh FILE: the CFD mesh, whose markers --cfd-config FILE (or "
            "the mesh's companion file) gives roles and control surfaces");
    if (!euler && (!a.mesh.empty() || !a.cfd_config.empty() || a.cfd_start != "steady"))
        throw InputError(fmt::format(
            "--mesh, --cfd-config and --cfd-start are options of --source euler; expected them "
            "with it, or "
            "neither with --source {}",
            a.source));
    if (!euler && a.snapshot_given)
        throw InputError(fmt::format(
            "--snapshot-every is an option of --source euler (the vortex lattice has no surface "
            "to write); expected it with --source euler, or not with --source {}",
            a.source));
    const aircraft::AircraftDefinition def = aircraft::load_aircraft(a.aircraft);
    const auto tables = load_tables(a.tables, def);
    const replay::Trajectory tr = replay::read_trajectory(a.trajectory);

    // The inputs compared with each other before the mesh is read and anything is solved
    // (docs/replay.md, "Bad input"): errors here, warnings printed by run_replay once its own
    // checks have passed.
    const replay::Trajectory replayed = a.until > 0.0 ? replay::first_seconds(tr, a.until) : tr;
    replay::AircraftFacts aircraft_facts;
    aircraft_facts.file = a.aircraft;
    aircraft_facts.name = def.name;
    aircraft_facts.reference = reference_facts(def.reference.area, def.reference.chord,
                                               def.reference.span, def.moment_reference_geom);
    replay::TablesFacts tables_facts;
    tables_facts.file = a.tables;
    tables_facts.database = tables.get();
    tables_facts.mesh_companions = tables_mesh_companions(a.tables);
    std::vector<std::string> warnings =
        replay::check_tables(tables_facts, aircraft_facts, replayed);
    if (euler)
        for (std::string& w :
             replay::check_euler_setup(euler_facts(a.mesh, a.cfd_config), aircraft_facts, replayed))
            warnings.push_back(std::move(w));

    replay::ReplaySettings s;
    s.dt = a.dt;
    s.until = a.until;
    s.whole_steps = euler;  // its run takes whole steps only (duration / N)
    s.span = def.reference.span;
    s.chord = def.reference.chord;
    s.viscous = !a.no_viscous;
    s.checkpoint_steps = a.checkpoint_steps;
    s.checkpoint_seconds = a.checkpoint_seconds;
    s.restart = a.restart;
    s.keep_checkpoint = a.keep_checkpoint;
    s.trajectory_label = a.trajectory;
    s.input_warnings = warnings;
    s.warn = [](const std::string& w) { std::fprintf(stderr, "%s\n", w.c_str()); };
    for (const std::string& t : a.tolerances) {
        const auto eq = t.find('=');
        bool ok = false;
        if (eq != std::string::npos)
            for (std::size_t k = 0; k < 6; ++k)
                if (t.substr(0, eq) == replay::coefficient_names[k]) {
                    try {
                        std::size_t used = 0;
                        const double v = std::stod(t.substr(eq + 1), &used);
                        ok = used == t.size() - eq - 1 && v > 0.0 && std::isfinite(v);
                        s.tolerances[k] = v;
                    } catch (const std::exception&) {
                        ok = false;
                    }
                }
        if (!ok)
            throw InputError(fmt::format(
                "--tolerance {}: expected NAME=VALUE with NAME one of CL CD CY Cl Cm Cn and "
                "VALUE > 0",
                t));
    }

    std::unique_ptr<aero::AeroSource> source;
    std::string source_size;
    if (euler) {
        // Serial time-accurate Euler CFD on the mesh (docs/replay.md#the-euler-source); the
        // configuration's text is in the fingerprint (its control surfaces and unsteady settings
        // change the result; the source's own fingerprint has the mesh and the numerics).
        auto e = euler::EulerSource::from_files(a.mesh, a.cfd_config);
        e->set_unsteady_start(a.cfd_start == "free-stream" ? euler::UnsteadyStart::free_stream
                                                           : euler::UnsteadyStart::steady);
        source_size = fmt::format("{} nodes", e->n_nodes());
        // The steady start takes minutes on an aircraft mesh: its own status line.
        e->set_start_progress([name = tr.meta("manoeuvre", "trajectory"),
                               tty = isatty(fileno(stderr)) != 0, last = -1e300](
                                  int it, double drop, double target, double wall_s) mutable {
            if (wall_s - last < (tty ? 1.0 : 10.0)) return;
            last = wall_s;
            std::fprintf(stderr,
                         "%sreplay %s: steady start, iteration %d, residual %.2f of %.2f orders "
                         "down, %.0f s%s",
                         tty ? "\r" : "", name.c_str(), it, drop, target, wall_s,
                         tty ? "   " : "\n");
        });
        s.snapshot_every = a.snapshot_every;
        s.write_snapshot = [](const aero::UnsteadyRun& run, const fs::path& file) {
            return euler::write_surface_snapshot(run, file);
        };
        s.extra_fingerprint =
            "euler start=" + a.cfd_start +
            " cfd_config=" + (a.cfd_config.empty() ? std::string() : core::read_file(a.cfd_config));
        source = std::move(e);
    } else {
        s.extra_fingerprint = fmt::format("n_chord={} strip_width={} wake_length={}", a.n_chord,
                                          a.strip_width, a.wake_length);
        vlm::LatticeDensity density;
        density.n_chord = a.n_chord;
        density.strip_width = a.strip_width;
        const VlmInput in = load_vlm_input(a.aircraft, density);
        auto v = std::make_unique<vlm::VlmSource>(in.model, in.geometry);
        vlm::UnsteadyOptions uo;
        uo.wake_length = a.wake_length;
        uo.threads = a.threads;
        uo.span_loading = false;
        // The wake whose steady limit is the source's steady lattice (vlm::default_trailing_legs):
        // convected along the free stream with free-stream legs, planar with body-axis legs (AVL).
        uo.wake = v->trailing_legs() == vlm::TrailingLegs::freestream ? vlm::WakeModel::prescribed
                                                                      : vlm::WakeModel::planar;
        v->set_unsteady_options(uo);
        source_size = fmt::format("{} vortices", v->lattice().size());
        source = std::move(v);
    }

    // A live status line on a terminal; a line every 10 s otherwise (logs).
    const bool tty = isatty(fileno(stderr)) != 0;
    const double every = tty ? 1.0 : 10.0;
    double last = -every;
    bool printed = false;
    s.progress = [&](const replay::ReplayProgress& p) {
        if (p.elapsed_s - last < every && p.step < p.n_steps) return;
        last = p.elapsed_s;
        printed = true;
        std::fprintf(
            stderr,
            "%sreplay %s: step %d/%d  t %.2f s  %.0f%%  %.0f s spent, about %.0f s left%s%s",
            tty ? "\r" : "", tr.meta("manoeuvre", "trajectory").c_str(), p.step, p.n_steps, p.t,
            100.0 * p.step / std::max(1, p.n_steps), p.elapsed_s, p.remaining_s,
            p.resumed_from >= 0 ? fmt::format(" (resumed at step {})", p.resumed_from).c_str() : "",
            tty ? "   " : "\n");
    };
    // The replay writes --out (checkpoints included) from here on: one command at a time. (The
    // source is made first: a mesh or configuration it refuses leaves no folder behind.)
    const core::RunFolderLock lock(a.out, "replay");
    const replay::ReplayOutcome oc = replay::run_replay(*source, *tables, tr, s, a.out);
    if (tty && printed) std::fprintf(stderr, "\n");
    const nlohmann::json& j = oc.summary;
    if (a.json) {
        print_json(j);
        return 0;
    }
    fmt::print("{} steps of {:.4f} s ({}){} through the {} source ({}) in {:.1f} s{}\n", oc.steps,
               oc.dt, oc.dt_reason,
               a.until > 0.0 ? fmt::format(", the first {} s of flight", a.until) : "",
               source->name(), source_size, j.value("wall_time_s", 0.0),
               oc.resumed_from >= 0 ? fmt::format(", resumed from step {}", oc.resumed_from) : "");
    const double mismatch = j["trajectory_check"]["rate_mismatch_max"].get<double>();
    if (mismatch > 0.05)
        fmt::print(
            "warning: the trajectory's Euler angles and its p q r disagree by up to {:.3g} rad/s "
            "(t = {:.2f} s); the replay follows the angles\n",
            mismatch, j["trajectory_check"]["t"].get<double>());
    fmt::print("{:<4} {:>10} {:>10} {:>8}\n", "", "rms diff", "max |diff|", "at t [s]");
    for (const char* c : replay::coefficient_names) {
        const auto& o = j["coefficients"][c];
        fmt::print("{:<4} {:>10.4f} {:>10.4f} {:>8.2f}\n", c, o["rms"].get<double>(),
                   o["max_abs"].get<double>(), o["t_max"].get<double>());
    }
    fmt::print("{} flagged interval(s), {} step(s) over tolerance\n", j["flags"].size(),
               j.value("flagged_steps", 0));
    fmt::print("wrote {}, {}, {}\n", oc.motion_file.string(), oc.comparison_file.string(),
               oc.summary_file.string());
    if (oc.snapshots > 0)
        fmt::print("wrote {} surface snapshot(s) every {} s in {} ({:.2f} s to write here)\n",
                   oc.snapshots, a.snapshot_every, (fs::path(a.out) / "surface").string(),
                   j["snapshots"].value("write_wall_s", 0.0));
    return 0;
}

}  // namespace

void add_replay(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "replay",
        "Replay a trajectory through a time-accurate aero source and compare it with the tables\n"
        "(docs/replay.md): motion.csv, comparison.csv and summary.json in --out. A killed replay\n"
        "run again with the same command continues from its last checkpoint.");
    auto a = std::make_shared<ReplayArgs>();
    cmd->add_option("--trajectory", a->trajectory,
                    "Trajectory CSV (docs/formats.md#trajectory-csv; manta optimise/simulate)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--source", a->source,
                    "Time-accurate source: vlm (default) or euler (Euler CFD on --mesh; hours on "
                    "an aircraft mesh: docs/replay.md)")
        ->check(CLI::IsMember({"vlm", "euler"}));
    cmd->add_option("--mesh", a->mesh,
                    "--source euler: the CFD mesh (docs/mesh.md; required with euler)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--cfd-config", a->cfd_config,
                    "--source euler: the file `manta cfd --config` reads (docs/formats.md#cfd-"
                    "configuration: marker roles, control_surfaces, unsteady: settings); named "
                    "--cfd-config since it configures the CFD, not the replay")
        ->check(CLI::ExistingFile);
    cmd->add_option("--cfd-start", a->cfd_start,
                    "--source euler: steady (default: the steady solution at the entry state) or "
                    "free-stream (as manta cfd --motion, with a start transient)")
        ->check(CLI::IsMember({"steady", "free-stream"}));
    cmd->add_option("--aircraft", a->aircraft, "Aircraft file (geometry, reference, aero model)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--out", a->out, "Output folder")->required()->check(output_path());
    cmd->add_option("--tables", a->tables,
                    "Aero database (database.yaml or a `manta tables` folder; default: the "
                    "aircraft file's aero model)")
        ->check(CLI::ExistingPath);
    cmd->add_option("--dt", a->dt, "Time step [s] (default: from the manoeuvre's time scales)")
        ->check(real_positive(1.0, "s"));
    cmd->add_option("--until", a->until,
                    "Replay only the first S seconds of flight: the trajectory cut there, as if "
                    "the file ended (default: the whole trajectory)")
        ->check(real_positive(1e6, "s"));
    cmd->add_option("--snapshot-every", a->snapshot_every,
                    "--source euler: write the wall's surface (x y z Cp, triangles) every S "
                    "seconds of flight into --out/surface/ (docs/formats.md#surface-snapshot; "
                    "default 1; 0: none)")
        ->check(real_in(0.0, 1e6, "s"))
        ->each([a](const std::string&) { a->snapshot_given = true; });
    cmd->add_option("--n-chord", a->n_chord,
                    fmt::format("vlm: chordwise vortices per strip (default {})", replay_n_chord))
        ->check(integer_in(1, 100));
    cmd->add_option("--strip-width", a->strip_width,
                    fmt::format("vlm: strip width / span (default {})", replay_strip_width))
        ->check(real_in(1e-4, 0.5));
    cmd->add_option("--wake-length", a->wake_length,
                    "vlm: wake kept [reference chords] (default 10)")
        ->check(real_positive(1000.0, "chords"));
    cmd->add_option("--threads", a->threads,
                    "vlm: worker threads (default 0: all; euler runs serial)")
        ->check(integer_in(0, 256));
    cmd->add_option("--tolerance", a->tolerances,
                    "Flag tolerance NAME=VALUE (CL CD CY Cl Cm Cn; defaults in docs/replay.md)");
    cmd->add_option("--checkpoint-steps", a->checkpoint_steps,
                    "Checkpoint every N steps (default 0: by time only)")
        ->check(integer_in(0, 1000000000));
    cmd->add_option("--checkpoint-seconds", a->checkpoint_seconds,
                    "Checkpoint every T seconds of wall time (default 30; 0: never by time)")
        ->check(real_in(0.0, 1e6, "s"));
    cmd->add_flag("--restart", a->restart, "Discard a checkpoint in --out and start afresh");
    cmd->add_flag("--keep-checkpoint", a->keep_checkpoint, "Keep --out/checkpoint when done");
    cmd->add_flag("--no-viscous", a->no_viscous,
                  "Leave out the viscous drag estimate (vlm; euler has none)");
    cmd->add_flag("--json", a->json, "Print summary.json on stdout");
    cmd->callback([a, &action] { action = [a]() -> int { return run_replay_command(*a); }; });
}

}  // namespace manta::cli
