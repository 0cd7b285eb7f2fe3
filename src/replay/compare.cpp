/// @file compare.cpp
/// Phases, statistics, flags and the comparison CSV of a replay (replay.hpp, docs/replay.md).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "manta/core/io.hpp"
#include "manta/replay/replay.hpp"

namespace manta::replay {

namespace {

constexpr double deg = std::numbers::pi / 180.0;

/// Automatic phase classes (docs/replay.md, "Phases").
std::string classify(double p, double q, double r) {
    if (std::abs(p) >= 20 * deg && std::abs(p) >= std::abs(q)) return "roll";
    if (q >= 5 * deg) return "pull-up";
    if (q <= -5 * deg) return "push-over";
    if (std::abs(r) >= 5 * deg) return "yaw";
    return "steady";
}

}  // namespace

std::array<double, 6> default_tolerances() {
    return {0.05, 0.01, 0.02, 0.01, 0.02, 0.01};
}

std::vector<Phase> trajectory_phases(const Trajectory& tr, std::vector<int>* row_phase) {
    const std::size_t n = tr.size();
    std::vector<int> idx(n, 0);
    std::vector<Phase> out;
    // A phase column with one value says nothing about the manoeuvre's structure: segment it.
    const bool given =
        !tr.phase.empty() &&
        std::any_of(tr.phase.begin(), tr.phase.end(), [&](int k) { return k != tr.phase.front(); });
    if (given) {
        for (std::size_t i = 0; i < n; ++i) {
            const int k = tr.phase[i];
            idx[i] = k;
            const std::string name = static_cast<std::size_t>(k) < tr.phase_names.size()
                                         ? tr.phase_names[static_cast<std::size_t>(k)]
                                         : fmt::format("phase {}", k);
            if (out.empty() || idx[i] != idx[i - 1]) out.push_back({name, tr.t[i], tr.t[i]});
            out.back().t_end = tr.t[i];
        }
    } else {
        // Classify every row, then merge runs shorter than min(1 s, duration / 10) into the
        // run before (the first into the next).
        std::vector<std::string> cls(n);
        for (std::size_t i = 0; i < n; ++i)
            cls[i] = classify(tr.rates[0][i], tr.rates[1][i], tr.rates[2][i]);
        struct Run {
            std::string name;
            std::size_t b, e;  // rows [b, e)
        };
        std::vector<Run> runs;
        for (std::size_t i = 0; i < n; ++i)
            if (runs.empty() || cls[i] != runs.back().name)
                runs.push_back({cls[i], i, i + 1});
            else
                runs.back().e = i + 1;
        const double shortest = std::min(1.0, (tr.t.back() - tr.t.front()) / 10.0);
        auto duration = [&](const Run& r) { return tr.t[r.e - 1] - tr.t[r.b]; };
        bool merged = true;
        while (merged && runs.size() > 1) {
            merged = false;
            std::size_t worst = runs.size();
            for (std::size_t k = 0; k < runs.size(); ++k)
                if (duration(runs[k]) < shortest &&
                    (worst == runs.size() || duration(runs[k]) < duration(runs[worst])))
                    worst = k;
            if (worst == runs.size()) break;
            if (worst > 0) {
                runs[worst - 1].e = runs[worst].e;
            } else {
                runs[1].b = runs[0].b;
            }
            runs.erase(runs.begin() + static_cast<std::ptrdiff_t>(worst));
            // Neighbours of the same class join.
            for (std::size_t k = 1; k < runs.size();)
                if (runs[k].name == runs[k - 1].name) {
                    runs[k - 1].e = runs[k].e;
                    runs.erase(runs.begin() + static_cast<std::ptrdiff_t>(k));
                } else {
                    ++k;
                }
            merged = true;
        }
        for (std::size_t k = 0; k < runs.size(); ++k) {
            out.push_back({runs[k].name, tr.t[runs[k].b], tr.t[runs[k].e - 1]});
            for (std::size_t i = runs[k].b; i < runs[k].e; ++i) idx[i] = static_cast<int>(k);
        }
        // Consecutive phases share their boundary.
        for (std::size_t k = 1; k < out.size(); ++k) out[k - 1].t_end = out[k].t_start;
    }
    if (row_phase) *row_phase = std::move(idx);
    return out;
}

std::string comparison_csv(const std::vector<ComparisonRow>& rows) {
    std::string s =
        "t,phase,alpha,beta,V,mach,p,q,r,elevator,aileron,rudder,elevator_rate,aileron_rate,"
        "rudder_rate";
    for (const char* c : coefficient_names) s += fmt::format(",{0}_replay,{0}_table,{0}_diff", c);
    // An iterative source's iterations per step (the Euler source's inner iterations).
    const bool iterative = std::any_of(rows.begin(), rows.end(), [](const ComparisonRow& r) {
        return r.source_iterations > 0 || !r.source_converged;
    });
    s += iterative ? ",flag,source_iterations,source_converged\n" : ",flag\n";
    auto x = [](double v) { return core::format_exact(v); };
    for (const ComparisonRow& r : rows) {
        s += fmt::format("{},{},{},{},{},{}", x(r.t), r.phase, x(r.alpha), x(r.beta), x(r.V),
                         x(r.mach));
        for (const auto* group : {&r.rates, &r.controls, &r.control_rates})
            for (const double v : *group) {
                s += ',';
                s += x(v);
            }
        for (std::size_t k = 0; k < 6; ++k)
            s += fmt::format(",{},{},{}", x(r.replay[k]), x(r.table[k]), x(r.diff[k]));
        s += r.flag ? ",1" : ",0";
        if (iterative) s += fmt::format(",{},{}", r.source_iterations, r.source_converged ? 1 : 0);
        s += '\n';
    }
    return s;
}

nlohmann::json summarise(const std::vector<ComparisonRow>& rows, const std::vector<Phase>& phases,
                         const std::array<double, 6>& tol, double entry_mach, double chord,
                         double span) {
    nlohmann::json j;
    nlohmann::json tj = nlohmann::json::object();
    for (std::size_t k = 0; k < 6; ++k) tj[coefficient_names[k]] = tol[k];
    j["tolerances"] = tj;
    auto stats = [&](std::size_t b, std::size_t e, bool full) {
        nlohmann::json c = nlohmann::json::object();
        for (std::size_t k = 0; k < 6; ++k) {
            double ss = 0.0, mx = 0.0, tmax = rows.empty() ? 0.0 : rows[b].t, mr = 0.0, mt = 0.0;
            for (std::size_t i = b; i < e; ++i) {
                const double d = rows[i].diff[k];
                ss += d * d;
                if (std::abs(d) > mx) {
                    mx = std::abs(d);
                    tmax = rows[i].t;
                }
                mr += rows[i].replay[k];
                mt += rows[i].table[k];
            }
            const double n = std::max<double>(1.0, static_cast<double>(e - b));
            nlohmann::json o = {{"rms", std::sqrt(ss / n)}, {"max_abs", mx}};
            if (full) {
                o["t_max"] = tmax;
                o["mean_replay"] = mr / n;
                o["mean_table"] = mt / n;
            }
            c[coefficient_names[k]] = o;
        }
        return c;
    };
    j["coefficients"] = stats(0, rows.size(), true);
    nlohmann::json pj = nlohmann::json::array();
    for (std::size_t k = 0; k < phases.size(); ++k) {
        const Phase& ph = phases[k];
        const bool last = k + 1 == phases.size();
        std::size_t b = rows.size(), e = 0;
        for (std::size_t i = 0; i < rows.size(); ++i)
            if (rows[i].t >= ph.t_start &&
                (rows[i].t < ph.t_end || (last && rows[i].t <= ph.t_end))) {
                b = std::min(b, i);
                e = i + 1;
            }
        nlohmann::json o = {{"name", ph.name}, {"t_start", ph.t_start}, {"t_end", ph.t_end}};
        o["steps"] = b < e ? static_cast<int>(e - b) : 0;
        o["coefficients"] = b < e ? stats(b, e, false) : nlohmann::json::object();
        pj.push_back(o);
    }
    j["phases"] = pj;
    // An iterative source's effort: the start's iterations (row 0) and those of the steps.
    const bool iterative = std::any_of(rows.begin(), rows.end(), [](const ComparisonRow& r) {
        return r.source_iterations > 0 || !r.source_converged;
    });
    if (iterative) {
        long total = 0;
        int most = 0, unconverged = 0;
        double t_most = rows.front().t;
        for (std::size_t i = 1; i < rows.size(); ++i) {
            total += rows[i].source_iterations;
            if (rows[i].source_iterations > most) {
                most = rows[i].source_iterations;
                t_most = rows[i].t;
            }
            if (!rows[i].source_converged) ++unconverged;
        }
        const auto steps = static_cast<long>(rows.size()) - 1;
        j["source_iterations"] = {
            {"start", rows.front().source_iterations},
            {"start_converged", rows.front().source_converged},
            {"steps", steps},
            {"total", total},
            {"mean_per_step", steps > 0 ? static_cast<double>(total) / steps : 0.0},
            {"max", most},
            {"t_max", t_most},
            {"unconverged_steps", unconverged}};
    } else {
        j["source_iterations"] = nullptr;
    }
    // Mean difference of each coefficient over the replay: a flag of a coefficient whose mean
    // difference exceeds half its tolerance is (also) a systematic source-table offset.
    std::array<double, 6> mean_diff{};
    for (const ComparisonRow& w : rows)
        for (std::size_t k = 0; k < 6; ++k)
            mean_diff[k] += w.diff[k] / static_cast<double>(rows.size());
    // Flagged intervals: runs of consecutive flagged rows.
    nlohmann::json fj = nlohmann::json::array();
    int flagged = 0, extrapolated = 0;
    for (std::size_t i = 0; i < rows.size();) {
        if (rows[i].extrapolated) ++extrapolated;
        if (!rows[i].flag) {
            ++i;
            continue;
        }
        std::size_t e = i;
        while (e < rows.size() && rows[e].flag) ++e;
        flagged += static_cast<int>(e - i);
        std::array<double, 6> maxd{};
        std::array<bool, 6> over{};
        double a_max = 0.0, b_max = 0.0, w_max = 0.0, dr_max = 0.0, m_max = 0.0, dm_max = 0.0;
        std::array<double, 3> hat_max{}, rate_max{};
        bool extra = false;
        for (std::size_t r = i; r < e; ++r) {
            const ComparisonRow& w = rows[r];
            for (std::size_t k = 0; k < 6; ++k) {
                if (std::abs(w.diff[k]) > std::abs(maxd[k])) maxd[k] = w.diff[k];
                if (std::abs(w.diff[k]) > tol[k]) over[k] = true;
            }
            a_max = std::max(a_max, std::abs(w.alpha));
            b_max = std::max(b_max, std::abs(w.beta));
            const std::array<double, 3> len{span, chord, span};
            for (std::size_t k = 0; k < 3; ++k) {
                w_max = std::max(w_max, std::abs(w.rates[k]));
                hat_max[k] = std::max(hat_max[k], std::abs(w.rates[k]) * len[k] / (2.0 * w.V));
                rate_max[k] = std::max(rate_max[k], std::abs(w.control_rates[k]));
                dr_max = std::max(dr_max, std::abs(w.control_rates[k]));
            }
            m_max = std::max(m_max, w.mach);
            dm_max = std::max(dm_max, std::abs(w.mach - entry_mach));
            extra = extra || w.extrapolated;
        }
        nlohmann::json o;
        o["t_start"] = rows[i].t;
        o["t_end"] = rows[e - 1].t;
        o["steps"] = static_cast<int>(e - i);
        nlohmann::json names = nlohmann::json::array(), md = nlohmann::json::object();
        for (std::size_t k = 0; k < 6; ++k)
            if (over[k]) {
                names.push_back(coefficient_names[k]);
                md[coefficient_names[k]] = maxd[k];
            }
        o["coefficients"] = names;
        o["max_diff"] = md;
        o["state"] = {{"alpha_max", a_max},      {"beta_max", b_max},
                      {"rate_max", w_max},       {"control_rate_max", dr_max},
                      {"mach_max", m_max},       {"p_hat_max", hat_max[0]},
                      {"q_hat_max", hat_max[1]}, {"r_hat_max", hat_max[2]}};
        nlohmann::json why = nlohmann::json::array();
        if (a_max > 10 * deg) why.push_back("high angle of attack");
        if (b_max > 5 * deg) why.push_back("high sideslip");
        if (hat_max[1] > 0.005) why.push_back("high pitch rate");
        if (hat_max[0] > 0.05) why.push_back("high roll rate");
        if (hat_max[2] > 0.01) why.push_back("high yaw rate");
        const std::array<const char*, 3> ctl{"elevator", "aileron", "rudder"};
        for (std::size_t k = 0; k < 3; ++k)
            if (rate_max[k] > 0.5) why.push_back(fmt::format("fast {} motion", ctl[k]));
        if (m_max > 0.6) why.push_back("high Mach");
        if (dm_max > 0.05)
            why.push_back("Mach away from the entry Mach (the source keeps the entry free stream)");
        if (extra) why.push_back("outside the table's range (extrapolated)");
        for (std::size_t k = 0; k < 6; ++k)
            if (over[k] && std::abs(mean_diff[k]) > 0.5 * tol[k])
                why.push_back(fmt::format(
                    "systematic {} offset between source and tables (mean difference {:.3g} over "
                    "the replay)",
                    coefficient_names[k], mean_diff[k]));
        if (why.empty())
            why.push_back(
                "none of the listed state extremes: unsteady (wake) effects or table "
                "resolution");
        o["reasons"] = why;
        fj.push_back(o);
        i = e;
    }
    j["flags"] = fj;
    j["flagged_steps"] = flagged;
    j["extrapolated_steps"] = extrapolated;
    return j;
}

}  // namespace manta::replay
