#pragma once
/// @file slab_case.hpp
/// Time-accurate runs of the NACA 0012 slab (`test::write_naca0012_msh`) through the CFD case
/// driver `euler::CfdCase` (what `manta cfd --mesh --motion` runs), for the 2-D unsteady
/// validations: harmonic pitch about a point of the chord (Theodorsen) and a flap deflection
/// ramped and then held until the flow is steady. Each run writes its mesh, configuration and
/// motion file into a scratch folder and reads the run's coefficients.csv back.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "manta/aero/oscillation.hpp"
#include "manta/euler/case.hpp"
#include "manta/parallel/communicator.hpp"
#include "test_meshes.hpp"

namespace manta::test {

/// One time-accurate slab run.
struct SlabRun {
    int level = 0;            ///< naca0012_slab level (0, 1, 2)
    double mach = 0.2;        ///< free-stream Mach number
    double flap_hinge = 0.0;  ///< x/c of the flap hinge (0: no flap marker)
    /// Pitch theta = amplitude sin(omega t) about (pivot, 0) [rad]; omega = 2 k U / c.
    double pitch_amplitude = 0.0;
    double reduced_frequency = 0.0;  ///< k = omega c / (2 U)
    int steps_per_period = 32;       ///< pitch: dt = period / steps_per_period
    double pivot = 0.25;             ///< x/c of the pitch axis and of the moment point
    /// Flap deflection (mode_flap, trailing edge down positive) [rad], ramped from 0 as
    /// (1 - cos(pi s / ramp_steps)) / 2 over the first `ramp_steps` steps, then held.
    double flap_deflection = 0.0;
    int ramp_steps = 0;
    double dt_chords = 0.25;  ///< without pitch: dt in chord transit times c / U
    int n_steps = 0;          ///< physical steps in all
    int max_inner = 40;
    double inner_drop = 3.0;
    std::string extra_yaml;  ///< appended to the configuration (e.g. control_surfaces)
    std::string name = "slab";
};

/// What came back: the run's per-step history.
struct SlabHistory {
    std::vector<double> t, CL, Cm, alpha, inner;
    double omega = 0.0;  ///< pitch angular frequency [rad/s] (0 without pitch)
    double v0 = 0.0;     ///< free-stream speed [m/s]
    double seconds_per_step = 0.0, inner_per_step = 0.0;
};

/// Columns `names` of a CSV file with a header line.
inline std::vector<std::vector<double>> read_csv_columns(const std::filesystem::path& f,
                                                         const std::vector<std::string>& names) {
    std::ifstream in(f);
    std::string line;
    std::vector<std::size_t> idx;
    std::vector<std::vector<double>> cols(names.size());
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> cells;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
        if (idx.empty()) {
            for (const auto& n : names)
                for (std::size_t k = 0; k < cells.size(); ++k)
                    if (cells[k] == n) idx.push_back(k);
            EXPECT_EQ(idx.size(), names.size()) << f;
            if (idx.size() != names.size()) return cols;
            continue;
        }
        for (std::size_t k = 0; k < names.size(); ++k) cols[k].push_back(std::stod(cells[idx[k]]));
    }
    return cols;
}

/// Run `run` (serial) in a scratch folder named after `run.name` under the temporary directory.
inline SlabHistory run_slab(const SlabRun& run) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("manta_" + run.name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_naca0012_msh(run.level, dir / "mesh.msh", run.flap_hinge);

    const double c_inf = std::sqrt(1.4 * 287.058 * 288.15);
    SlabHistory h;
    h.v0 = run.mach * c_inf;
    h.omega = 2.0 * run.reduced_frequency * h.v0;  // chord 1 m
    const double dt = run.pitch_amplitude > 0.0
                          ? 2.0 * std::numbers::pi / h.omega / run.steps_per_period
                          : run.dt_chords / h.v0;
    {
        std::ofstream m(dir / "motion.csv");
        m.precision(17);
        m << "# v0: " << h.v0 << "\n# mach: " << run.mach << "\n";
        m << "t,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder,mode_flap\n";
        for (int i = 0; i <= run.n_steps; ++i) {
            const double t = i * dt;
            // The pitch from the sample index (exactly periodic, as tests/data/naca64a010_ct5).
            const double theta =
                run.pitch_amplitude * std::sin(2.0 * std::numbers::pi * (i % run.steps_per_period) /
                                               run.steps_per_period);
            double flap = run.flap_deflection;
            if (i < run.ramp_steps)
                flap *= 0.5 * (1.0 - std::cos(std::numbers::pi * i / run.ramp_steps));
            m << t << ",0,0,0,0," << (run.pitch_amplitude > 0.0 ? theta : 0.0) << ",0,0,0,0,"
              << flap << "\n";
        }
    }
    {
        std::ofstream c(dir / "case.yaml");
        c << "flow: {mach: " << run.mach << "}\n"
          << "mesh: {up: y}\n"
          << "markers: {airfoil: wall, " << (run.flap_hinge > 0.0 ? "flap: wall, " : "")
          << "farfield: farfield, symmetry_back: symmetry, symmetry_front: symmetry}\n"
          << "reference: {area: 1.0, chord: 1.0, span: 1.0, moment_point: [" << run.pivot
          << ", 0, 0]}\n"
          << "unsteady: {order: 2, max_inner: " << run.max_inner
          << ", inner_drop: " << run.inner_drop << "}\n"
          << "output: {volume: false, surface: false, checkpoint_interval_s: 1e9}\n"
          << run.extra_yaml;
    }
    euler::CaseInputs in;
    in.mesh = dir / "mesh.msh";
    in.motion = dir / "motion.csv";
    in.config = dir / "case.yaml";
    in.out = dir / "run";
    in.restart = true;
    parallel::SerialCommunicator comm;
    euler::CfdCase cfd(in, comm);
    const euler::CaseResult r = cfd.run();
    const auto cols = read_csv_columns(in.out / "coefficients.csv",
                                       {"t", "CL", "Cm", "alpha", "inner_iterations"});
    h.t = cols[0];
    h.CL = cols[1];
    h.Cm = cols[2];
    h.alpha = cols[3];
    h.inner = cols[4];
    h.seconds_per_step = r.summary["seconds_per_step"].get<double>();
    h.inner_per_step = r.summary["inner_iterations_per_step"].get<double>();
    return h;
}

/// First harmonic of c(t) over the last whole period of a pitching history: c ~ mean +
/// amplitude sin(omega t + phase) (aero::analyse_oscillation's Fourier estimate); phase in
/// degrees, positive = leading the pitch.
struct FirstHarmonic {
    double mean = 0.0, amplitude = 0.0, phase_deg = 0.0;
};
inline FirstHarmonic first_harmonic(const SlabHistory& h, const std::vector<double>& c,
                                    double amplitude, double reduced_frequency) {
    aero::OscillationSpec s;
    s.amplitude = amplitude;
    s.omega = h.omega;
    s.reduced_frequency = reduced_frequency;
    s.n_periods = 1;
    s.period_tolerance = 1e-3;
    const aero::OscillationResult r = aero::analyse_oscillation(h.t, c, s);
    return {r.fourier.c0, std::hypot(r.fourier.c_sin, r.fourier.c_cos),
            std::atan2(r.fourier.c_cos, r.fourier.c_sin) * 180.0 / std::numbers::pi};
}

}  // namespace manta::test
