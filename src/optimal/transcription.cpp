/// @file transcription.cpp
/// LGL transcription: layout, bounds, scaling, sparse derivatives (detail/transcription.hpp).

#include "detail/transcription.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "manta/core/error.hpp"

namespace manta::optimal::detail {

namespace {

double to_nlp(double b) {
    if (b >= kNlpInf) return kNlpInf;
    if (b <= -kNlpInf) return -kNlpInf;
    return b;
}

/// Typical magnitude from bounds (finite ones) and a guess magnitude.
double magnitude(double user, double lo, double hi, double guess_abs) {
    if (user > 0.0) return user;
    double s = 0.0;
    const bool lo_fin = std::isfinite(lo);
    const bool hi_fin = std::isfinite(hi);
    if (lo_fin && hi_fin) {
        s = std::max(std::abs(lo), std::abs(hi));
    } else if (lo_fin || hi_fin) {
        s = std::max(lo_fin ? std::abs(lo) : 0.0, hi_fin ? std::abs(hi) : 0.0);
        s = std::max(s, guess_abs);
    } else {
        s = guess_abs;
    }
    return s > 1e-12 ? s : 1.0;
}

}  // namespace

Transcription::Transcription(const Model& model, const Mesh& mesh) : model_(model), mesh_(mesh) {
    mesh_.validate();
    const ProblemInfo& info = model.info();
    nx_ = info.n_states();
    nu_ = info.n_controls();
    np_ = info.n_parameters();
    ng_ = info.n_path();
    ne_ = info.n_events();
    lagrange_ = model.has_lagrange();
    mayer_ = model.has_mayer();
    const int K = mesh_.n_segments();
    const bool free = mesh_.free_breaks && K > 1;

    int mesh_points = 0;
    int points = 0;
    int row = 0;
    for (int k = 0; k < K; ++k) {
        Segment s;
        s.n = mesh_.nodes[k];
        s.state_offset = mesh_points;
        s.point_offset = points;
        s.defect_row = row;
        s.rule = lgl_rule(s.n);
        s.seed_lo = free && k > 0;
        s.seed_hi = free && k < K - 1;
        mesh_points += s.n - 1;
        points += s.n;
        row += s.n * nx_;
        seg_.push_back(std::move(s));
    }
    n_mesh_points_ = mesh_points + 1;
    n_points_ = points;
    u0_ = n_mesh_points_ * nx_;
    p0_ = u0_ + n_points_ * nu_;
    t0_ = p0_ + np_;
    b0_ = t0_ + 2;
    n_vars_ = b0_ + (free ? K - 1 : 0);
    path_row_ = row;
    row += n_points_ * ng_;
    event_row_ = row;
    row += ne_;
    interior_row_ = row;
    ni_ = info.n_interior_events();
    for (int j = 1; j < K; ++j) {
        Junction jn;
        jn.index = j;
        for (int e = 0; e < ni_; ++e) {
            if (info.interior_events[e].junction == j) jn.events.push_back(e);
        }
        if (jn.events.empty()) continue;
        jn.first_row = row;
        jn.n = static_cast<int>(jn.events.size());
        row += jn.n;
        junctions_.push_back(std::move(jn));
    }
    for (const auto& e : info.interior_events) {
        if (e.junction >= K) {
            throw InputError("optimal control problem '" + info.name + "': interior event '" +
                             e.constraint.name + "' at junction " + std::to_string(e.junction) +
                             " of a mesh of " + std::to_string(K) + " segment(s), expected 1 to " +
                             std::to_string(K - 1));
        }
    }
    order_row_ = row;
    row += (free && K > 2) ? K - 2 : 0;
    tie_row_ = row;
    if (free && !mesh_.phase_breaks.empty()) {
        std::vector<int> anchors{0};
        anchors.insert(anchors.end(), mesh_.phase_breaks.begin(), mesh_.phase_breaks.end());
        anchors.push_back(K);
        for (std::size_t i = 0; i + 1 < anchors.size(); ++i) {
            const int a = anchors[i], c = anchors[i + 1];
            const double ba = mesh_.breaks[static_cast<std::size_t>(a)];
            const double bc = mesh_.breaks[static_cast<std::size_t>(c)];
            for (int k = a + 1; k < c; ++k) {
                ties_.push_back(
                    {k, a, c, (mesh_.breaks[static_cast<std::size_t>(k)] - ba) / (bc - ba), 0});
            }
        }
        row += static_cast<int>(ties_.size());
    }
    nq_ = info.n_integrals();
    integral_row_ = row;
    row += nq_;
    integral_out_ = nx_ + ng_ + (lagrange_ ? 1 : 0);
    for (int j = 0; j < nu_; ++j) {
        if (info.controls[static_cast<std::size_t>(j)].has_rate_bounds())
            rate_controls_.push_back(j);
    }
    rate_row_ = row;
    row += static_cast<int>(rate_controls_.size()) * n_points_;
    // a rate-bounded control is continuous across the breaks (a jump is an unbounded rate)
    continuity_row_ = row;
    row += static_cast<int>(rate_controls_.size()) * (K - 1);
    n_rows_ = row;
    sign_ = info.maximise ? -1.0 : 1.0;
    for (int k = 0; k < K; ++k) {
        Segment& s = seg_[k];
        s.time_cols = {t0_col(), tf_col()};
        if (s.seed_lo) s.time_cols.push_back(break_col(k));
        if (s.seed_hi) s.time_cols.push_back(break_col(k + 1));
    }

    n_node_out_ = model.n_node_outputs();
    n_boundary_out_ = model.n_boundary_outputs();
    for (int k = 0; k < K; ++k) {
        for (int i = 0; i < seg_[k].n; ++i) node_cols_.push_back(node_columns(k, i));
    }
    boundary_cols_ = boundary_columns();
    for (auto& jn : junctions_) jn.cols = interior_columns(jn.index);

    // Jacobian structure: defect rows hold the constant D part, then the node's local columns.
    for (int k = 0; k < K; ++k) {
        const Segment& s = seg_[k];
        for (int i = 0; i < s.n; ++i) {
            const auto& cols = node_cols_[s.point_offset + i];
            for (int r = 0; r < nx_; ++r) {
                const int rr = s.defect_row + i * nx_ + r;
                defect_jac_start_.push_back(static_cast<int>(jac_row_.size()));
                for (int l = 0; l < s.n; ++l) {
                    if (l == i) continue;
                    jac_row_.push_back(rr);
                    jac_col_.push_back(x_col(s.state_offset + l, r));
                }
                for (const int c : cols) {
                    jac_row_.push_back(rr);
                    jac_col_.push_back(c);
                }
            }
        }
    }
    for (int pt = 0; pt < n_points_; ++pt) {
        for (int j = 0; j < ng_; ++j) {
            path_jac_start_.push_back(static_cast<int>(jac_row_.size()));
            for (const int c : node_cols_[pt]) {
                jac_row_.push_back(path_row_ + pt * ng_ + j);
                jac_col_.push_back(c);
            }
        }
    }
    event_jac_start_ = static_cast<int>(jac_row_.size());
    for (int e = 0; e < ne_; ++e) {
        for (const int c : boundary_cols_) {
            jac_row_.push_back(event_row_ + e);
            jac_col_.push_back(c);
        }
    }
    for (auto& jn : junctions_) {
        jn.jac_start = static_cast<int>(jac_row_.size());
        for (int e = 0; e < jn.n; ++e) {
            for (const int c : jn.cols) {
                if (c < 0) continue;
                jac_row_.push_back(jn.first_row + e);
                jac_col_.push_back(c);
            }
        }
    }
    order_jac_start_ = static_cast<int>(jac_row_.size());
    for (int m = 0; m + 2 <= K - 1 && free; ++m) {
        jac_row_.push_back(order_row_ + m);
        jac_col_.push_back(break_col(m + 1));
        jac_row_.push_back(order_row_ + m);
        jac_col_.push_back(break_col(m + 2));
    }
    for (std::size_t i = 0; i < ties_.size(); ++i) {
        Tie& t = ties_[i];
        t.jac_start = static_cast<int>(jac_row_.size());
        for (const int b : {t.k, t.a, t.c}) {
            if (b <= 0 || b >= K) continue;
            jac_row_.push_back(tie_row_ + static_cast<int>(i));
            jac_col_.push_back(break_col(b));
        }
    }
    // integral constraints: one dense row over the union of the node columns (each node's
    // (h/2) w q adds into it; shared interface states and t0, tf, p appear once)
    if (nq_ > 0) {
        std::set<int> all;
        for (const auto& cols : node_cols_) all.insert(cols.begin(), cols.end());
        integral_cols_.assign(all.begin(), all.end());
        integral_pos_.resize(static_cast<std::size_t>(n_points_));
        for (int pt = 0; pt < n_points_; ++pt) {
            for (const int c : node_cols_[pt]) {
                const auto it = std::lower_bound(integral_cols_.begin(), integral_cols_.end(), c);
                integral_pos_[pt].push_back(static_cast<int>(it - integral_cols_.begin()));
            }
        }
        integral_jac_start_ = static_cast<int>(jac_row_.size());
        for (int j = 0; j < nq_; ++j) {
            for (const int c : integral_cols_) {
                jac_row_.push_back(integral_row_ + j);
                jac_col_.push_back(c);
            }
        }
    }
    // control rates: the segment's controls (D row) and its time columns (through 2/h)
    for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
        const int j = rate_controls_[c];
        for (const Segment& s : seg_) {
            for (int i = 0; i < s.n; ++i) {
                const int rr = rate_row_ + static_cast<int>(c) * n_points_ + s.point_offset + i;
                rate_jac_start_.push_back(static_cast<int>(jac_row_.size()));
                for (int l = 0; l < s.n; ++l) {
                    jac_row_.push_back(rr);
                    jac_col_.push_back(u_col(s.point_offset + l, j));
                }
                for (const int tc : s.time_cols) {
                    jac_row_.push_back(rr);
                    jac_col_.push_back(tc);
                }
            }
        }
    }
    continuity_jac_start_ = static_cast<int>(jac_row_.size());
    for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
        for (int k = 1; k < K; ++k) {
            const int rr = continuity_row_ + static_cast<int>(c) * (K - 1) + (k - 1);
            jac_row_.push_back(rr);
            jac_col_.push_back(u_col(seg_[k].point_offset - 1, rate_controls_[c]));
            jac_row_.push_back(rr);
            jac_col_.push_back(u_col(seg_[k].point_offset, rate_controls_[c]));
        }
    }

    // Hessian structure (lower triangle), union of the node and boundary blocks.
    std::map<std::pair<int, int>, int> index;
    auto entry = [&](int a, int b) {
        const auto key = std::make_pair(std::max(a, b), std::min(a, b));
        const auto it = index.find(key);
        if (it != index.end()) return it->second;
        const int id = static_cast<int>(hess_row_.size());
        index.emplace(key, id);
        hess_row_.push_back(key.first);
        hess_col_.push_back(key.second);
        return id;
    };
    for (int pt = 0; pt < n_points_; ++pt) {
        const auto& cols = node_cols_[pt];
        const int nv = static_cast<int>(cols.size());
        std::vector<int> idx(static_cast<std::size_t>(nv * nv), -1);
        for (int a = 0; a < nv; ++a) {
            for (int b = 0; b <= a; ++b) idx[a * nv + b] = entry(cols[a], cols[b]);
        }
        node_hess_index_.push_back(std::move(idx));
    }
    if (n_boundary_out_ > 0) {
        const int nb = static_cast<int>(boundary_cols_.size());
        boundary_hess_index_.assign(static_cast<std::size_t>(nb * nb), -1);
        for (int a = 0; a < nb; ++a) {
            for (int b = 0; b <= a; ++b) {
                boundary_hess_index_[a * nb + b] = entry(boundary_cols_[a], boundary_cols_[b]);
            }
        }
    }

    for (auto& jn : junctions_) {
        const int nv = static_cast<int>(jn.cols.size());
        jn.hess_index.assign(static_cast<std::size_t>(nv * nv), -1);
        for (int a = 0; a < nv; ++a) {
            for (int b = 0; b <= a; ++b) {
                if (jn.cols[a] >= 0 && jn.cols[b] >= 0) {
                    jn.hess_index[a * nv + b] = entry(jn.cols[a], jn.cols[b]);
                }
            }
        }
        jn.out.resize(static_cast<std::size_t>(jn.n));
        jn.jac.resize(static_cast<std::size_t>(jn.n * nv));
    }
    if (!rate_controls_.empty()) {
        // (time, time) and (U_l, time) entries: all within the node blocks already
        for (Segment& s : seg_) {
            const int ntv = static_cast<int>(s.time_cols.size());
            s.time_hess.assign(static_cast<std::size_t>(ntv * ntv), -1);
            for (int a = 0; a < ntv; ++a) {
                for (int b = 0; b <= a; ++b)
                    s.time_hess[a * ntv + b] = entry(s.time_cols[a], s.time_cols[b]);
            }
            s.rate_u_hess.assign(rate_controls_.size(), {});
            for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
                for (int l = 0; l < s.n; ++l) {
                    for (int v = 0; v < ntv; ++v) {
                        s.rate_u_hess[c].push_back(
                            entry(u_col(s.point_offset + l, rate_controls_[c]), s.time_cols[v]));
                    }
                }
            }
        }
    }

    node_out_.assign(n_points_, std::vector<double>(n_node_out_));
    node_jac_.resize(n_points_);
    for (int pt = 0; pt < n_points_; ++pt) {
        node_jac_[pt].resize(static_cast<std::size_t>(n_node_out_) * node_cols_[pt].size());
    }
    boundary_out_.resize(n_boundary_out_);
    boundary_jac_.resize(static_cast<std::size_t>(n_boundary_out_) * boundary_cols_.size());
}

double Transcription::break_value(const double* z, int k) const {
    const int K = n_segments();
    if (k <= 0) return 0.0;
    if (k >= K) return 1.0;
    return (mesh_.free_breaks && K > 1) ? z[break_col(k)] : mesh_.breaks[k];
}

NodePlacement Transcription::placement(int k, int i, const double* z) const {
    const Segment& s = seg_[k];
    NodePlacement at;
    at.s_lo = break_value(z, k);
    at.s_hi = break_value(z, k + 1);
    at.a = 0.5 * (s.rule.points(i) + 1.0);
    at.weight = s.rule.weights(i);
    at.seed_lo = s.seed_lo;
    at.seed_hi = s.seed_hi;
    return at;
}

double Transcription::node_time(int k, int i, const double* z) const {
    const NodePlacement at = placement(k, i, z);
    const double t0 = z[t0_col()];
    const double tf = z[tf_col()];
    return t0 + (tf - t0) * (at.s_lo + (at.s_hi - at.s_lo) * at.a);
}

std::vector<int> Transcription::node_columns(int k, int i) const {
    const Segment& s = seg_[k];
    std::vector<int> cols;
    for (int r = 0; r < nx_; ++r) cols.push_back(x_col(s.state_offset + i, r));
    for (int j = 0; j < nu_; ++j) cols.push_back(u_col(s.point_offset + i, j));
    for (int j = 0; j < np_; ++j) cols.push_back(p_col(j));
    cols.push_back(t0_col());
    cols.push_back(tf_col());
    if (s.seed_lo) cols.push_back(break_col(k));
    if (s.seed_hi) cols.push_back(break_col(k + 1));
    return cols;
}

std::vector<int> Transcription::boundary_columns() const {
    std::vector<int> cols;
    for (int r = 0; r < nx_; ++r) cols.push_back(x_col(0, r));
    for (int r = 0; r < nx_; ++r) cols.push_back(x_col(n_mesh_points_ - 1, r));
    for (int j = 0; j < np_; ++j) cols.push_back(p_col(j));
    cols.push_back(t0_col());
    cols.push_back(tf_col());
    return cols;
}

std::vector<int> Transcription::interior_columns(int j) const {
    std::vector<int> cols;
    for (int r = 0; r < nx_; ++r) cols.push_back(x_col(seg_[j].state_offset, r));
    for (int q = 0; q < np_; ++q) cols.push_back(p_col(q));
    cols.push_back(t0_col());
    cols.push_back(tf_col());
    cols.push_back((mesh_.free_breaks && n_segments() > 1) ? break_col(j) : -1);
    return cols;
}

void Transcription::gather_interior(int j, const double* z, std::vector<double>& v) const {
    const std::vector<int> cols = interior_columns(j);
    v.resize(cols.size());
    for (std::size_t c = 0; c + 1 < cols.size(); ++c) v[c] = z[cols[c]];
    v.back() = break_value(z, j);
}

void Transcription::gather(const std::vector<int>& cols, const double* z,
                           std::vector<double>& v) const {
    v.resize(cols.size());
    for (std::size_t c = 0; c < cols.size(); ++c) v[c] = z[cols[c]];
}

void Transcription::update(const double* z, bool need_jacobian) {
    const std::size_t n = static_cast<std::size_t>(n_vars_);
    if (z_cache_.size() != n || std::memcmp(z_cache_.data(), z, n * sizeof(double)) != 0) {
        z_cache_.assign(z, z + n);
        values_ok_ = false;
        jacobian_ok_ = false;
    }
    if (need_jacobian && !jacobian_ok_) {
        int pt = 0;
        for (int k = 0; k < n_segments(); ++k) {
            for (int i = 0; i < seg_[k].n; ++i, ++pt) {
                gather(node_cols_[pt], z, work_v_);
                model_.node_jacobian(work_v_, placement(k, i, z), node_out_[pt], node_jac_[pt]);
            }
        }
        if (n_boundary_out_ > 0) {
            gather(boundary_cols_, z, work_v_);
            model_.boundary_jacobian(work_v_, boundary_out_, boundary_jac_);
        }
        for (auto& jn : junctions_) {
            gather_interior(jn.index, z, work_v_);
            model_.interior_jacobian(jn.index, work_v_, jn.out, jn.jac);
        }
        jacobian_ok_ = true;
        values_ok_ = true;
    } else if (!values_ok_) {
        int pt = 0;
        for (int k = 0; k < n_segments(); ++k) {
            for (int i = 0; i < seg_[k].n; ++i, ++pt) {
                gather(node_cols_[pt], z, work_v_);
                model_.node_values(work_v_, placement(k, i, z), node_out_[pt]);
            }
        }
        if (n_boundary_out_ > 0) {
            gather(boundary_cols_, z, work_v_);
            model_.boundary_values(work_v_, boundary_out_);
        }
        for (auto& jn : junctions_) {
            gather_interior(jn.index, z, work_v_);
            model_.interior_values(jn.index, work_v_, jn.out);
        }
        values_ok_ = true;
    }
}

void Transcription::bounds(double* x_l, double* x_u, double* g_l, double* g_u) const {
    const ProblemInfo& info = model_.info();
    for (int g = 0; g < n_mesh_points_; ++g) {
        for (int r = 0; r < nx_; ++r) {
            double lo = info.states[r].lower;
            double hi = info.states[r].upper;
            if (g == 0 && !info.initial_states.empty()) {
                lo = std::max(lo, info.initial_states[r].lower);
                hi = std::min(hi, info.initial_states[r].upper);
            }
            if (g == n_mesh_points_ - 1 && !info.final_states.empty()) {
                lo = std::max(lo, info.final_states[r].lower);
                hi = std::min(hi, info.final_states[r].upper);
            }
            x_l[x_col(g, r)] = to_nlp(lo);
            x_u[x_col(g, r)] = to_nlp(hi);
        }
    }
    for (int pt = 0; pt < n_points_; ++pt) {
        for (int j = 0; j < nu_; ++j) {
            x_l[u_col(pt, j)] = to_nlp(info.controls[j].lower);
            x_u[u_col(pt, j)] = to_nlp(info.controls[j].upper);
        }
    }
    for (int j = 0; j < np_; ++j) {
        x_l[p_col(j)] = to_nlp(info.parameters[j].lower);
        x_u[p_col(j)] = to_nlp(info.parameters[j].upper);
    }
    x_l[t0_col()] = to_nlp(info.initial_time.lower);
    x_u[t0_col()] = to_nlp(info.initial_time.upper);
    x_l[tf_col()] = to_nlp(info.final_time.lower);
    x_u[tf_col()] = to_nlp(info.final_time.upper);
    const int K = n_segments();
    if (mesh_.free_breaks && K > 1) {
        const double m = mesh_.min_segment_fraction;
        for (int k = 1; k < K; ++k) {
            x_l[break_col(k)] = k * m;
            x_u[break_col(k)] = 1.0 - (K - k) * m;
        }
    }
    for (int r = 0; r < path_row_; ++r) g_l[r] = g_u[r] = 0.0;
    for (int pt = 0; pt < n_points_; ++pt) {
        for (int j = 0; j < ng_; ++j) {
            g_l[path_row_ + pt * ng_ + j] = to_nlp(info.path[j].lower);
            g_u[path_row_ + pt * ng_ + j] = to_nlp(info.path[j].upper);
        }
    }
    for (int e = 0; e < ne_; ++e) {
        g_l[event_row_ + e] = to_nlp(info.events[e].lower);
        g_u[event_row_ + e] = to_nlp(info.events[e].upper);
    }
    for (const auto& jn : junctions_) {
        for (int e = 0; e < jn.n; ++e) {
            const Constraint& c = info.interior_events[jn.events[e]].constraint;
            g_l[jn.first_row + e] = to_nlp(c.lower);
            g_u[jn.first_row + e] = to_nlp(c.upper);
        }
    }
    for (int r = order_row_; r < tie_row_; ++r) {
        g_l[r] = mesh_.min_segment_fraction;
        g_u[r] = kNlpInf;
    }
    for (int r = tie_row_; r < integral_row_; ++r) g_l[r] = g_u[r] = 0.0;
    for (int j = 0; j < nq_; ++j) {
        g_l[integral_row_ + j] = to_nlp(info.integrals[j].lower);
        g_u[integral_row_ + j] = to_nlp(info.integrals[j].upper);
    }
    for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
        const Bounds& b = info.controls[rate_controls_[c]].rate;
        for (int pt = 0; pt < n_points_; ++pt) {
            g_l[rate_row_ + static_cast<int>(c) * n_points_ + pt] = to_nlp(b.lower);
            g_u[rate_row_ + static_cast<int>(c) * n_points_ + pt] = to_nlp(b.upper);
        }
    }
    for (int r = continuity_row_; r < n_rows_; ++r) g_l[r] = g_u[r] = 0.0;
}

bool Transcription::reference_scaling(Eigen::VectorXd& offset, Eigen::VectorXd& span) const {
    const ProblemInfo& info = model_.info();
    offset = Eigen::VectorXd::Zero(n_vars_);
    span = Eigen::VectorXd::Zero(n_vars_);
    bool any = false;
    auto set = [&](const Variable& v, int col) {
        if (!v.has_reference()) return;
        offset(col) = v.ref0.value_or(0.0);
        span(col) = *v.ref - v.ref0.value_or(0.0);
        any = true;
    };
    for (int g = 0; g < n_mesh_points_; ++g) {
        for (int r = 0; r < nx_; ++r) set(info.states[r], x_col(g, r));
    }
    for (int pt = 0; pt < n_points_; ++pt) {
        for (int j = 0; j < nu_; ++j) set(info.controls[j], u_col(pt, j));
    }
    for (int j = 0; j < np_; ++j) set(info.parameters[j], p_col(j));
    return any;
}

void Transcription::rate_factor(int k, const double* z, double& g, std::vector<double>& dg,
                                std::vector<double>& d2g) const {
    const Segment& s = seg_[k];
    const double T = z[tf_col()] - z[t0_col()];
    const double S = break_value(z, k + 1) - break_value(z, k);
    g = 2.0 / (T * S);
    const std::size_t ntv = s.time_cols.size();
    std::vector<double> dT(ntv, 0.0), dS(ntv, 0.0);
    dT[0] = -1.0;
    dT[1] = 1.0;
    std::size_t v = 2;
    if (s.seed_lo) dS[v++] = -1.0;
    if (s.seed_hi) dS[v] = 1.0;
    dg.assign(ntv, 0.0);
    d2g.assign(ntv * ntv, 0.0);
    for (std::size_t a = 0; a < ntv; ++a) {
        dg[a] = -g * (dT[a] / T + dS[a] / S);
        for (std::size_t b = 0; b < ntv; ++b) {
            d2g[a * ntv + b] =
                g * (2.0 * dT[a] * dT[b] / (T * T) + (dT[a] * dS[b] + dS[a] * dT[b]) / (T * S) +
                     2.0 * dS[a] * dS[b] / (S * S));
        }
    }
}

void Transcription::initial_point(const Guess& guess, double* z) const {
    const ProblemInfo& info = model_.info();
    const double t0g = guess.initial_time();
    const double tfg = guess.final_time();
    Eigen::VectorXd x;
    Eigen::VectorXd u;
    const int K = n_segments();
    for (int k = 0; k < K; ++k) {
        const Segment& s = seg_[k];
        const double lo = k == 0 ? 0.0 : mesh_.breaks[k];
        const double hi = k == K - 1 ? 1.0 : mesh_.breaks[k + 1];
        for (int i = 0; i < s.n; ++i) {
            const double a = 0.5 * (s.rule.points(i) + 1.0);
            const double t = t0g + (tfg - t0g) * (lo + (hi - lo) * a);
            guess.at(t, x, u);
            if (x.size() != nx_ || u.size() != nu_) {
                throw InputError("initial guess of '" + info.name +
                                 "': " + std::to_string(x.size()) + " states and " +
                                 std::to_string(u.size()) + " controls, expected " +
                                 std::to_string(nx_) + " and " + std::to_string(nu_));
            }
            for (int r = 0; r < nx_; ++r) z[x_col(s.state_offset + i, r)] = x(r);
            for (int j = 0; j < nu_; ++j) z[u_col(s.point_offset + i, j)] = u(j);
        }
    }
    const Eigen::VectorXd& p = guess.parameters();
    if (p.size() != 0 && p.size() != np_) {
        throw InputError("initial guess of '" + info.name + "': " + std::to_string(p.size()) +
                         " parameters, expected " + std::to_string(np_));
    }
    for (int j = 0; j < np_; ++j) {
        if (p.size() == np_) {
            z[p_col(j)] = p(j);
        } else {
            const double lo = info.parameters[j].lower;
            const double hi = info.parameters[j].upper;
            z[p_col(j)] = std::isfinite(lo) && std::isfinite(hi) ? 0.5 * (lo + hi)
                          : std::isfinite(lo)                    ? lo
                          : std::isfinite(hi)                    ? hi
                                                                 : 0.0;
        }
    }
    z[t0_col()] = t0g;
    z[tf_col()] = tfg;
    if (mesh_.free_breaks && K > 1) {
        for (int k = 1; k < K; ++k) z[break_col(k)] = mesh_.breaks[k];
    }
    std::vector<double> xl(n_vars_), xu(n_vars_), gl(n_rows_), gu(n_rows_);
    bounds(xl.data(), xu.data(), gl.data(), gu.data());
    for (int c = 0; c < n_vars_; ++c) z[c] = std::clamp(z[c], xl[c], xu[c]);
}

void Transcription::scaling(const double* z0, Eigen::VectorXd& var_scale,
                            Eigen::VectorXd& row_scale, double& obj_scale) {
    const ProblemInfo& info = model_.info();
    var_scale = Eigen::VectorXd::Ones(n_vars_);
    Eigen::VectorXd xs(nx_);
    for (int r = 0; r < nx_; ++r) {
        double gmax = 0.0;
        for (int g = 0; g < n_mesh_points_; ++g) gmax = std::max(gmax, std::abs(z0[x_col(g, r)]));
        xs(r) = magnitude(info.states[r].scale, info.states[r].lower, info.states[r].upper, gmax);
        if (info.states[r].has_reference()) {
            xs(r) = std::abs(*info.states[r].ref - info.states[r].ref0.value_or(0.0));
        }
        for (int g = 0; g < n_mesh_points_; ++g) var_scale(x_col(g, r)) = xs(r);
    }
    for (int j = 0; j < nu_; ++j) {
        double gmax = 0.0;
        for (int pt = 0; pt < n_points_; ++pt) gmax = std::max(gmax, std::abs(z0[u_col(pt, j)]));
        double s =
            magnitude(info.controls[j].scale, info.controls[j].lower, info.controls[j].upper, gmax);
        if (info.controls[j].has_reference()) {
            s = std::abs(*info.controls[j].ref - info.controls[j].ref0.value_or(0.0));
        }
        for (int pt = 0; pt < n_points_; ++pt) var_scale(u_col(pt, j)) = s;
    }
    for (int j = 0; j < np_; ++j) {
        var_scale(p_col(j)) = magnitude(info.parameters[j].scale, info.parameters[j].lower,
                                        info.parameters[j].upper, std::abs(z0[p_col(j)]));
        if (info.parameters[j].has_reference()) {
            var_scale(p_col(j)) =
                std::abs(*info.parameters[j].ref - info.parameters[j].ref0.value_or(0.0));
        }
    }
    const double guess_t = std::max(std::abs(z0[t0_col()]), std::abs(z0[tf_col()]));
    const double ts = info.time_scale > 0.0
                          ? info.time_scale
                          : magnitude(0.0, info.final_time.lower, info.final_time.upper, guess_t);
    var_scale(t0_col()) = ts;
    var_scale(tf_col()) = ts;

    row_scale = Eigen::VectorXd::Ones(n_rows_);
    for (int r = 0; r < path_row_; ++r) row_scale(r) = xs(r % nx_);
    for (int pt = 0; pt < n_points_; ++pt) {
        for (int j = 0; j < ng_; ++j) {
            const Constraint& c = info.path[j];
            row_scale(path_row_ + pt * ng_ + j) = magnitude(c.scale, c.lower, c.upper, 0.0);
        }
    }
    for (int e = 0; e < ne_; ++e) {
        const Constraint& c = info.events[e];
        row_scale(event_row_ + e) = magnitude(c.scale, c.lower, c.upper, 0.0);
    }
    for (const auto& jn : junctions_) {
        for (int e = 0; e < jn.n; ++e) {
            const Constraint& c = info.interior_events[jn.events[e]].constraint;
            row_scale(jn.first_row + e) = magnitude(c.scale, c.lower, c.upper, 0.0);
        }
    }
    for (int j = 0; j < nq_; ++j) {
        const Constraint& c = info.integrals[j];
        row_scale(integral_row_ + j) = magnitude(c.scale, c.lower, c.upper, 0.0);
    }
    for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
        const Bounds& b = info.controls[rate_controls_[c]].rate;
        const double rs = magnitude(0.0, b.lower, b.upper, 0.0);
        for (int pt = 0; pt < n_points_; ++pt)
            row_scale(rate_row_ + static_cast<int>(c) * n_points_ + pt) = rs;
        const int K = n_segments();
        for (int k = 1; k < K; ++k) {
            row_scale(continuity_row_ + static_cast<int>(c) * (K - 1) + (k - 1)) =
                var_scale(u_col(0, rate_controls_[c]));
        }
    }
    row_scale_ = row_scale;
    if (info.objective_scale > 0.0) {
        obj_scale = info.objective_scale;
    } else {
        const double j0 = std::abs(objective(z0));
        obj_scale = std::isfinite(j0) && j0 > 1e-8 ? j0 : 1.0;
    }
}

void Transcription::jacobian_structure(int* rows, int* cols) const {
    std::copy(jac_row_.begin(), jac_row_.end(), rows);
    std::copy(jac_col_.begin(), jac_col_.end(), cols);
}

void Transcription::hessian_structure(int* rows, int* cols) const {
    std::copy(hess_row_.begin(), hess_row_.end(), rows);
    std::copy(hess_col_.begin(), hess_col_.end(), cols);
}

double Transcription::user_objective(const double* z) {
    update(z, false);
    double j = mayer_ ? boundary_out_[ne_] : 0.0;
    if (lagrange_) {
        for (int pt = 0; pt < n_points_; ++pt) j += node_out_[pt][nx_ + ng_];
    }
    return j;
}

double Transcription::objective(const double* z) {
    const double j = user_objective(z);
    return sign_ < 0.0 ? -j : j;
}

void Transcription::gradient(const double* z, double* grad) {
    update(z, true);
    std::fill(grad, grad + n_vars_, 0.0);
    if (mayer_) {
        const std::size_t nb = boundary_cols_.size();
        for (std::size_t c = 0; c < nb; ++c) grad[boundary_cols_[c]] += boundary_jac_[ne_ * nb + c];
    }
    if (lagrange_) {
        const int row = nx_ + ng_;
        for (int pt = 0; pt < n_points_; ++pt) {
            const auto& cols = node_cols_[pt];
            const std::size_t nv = cols.size();
            for (std::size_t c = 0; c < nv; ++c) grad[cols[c]] += node_jac_[pt][row * nv + c];
        }
    }
    if (sign_ < 0.0) {
        for (int c = 0; c < n_vars_; ++c) grad[c] = -grad[c];
    }
}

void Transcription::constraints(const double* z, double* g) {
    update(z, false);
    for (const Segment& s : seg_) {
        const Eigen::MatrixXd& D = s.rule.differentiation;
        for (int i = 0; i < s.n; ++i) {
            const auto& out = node_out_[s.point_offset + i];
            for (int r = 0; r < nx_; ++r) {
                double dx = 0.0;
                for (int l = 0; l < s.n; ++l) dx += D(i, l) * z[x_col(s.state_offset + l, r)];
                g[s.defect_row + i * nx_ + r] = dx - out[r];
            }
        }
    }
    for (int pt = 0; pt < n_points_; ++pt) {
        for (int j = 0; j < ng_; ++j) g[path_row_ + pt * ng_ + j] = node_out_[pt][nx_ + j];
    }
    for (int e = 0; e < ne_; ++e) g[event_row_ + e] = boundary_out_[e];
    for (const auto& jn : junctions_) {
        for (int e = 0; e < jn.n; ++e) g[jn.first_row + e] = jn.out[e];
    }
    for (int m = 0; order_row_ + m < tie_row_; ++m) {
        g[order_row_ + m] = z[break_col(m + 2)] - z[break_col(m + 1)];
    }
    const int K = n_segments();
    const auto brk = [&](int b) { return b == 0 ? 0.0 : b == K ? 1.0 : z[break_col(b)]; };
    for (std::size_t i = 0; i < ties_.size(); ++i) {
        const Tie& t = ties_[i];
        g[tie_row_ + static_cast<int>(i)] = brk(t.k) - (1.0 - t.w) * brk(t.a) - t.w * brk(t.c);
    }
    for (int j = 0; j < nq_; ++j) {
        double v = 0.0;
        for (int pt = 0; pt < n_points_; ++pt) v += node_out_[pt][integral_out_ + j];
        g[integral_row_ + j] = v;
    }
    std::vector<double> dg, d2g;
    for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
        const int j = rate_controls_[c];
        for (int k = 0; k < K; ++k) {
            const Segment& s = seg_[k];
            const Eigen::MatrixXd& D = s.rule.differentiation;
            double fac = 0.0;
            rate_factor(k, z, fac, dg, d2g);
            for (int i = 0; i < s.n; ++i) {
                double a = 0.0;
                for (int l = 0; l < s.n; ++l) a += D(i, l) * z[u_col(s.point_offset + l, j)];
                g[rate_row_ + static_cast<int>(c) * n_points_ + s.point_offset + i] = fac * a;
            }
        }
        for (int k = 1; k < K; ++k) {
            g[continuity_row_ + static_cast<int>(c) * (K - 1) + (k - 1)] =
                z[u_col(seg_[k].point_offset - 1, j)] - z[u_col(seg_[k].point_offset, j)];
        }
    }
}

void Transcription::jacobian(const double* z, double* values) {
    update(z, true);
    int row = 0;
    for (const Segment& s : seg_) {
        const Eigen::MatrixXd& D = s.rule.differentiation;
        for (int i = 0; i < s.n; ++i) {
            const int pt = s.point_offset + i;
            const std::size_t nv = node_cols_[pt].size();
            for (int r = 0; r < nx_; ++r, ++row) {
                int idx = defect_jac_start_[row];
                for (int l = 0; l < s.n; ++l) {
                    if (l != i) values[idx++] = D(i, l);
                }
                for (std::size_t c = 0; c < nv; ++c) values[idx + c] = -node_jac_[pt][r * nv + c];
                values[idx + r] += D(i, i);  // the node's own state r is local column r
            }
        }
    }
    for (int pt = 0; pt < n_points_; ++pt) {
        const std::size_t nv = node_cols_[pt].size();
        for (int j = 0; j < ng_; ++j) {
            const int idx = path_jac_start_[pt * ng_ + j];
            for (std::size_t c = 0; c < nv; ++c)
                values[idx + c] = node_jac_[pt][(nx_ + j) * nv + c];
        }
    }
    const std::size_t nb = boundary_cols_.size();
    for (int e = 0; e < ne_; ++e) {
        for (std::size_t c = 0; c < nb; ++c) {
            values[event_jac_start_ + e * nb + c] = boundary_jac_[e * nb + c];
        }
    }
    for (const auto& jn : junctions_) {
        const std::size_t nv = jn.cols.size();
        int idx = jn.jac_start;
        for (int e = 0; e < jn.n; ++e) {
            for (std::size_t c = 0; c < nv; ++c) {
                if (jn.cols[c] >= 0) values[idx++] = jn.jac[e * nv + c];
            }
        }
    }
    for (int m = 0; order_row_ + m < tie_row_; ++m) {
        values[order_jac_start_ + 2 * m] = -1.0;
        values[order_jac_start_ + 2 * m + 1] = 1.0;
    }
    const int K = n_segments();
    for (const Tie& t : ties_) {
        int idx = t.jac_start;
        values[idx++] = 1.0;  // b_k is interior
        if (t.a > 0) values[idx++] = -(1.0 - t.w);
        if (t.c < K) values[idx++] = -t.w;
    }
    if (nq_ > 0) {
        const std::size_t nc = integral_cols_.size();
        for (int j = 0; j < nq_; ++j) {
            double* row = values + integral_jac_start_ + static_cast<std::size_t>(j) * nc;
            std::fill(row, row + nc, 0.0);
            for (int pt = 0; pt < n_points_; ++pt) {
                const std::size_t nv = node_cols_[pt].size();
                const auto& pos = integral_pos_[pt];
                const auto out = static_cast<std::size_t>(integral_out_ + j);
                for (std::size_t c = 0; c < nv; ++c) row[pos[c]] += node_jac_[pt][out * nv + c];
            }
        }
    }
    std::vector<double> dg, d2g;
    int rate = 0;
    for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
        const int j = rate_controls_[c];
        for (int k = 0; k < K; ++k) {
            const Segment& s = seg_[k];
            const Eigen::MatrixXd& D = s.rule.differentiation;
            double fac = 0.0;
            rate_factor(k, z, fac, dg, d2g);
            for (int i = 0; i < s.n; ++i, ++rate) {
                int idx = rate_jac_start_[rate];
                double a = 0.0;
                for (int l = 0; l < s.n; ++l) {
                    a += D(i, l) * z[u_col(s.point_offset + l, j)];
                    values[idx++] = fac * D(i, l);
                }
                for (const double d : dg) values[idx++] = a * d;
            }
        }
    }
    for (int r = continuity_jac_start_; r < nnz_jacobian(); r += 2) {
        values[r] = 1.0;
        values[r + 1] = -1.0;
    }
}

void Transcription::hessian(const double* z, double obj_factor, const double* lambda,
                            double* values) {
    std::fill(values, values + nnz_hessian(), 0.0);
    std::vector<double> w(n_node_out_);
    std::vector<double> H;
    int pt = 0;
    for (int k = 0; k < n_segments(); ++k) {
        const Segment& s = seg_[k];
        for (int i = 0; i < s.n; ++i, ++pt) {
            bool any = false;
            for (int r = 0; r < nx_; ++r) {
                w[r] = -lambda[s.defect_row + i * nx_ + r];
                any = any || w[r] != 0.0;
            }
            for (int j = 0; j < ng_; ++j) {
                w[nx_ + j] = lambda[path_row_ + pt * ng_ + j];
                any = any || w[nx_ + j] != 0.0;
            }
            if (lagrange_) {
                w[nx_ + ng_] = sign_ * obj_factor;
                any = any || obj_factor != 0.0;
            }
            for (int j = 0; j < nq_; ++j) {
                w[integral_out_ + j] = lambda[integral_row_ + j];
                any = any || w[integral_out_ + j] != 0.0;
            }
            if (!any) continue;
            const auto& cols = node_cols_[pt];
            const int nv = static_cast<int>(cols.size());
            gather(cols, z, work_v_);
            H.resize(static_cast<std::size_t>(nv * nv));
            model_.node_hessian(work_v_, placement(k, i, z), w, H);
            const auto& idx = node_hess_index_[pt];
            for (int a = 0; a < nv; ++a) {
                for (int b = 0; b <= a; ++b) values[idx[a * nv + b]] += H[a * nv + b];
            }
        }
    }
    if (n_boundary_out_ > 0) {
        std::vector<double> wb(n_boundary_out_);
        bool any = false;
        for (int e = 0; e < ne_; ++e) {
            wb[e] = lambda[event_row_ + e];
            any = any || wb[e] != 0.0;
        }
        if (mayer_) {
            wb[ne_] = sign_ * obj_factor;
            any = any || obj_factor != 0.0;
        }
        if (any) {
            const int nb = static_cast<int>(boundary_cols_.size());
            gather(boundary_cols_, z, work_v_);
            H.resize(static_cast<std::size_t>(nb * nb));
            model_.boundary_hessian(work_v_, wb, H);
            for (int a = 0; a < nb; ++a) {
                for (int b = 0; b <= a; ++b)
                    values[boundary_hess_index_[a * nb + b]] += H[a * nb + b];
            }
        }
    }
    interior_hessian(z, lambda, values);
    // control rates r = (2/h) a, a = D_i U: d2r = a d2(2/h) (time, time) + D_il d(2/h) (U_l, time)
    std::vector<double> dg, d2g;
    for (std::size_t c = 0; c < rate_controls_.size(); ++c) {
        const int j = rate_controls_[c];
        for (int k = 0; k < n_segments(); ++k) {
            const Segment& s = seg_[k];
            const Eigen::MatrixXd& D = s.rule.differentiation;
            const int ntv = static_cast<int>(s.time_cols.size());
            double fac = 0.0;
            rate_factor(k, z, fac, dg, d2g);
            for (int i = 0; i < s.n; ++i) {
                const double lam =
                    lambda[rate_row_ + static_cast<int>(c) * n_points_ + s.point_offset + i];
                if (lam == 0.0) continue;
                double a = 0.0;
                for (int l = 0; l < s.n; ++l) a += D(i, l) * z[u_col(s.point_offset + l, j)];
                for (int p = 0; p < ntv; ++p) {
                    for (int q = 0; q <= p; ++q)
                        values[s.time_hess[p * ntv + q]] += lam * a * d2g[p * ntv + q];
                }
                for (int l = 0; l < s.n; ++l) {
                    for (int v = 0; v < ntv; ++v)
                        values[s.rate_u_hess[c][l * ntv + v]] += lam * D(i, l) * dg[v];
                }
            }
        }
    }
}

void Transcription::interior_hessian(const double* z, const double* lambda, double* values) {
    std::vector<double> w, H;
    for (const auto& jn : junctions_) {
        w.assign(static_cast<std::size_t>(jn.n), 0.0);
        bool any = false;
        for (int e = 0; e < jn.n; ++e) {
            w[e] = lambda[jn.first_row + e];
            any = any || w[e] != 0.0;
        }
        if (!any) continue;
        const int nv = static_cast<int>(jn.cols.size());
        gather_interior(jn.index, z, work_v_);
        H.resize(static_cast<std::size_t>(nv * nv));
        model_.interior_hessian(jn.index, work_v_, w, H);
        for (int a = 0; a < nv; ++a) {
            for (int b = 0; b <= a; ++b) {
                const int id = jn.hess_index[a * nv + b];
                if (id >= 0) values[id] += H[a * nv + b];
            }
        }
    }
}

void Transcription::extract(const double* z, const double* lambda, int n_report, Solution& sol) {
    const ProblemInfo& info = model_.info();
    sol.info = info;
    sol.initial_time = z[t0_col()];
    sol.final_time = z[tf_col()];
    sol.parameters.resize(np_);
    for (int j = 0; j < np_; ++j) sol.parameters(j) = z[p_col(j)];
    const int K = n_segments();
    sol.breaks.clear();
    for (int k = 0; k <= K; ++k) {
        sol.breaks.push_back(sol.initial_time +
                             (sol.final_time - sol.initial_time) * break_value(z, k));
    }
    update(z, false);
    sol.integrals.resize(nq_);
    for (int j = 0; j < nq_; ++j) {
        double v = 0.0;
        for (int pt = 0; pt < n_points_; ++pt) v += node_out_[pt][integral_out_ + j];
        sol.integrals(j) = v;
    }
    sol.segments.clear();
    for (int k = 0; k < K; ++k) {
        const Segment& s = seg_[k];
        SegmentSolution out;
        out.tau = s.rule.points;
        out.weights = s.rule.weights;
        out.bary = s.rule.barycentric;
        out.time.resize(s.n);
        out.states.resize(s.n, nx_);
        out.controls.resize(s.n, nu_);
        out.costates = Eigen::MatrixXd::Zero(s.n, nx_);
        out.path.resize(s.n, ng_);
        for (int i = 0; i < s.n; ++i) {
            const int pt = s.point_offset + i;
            out.time(i) = node_time(k, i, z);
            for (int r = 0; r < nx_; ++r) out.states(i, r) = z[x_col(s.state_offset + i, r)];
            for (int j = 0; j < nu_; ++j) out.controls(i, j) = z[u_col(pt, j)];
            for (int j = 0; j < ng_; ++j) out.path(i, j) = node_out_[pt][nx_ + j];
            if (lambda != nullptr) {
                for (int r = 0; r < nx_; ++r) {
                    out.costates(i, r) = -lambda[s.defect_row + i * nx_ + r] / s.rule.weights(i);
                }
            }
        }
        sol.segments.push_back(std::move(out));
    }

    // violation report
    std::vector<double> g(n_rows_), gl(n_rows_), gu(n_rows_);
    std::vector<double> xl(n_vars_), xu(n_vars_);
    bounds(xl.data(), xu.data(), gl.data(), gu.data());
    constraints(z, g.data());
    std::vector<Violation> all;
    sol.max_violation = 0.0;
    sol.max_scaled_violation = 0.0;
    for (int row = 0; row < n_rows_; ++row) {
        const double amount = std::max({gl[row] - g[row], g[row] - gu[row], 0.0});
        if (!(amount > 0.0) && !std::isnan(g[row])) continue;
        Violation v;
        v.value = g[row];
        v.lower = gl[row] <= -kNlpInf ? -kInf : gl[row];
        v.upper = gu[row] >= kNlpInf ? kInf : gu[row];
        v.amount = std::isnan(g[row]) ? kInf : amount;
        v.scaled = row_scale_.size() == n_rows_ ? v.amount / row_scale_(row) : v.amount;
        if (row < path_row_) {
            int k = K - 1;
            while (k > 0 && seg_[k].defect_row > row) --k;
            const int local = row - seg_[k].defect_row;
            v.kind = "defect";
            v.name = "defect " + info.states[local % nx_].name;
            v.segment = k;
            v.node = local / nx_;
            v.time = node_time(k, v.node, z);
        } else if (row < event_row_) {
            const int pt = (row - path_row_) / ng_;
            int k = K - 1;
            while (k > 0 && seg_[k].point_offset > pt) --k;
            v.kind = "path";
            v.name = info.path[(row - path_row_) % ng_].name;
            v.segment = k;
            v.node = pt - seg_[k].point_offset;
            v.time = node_time(k, v.node, z);
        } else if (row < interior_row_) {
            v.kind = "event";
            v.name = info.events[row - event_row_].name;
            v.time = sol.final_time;
        } else if (row < order_row_) {
            v.kind = "interior event";
            for (const auto& jn : junctions_) {
                if (row >= jn.first_row && row < jn.first_row + jn.n) {
                    v.name = info.interior_events[jn.events[row - jn.first_row]].constraint.name;
                    v.segment = jn.index;
                    v.node = 0;
                    v.time = sol.breaks[static_cast<std::size_t>(jn.index)];
                }
            }
        } else if (row < integral_row_) {
            v.kind = "mesh";
            v.name = row < tie_row_ ? "segment order" : "segment tie";
        } else if (row < rate_row_) {
            v.kind = "integral";
            v.name = info.integrals[row - integral_row_].name;
            v.time = sol.final_time;
        } else if (row >= continuity_row_) {
            const int c = (row - continuity_row_) / (K - 1);
            const int k = (row - continuity_row_) % (K - 1) + 1;
            v.kind = "rate";
            v.name = "continuity " + info.controls[rate_controls_[c]].name;
            v.segment = k;
            v.node = 0;
            v.time = sol.breaks[static_cast<std::size_t>(k)];
        } else {
            const int c = (row - rate_row_) / n_points_;
            const int pt = (row - rate_row_) % n_points_;
            int k = K - 1;
            while (k > 0 && seg_[k].point_offset > pt) --k;
            v.kind = "rate";
            v.name = "rate " + info.controls[rate_controls_[c]].name;
            v.segment = k;
            v.node = pt - seg_[k].point_offset;
            v.time = node_time(k, v.node, z);
        }
        sol.max_violation = std::max(sol.max_violation, v.amount);
        sol.max_scaled_violation = std::max(sol.max_scaled_violation, v.scaled);
        all.push_back(std::move(v));
    }
    std::sort(all.begin(), all.end(),
              [](const Violation& a, const Violation& b) { return a.scaled > b.scaled; });
    if (static_cast<int>(all.size()) > n_report) all.resize(static_cast<std::size_t>(n_report));
    sol.violations = std::move(all);
}

}  // namespace manta::optimal::detail
