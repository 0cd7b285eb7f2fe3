/// @file replay.cpp
/// The replay loop: motion, unsteady source, table prediction, checkpoints (replay.hpp).

#include "manta/replay/replay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ctime>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/version.hpp"
#include "manta/flightdyn/atmosphere.hpp"

namespace manta::replay {

namespace fs = std::filesystem;

namespace {

/// FNV-1a over bytes.
struct Hash {
    std::uint64_t h = 1469598103934665603ULL;
    void bytes(const void* p, std::size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) {
            h ^= c[i];
            h *= 1099511628211ULL;
        }
    }
    void num(double x) { bytes(&x, sizeof x); }
    void vec(const std::vector<double>& v) {
        num(static_cast<double>(v.size()));
        if (!v.empty()) bytes(v.data(), v.size() * sizeof(double));
    }
    void str(const std::string& s) {
        num(static_cast<double>(s.size()));
        bytes(s.data(), s.size());
    }
};

std::string fingerprint(const aero::AeroSource& source, const aero::AeroDatabase& tables,
                        const Trajectory& tr, const ReplaySettings& s, double dt) {
    Hash h;
    h.str(core::version());
    h.vec(tr.t);
    for (const auto* group : {&tr.position, &tr.euler, &tr.rates, &tr.controls})
        for (const auto& v : *group) h.vec(v);
    h.vec(tr.V);
    h.vec(tr.alpha);
    h.vec(tr.beta);
    h.vec(tr.mach);
    for (const int p : tr.phase) h.num(p);
    h.str(source.fingerprint());
    h.str(tables.to_text());
    h.num(dt);
    h.num(s.max_sample_dt);
    h.num(s.span);
    h.num(s.chord);
    h.num(s.viscous ? 1.0 : 0.0);
    for (const double t : s.tolerances) h.num(t);
    h.str(s.extra_fingerprint);
    // Snapshots: a resumed run must write those of the uninterrupted one.
    if (s.snapshot_every > 0.0 && s.write_snapshot) h.num(s.snapshot_every);
    return fmt::format("{:016x}", h.h);
}

/// Doubles per row in the checkpoint's row file.
constexpr std::size_t row_doubles = 37;

std::string rows_to_bytes(const std::vector<ComparisonRow>& rows) {
    std::vector<double> v;
    v.reserve(rows.size() * row_doubles);
    for (const ComparisonRow& r : rows) {
        v.insert(v.end(), {r.t, static_cast<double>(r.phase), r.alpha, r.beta, r.V, r.mach});
        v.insert(v.end(), r.rates.begin(), r.rates.end());
        v.insert(v.end(), r.controls.begin(), r.controls.end());
        v.insert(v.end(), r.control_rates.begin(), r.control_rates.end());
        for (std::size_t k = 0; k < 6; ++k) v.insert(v.end(), {r.replay[k], r.table[k], r.diff[k]});
        v.insert(v.end(),
                 {r.flag ? 1.0 : 0.0, r.extrapolated ? 1.0 : 0.0,
                  static_cast<double>(r.source_iterations), r.source_converged ? 1.0 : 0.0});
    }
    return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double)};
}

std::vector<ComparisonRow> rows_from_bytes(const std::string& b, const fs::path& file) {
    if (b.size() % (row_doubles * sizeof(double)) != 0)
        throw InputError(fmt::format(
            "{}: {} bytes; expected whole rows of {} doubles (a damaged checkpoint: use --restart)",
            file.string(), b.size(), row_doubles));
    std::vector<double> v(b.size() / sizeof(double));
    std::memcpy(v.data(), b.data(), b.size());
    std::vector<ComparisonRow> rows(v.size() / row_doubles);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const double* x = v.data() + i * row_doubles;
        ComparisonRow& r = rows[i];
        r.t = x[0];
        r.phase = static_cast<int>(x[1]);
        r.alpha = x[2];
        r.beta = x[3];
        r.V = x[4];
        r.mach = x[5];
        for (std::size_t k = 0; k < 3; ++k) {
            r.rates[k] = x[6 + k];
            r.controls[k] = x[9 + k];
            r.control_rates[k] = x[12 + k];
        }
        for (std::size_t k = 0; k < 6; ++k) {
            r.replay[k] = x[15 + 3 * k];
            r.table[k] = x[16 + 3 * k];
            r.diff[k] = x[17 + 3 * k];
        }
        r.flag = x[33] != 0.0;
        r.extrapolated = x[34] != 0.0;
        r.source_iterations = static_cast<int>(x[35]);
        r.source_converged = x[36] != 0.0;
    }
    return rows;
}

double cpu_seconds() {
    return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

}  // namespace

std::vector<int> snapshot_steps(int n_steps, double dt, double every) {
    std::vector<int> out;
    if (!(every > 0.0) || !(dt > 0.0) || n_steps < 0) return out;
    auto slot = [&](int k) { return std::floor(k * dt / every + 1e-9); };
    out.push_back(0);
    for (int k = 1; k <= n_steps; ++k)
        if (slot(k) > slot(k - 1) || k == n_steps) out.push_back(k);
    return out;
}

ReplayOutcome run_replay(const aero::AeroSource& source, const aero::AeroDatabase& tables,
                         const Trajectory& trajectory, const ReplaySettings& s,
                         const fs::path& out) {
    using clock = std::chrono::steady_clock;
    const auto wall0 = clock::now();
    const double cpu0 = cpu_seconds();
    if (!source.unsteady())
        throw InputError(fmt::format(
            "replay: aero source '{}' cannot move (no time-accurate mode yet); expected a source "
            "with an unsteady mode (vlm)",
            source.name()));
    if (!(s.span > 0.0 && s.chord > 0.0))
        throw InputError(fmt::format("replay: reference span {} m and chord {} m; expected > 0",
                                     s.span, s.chord));
    for (std::size_t k = 0; k < 6; ++k)
        if (!(s.tolerances[k] > 0.0 && std::isfinite(s.tolerances[k])))
            throw InputError(fmt::format("replay: tolerance of {} is {}; expected > 0",
                                         coefficient_names[k], s.tolerances[k]));
    if (s.snapshot_every < 0.0 || !std::isfinite(s.snapshot_every))
        throw InputError(fmt::format(
            "replay: snapshot every {} s; expected a time > 0 s, or 0 for no surface snapshots",
            s.snapshot_every));
    if (s.until < 0.0 || !std::isfinite(s.until))
        throw InputError(fmt::format(
            "replay: until {} s; expected a duration > 0 s, or 0 for the whole trajectory",
            s.until));
    // A partial replay is that of the trajectory cut at t0 + until, as if the file ended there.
    const Trajectory tr = s.until > 0.0 ? first_seconds(trajectory, s.until) : trajectory;
    ReplayOutcome oc;
    TimeStepChoice choice;
    if (s.dt > 0.0) {
        choice.dt = s.dt;
        choice.reason = "given";
    } else {
        choice = choose_time_step(tr, s.rule, s.chord);
    }
    const double duration = tr.t.back() - tr.t.front();
    if (s.whole_steps && s.dt <= 0.0 && choice.dt > 0.0 && choice.dt < duration) {
        const double n = std::ceil(duration / choice.dt - 1e-9);
        choice.dt = duration / n;
        choice.reason +=
            fmt::format("; rounded down to {:.0f} whole steps of the {} s", n, duration);
    }
    if (!(choice.dt > 0.0 && std::isfinite(choice.dt) && choice.dt <= duration))
        throw InputError(
            fmt::format("replay: time step {} s; expected > 0 and at most the trajectory's {} s",
                        choice.dt, duration));
    oc.dt = choice.dt;
    oc.dt_reason = choice.reason;
    const int parts = std::max(1, static_cast<int>(std::ceil(choice.dt / s.max_sample_dt - 1e-9)));
    const ReplayMotion rm = build_motion(tr, choice.dt / parts);
    const aero::Motion interp = trajectory_interpolant(tr);
    std::vector<int> row_phase;
    const std::vector<Phase> phases = trajectory_phases(tr, &row_phase);

    aero::UnsteadySettings us;
    us.dt = choice.dt;
    if (s.viscous) {
        const auto atm = flightdyn::us1976(rm.altitude0);
        us.conditions.reynolds_per_metre = atm.density * rm.v0 / atm.dynamic_viscosity;
    }
    // Before anything is written: a source that cannot move throws here.
    const std::unique_ptr<aero::UnsteadyRun> run = source.start_unsteady(rm.motion, us);
    const int n_steps = run->n_steps();
    oc.steps = n_steps;

    const std::string fp = fingerprint(source, tables, tr, s, choice.dt);
    const fs::path ck = out / "checkpoint";
    std::vector<ComparisonRow> rows;
    rows.reserve(static_cast<std::size_t>(n_steps) + 1);
    double wall_before = 0.0, cpu_before = 0.0;
    if (fs::exists(ck / "checkpoint.json")) {
        if (s.restart) {
            fs::remove_all(ck);
        } else {
            nlohmann::json cj;
            try {
                cj = nlohmann::json::parse(core::read_file(ck / "checkpoint.json"));
            } catch (const nlohmann::json::exception& e) {
                throw InputError(
                    fmt::format("{}: not a checkpoint ({}); use --restart to discard it",
                                (ck / "checkpoint.json").string(), e.what()));
            }
            const std::string other = cj.value("fingerprint", std::string());
            if (other != fp)
                throw InputError(fmt::format(
                    "{}: checkpoint of another replay (fingerprint {}, this replay {}: the "
                    "trajectory, source, tables or settings differ); expected the same command, "
                    "or --restart to discard it",
                    (ck / "checkpoint.json").string(), other, fp));
            const int step = cj.value("step", -1);
            run->restore(ck / fmt::format("state-{}.bin", step));
            rows = rows_from_bytes(core::read_file(ck / fmt::format("rows-{}.bin", step)),
                                   ck / fmt::format("rows-{}.bin", step));
            if (run->current().index != step || rows.size() != static_cast<std::size_t>(step) + 1)
                throw InputError(fmt::format(
                    "{}: checkpoint at step {} with {} comparison rows and a state at step {}; "
                    "expected them to agree (a damaged checkpoint: use --restart)",
                    ck.string(), step, rows.size(), run->current().index));
            oc.resumed_from = step;
            wall_before = cj.value("wall_time_s", 0.0);
            cpu_before = cj.value("cpu_time_s", 0.0);
        }
    }
    // The inputs passed every check: the caller's warnings about them, before the source's work
    // (an Euler source's steady start) begins.
    if (s.warn)
        for (const std::string& w : s.input_warnings) s.warn(w);
    fs::create_directories(out);
    // Surface snapshots: a fresh run replaces those of an earlier one; a resumed run keeps those
    // up to its checkpoint and writes the rest.
    const fs::path surface = out / "surface";
    const std::vector<int> snap_steps = s.write_snapshot
                                            ? snapshot_steps(n_steps, choice.dt, s.snapshot_every)
                                            : std::vector<int>{};
    std::vector<char> snap_at(static_cast<std::size_t>(n_steps) + 1, 0);
    for (const int k : snap_steps) snap_at[static_cast<std::size_t>(k)] = 1;
    if (oc.resumed_from < 0) fs::remove_all(surface);
    bool snapshots_ok = !snap_steps.empty();
    double snapshot_wall = 0.0;
    int snapshots_here = 0;
    auto snapshot_file = [](int step) { return fmt::format("step-{:06d}.csv", step); };
    auto take_snapshot = [&](int step) {
        if (!snapshots_ok || !snap_at[static_cast<std::size_t>(step)]) return;
        const auto w0 = clock::now();
        fs::create_directories(surface);
        snapshots_ok = s.write_snapshot(*run, surface / snapshot_file(step));
        snapshot_wall += std::chrono::duration<double>(clock::now() - w0).count();
        if (snapshots_ok) ++snapshots_here;
    };
    oc.motion_file = out / "motion.csv";
    aero::write_motion(oc.motion_file, rm.motion);

    const double t0 = tr.t.front();
    // Largest difference between the body rates of the motion (from the Euler angles) and the
    // trajectory's p q r at its rows: a check of the trajectory's own consistency.
    double rate_mismatch = 0.0, rate_mismatch_t = t0;
    for (std::size_t i = 0; i < tr.size(); ++i) {
        const aero::MotionState ms = rm.motion.at(tr.t[i]);
        for (std::size_t k = 0; k < 3; ++k) {
            const double mis = std::abs(ms.omega_body[k] - tr.rates[k][i]);
            if (mis > rate_mismatch) {
                rate_mismatch = mis;
                rate_mismatch_t = tr.t[i];
            }
        }
    }
    // Table prediction at the step's instantaneous state.
    auto compare = [&](const aero::UnsteadySample& smp) {
        ComparisonRow r;
        r.t = smp.t;
        const aero::MotionState ms = rm.motion.at(smp.t);
        const aero::MotionState ts = interp.at(smp.t);
        // Phase: that of the last trajectory row at or before t.
        const auto it = std::upper_bound(tr.t.begin(), tr.t.end(), smp.t + 1e-12);
        const auto row =
            static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - tr.t.begin()) - 1));
        r.phase = row_phase[row];
        r.alpha = smp.alpha;
        r.beta = smp.beta;
        r.source_iterations = smp.iterations;
        r.source_converged = smp.converged;
        r.V = smp.airspeed;
        r.mach = ts.modes[6];
        for (std::size_t k = 0; k < 3; ++k) {
            r.rates[k] = ms.omega_body[k];
            r.controls[k] = ms.modes[k];
            r.control_rates[k] = ms.mode_rates[k];
        }
        // alpha_dot, beta_dot by a central difference of the motion's air state.
        const double h = 1e-4 * choice.dt;
        const double ta = std::max(t0, smp.t - h), tb = std::min(tr.t.back(), smp.t + h);
        const AirState a = motion_air_state(rm.motion, rm.v0, ta);
        const AirState b = motion_air_state(rm.motion, rm.v0, tb);
        const double alpha_dot = (b.alpha - a.alpha) / (tb - ta);
        const double beta_dot = (b.beta - a.beta) / (tb - ta);
        aero::AeroQuery<double> q;
        q.alpha = r.alpha;
        q.beta = r.beta;
        q.mach = r.mach;
        const double V2 = 2.0 * r.V;
        q.p_hat = r.rates[0] * s.span / V2;
        q.q_hat = r.rates[1] * s.chord / V2;
        q.r_hat = r.rates[2] * s.span / V2;
        q.alpha_dot_hat = alpha_dot * s.chord / V2;
        q.beta_dot_hat = beta_dot * s.span / V2;
        q.elevator = r.controls[0];
        q.aileron = r.controls[1];
        q.rudder = r.controls[2];
        tables.reset_out_of_range();
        const aero::BodyCoefficients<double> tb_ =
            tables.evaluate(q, aero::Interpolation::multilinear);
        r.extrapolated = tables.out_of_range().total() > 0;
        const auto tw = aero::wind_from_body(tb_.CX, tb_.CY, tb_.CZ, r.alpha, r.beta);
        r.table = {tw.CL, tw.CD, tw.CY, tb_.Cl, tb_.Cm, tb_.Cn};
        r.replay = {smp.wind.CL, smp.wind.CD, smp.wind.CY, smp.body.Cl, smp.body.Cm, smp.body.Cn};
        for (std::size_t k = 0; k < 6; ++k) {
            r.diff[k] = r.replay[k] - r.table[k];
            if (std::abs(r.diff[k]) > s.tolerances[k]) r.flag = true;
        }
        rows.push_back(r);
    };
    if (rows.empty()) {
        compare(run->current());
        take_snapshot(0);
    }

    auto elapsed = [&] { return std::chrono::duration<double>(clock::now() - wall0).count(); };
    auto write_checkpoint = [&] {
        const int step = run->current().index;
        fs::create_directories(ck);
        run->save(ck / fmt::format("state-{}.bin", step));
        core::write_file_atomic(ck / fmt::format("rows-{}.bin", step), rows_to_bytes(rows));
        const nlohmann::json cj = {{"fingerprint", fp},
                                   {"step", step},
                                   {"n_steps", n_steps},
                                   {"t", run->current().t},
                                   {"wall_time_s", wall_before + elapsed()},
                                   {"cpu_time_s", cpu_before + cpu_seconds() - cpu0}};
        core::write_file_atomic(ck / "checkpoint.json", cj.dump(2) + "\n");
        // Older states go once the new one is in place.
        for (const auto& e : fs::directory_iterator(ck)) {
            const std::string n = e.path().filename().string();
            if ((n.starts_with("state-") || n.starts_with("rows-")) &&
                n != fmt::format("state-{}.bin", step) && n != fmt::format("rows-{}.bin", step))
                fs::remove(e.path());
        }
    };
    const int start_step = run->current().index;
    auto last_checkpoint = clock::now();
    int done_here = 0;
    // The time left from the steps alone: a source's start (the Euler replay's steady solution,
    // as long as 40 of its steps on the Ranger) is not a step's cost.
    const double steps0 = elapsed();
    while (!run->finished()) {
        compare(run->step());
        ++done_here;
        const int step = run->current().index;
        take_snapshot(step);
        if (s.progress) {
            ReplayProgress p;
            p.step = step;
            p.n_steps = n_steps;
            p.t = run->current().t;
            p.elapsed_s = elapsed();
            p.remaining_s = (p.elapsed_s - steps0) / done_here * (n_steps - step);
            p.resumed_from = oc.resumed_from;
            s.progress(p);
        }
        if (s.stop_after_steps >= 0 && done_here >= s.stop_after_steps && !run->finished()) {
            write_checkpoint();
            oc.completed = false;
            return oc;
        }
        const bool by_count =
            s.checkpoint_steps > 0 && (step - start_step) % s.checkpoint_steps == 0;
        const bool by_time =
            s.checkpoint_seconds > 0.0 &&
            std::chrono::duration<double>(clock::now() - last_checkpoint).count() >=
                s.checkpoint_seconds;
        if ((by_count || by_time) && !run->finished()) {
            write_checkpoint();
            last_checkpoint = clock::now();
        }
    }

    nlohmann::json j;
    j["source"] = source.name();
    j["source_fingerprint"] = source.fingerprint();
    j["trajectory"] = s.trajectory_label.empty() ? tr.source : s.trajectory_label;
    j["manoeuvre"] = tr.meta("manoeuvre", fs::path(tr.source).stem().string());
    j["until"] = s.until > 0.0 ? nlohmann::json(s.until) : nlohmann::json(nullptr);
    j["duration"] = tr.t.back() - tr.t.front();
    j["dt"] = choice.dt;
    j["dt_reason"] = choice.reason;
    j["steps"] = n_steps;
    j["motion_sample_dt"] = rm.sample_dt;
    j["entry"] = {{"v0", rm.v0},
                  {"mach", rm.mach0},
                  {"altitude", rm.altitude0},
                  {"track", rm.chi0},
                  {"flight_path", rm.gamma0},
                  {"reynolds_per_metre", us.conditions.reynolds_per_metre}};
    j["tables"] = tables.info().name;
    j["input_warnings"] = s.input_warnings;
    j["trajectory_check"] = {
        {"rate_mismatch_max", rate_mismatch},
        {"t", rate_mismatch_t},
        {"note",
         "largest |body rate from the Euler-angle history - the trajectory's p q r| [rad/s] at "
         "the trajectory's rows"}};
    j["wall_time_s"] = wall_before + elapsed();
    j["cpu_time_s"] = cpu_before + cpu_seconds() - cpu0;
    j["resumed_from_step"] =
        oc.resumed_from >= 0 ? nlohmann::json(oc.resumed_from) : nlohmann::json(nullptr);
    j.update(summarise(rows, phases, s.tolerances, rm.mach0, s.chord, s.span));
    // The snapshots' index (every scheduled step has its file: those before a resume were
    // written by the run that reached the checkpoint).
    if (snapshots_ok) {
        std::string index = "step,t,file\n";
        oc.snapshots = 0;
        for (const int k : snap_steps) {
            if (!fs::exists(surface / snapshot_file(k))) continue;  // removed since
            ++oc.snapshots;
            index += fmt::format("{},{},{}\n", k,
                                 core::format_exact(rows[static_cast<std::size_t>(k)].t),
                                 snapshot_file(k));
        }
        core::write_file_atomic(surface / "index.csv", index);
        j["snapshots"] = {{"every_s", s.snapshot_every},
                          {"count", oc.snapshots},
                          {"index", "surface/index.csv"},
                          {"written_here", snapshots_here},
                          {"write_wall_s", snapshot_wall}};
    } else {
        j["snapshots"] = nullptr;
    }
    oc.comparison_file = out / "comparison.csv";
    oc.summary_file = out / "summary.json";
    core::write_file_atomic(oc.comparison_file, comparison_csv(rows));
    core::write_file_atomic(oc.summary_file, j.dump(2) + "\n");
    if (!s.keep_checkpoint) fs::remove_all(ck);
    oc.completed = true;
    oc.summary = std::move(j);
    return oc;
}

}  // namespace manta::replay
