/// @file multiphase.cpp
/// Multi-phase problems: input checks, the NLP of the phases side by side with their linkage
/// rows (detail/multiphase.hpp), the derivative check and the summary. `solve`: nlp.cpp.

#include "detail/multiphase.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "detail/check.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"

namespace manta::optimal {

namespace {

std::string phase_name(const MultiPhaseProblem& mp, int k) {
    const auto& m = mp.phases[static_cast<std::size_t>(k)].model;
    const std::string n = m ? m->info().name : std::string();
    return n.empty() ? fmt::format("phase {}", k) : fmt::format("phase {} '{}'", k, n);
}

std::string where(const MultiPhaseProblem& mp) {
    return "multi-phase problem" + (mp.name.empty() ? std::string() : " '" + mp.name + "'");
}

/// The bounds of x(t0) (initial) or x(tf) of state r: the state's own, narrowed by
/// initial_states / final_states.
Bounds end_bounds(const ProblemInfo& info, int r, bool initial) {
    const Variable& v = info.states[static_cast<std::size_t>(r)];
    Bounds b{v.lower, v.upper};
    const auto& ends = initial ? info.initial_states : info.final_states;
    if (!ends.empty()) {
        b.lower = std::max(b.lower, ends[static_cast<std::size_t>(r)].lower);
        b.upper = std::min(b.upper, ends[static_cast<std::size_t>(r)].upper);
    }
    return b;
}

double nlp_bound(double b) {
    if (b >= detail::kNlpInf) return detail::kNlpInf;
    if (b <= -detail::kNlpInf) return -detail::kNlpInf;
    return b;
}

/// Typical magnitude of a linkage row: its scale, else the larger finite bound, else 1.
double row_magnitude(const Constraint& c) {
    if (c.scale > 0.0) return c.scale;
    double s = 0.0;
    if (std::isfinite(c.lower)) s = std::max(s, std::abs(c.lower));
    if (std::isfinite(c.upper)) s = std::max(s, std::abs(c.upper));
    return s > 1e-12 ? s : 1.0;
}

}  // namespace

int MultiPhaseProblem::n_links() const {
    return links.empty() ? std::max(0, n_phases() - 1) : static_cast<int>(links.size());
}

Link MultiPhaseProblem::link(int k) const {
    Link L = links.empty() ? Link{} : links.at(static_cast<std::size_t>(k));
    if (L.from == -1 && L.to == -1) {
        L.from = k;
        L.to = k + 1;
    }
    return L;
}

void MultiPhaseProblem::validate() const {
    const std::string w = where(*this);
    if (phases.empty()) throw InputError(w + ": 0 phases, expected at least 1");
    const int N = n_phases();
    for (int k = 0; k < N; ++k) {
        const Phase& ph = phases[static_cast<std::size_t>(k)];
        if (!ph.model) throw InputError(w + ": phase " + std::to_string(k) + " has no model");
        ph.model->info().validate();
        ph.mesh.validate();
    }
    const bool by_position = std::all_of(links.begin(), links.end(),
                                         [](const Link& l) { return l.from == -1 && l.to == -1; });
    if (!links.empty() && by_position && static_cast<int>(links.size()) != N - 1) {
        throw InputError(
            fmt::format("{}: {} links for {} phases, expected {} (one per pair of "
                        "consecutive phases) or none (continuity everywhere), or links with "
                        "from and to set",
                        w, links.size(), N, N - 1));
    }
    for (std::size_t k = 0; k < links.size(); ++k) {
        const Link& L = links[k];
        if (L.from == -1 && L.to == -1) {
            if (static_cast<int>(k) + 1 >= N) {
                throw InputError(fmt::format(
                    "{}: link {} is by position (from = to = -1), phase {} to {}, but there are "
                    "{} phases; expected from and to set for it",
                    w, k, k, k + 1, N));
            }
            continue;
        }
        if (L.from < 0 || L.from >= N || L.to < 0 || L.to >= N) {
            throw InputError(fmt::format(
                "{}: link {}: from = {} and to = {}, expected phase indices in [0, {}] (or both "
                "-1: phase {} to {})",
                w, k, L.from, L.to, N - 1, k, k + 1));
        }
        if (L.from == L.to) {
            throw InputError(fmt::format(
                "{}: link {}: from = to = {}, expected two different phases", w, k, L.from));
        }
    }
    // time continuity around a cycle of links (a -> b -> ... -> a) would make the phases'
    // durations sum to zero: a link that closes such a cycle is rejected (one link of a periodic
    // cycle must leave its times independent)
    {
        std::vector<std::vector<int>> next(static_cast<std::size_t>(N));
        for (int k = 0; k < n_links(); ++k) {
            const Link L = link(k);
            if (!L.time_continuity) continue;
            std::vector<int> stack{L.to};
            std::vector<bool> seen(static_cast<std::size_t>(N), false);
            bool cycle = false;
            while (!stack.empty() && !cycle) {
                const int v = stack.back();
                stack.pop_back();
                if (v == L.from) cycle = true;
                if (seen[static_cast<std::size_t>(v)]) continue;
                seen[static_cast<std::size_t>(v)] = true;
                for (int u : next[static_cast<std::size_t>(v)]) stack.push_back(u);
            }
            if (cycle) {
                throw InputError(fmt::format(
                    "{}: link {} (phase {} -> {}) closes a cycle of links with time continuity, "
                    "expected time_continuity = false on one link of a cycle",
                    w, k, L.from, L.to));
            }
            next[static_cast<std::size_t>(L.from)].push_back(L.to);
        }
    }
    const ProblemInfo& first = phases[0].model->info();
    for (int k = 1; k < N; ++k) {
        const ProblemInfo& info = phases[static_cast<std::size_t>(k)].model->info();
        bool same = info.n_parameters() == first.n_parameters();
        for (int j = 0; same && j < first.n_parameters(); ++j) {
            same = info.parameters[static_cast<std::size_t>(j)].name ==
                   first.parameters[static_cast<std::size_t>(j)].name;
        }
        if (!same) {
            auto names = [](const ProblemInfo& p) {
                std::string s;
                for (const auto& v : p.parameters) s += (s.empty() ? "" : ", ") + v.name;
                return "[" + s + "]";
            };
            throw InputError(fmt::format(
                "{}: {} has parameters {}, expected those of {}, {} "
                "(static parameters are shared by all phases)",
                w, phase_name(*this, k), names(info), phase_name(*this, 0), names(first)));
        }
    }
    // the sense of the sum: that of the phases with an objective (Mayer or Lagrange)
    int sense_phase = -1;
    for (int k = 0; k < N; ++k) {
        const Model& m = *phases[static_cast<std::size_t>(k)].model;
        if (!m.has_mayer() && !m.has_lagrange()) continue;
        if (sense_phase < 0) {
            sense_phase = k;
            continue;
        }
        const bool a = phases[static_cast<std::size_t>(sense_phase)].model->info().maximise;
        if (m.info().maximise != a) {
            throw InputError(
                fmt::format("{}: {} is {} and {} {}, expected one sense for the sum "
                            "of the phases' objectives",
                            w, phase_name(*this, k), m.info().maximise ? "maximised" : "minimised",
                            phase_name(*this, sense_phase), a ? "maximised" : "minimised"));
        }
    }
    if (mayer) {
        const std::vector<int>& mp = mayer->phases();
        if (mp.empty()) {
            throw InputError(w +
                             ": the cross-phase Mayer term lists no phases, expected at least one");
        }
        for (std::size_t i = 0; i < mp.size(); ++i) {
            if (mp[i] < 0 || mp[i] >= N) {
                throw InputError(fmt::format(
                    "{}: the cross-phase Mayer term's phase {} is {}, expected a phase index in "
                    "[0, {}]",
                    w, i, mp[i], N - 1));
            }
            if (std::find(mp.begin(), mp.begin() + static_cast<std::ptrdiff_t>(i), mp[i]) !=
                mp.begin() + static_cast<std::ptrdiff_t>(i)) {
                throw InputError(
                    fmt::format("{}: the cross-phase Mayer term lists phase {} twice, expected "
                                "each phase once",
                                w, mp[i]));
            }
        }
        if (sense_phase >= 0) {
            const bool a = phases[static_cast<std::size_t>(sense_phase)].model->info().maximise;
            if (mayer->maximise() != a) {
                throw InputError(fmt::format(
                    "{}: the cross-phase Mayer term is {} and {} {}, expected one sense for "
                    "the sum of the objectives",
                    w, mayer->maximise() ? "maximised" : "minimised",
                    phase_name(*this, sense_phase), a ? "maximised" : "minimised"));
            }
        }
    }
    for (int k = 0; k < n_links(); ++k) {
        const Link L = link(k);
        const ProblemInfo& a = phases[static_cast<std::size_t>(L.from)].model->info();
        const ProblemInfo& b = phases[static_cast<std::size_t>(L.to)].model->info();
        const std::string lk = fmt::format("{}: link {} ({} -> {})", w, k,
                                           phase_name(*this, L.from), phase_name(*this, L.to));
        if (L.time_continuity) {
            const Bounds tf = a.final_time, t0 = b.initial_time;
            if (std::max(tf.lower, t0.lower) > std::min(tf.upper, t0.upper)) {
                throw InputError(fmt::format(
                    "{}: tf in [{:g}, {:g}] and the next t0 in [{:g}, {:g}] do not overlap, "
                    "expected overlapping bounds for t0_{} = tf_{} (set the next phase's "
                    "initial_time free or equal)",
                    lk, tf.lower, tf.upper, t0.lower, t0.upper, L.to, L.from));
            }
        }
        if (!L.function) {
            if (a.n_states() != b.n_states()) {
                throw InputError(fmt::format(
                    "{}: continuity needs equal state counts, {} and {} states, expected a "
                    "linkage function (make_link) for phases with different states",
                    lk, a.n_states(), b.n_states()));
            }
            for (int r = 0; r < a.n_states(); ++r) {
                const Bounds e = end_bounds(a, r, false), s = end_bounds(b, r, true);
                if (std::max(e.lower, s.lower) > std::min(e.upper, s.upper)) {
                    throw InputError(fmt::format(
                        "{}: state '{}' ends in [{:g}, {:g}] and the next phase's '{}' starts in "
                        "[{:g}, {:g}], expected overlapping bounds across a continuity link",
                        lk, a.states[static_cast<std::size_t>(r)].name, e.lower, e.upper,
                        b.states[static_cast<std::size_t>(r)].name, s.lower, s.upper));
                }
            }
        } else {
            const LinkModel& f = *L.function;
            if (f.n_from() != a.n_states() || f.n_to() != b.n_states()) {
                throw InputError(fmt::format(
                    "{}: the linkage function takes {} final and {} initial states, expected {} "
                    "and {} (the states of the two phases)",
                    lk, f.n_from(), f.n_to(), a.n_states(), b.n_states()));
            }
            if (f.constraints().empty()) {
                throw InputError(lk +
                                 ": the linkage function has no constraints, expected at "
                                 "least one");
            }
            for (const auto& c : f.constraints()) {
                if (!(c.lower <= c.upper)) {
                    throw InputError(
                        fmt::format("{}: linkage constraint '{}': bounds [{:g}, "
                                    "{:g}], expected lower <= upper",
                                    lk, c.name, c.lower, c.upper));
                }
            }
        }
    }
}

double MultiPhaseSolution::max_resimulation_error() const {
    double e = 0.0;
    for (const auto& s : phases) {
        if (s.resimulation.done) e = std::max(e, s.resimulation.max_scaled_error);
    }
    return e;
}

std::string summary(const MultiPhaseSolution& sol) {
    std::string s = fmt::format(
        "status {}, objective {:.10g}, {} phases, {} IPOPT iterations, "
        "{:.3f} s CPU, max violation {:.2e} (links {:.2e})\n",
        to_string(sol.status), sol.objective, sol.phases.size(), sol.iterations, sol.cpu_time,
        sol.max_violation, sol.max_link_violation);
    for (std::size_t k = 0; k < sol.phases.size(); ++k) {
        const Solution& p = sol.phases[k];
        s += fmt::format("phase {} '{}': t0 {:.10g}, tf {:.10g}, objective part {:.10g}", k,
                         p.info.name, p.initial_time, p.final_time, p.objective);
        const int nx = p.info.n_states();
        if (!p.segments.empty()) {
            const auto& a = p.segments.front().states;
            const auto& b = p.segments.back().states;
            for (int r = 0; r < nx; ++r) {
                s += fmt::format(", {} {:.8g} -> {:.8g}",
                                 p.info.states[static_cast<std::size_t>(r)].name, a(0, r),
                                 b(b.rows() - 1, r));
            }
        }
        s += "\n";
    }
    return s;
}

void write_csv(const MultiPhaseSolution& sol, const std::filesystem::path& file) {
    // the union of the phases' columns by name, in order of first appearance, per kind
    enum Kind { state, control, costate, path, n_kinds };
    std::vector<std::string> names[n_kinds];
    auto add = [&](Kind kind, const std::string& n) {
        auto& v = names[kind];
        if (std::find(v.begin(), v.end(), n) == v.end()) v.push_back(n);
    };
    for (const Solution& p : sol.phases) {
        for (const auto& v : p.info.states) add(state, v.name);
        for (const auto& v : p.info.controls) add(control, v.name);
        for (const auto& v : p.info.states) add(costate, v.name);
        for (const auto& c : p.info.path) add(path, c.name);
    }
    std::ostringstream out;
    out << "phase,t,segment,node";
    for (const auto& n : names[state]) out << ',' << n;
    for (const auto& n : names[control]) out << ',' << n;
    for (const auto& n : names[costate]) out << ",lambda_" << n;
    for (const auto& n : names[path]) out << ',' << n;
    out << '\n';
    for (std::size_t k = 0; k < sol.phases.size(); ++k) {
        const Solution& p = sol.phases[k];
        // per union column, the phase's column index (-1: none)
        auto index = [](const auto& own, const std::string& n) {
            for (std::size_t i = 0; i < own.size(); ++i) {
                if (own[i].name == n) return static_cast<Eigen::Index>(i);
            }
            return Eigen::Index{-1};
        };
        std::vector<Eigen::Index> at[n_kinds];
        for (const auto& n : names[state]) at[state].push_back(index(p.info.states, n));
        for (const auto& n : names[control]) at[control].push_back(index(p.info.controls, n));
        for (const auto& n : names[costate]) at[costate].push_back(index(p.info.states, n));
        for (const auto& n : names[path]) at[path].push_back(index(p.info.path, n));
        for (std::size_t s = 0; s < p.segments.size(); ++s) {
            const SegmentSolution& seg = p.segments[s];
            const Eigen::MatrixXd* m[n_kinds] = {&seg.states, &seg.controls, &seg.costates,
                                                 &seg.path};
            for (Eigen::Index i = 0; i < seg.time.size(); ++i) {
                out << fmt::format("{},{:.17g},{},{}", k, seg.time(i), s, i);
                for (int kind = 0; kind < n_kinds; ++kind) {
                    for (Eigen::Index c : at[kind]) {
                        out << ',';
                        if (c >= 0 && c < m[kind]->cols())
                            out << fmt::format("{:.17g}", (*m[kind])(i, c));
                    }
                }
                out << '\n';
            }
        }
    }
    core::write_file_atomic(file, out.str());  // creates the folder
}

DerivativeCheck check_derivatives(const MultiPhaseProblem& problem, double perturbation,
                                  unsigned seed) {
    detail::MultiTranscription tr(problem);
    std::vector<double> z(static_cast<std::size_t>(tr.n_vars()));
    tr.initial_point(z.data());
    return detail::check_nlp(tr, std::move(z), perturbation, seed);
}

}  // namespace manta::optimal

namespace manta::optimal::detail {

MultiTranscription::MultiTranscription(const MultiPhaseProblem& problem) : problem_(problem) {
    problem.validate();
    const int N = problem.n_phases();
    std::map<std::pair<int, int>, int> hess_index;
    for (int k = 0; k < N; ++k) {
        const Phase& ph = problem.phases[static_cast<std::size_t>(k)];
        tr_.push_back(std::make_unique<Transcription>(*ph.model, ph.mesh));
        Transcription& t = *tr_.back();
        var_off_.push_back(n_vars_);
        row_off_.push_back(n_rows_);
        jac_off_.push_back(nnz_jacobian());
        hess_off_.push_back(nnz_hessian());
        std::vector<int> r(static_cast<std::size_t>(t.nnz_jacobian())),
            c(static_cast<std::size_t>(t.nnz_jacobian()));
        t.jacobian_structure(r.data(), c.data());
        for (std::size_t e = 0; e < r.size(); ++e) {
            jac_row_.push_back(n_rows_ + r[e]);
            jac_col_.push_back(n_vars_ + c[e]);
        }
        r.resize(static_cast<std::size_t>(t.nnz_hessian()));
        c.resize(r.size());
        t.hessian_structure(r.data(), c.data());
        for (std::size_t e = 0; e < r.size(); ++e) {
            const int hr = n_vars_ + r[e], hc = n_vars_ + c[e];
            hess_index.emplace(std::make_pair(hr, hc), static_cast<int>(hess_row_.size()));
            hess_row_.push_back(hr);
            hess_col_.push_back(hc);
        }
        n_vars_ += t.n_vars();
        n_rows_ += t.n_rows();
    }
    const ProblemInfo& first = problem.phases[0].model->info();
    np_ = first.n_parameters();
    bool sense_found = false;
    for (const auto& t : tr_) {
        if (t->model().has_mayer() || t->model().has_lagrange()) {
            maximise_ = t->model().info().maximise;
            sense_found = true;
            break;
        }
    }
    if (!sense_found && problem.mayer) maximise_ = problem.mayer->maximise();
    auto col = [&](int k, int local) { return var_off_[static_cast<std::size_t>(k)] + local; };
    // a Hessian entry at (ci, cj) of the whole NLP, shared with a phase's or a link's entry
    auto hess_entry = [&](int ci, int cj) {
        const auto key = std::make_pair(std::max(ci, cj), std::min(ci, cj));
        auto it = hess_index.find(key);
        if (it == hess_index.end()) {
            it = hess_index.emplace(key, static_cast<int>(hess_row_.size())).first;
            hess_row_.push_back(key.first);
            hess_col_.push_back(key.second);
        }
        return it->second;
    };
    // the rows p^b - p^0 = 0 of phase b (b >= 1), once per phase
    std::vector<bool> tied(static_cast<std::size_t>(N), false);
    tied[0] = true;
    auto tie_rows = [&](int b) {
        const int row = n_rows_;
        for (int j = 0; j < np_; ++j) {
            jac_row_.push_back(row + j);
            jac_col_.push_back(col(b, tr_[static_cast<std::size_t>(b)]->parameter_col(j)));
            jac_row_.push_back(row + j);
            jac_col_.push_back(col(0, tr_[0]->parameter_col(j)));
        }
        n_rows_ += np_;
        tied[static_cast<std::size_t>(b)] = true;
        return row;
    };
    for (int k = 0; k < problem.n_links(); ++k) {
        const Link lk = problem.link(k);
        const Transcription& a = *tr_[static_cast<std::size_t>(lk.from)];
        const Transcription& b = *tr_[static_cast<std::size_t>(lk.to)];
        const ProblemInfo& ia = a.model().info();
        const ProblemInfo& ib = b.model().info();
        LinkRows L;
        L.from = lk.from;
        L.to = lk.to;
        L.fn = lk.function;
        L.jac_start = nnz_jacobian();
        // a row between two fixed values (checked equal by validate) would leave IPOPT an
        // equality without free variables: such time and continuity rows are left out
        if (lk.time_continuity && !(ia.final_time.is_fixed() && ib.initial_time.is_fixed())) {
            L.time_row = n_rows_++;
            jac_row_.push_back(L.time_row);
            jac_col_.push_back(col(L.to, b.initial_time_col()));
            jac_row_.push_back(L.time_row);
            jac_col_.push_back(col(L.from, a.final_time_col()));
        }
        L.first_row = n_rows_;
        if (!L.fn) {
            for (int r = 0; r < ia.n_states(); ++r) {
                if (end_bounds(ia, r, false).is_fixed() && end_bounds(ib, r, true).is_fixed())
                    continue;
                const int row = L.first_row + L.n++;
                L.states.push_back(r);
                L.constraints.push_back(
                    {"continuity " + ia.states[static_cast<std::size_t>(r)].name, 0.0, 0.0, 0.0});
                jac_row_.push_back(row);
                jac_col_.push_back(col(L.to, b.initial_state_col(r)));
                jac_row_.push_back(row);
                jac_col_.push_back(col(L.from, a.final_state_col(r)));
            }
        } else {
            L.constraints = L.fn->constraints();
            L.n = static_cast<int>(L.constraints.size());
            for (int r = 0; r < ia.n_states(); ++r)
                L.cols.push_back(col(L.from, a.final_state_col(r)));
            for (int r = 0; r < ib.n_states(); ++r)
                L.cols.push_back(col(L.to, b.initial_state_col(r)));
            for (int j = 0; j < np_; ++j) L.cols.push_back(col(0, tr_[0]->parameter_col(j)));
            if (L.fn->uses_times()) {
                L.cols.push_back(col(L.from, a.initial_time_col()));
                L.cols.push_back(col(L.from, a.final_time_col()));
                L.cols.push_back(col(L.to, b.initial_time_col()));
                L.cols.push_back(col(L.to, b.final_time_col()));
            }
            const int nc = static_cast<int>(L.cols.size());
            for (int r = 0; r < L.n; ++r) {
                for (int c = 0; c < nc; ++c) {
                    jac_row_.push_back(L.first_row + r);
                    jac_col_.push_back(L.cols[static_cast<std::size_t>(c)]);
                }
            }
            if (!L.fn->linear()) {
                L.hess_index.assign(static_cast<std::size_t>(nc * nc), -1);
                for (int i = 0; i < nc; ++i) {
                    for (int j = 0; j <= i; ++j) {
                        L.hess_index[static_cast<std::size_t>(i * nc + j)] =
                            hess_entry(L.cols[static_cast<std::size_t>(i)],
                                       L.cols[static_cast<std::size_t>(j)]);
                    }
                }
            }
        }
        n_rows_ += L.n;
        if (np_ > 0 && !tied[static_cast<std::size_t>(L.to)]) L.param_row = tie_rows(L.to);
        links_.push_back(std::move(L));
    }
    untied_jac_start_ = nnz_jacobian();
    if (np_ > 0) {
        for (int k = 1; k < N; ++k) {
            if (!tied[static_cast<std::size_t>(k)]) untied_.emplace_back(k, tie_rows(k));
        }
    }
    if (problem.mayer) {
        mayer_ = problem.mayer;
        mayer_sign_ = mayer_->maximise() ? -1.0 : 1.0;
        for (int k : mayer_->phases()) {
            const Transcription& t = *tr_[static_cast<std::size_t>(k)];
            const int nx = t.model().info().n_states();
            mayer_n_states_.push_back(nx);
            for (int r = 0; r < nx; ++r) mayer_cols_.push_back(col(k, t.initial_state_col(r)));
            for (int r = 0; r < nx; ++r) mayer_cols_.push_back(col(k, t.final_state_col(r)));
            mayer_cols_.push_back(col(k, t.initial_time_col()));
            mayer_cols_.push_back(col(k, t.final_time_col()));
        }
        for (int j = 0; j < np_; ++j) mayer_cols_.push_back(col(0, tr_[0]->parameter_col(j)));
        const int nc = static_cast<int>(mayer_cols_.size());
        mayer_hess_index_.assign(static_cast<std::size_t>(nc * nc), -1);
        for (int i = 0; i < nc; ++i) {
            for (int j = 0; j <= i; ++j) {
                mayer_hess_index_[static_cast<std::size_t>(i * nc + j)] =
                    hess_entry(mayer_cols_[static_cast<std::size_t>(i)],
                               mayer_cols_[static_cast<std::size_t>(j)]);
            }
        }
    }
}

void MultiTranscription::bounds(double* x_l, double* x_u, double* g_l, double* g_u) const {
    for (std::size_t k = 0; k < tr_.size(); ++k) {
        tr_[k]->bounds(x_l + var_off_[k], x_u + var_off_[k], g_l + row_off_[k], g_u + row_off_[k]);
    }
    for (const auto& L : links_) {
        if (L.time_row >= 0) g_l[L.time_row] = g_u[L.time_row] = 0.0;
        for (int r = 0; r < L.n; ++r) {
            const Constraint& c = L.constraints[static_cast<std::size_t>(r)];
            g_l[L.first_row + r] = nlp_bound(c.lower);
            g_u[L.first_row + r] = nlp_bound(c.upper);
        }
        if (L.param_row >= 0) {
            for (int j = 0; j < np_; ++j) g_l[L.param_row + j] = g_u[L.param_row + j] = 0.0;
        }
    }
    for (const auto& [k, row] : untied_) {
        for (int j = 0; j < np_; ++j) g_l[row + j] = g_u[row + j] = 0.0;
    }
}

void MultiTranscription::initial_point(double* z) const {
    for (std::size_t k = 0; k < tr_.size(); ++k) {
        tr_[k]->initial_point(problem_.phases[k].guess, z + var_off_[k]);
    }
}

void MultiTranscription::scaling(const double* z0, Eigen::VectorXd& var_scale,
                                 Eigen::VectorXd& row_scale, double& obj_scale) {
    var_scale = Eigen::VectorXd::Ones(n_vars_);
    row_scale = Eigen::VectorXd::Ones(n_rows_);
    double user_obj_scale = 0.0;
    for (std::size_t k = 0; k < tr_.size(); ++k) {
        Eigen::VectorXd vs, rs;
        double os = 1.0;
        tr_[k]->scaling(z0 + var_off_[k], vs, rs, os);
        var_scale.segment(var_off_[k], vs.size()) = vs;
        row_scale.segment(row_off_[k], rs.size()) = rs;
        user_obj_scale = std::max(user_obj_scale, tr_[k]->model().info().objective_scale);
    }
    for (const auto& L : links_) {
        const Transcription& a = *tr_[static_cast<std::size_t>(L.from)];
        const int off = var_off_[static_cast<std::size_t>(L.from)];
        if (L.time_row >= 0) row_scale(L.time_row) = var_scale(off + a.final_time_col());
        for (int r = 0; r < L.n; ++r) {
            row_scale(L.first_row + r) =
                L.fn ? row_magnitude(L.constraints[static_cast<std::size_t>(r)])
                     : var_scale(off + a.final_state_col(L.states[static_cast<std::size_t>(r)]));
        }
        if (L.param_row >= 0) {
            for (int j = 0; j < np_; ++j)
                row_scale(L.param_row + j) = var_scale(var_off_[0] + tr_[0]->parameter_col(j));
        }
    }
    for (const auto& [k, row] : untied_) {
        for (int j = 0; j < np_; ++j)
            row_scale(row + j) = var_scale(var_off_[0] + tr_[0]->parameter_col(j));
    }
    row_scale_ = row_scale;
    if (user_obj_scale > 0.0) {
        obj_scale = user_obj_scale;
    } else {
        const double j0 = std::abs(objective(z0));
        obj_scale = std::isfinite(j0) && j0 > 1e-8 ? j0 : 1.0;
    }
}

bool MultiTranscription::reference_scaling(Eigen::VectorXd& offset, Eigen::VectorXd& span) const {
    offset = Eigen::VectorXd::Zero(n_vars_);
    span = Eigen::VectorXd::Zero(n_vars_);
    bool any = false;
    for (std::size_t k = 0; k < tr_.size(); ++k) {
        Eigen::VectorXd o, s;
        if (tr_[k]->reference_scaling(o, s)) {
            any = true;
            offset.segment(var_off_[k], o.size()) = o;
            span.segment(var_off_[k], s.size()) = s;
        }
    }
    return any;
}

void MultiTranscription::jacobian_structure(int* rows, int* cols) const {
    std::copy(jac_row_.begin(), jac_row_.end(), rows);
    std::copy(jac_col_.begin(), jac_col_.end(), cols);
}

void MultiTranscription::hessian_structure(int* rows, int* cols) const {
    std::copy(hess_row_.begin(), hess_row_.end(), rows);
    std::copy(hess_col_.begin(), hess_col_.end(), cols);
}

double MultiTranscription::mayer_value(const double* z) const {
    if (!mayer_) return 0.0;
    work_.clear();
    for (int c : mayer_cols_) work_.push_back(z[c]);
    return mayer_->value(work_, mayer_n_states_);
}

double MultiTranscription::user_objective(const double* z) {
    double j = 0.0;
    for (std::size_t k = 0; k < tr_.size(); ++k) j += tr_[k]->user_objective(z + var_off_[k]);
    return j + mayer_value(z);
}

double MultiTranscription::objective(const double* z) {
    double j = 0.0;
    for (std::size_t k = 0; k < tr_.size(); ++k) j += tr_[k]->objective(z + var_off_[k]);
    return j + mayer_sign_ * mayer_value(z);
}

void MultiTranscription::gradient(const double* z, double* grad) {
    for (std::size_t k = 0; k < tr_.size(); ++k)
        tr_[k]->gradient(z + var_off_[k], grad + var_off_[k]);
    if (mayer_) {
        work_.clear();
        for (int c : mayer_cols_) work_.push_back(z[c]);
        std::vector<double> g(mayer_cols_.size());
        (void)mayer_->gradient(work_, mayer_n_states_, g);
        for (std::size_t i = 0; i < g.size(); ++i) grad[mayer_cols_[i]] += mayer_sign_ * g[i];
    }
}

void MultiTranscription::link_values(const LinkRows& L, const double* z, std::vector<double>& out,
                                     std::vector<double>* jac) const {
    work_.clear();
    for (int c : L.cols) work_.push_back(z[c]);
    out.resize(static_cast<std::size_t>(L.n));
    if (jac != nullptr) {
        jac->resize(static_cast<std::size_t>(L.n) * L.cols.size());
        L.fn->jacobian(work_, out, *jac);
    } else {
        L.fn->values(work_, out);
    }
}

void MultiTranscription::constraints(const double* z, double* g) {
    for (std::size_t k = 0; k < tr_.size(); ++k)
        tr_[k]->constraints(z + var_off_[k], g + row_off_[k]);
    std::vector<double> out;
    auto ties = [&](int b, int row) {
        const int ob = var_off_[static_cast<std::size_t>(b)];
        for (int j = 0; j < np_; ++j) {
            g[row + j] = z[ob + tr_[static_cast<std::size_t>(b)]->parameter_col(j)] -
                         z[var_off_[0] + tr_[0]->parameter_col(j)];
        }
    };
    for (const auto& L : links_) {
        const auto ka = static_cast<std::size_t>(L.from), kb = static_cast<std::size_t>(L.to);
        const Transcription& a = *tr_[ka];
        const Transcription& b = *tr_[kb];
        const int oa = var_off_[ka], ob = var_off_[kb];
        if (L.time_row >= 0)
            g[L.time_row] = z[ob + b.initial_time_col()] - z[oa + a.final_time_col()];
        if (!L.fn) {
            for (int r = 0; r < L.n; ++r) {
                const int i = L.states[static_cast<std::size_t>(r)];
                g[L.first_row + r] = z[ob + b.initial_state_col(i)] - z[oa + a.final_state_col(i)];
            }
        } else {
            link_values(L, z, out, nullptr);
            for (int r = 0; r < L.n; ++r) g[L.first_row + r] = out[static_cast<std::size_t>(r)];
        }
        if (L.param_row >= 0) ties(L.to, L.param_row);
    }
    for (const auto& [k, row] : untied_) ties(k, row);
}

void MultiTranscription::jacobian(const double* z, double* values) {
    for (std::size_t k = 0; k < tr_.size(); ++k)
        tr_[k]->jacobian(z + var_off_[k], values + jac_off_[k]);
    std::vector<double> out, jac;
    for (const auto& L : links_) {
        int e = L.jac_start;
        if (L.time_row >= 0) {
            values[e++] = 1.0;
            values[e++] = -1.0;
        }
        if (!L.fn) {
            for (int r = 0; r < L.n; ++r) {
                values[e++] = 1.0;
                values[e++] = -1.0;
            }
        } else {
            link_values(L, z, out, &jac);
            for (double v : jac) values[e++] = v;
        }
        if (L.param_row >= 0) {
            for (int j = 0; j < np_; ++j) {
                values[e++] = 1.0;
                values[e++] = -1.0;
            }
        }
    }
    int e = untied_jac_start_;
    for (std::size_t i = 0; i < untied_.size(); ++i) {
        for (int j = 0; j < np_; ++j) {
            values[e++] = 1.0;
            values[e++] = -1.0;
        }
    }
}

void MultiTranscription::hessian(const double* z, double obj_factor, const double* lambda,
                                 double* values) {
    for (std::size_t k = 0; k < tr_.size(); ++k) {
        tr_[k]->hessian(z + var_off_[k], obj_factor, lambda + row_off_[k], values + hess_off_[k]);
    }
    std::fill(values + (tr_.empty() ? 0 : hess_off_.back() + tr_.back()->nnz_hessian()),
              values + nnz_hessian(), 0.0);
    std::vector<double> w, H;
    for (const auto& L : links_) {
        if (!L.fn || L.fn->linear()) continue;
        w.assign(lambda + L.first_row, lambda + L.first_row + L.n);
        if (std::all_of(w.begin(), w.end(), [](double x) { return x == 0.0; })) continue;
        work_.clear();
        for (int c : L.cols) work_.push_back(z[c]);
        const int nc = static_cast<int>(L.cols.size());
        H.assign(static_cast<std::size_t>(nc * nc), 0.0);
        L.fn->hessian(work_, w, H);
        for (int i = 0; i < nc; ++i) {
            for (int j = 0; j <= i; ++j)
                values[L.hess_index[static_cast<std::size_t>(i * nc + j)]] +=
                    H[static_cast<std::size_t>(i * nc + j)];
        }
    }
    if (mayer_ && obj_factor != 0.0) {
        work_.clear();
        for (int c : mayer_cols_) work_.push_back(z[c]);
        const int nc = static_cast<int>(mayer_cols_.size());
        H.assign(static_cast<std::size_t>(nc * nc), 0.0);
        mayer_->hessian(work_, mayer_n_states_, H);
        const double f = obj_factor * mayer_sign_;
        for (int i = 0; i < nc; ++i) {
            for (int j = 0; j <= i; ++j)
                values[mayer_hess_index_[static_cast<std::size_t>(i * nc + j)]] +=
                    f * H[static_cast<std::size_t>(i * nc + j)];
        }
    }
}

void MultiTranscription::extract(const double* z, const double* lambda, int n_report,
                                 MultiPhaseSolution& sol) {
    sol.phases.clear();
    sol.max_violation = 0.0;
    for (std::size_t k = 0; k < tr_.size(); ++k) {
        Solution s;
        tr_[k]->extract(z + var_off_[k], lambda != nullptr ? lambda + row_off_[k] : nullptr,
                        n_report, s);
        s.objective = tr_[k]->user_objective(z + var_off_[k]);
        sol.max_violation = std::max(sol.max_violation, s.max_violation);
        sol.phases.push_back(std::move(s));
    }
    sol.parameters = sol.phases.front().parameters;
    std::vector<double> g(static_cast<std::size_t>(n_rows_)), gl(g.size()), gu(g.size()),
        xl(static_cast<std::size_t>(n_vars_)), xu(xl.size());
    constraints(z, g.data());
    bounds(xl.data(), xu.data(), gl.data(), gu.data());
    sol.links.clear();
    sol.max_link_violation = 0.0;
    for (const auto& L : links_) {
        std::vector<int> rows;
        if (L.time_row >= 0) rows.push_back(L.time_row);
        for (int r = 0; r < L.n; ++r) rows.push_back(L.first_row + r);
        if (L.param_row >= 0) {
            for (int j = 0; j < np_; ++j) rows.push_back(L.param_row + j);
        }
        Eigen::VectorXd v(static_cast<Eigen::Index>(rows.size()));
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const auto r = static_cast<std::size_t>(rows[i]);
            v(static_cast<Eigen::Index>(i)) = g[r];
            sol.max_link_violation =
                std::max(sol.max_link_violation, std::max({gl[r] - g[r], g[r] - gu[r], 0.0}));
        }
        sol.links.push_back(v);
    }
    for (const auto& [k, row] : untied_) {
        for (int j = 0; j < np_; ++j) {
            const auto r = static_cast<std::size_t>(row + j);
            sol.max_link_violation =
                std::max(sol.max_link_violation, std::max({gl[r] - g[r], g[r] - gu[r], 0.0}));
        }
    }
    sol.mayer = mayer_value(z);
    sol.max_violation = std::max(sol.max_violation, sol.max_link_violation);
    sol.n_variables = n_vars_;
    sol.n_constraints = n_rows_;
    sol.n_jacobian_nonzeros = nnz_jacobian();
    sol.n_hessian_nonzeros = nnz_hessian();
}

}  // namespace manta::optimal::detail
