/// `manta oscillation --source vlm|euler`: dynamic derivatives by forced harmonic oscillation on
/// the unsteady vortex lattice or the Euler CFD (aero::forced_oscillation); `manta
/// vlm-oscillation` is `manta oscillation --source vlm`. The arguments and the printing only.

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aero/forced_oscillation.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/text.hpp"
#include "manta/core/units.hpp"
#include "manta/euler/case.hpp"
#include "manta/euler/config.hpp"
#include "manta/euler/source.hpp"
#include "manta/vlm/dynamic.hpp"
#include "manta/vlm/source.hpp"

namespace manta::cli {

namespace {

struct OscillationArgs {
    std::string command;  ///< "oscillation" or "vlm-oscillation" (messages)
    std::string source = "vlm";
    std::string aircraft, mesh, config;
    std::string axis = "pitch";
    double k = 0.05;
    double amplitude_deg = 1.0;
    double alpha_deg = 0.0;
    std::optional<double> mach;
    int periods = 3;
    int steps_per_period = 48;
    int n_chord = 6;
    double strip_width = 0.02;
    std::string checkpoint;
    double checkpoint_seconds = 60.0;
    std::string history;
    bool json = false;
    // Options given on the command line (source-specific ones are refused for the other).
    bool given_n_chord = false, given_strip_width = false;
};

aero::OscillationAxis parse_axis(const OscillationArgs& a) {
    if (a.axis == "pitch") return aero::OscillationAxis::pitch;
    if (a.axis == "roll") return aero::OscillationAxis::roll;
    if (a.axis == "yaw") return aero::OscillationAxis::yaw;
    if (a.axis == "plunge") return aero::OscillationAxis::plunge;
    throw InputError(fmt::format("{}: --axis '{}'; expected pitch, roll, yaw or plunge", a.command,
                                 core::printable(a.axis)));
}

void check_source_options(const OscillationArgs& a) {
    if (a.source == "vlm") {
        if (a.aircraft.empty())
            throw InputError(fmt::format(
                "{} --source vlm: no --aircraft; expected a MANTA aircraft file or an AVL "
                "geometry file",
                a.command));
        if (!a.mesh.empty() || !a.config.empty())
            throw InputError(
                fmt::format("{} --source vlm: --mesh and --config are for --source euler; expected "
                            "--aircraft only",
                            a.command));
        return;
    }
    if (a.mesh.empty())
        throw InputError(fmt::format(
            "{} --source euler: no --mesh; expected the CFD mesh file (and optionally its "
            "--config, as for manta cfd)",
            a.command));
    if (!a.aircraft.empty() || a.given_n_chord || a.given_strip_width)
        throw InputError(fmt::format(
            "{} --source euler: --aircraft, --n-chord and --strip-width are for --source vlm; "
            "the reference lengths and the flow set-up come from --config",
            a.command));
}

std::string history_csv(const std::vector<aero::UnsteadySample>& h) {
    std::string s = "t,CL,CD,CY,Cl,Cm,Cn,CX,CZ,alpha,beta,airspeed\n";
    for (const auto& st : h) {
        s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", core::format_exact(st.t),
                         core::format_exact(st.wind.CL), core::format_exact(st.wind.CD),
                         core::format_exact(st.wind.CY), core::format_exact(st.body.Cl),
                         core::format_exact(st.body.Cm), core::format_exact(st.body.Cn),
                         core::format_exact(st.body.CX), core::format_exact(st.body.CZ),
                         core::format_exact(st.alpha), core::format_exact(st.beta),
                         core::format_exact(st.airspeed));
    }
    return s;
}

int run_oscillation(const OscillationArgs& a) {
    check_source_options(a);
    aero::ForcedOscillationOptions o;
    o.axis = parse_axis(a);
    o.reduced_frequency = a.k;
    o.amplitude = a.amplitude_deg * core::deg_to_rad;
    o.alpha0 = a.alpha_deg * core::deg_to_rad;
    o.n_periods = a.periods;
    o.steps_per_period = a.steps_per_period;
    o.checkpoint = a.checkpoint;
    o.checkpoint_seconds = a.checkpoint_seconds;
    if (!a.checkpoint.empty()) core::prepare_output_file(a.checkpoint, "--checkpoint");
    if (!a.history.empty()) core::prepare_output_file(a.history, "--history");

    std::unique_ptr<aero::AeroSource> source;
    double mach = 0.0;
    if (a.source == "vlm") {
        vlm::LatticeDensity density;
        density.n_chord = a.n_chord;
        density.strip_width = a.strip_width;
        VlmInput in = load_vlm_input(a.aircraft, density);
        vlm::ForcedOscillationOptions vo;
        vo.axis = o.axis;
        vo.amplitude = o.amplitude;
        vo.reduced_frequency = o.reduced_frequency;
        vo.alpha0 = o.alpha0;
        vo.n_periods = o.n_periods;
        vo.steps_per_period = o.steps_per_period;
        mach = a.mach.value_or(0.0);
        vo.solver.mach = mach;
        const aero::ForcedOscillationOptions base = vlm::oscillation_options(in.model, vo);
        o.speed = base.speed;
        o.mach = base.mach;
        o.chord = base.chord;
        o.span = base.span;
        aero::check_options(o);  // before the lattice is built
        auto vs = std::make_unique<vlm::VlmSource>(std::move(in.model));
        vlm::UnsteadyOptions so = vo.solver;
        so.speed = vo.speed;
        vs->set_unsteady_options(so);
        source = std::move(vs);
    } else {
        // The reference lengths as the source will have them: the configuration's, else the
        // mesh companion file's (EulerSource::from_files).
        euler::CfdConfig cfg =
            a.config.empty() ? euler::CfdConfig{} : euler::read_cfd_config(a.config);
        euler::apply_mesh_companion(cfg, a.mesh);
        const euler::CaseSetup setup = euler::case_setup(cfg);
        o.chord = setup.reference.chord;
        o.span = setup.reference.span;
        o.mach = a.mach;
        mach = a.mach.value_or(setup.flow.mach);
        aero::check_options(o);  // before the mesh is read
        source = euler::EulerSource::from_files(a.mesh, a.config);
    }

    // The progress line: rewritten in place on a terminal, a line every 10 s in a log.
    const bool tty = isatty(fileno(stderr)) != 0;
    const double every = tty ? 1.0 : 10.0;
    double last_print = 0.0;  // the first line after `every` seconds, so short runs stay quiet
    bool printed = false, told_resume = false;
    const aero::ForcedOscillationResult r =
        aero::forced_oscillation(*source, o, [&](const aero::ForcedOscillationProgress& p) {
            if (p.resumed_from >= 0 && !told_resume) {
                std::fprintf(stderr, "resumed from %s at step %d of %d\n", a.checkpoint.c_str(),
                             p.resumed_from, p.n_steps);
                told_resume = true;
            }
            if (p.wall_s - last_print < every && !(printed && p.step == p.n_steps)) return;
            last_print = p.wall_s;
            printed = true;
            const std::string left =
                p.seconds_left ? fmt::format("about {:.0f} s left", *p.seconds_left) : "";
            std::fprintf(stderr, "%sstep %d/%d  t %.4f of %.4f s  CL %.5f  Cm %.5f  %s%s%s",
                         tty ? "\r" : "", p.step, p.n_steps, p.t, p.end_time, p.sample->wind.CL,
                         p.sample->body.Cm, left.c_str(),
                         p.checkpoint_written ? "  (checkpoint)" : "", tty ? "   " : "\n");
        });
    if (tty && printed) std::fprintf(stderr, "\n");
    if (!a.history.empty()) core::write_file_atomic(a.history, history_csv(r.history));

    nlohmann::json j;
    j["source"] = a.source;
    if (a.source == "vlm") {
        j["aircraft"] = a.aircraft;
    } else {
        j["mesh"] = a.mesh;
        j["config"] = a.config;
    }
    j["axis"] = a.axis;
    j["reduced_frequency"] = a.k;
    j["amplitude"] = o.amplitude;
    j["alpha0"] = o.alpha0;
    j["mach"] = mach;
    j["omega"] = r.omega;
    j["periods"] = o.n_periods;
    j["steps_per_period"] = o.steps_per_period;
    j["steps"] = static_cast<int>(r.history.size()) - 1;
    j["chord"] = o.chord;
    j["span"] = o.span;
    j["resumed_from"] = r.resumed_from;
    j["wall_time_s"] = r.wall_s;
    if (!a.checkpoint.empty()) j["checkpoint"] = a.checkpoint;
    if (!a.history.empty()) j["history"] = a.history;
    for (std::size_t c = 0; c < 6; ++c) {
        const auto& x = r.coefficients[c];
        j["coefficients"][aero::oscillation_coefficient_names[c]] = {
            {"mean", x.mean},
            {"in_phase_fourier", x.fourier.in_phase},
            {"out_of_phase_fourier", x.fourier.out_of_phase},
            {"in_phase_regression", x.regression.in_phase},
            {"out_of_phase_regression", x.regression.out_of_phase},
            {"r_squared", x.regression.r_squared}};
    }
    if (a.json) {
        print_json(j);
        return 0;
    }
    fmt::print("{} oscillation ({}), k = {}, amplitude {} deg, alpha0 {} deg, Mach {}\n", a.axis,
               a.source, a.k, a.amplitude_deg, a.alpha_deg, mach);
    fmt::print("{:>4} {:>12} {:>14} {:>14} {:>14} {:>14}\n", "", "mean", "in-phase (F)",
               "out-phase (F)", "in-phase (R)", "out-phase (R)");
    for (std::size_t c = 0; c < 6; ++c) {
        const auto& x = r.coefficients[c];
        fmt::print("{:>4} {:12.5f} {:14.5f} {:14.5f} {:14.5f} {:14.5f}\n",
                   aero::oscillation_coefficient_names[c], x.mean, x.fourier.in_phase,
                   x.fourier.out_of_phase, x.regression.in_phase, x.regression.out_of_phase);
    }
    fmt::print(
        "(F: Fourier over the last {} periods; R: linear regression; see "
        "docs/forced-oscillation.md for what each axis measures)\n",
        a.periods - 1);
    return 0;
}

/// The options both commands share; `with_source`: also --source, --mesh and --config.
void add_options(CLI::App* cmd, OscillationArgs& b, bool with_source) {
    if (with_source) {
        cmd->add_option("--source", b.source,
                        "Time-accurate source: vlm (unsteady vortex lattice, default) or euler")
            ->check(CLI::IsMember({"vlm", "euler"}));
        cmd->add_option("--aircraft", b.aircraft,
                        "vlm: aircraft file, MANTA YAML or AVL geometry (.avl)")
            ->check(CLI::ExistingFile);
        cmd->add_option("--mesh", b.mesh, "euler: mesh file (.su2, .su2.gz, .msh, .cgns)")
            ->check(CLI::ExistingFile);
        cmd->add_option("--config", b.config,
                        "euler: CFD configuration file (as manta cfd; reference lengths, markers, "
                        "numerics)")
            ->check(CLI::ExistingFile);
    } else {
        cmd->add_option("--aircraft", b.aircraft,
                        "Aircraft file: MANTA YAML or AVL geometry (.avl)")
            ->required()
            ->check(CLI::ExistingFile);
    }
    cmd->add_option("--axis", b.axis, "pitch, roll, yaw or plunge (default pitch)");
    cmd->add_option("--k", b.k, "Reduced frequency (c/2V pitch and plunge, b/2V roll and yaw)")
        ->check(real_positive(10.0));
    cmd->add_option("--amplitude-deg", b.amplitude_deg, "Amplitude [deg] (default 1)")
        ->check(real_positive(30.0, "deg"));
    cmd->add_option("--alpha-deg", b.alpha_deg, "Mean angle of attack [deg] (default 0)")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    cmd->add_option("--mach", b.mach,
                    with_source ? "Mach number (vlm: default 0; euler: default flow.mach of "
                                  "--config)"
                                : "Mach number (default 0)")
        ->check(real_in(0.0, 0.95));
    cmd->add_option("--periods", b.periods, "Periods simulated, the first discarded (default 3)")
        ->check(integer_in(2, 100));
    cmd->add_option("--steps-per-period", b.steps_per_period, "Time steps per period (default 48)")
        ->check(integer_in(8, 10000));
    cmd->add_option("--n-chord", b.n_chord,
                    "vlm: chordwise vortices per strip (MANTA files; default 6)")
        ->check(integer_in(1, 100));
    cmd->add_option("--strip-width", b.strip_width,
                    "vlm: strip width / span (MANTA files; default 0.02)")
        ->check(real_in(1e-4, 0.5));
    cmd->add_option("--checkpoint", b.checkpoint,
                    "Checkpoint file: written atomically after the start, every "
                    "--checkpoint-seconds and at the end; the same command resumes from it")
        ->check(output_path());
    cmd->add_option("--checkpoint-seconds", b.checkpoint_seconds,
                    "Wall time between checkpoints [s] (default 60; 0: every step)")
        ->check(real_in(0.0, 1e6, "s"));
    cmd->add_option("--history", b.history,
                    "Write the coefficient history (CSV: t, CL CD CY Cl Cm Cn, CX CZ, alpha, "
                    "beta, airspeed)")
        ->check(output_path());
    cmd->add_flag("--json", b.json, "Print one JSON object");
}

}  // namespace

void add_oscillation(CLI::App& app, Action& action) {
    auto* osc = app.add_subcommand(
        "oscillation",
        "Dynamic derivatives by forced harmonic oscillation in pitch, roll, yaw or plunge about\n"
        "the reference point, on the unsteady vortex lattice (--source vlm --aircraft FILE) or\n"
        "the Euler CFD (--source euler --mesh FILE [--config FILE]): in-phase and out-of-phase\n"
        "derivatives of the six coefficients by Fourier analysis and by linear regression over\n"
        "all periods but the first (docs/forced-oscillation.md).");
    auto a = std::make_shared<OscillationArgs>();
    a->command = "oscillation";
    add_options(osc, *a, true);
    osc->callback([a, osc, &action] {
        a->given_n_chord = osc->count("--n-chord") > 0;
        a->given_strip_width = osc->count("--strip-width") > 0;
        action = [a]() -> int { return run_oscillation(*a); };
    });

    auto* vosc = app.add_subcommand(
        "vlm-oscillation",
        "Dynamic derivatives by forced harmonic oscillation of the unsteady vortex lattice:\n"
        "the same as 'manta oscillation --source vlm' (docs/forced-oscillation.md).");
    auto b = std::make_shared<OscillationArgs>();
    b->command = "vlm-oscillation";
    add_options(vosc, *b, false);
    vosc->callback([b, &action] { action = [b]() -> int { return run_oscillation(*b); }; });
}

}  // namespace manta::cli
