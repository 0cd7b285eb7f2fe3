/// @file generator.cpp
/// Campaign execution: scheduling through the store, concurrent evaluation, Kriging of the
/// static table with adaptive infill, control increments fused with the static model (Kriging of
/// dC / delta with the static slope as regressor, adaptive infill), central differences
/// of the dynamic derivatives. docs/tables.md explains every choice.

#include "manta/tables/generator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "manta/core/error.hpp"
#include "manta/surrogate/design.hpp"
#include "manta/surrogate/infill.hpp"

namespace manta::tables {

using surrogate::Matrix;
using surrogate::Prediction;
using surrogate::Vector;

namespace {

using clock_type = std::chrono::steady_clock;

/// The coefficient `j` (CL CD CY Cl Cm Cn) of a result.
double coefficient(const aero::SourceResult& r, int j) {
    switch (j) {
        case 0:
            return r.wind.CL;
        case 1:
            return r.wind.CD;
        case 2:
            return r.wind.CY;
        case 3:
            return r.body.Cl;
        case 4:
            return r.body.Cm;
        default:
            return r.body.Cn;
    }
}

/// Box of a three-axis grid and its unit-cube map.
struct Box3 {
    std::array<double, 3> lo{}, hi{};
    static Box3 of(const std::vector<double>& a, const std::vector<double>& b,
                   const std::vector<double>& c) {
        Box3 x;
        const std::vector<double>* axes[3] = {&a, &b, &c};
        for (int k = 0; k < 3; ++k) {
            x.lo[k] = axes[k]->front();
            x.hi[k] = axes[k]->back();
        }
        return x;
    }
    [[nodiscard]] double to_unit(int k, double v) const {
        return hi[k] > lo[k] ? (v - lo[k]) / (hi[k] - lo[k]) : 0.5;
    }
    [[nodiscard]] double from_unit(int k, double u) const { return lo[k] + u * (hi[k] - lo[k]); }
    [[nodiscard]] Vector unit(double a, double b, double c) const {
        Vector x(3);
        x << to_unit(0, a), to_unit(1, b), to_unit(2, c);
        return x;
    }
};

/// A full-factorial grid of three axes (last fastest) with the unit coordinates of its entries.
struct Grid3 {
    std::array<std::vector<double>, 3> axes;
    Box3 box;
    Matrix unit;  ///< entries x 3
    Grid3(std::vector<double> a, std::vector<double> b, std::vector<double> c)
        : axes{std::move(a), std::move(b), std::move(c)}, box(Box3::of(axes[0], axes[1], axes[2])) {
        unit.resize(static_cast<Eigen::Index>(size()), 3);
        for (std::size_t e = 0; e < size(); ++e) {
            const auto ijk = index(e);
            for (int k = 0; k < 3; ++k)
                unit(static_cast<Eigen::Index>(e), k) = box.to_unit(k, axes[k][ijk[k]]);
        }
    }
    [[nodiscard]] std::size_t size() const {
        return axes[0].size() * axes[1].size() * axes[2].size();
    }
    [[nodiscard]] std::array<std::size_t, 3> index(std::size_t e) const {
        const std::size_t n2 = axes[2].size(), n1 = axes[1].size();
        return {e / (n1 * n2), (e / n2) % n1, e % n2};
    }
    [[nodiscard]] double value(std::size_t e, int k) const { return axes[k][index(e)[k]]; }
    /// Entry of exact coordinates, or -1 if off the grid.
    [[nodiscard]] long find(double a, double b, double c) const {
        const double v[3] = {a, b, c};
        std::size_t ijk[3];
        for (int k = 0; k < 3; ++k) {
            const auto it = std::find(axes[k].begin(), axes[k].end(), v[k]);
            if (it == axes[k].end()) return -1;
            ijk[k] = static_cast<std::size_t>(it - axes[k].begin());
        }
        return static_cast<long>((ijk[0] * axes[1].size() + ijk[1]) * axes[2].size() + ijk[2]);
    }
};

/// Snap the rows of a unit-cube design, in order, to the nearest entries not yet `taken` (ties:
/// the lowest entry); marks the chosen entries taken.
std::vector<std::size_t> snap_to_grid(const Matrix& design, const Grid3& grid,
                                      std::vector<bool>& taken) {
    std::vector<std::size_t> chosen;
    for (Eigen::Index i = 0; i < design.rows(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        std::size_t pick = grid.size();
        for (std::size_t e = 0; e < grid.size(); ++e) {
            if (taken[e]) continue;
            const double d =
                (grid.unit.row(static_cast<Eigen::Index>(e)) - design.row(i)).squaredNorm();
            if (d < best) {
                best = d;
                pick = e;
            }
        }
        if (pick == grid.size()) break;  // grid exhausted
        taken[pick] = true;
        chosen.push_back(pick);
    }
    return chosen;
}

/// A model of one coefficient: a Kriging, or a constant when the data do not vary (a symmetric
/// aircraft's lateral coefficients in a longitudinal scenario).
struct CoefficientModel {
    std::optional<surrogate::Kriging> kriging;
    double constant = 0.0;
    double loo_rmse = 0.0;
    double range = 0.0;

    [[nodiscard]] Prediction predict(const Vector& x) const {
        if (kriging) return kriging->predict_with_mse(x);
        return {constant, 0.0};
    }
};

/// True if the values do not vary beyond rounding.
bool is_constant(const Vector& y) {
    const double range = y.maxCoeff() - y.minCoeff();
    return !(range > 1e-12 + 1e-9 * y.cwiseAbs().maxCoeff());
}

CoefficientModel fit_coefficient(const Matrix& X, const Vector& y,
                                 const surrogate::KrigingOptions& o) {
    CoefficientModel m;
    m.range = y.maxCoeff() - y.minCoeff();
    if (is_constant(y)) {
        m.constant = y.mean();
        return m;
    }
    m.kriging = surrogate::Kriging::fit(X, y, o);
    m.loo_rmse = m.kriging->loo_rmse();
    return m;
}

/// A query at (alpha, mach, beta) and a control setting.
aero::AeroQuery<double> query_at(double alpha, double mach, double beta) {
    aero::AeroQuery<double> q;
    q.alpha = alpha;
    q.mach = mach;
    q.beta = beta;
    return q;
}

void set_control(aero::AeroQuery<double>& q, aero::Axis control, double delta) {
    switch (control) {
        case aero::Axis::elevator:
            q.elevator = delta;
            break;
        case aero::Axis::aileron:
            q.aileron = delta;
            break;
        case aero::Axis::rudder:
            q.rudder = delta;
            break;
        default:
            break;
    }
}

double get_control(const aero::AeroQuery<double>& q, aero::Axis control) {
    switch (control) {
        case aero::Axis::elevator:
            return q.elevator;
        case aero::Axis::aileron:
            return q.aileron;
        case aero::Axis::rudder:
            return q.rudder;
        default:
            return 0.0;
    }
}

/// Campaign-wide bookkeeping: counts, timing, progress reports.
class Runner {
public:
    Runner(const Campaign& c, const aero::AeroSource& source, SampleStore& store,
           const RunOptions& o)
        : campaign_(c), source_(source), store_(store), options_(o), start_(clock_type::now()) {
        planned_ = c.static_table.budget;
        for (const auto& p : c.controls) planned_ += p.samples;
        if (c.dynamic)
            planned_ += static_cast<int>(6 * c.dynamic->alpha.size() * c.dynamic->mach.size());
        for (const Sample& s : store.samples()) {
            if (s.status == SampleStatus::pending) continue;
            ++finished_before_;
            stored_time_ += s.wall_time_s;
        }
    }

    /// Evaluate the pending samples of `scenario` (scheduling order) with up to `jobs` threads;
    /// each result is committed before the thread takes the next sample.
    void evaluate_pending(const std::string& scenario, int total) {
        std::vector<Sample> waiting;
        for (Sample& s : store_.samples(scenario))
            if (s.status == SampleStatus::pending) waiting.push_back(std::move(s));
        if (waiting.empty()) return;
        std::atomic<std::size_t> next{0};
        const int n_threads = static_cast<int>(std::min<std::size_t>(
            static_cast<std::size_t>(std::max(1, options_.jobs)), waiting.size()));
        auto work = [&] {
            for (;;) {
                const std::size_t i = next.fetch_add(1);
                if (i >= waiting.size()) return;
                const Sample& s = waiting[i];
                const auto t0 = clock_type::now();
                std::string error;
                aero::SourceResult r;
                try {
                    const aero::FlowConditions fc = options_.conditions
                                                        ? options_.conditions(s.query.mach)
                                                        : aero::FlowConditions{};
                    r = source_.evaluate(s.query, fc);
                    for (int j = 0; j < 6; ++j)
                        if (!std::isfinite(coefficient(r, j)))
                            throw NumericalError(fmt::format("source returned a non-finite {}",
                                                             coefficient_names[j]));
                } catch (const std::exception& e) {
                    error = e.what();
                    if (error.empty()) error = "unknown error";
                }
                const double dt = std::chrono::duration<double>(clock_type::now() - t0).count();
                if (error.empty())
                    store_.record_done(s.id, r, dt);
                else
                    store_.record_failed(s.id, error, dt);
                {
                    const std::lock_guard lock(mutex_);
                    ++evaluated_;
                    run_time_ += dt;
                    if (!error.empty()) ++failed_now_;
                }
                report(scenario, total, -1.0, false);
            }
        };
        std::vector<std::thread> threads;
        for (int t = 1; t < n_threads; ++t) threads.emplace_back(work);
        work();
        for (auto& t : threads) t.join();
    }

    /// Send a progress report (counting the scenario's finished samples).
    void report(const std::string& scenario, int total, double cv, bool count_store) {
        if (!options_.progress) return;
        const std::lock_guard lock(mutex_);
        if (cv >= 0.0) last_cv_ = cv;
        if (count_store || scenario != last_scenario_) {
            scenario_done_ = 0;
            for (const Sample& s : store_.samples(scenario))
                if (s.status != SampleStatus::pending) ++scenario_done_;
            last_scenario_ = scenario;
        } else {
            ++scenario_done_;
        }
        Progress p;
        p.phase = scenario;
        p.done = scenario_done_;
        p.total = total;
        p.cv_error = last_cv_;
        p.elapsed_s = std::chrono::duration<double>(clock_type::now() - start_).count();
        const int finished = finished_before_ + evaluated_;
        const double mean = evaluated_ > 0         ? run_time_ / evaluated_
                            : finished_before_ > 0 ? stored_time_ / finished_before_
                                                   : -1.0;
        if (mean >= 0.0)
            p.remaining_s = std::max(0, planned_ - finished) * mean / std::max(1, options_.jobs);
        options_.progress(p);
    }

    void new_phase(const std::string& scenario, int total, double cv) {
        if (!options_.progress) return;
        {
            const std::lock_guard lock(mutex_);
            last_cv_ = cv;
        }
        report(scenario, total, cv, true);
    }

    [[nodiscard]] int evaluated() const { return evaluated_; }
    [[nodiscard]] double elapsed() const {
        return std::chrono::duration<double>(clock_type::now() - start_).count();
    }

    const Campaign& campaign_;
    const aero::AeroSource& source_;
    SampleStore& store_;
    const RunOptions& options_;

private:
    clock_type::time_point start_;
    std::mutex mutex_;
    int planned_ = 0;
    int finished_before_ = 0;
    double stored_time_ = 0.0;
    int evaluated_ = 0;
    int failed_now_ = 0;
    double run_time_ = 0.0;
    double last_cv_ = -1.0;
    std::string last_scenario_;
    int scenario_done_ = 0;
};

/// Counts of a scenario's samples in the store.
void count_samples(const std::vector<Sample>& samples, ScenarioReport& r) {
    r.samples_done = 0;
    r.samples_failed = 0;
    r.sample_wall_time_s = 0.0;
    for (const Sample& s : samples) {
        if (s.status == SampleStatus::done) {
            ++r.samples_done;
            r.sample_wall_time_s += s.wall_time_s;
        } else if (s.status == SampleStatus::failed) {
            ++r.samples_failed;
        }
    }
}

int done_count(SampleStore& store, const std::string& scenario) {
    int n = 0;
    for (const Sample& s : store.samples(scenario))
        if (s.status == SampleStatus::done) ++n;
    return n;
}

}  // namespace

// ------------------------------------------------------------------------------ static model

struct StaticModel::Impl {
    Box3 box;
    std::array<CoefficientModel, 6> models;
};

std::array<Prediction, 6> StaticModel::predict(double alpha, double mach, double beta) const {
    const Vector x = impl_->box.unit(alpha, mach, beta);
    std::array<Prediction, 6> out;
    for (int j = 0; j < 6; ++j)
        out[static_cast<std::size_t>(j)] = impl_->models[static_cast<std::size_t>(j)].predict(x);
    return out;
}

// ----------------------------------------------------------------------------- control model

struct ControlModel::Impl {
    aero::Axis control = aero::Axis::elevator;
    Box3 box;
    /// Kriging of the increment per unit deflection g = dC / delta per coefficient (empty: g was
    /// constant over the samples, `constant`).
    std::array<std::optional<surrogate::Kriging>, 6> ratio;
    std::array<double, 6> constant{};
};

std::array<Prediction, 6> ControlModel::increment(double alpha, double mach, double delta) const {
    std::array<Prediction, 6> out;
    if (delta == 0.0) return out;  // exactly zero, with zero MSE
    const Vector x = impl_->box.unit(alpha, mach, delta);
    for (std::size_t j = 0; j < 6; ++j) {
        if (impl_->ratio[j]) {
            const Prediction g = impl_->ratio[j]->predict_with_mse(x);
            out[j] = {delta * g.mean, delta * delta * g.mse};
        } else {
            out[j] = {delta * impl_->constant[j], 0.0};
        }
    }
    return out;
}

aero::Axis ControlModel::control() const {
    return impl_->control;
}

namespace {

/// The static table's axes and columns, values and sigma zero, for `n` entries.
TableWithSigma empty_static_table(const StaticPlan& plan, std::size_t n) {
    TableWithSigma t;
    t.table.name = "static";
    t.table.kind = aero::TableKind::static_table;
    t.table.axes = {{aero::Axis::alpha, plan.alpha},
                    {aero::Axis::mach, plan.mach},
                    {aero::Axis::beta, plan.beta}};
    t.table.columns = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    t.table.values.assign(n * 6, 0.0);
    t.sigma.assign(n * 6, 0.0);
    return t;
}

}  // namespace

// ------------------------------------------------------------------------------- scenarios

namespace {

/// Scenario 1: the static table by adaptive sampling.
TableWithSigma run_static(Runner& run, int batch, ScenarioReport& report,
                          std::shared_ptr<const StaticModel>& model_out) {
    const StaticPlan& plan = run.campaign_.static_table;
    const std::string scenario = "static";
    const Grid3 grid(plan.alpha, plan.mach, plan.beta);
    SampleStore& store = run.store_;
    if (run.options_.retry_failed) store.reset_failed(scenario);
    const int reused = done_count(store, scenario);

    auto entries_taken = [&](const std::vector<Sample>& samples) {
        std::vector<bool> taken(grid.size(), false);
        for (const Sample& s : samples) {
            const long e = grid.find(s.query.alpha, s.query.mach, s.query.beta);
            if (e >= 0) taken[static_cast<std::size_t>(e)] = true;
        }
        return taken;
    };
    auto schedule_entries = [&](const std::vector<std::size_t>& chosen) {
        std::vector<aero::AeroQuery<double>> q;
        for (const std::size_t e : chosen)
            q.push_back(query_at(grid.value(e, 0), grid.value(e, 1), grid.value(e, 2)));
        store.schedule(scenario, q);
    };

    // Initial design: a maximin Latin hypercube snapped to the nearest distinct table entries
    // (the whole budget for the `random` criterion). Already stored entries are kept as they are.
    {
        const int n0 = plan.criterion == InfillCriterion::random ? plan.budget : plan.initial_size;
        const Matrix lhs = surrogate::latin_hypercube(n0, 3, plan.seed);
        std::vector<bool> taken(grid.size(), false);
        schedule_entries(snap_to_grid(lhs, grid, taken));
    }
    run.new_phase(scenario, plan.budget, -1.0);
    run.evaluate_pending(scenario, plan.budget);

    std::shared_ptr<StaticModel::Impl> impl;
    Matrix X;
    std::vector<Vector> Y;
    std::vector<Sample> done;
    int round = 0;
    for (;; ++round) {
        const std::vector<Sample> all = store.samples(scenario);
        done.clear();
        int failed = 0;
        for (const Sample& s : all) {
            if (s.status == SampleStatus::done) done.push_back(s);
            if (s.status == SampleStatus::failed) ++failed;
        }
        const int used = static_cast<int>(done.size()) + failed;
        if (done.size() < 4)
            throw ConvergenceError(fmt::format(
                "tables: the static scenario has {} done samples ({} failed); at least 4 are "
                "needed to fit the models (see the errors in samples.csv; --retry-failed "
                "evaluates failed samples again)",
                done.size(), failed));
        X.resize(static_cast<Eigen::Index>(done.size()), 3);
        Y.assign(6, Vector(static_cast<Eigen::Index>(done.size())));
        for (std::size_t i = 0; i < done.size(); ++i) {
            const auto& q = done[i].query;
            X.row(static_cast<Eigen::Index>(i)) = grid.box.unit(q.alpha, q.mach, q.beta);
            for (int j = 0; j < 6; ++j)
                Y[static_cast<std::size_t>(j)][static_cast<Eigen::Index>(i)] =
                    coefficient(done[i].result, j);
        }
        impl = std::make_shared<StaticModel::Impl>();
        impl->box = grid.box;
        double cv = 0.0;
        report.loo.clear();
        for (int j = 0; j < 6; ++j) {
            auto& m = impl->models[static_cast<std::size_t>(j)];
            m = fit_coefficient(X, Y[static_cast<std::size_t>(j)], plan.kriging);
            LooError e{coefficient_names[j], m.loo_rmse, m.range,
                       m.range > 0.0 && m.kriging ? m.loo_rmse / m.range : 0.0};
            cv = std::max(cv, e.relative);
            report.loo.push_back(e);
        }
        run.new_phase(scenario, plan.budget, cv);

        if (plan.criterion == InfillCriterion::random) {
            report.stop_reason = "design";
            break;
        }
        if (used >= plan.budget) {
            report.stop_reason = "budget";
            break;
        }
        if (plan.cv_threshold > 0.0 && cv < plan.cv_threshold) {
            report.stop_reason = "cv_threshold";
            break;
        }
        const std::vector<bool> taken = entries_taken(all);
        std::vector<std::size_t> free;
        for (std::size_t e = 0; e < grid.size(); ++e)
            if (!taken[e]) free.push_back(e);
        if (free.empty()) {
            report.stop_reason = "grid";
            break;
        }
        Matrix candidates(static_cast<Eigen::Index>(free.size()), 3);
        for (std::size_t i = 0; i < free.size(); ++i)
            candidates.row(static_cast<Eigen::Index>(i)) =
                grid.unit.row(static_cast<Eigen::Index>(free[i]));
        const int q = std::min({batch, plan.budget - used, static_cast<int>(free.size())});

        surrogate::InfillOptions io;
        io.batch = q;
        io.seed = plan.seed + static_cast<std::uint64_t>(round);
        std::vector<const surrogate::Kriging*> models;
        std::optional<surrogate::Kriging> ei_model;
        if (plan.criterion == InfillCriterion::ei) {
            io.criterion = surrogate::Criterion::expected_improvement;
            int j = 0;
            while (j < 6 && plan.ei_coefficient != coefficient_names[j]) ++j;
            const auto& m = impl->models[static_cast<std::size_t>(std::min(j, 5))];
            if (m.kriging) {
                if (plan.ei_maximise)
                    ei_model = surrogate::Kriging::with_hyperparameters(
                        m.kriging->points(), -m.kriging->values(), plan.kriging,
                        m.kriging->hyperparameters());
                models.push_back(ei_model ? &*ei_model : &*m.kriging);
            }
        } else {
            io.criterion = surrogate::Criterion::max_mse;
            for (const auto& m : impl->models)
                if (m.kriging) models.push_back(&*m.kriging);
        }
        std::vector<std::size_t> chosen;
        if (models.empty()) {
            // Every coefficient constant so far: fill space (farthest entries from the samples).
            std::vector<bool> t = taken;
            Matrix far(1, 3);
            for (int k = 0; k < q; ++k) {
                double best = -1.0;
                std::size_t pick = 0;
                for (const std::size_t e : free) {
                    if (t[e]) continue;
                    double dmin = std::numeric_limits<double>::infinity();
                    for (Eigen::Index i = 0; i < X.rows(); ++i)
                        dmin = std::min(
                            dmin,
                            (grid.unit.row(static_cast<Eigen::Index>(e)) - X.row(i)).squaredNorm());
                    if (dmin > best) {
                        best = dmin;
                        pick = e;
                    }
                }
                t[pick] = true;
                chosen.push_back(pick);
            }
        } else {
            for (const Eigen::Index r : surrogate::propose_from(models, candidates, io))
                chosen.push_back(free[static_cast<std::size_t>(r)]);
        }
        if (chosen.empty()) {
            report.stop_reason = "grid";
            break;
        }
        schedule_entries(chosen);
        run.evaluate_pending(scenario, plan.budget);
    }

    // The table: Kriging mean and MSE at every entry; sampled entries keep their sampled values
    // (exact data, sigma 0) unless a nugget was estimated (noisy data are smoothed).
    TableWithSigma t = empty_static_table(plan, grid.size());
    for (int j = 0; j < 6; ++j) {
        const auto& m = impl->models[static_cast<std::size_t>(j)];
        Vector mean, mse;
        if (m.kriging) {
            m.kriging->predict(grid.unit, mean, &mse);
        } else {
            mean = Vector::Constant(grid.unit.rows(), m.constant);
            mse = Vector::Zero(grid.unit.rows());
        }
        for (std::size_t e = 0; e < grid.size(); ++e) {
            t.table.values[e * 6 + static_cast<std::size_t>(j)] =
                mean[static_cast<Eigen::Index>(e)];
            t.sigma[e * 6 + static_cast<std::size_t>(j)] =
                std::sqrt(std::max(0.0, mse[static_cast<Eigen::Index>(e)]));
        }
    }
    if (!plan.kriging.estimate_nugget) {
        for (const Sample& s : done) {
            const long e = grid.find(s.query.alpha, s.query.mach, s.query.beta);
            if (e < 0) continue;
            for (int j = 0; j < 6; ++j) {
                const std::size_t k = static_cast<std::size_t>(e) * 6 + static_cast<std::size_t>(j);
                t.table.values[k] = coefficient(s.result, j);
                t.sigma[k] = 0.0;
            }
        }
    }
    model_out = std::make_shared<const StaticModel>(impl);
    count_samples(store.samples(scenario), report);
    report.scenario = scenario;
    report.reused = reused;
    return t;
}

/// Smallest correlation parameter of the control models (inputs on the unit cube): with about
/// 12 samples the likelihood can otherwise drift to theta -> 0 (a flat, nearly polynomial model
/// whose MSE says nothing); 0.1 is a correlation length of about 2.2 box widths.
constexpr double control_theta_min = 0.1;

/// Size of the initial Latin hypercube of a control scenario; the rest of the budget is chosen
/// by maximum increment MSE.
constexpr int control_initial_size = 7;

/// The static model's derivative of coefficient `j` at beta = 0 that scales a control's effect:
/// d/dalpha for a coefficient that varies with alpha at beta = 0 (longitudinal), d/dbeta for one
/// that does not (lateral: zero at beta = 0 by symmetry). Central differences of the Kriging.
struct StaticSlope {
    std::shared_ptr<const StaticModel> model;
    std::size_t j = 0;
    bool beta = false;
    static constexpr double h = 1e-3;  ///< [rad]
    [[nodiscard]] double operator()(double alpha, double mach) const {
        if (beta)
            return (model->predict(alpha, mach, h)[j].mean -
                    model->predict(alpha, mach, -h)[j].mean) /
                   (2 * h);
        return (model->predict(alpha + h, mach, 0.0)[j].mean -
                model->predict(alpha - h, mach, 0.0)[j].mean) /
               (2 * h);
    }
};

/// Scenario 2: the increment table of one control, dC = delta * g(alpha, M, delta), g a Kriging
/// of (C_sample - C_static(alpha, M, 0)) / delta with the static slope as a regressor.
TableWithSigma run_control(Runner& run, const ControlPlan& plan, int batch,
                           const std::shared_ptr<const StaticModel>& static_model,
                           ScenarioReport& report, std::shared_ptr<const ControlModel>& model_out) {
    const std::string name(aero::to_string(plan.control));
    const std::string scenario = "control:" + name;
    const Grid3 grid(plan.alpha, plan.mach, plan.deflection);
    SampleStore& store = run.store_;
    if (run.options_.retry_failed) store.reset_failed(scenario);
    const int reused = done_count(store, scenario);
    auto query_of = [&](std::size_t e) {
        aero::AeroQuery<double> p = query_at(grid.value(e, 0), grid.value(e, 1), 0.0);
        set_control(p, plan.control, grid.value(e, 2));
        return p;
    };

    // Initial design: a maximin Latin hypercube over (alpha, M, delta) snapped to the deflected
    // entries (delta != 0). Already stored entries are kept as they are.
    {
        std::vector<bool> taken(grid.size(), false);
        for (std::size_t e = 0; e < grid.size(); ++e)
            if (grid.value(e, 2) == 0.0) taken[e] = true;
        const Matrix lhs =
            surrogate::latin_hypercube(std::min(plan.samples, control_initial_size), 3, plan.seed);
        std::vector<aero::AeroQuery<double>> q;
        for (const std::size_t e : snap_to_grid(lhs, grid, taken)) q.push_back(query_of(e));
        store.schedule(scenario, q);
    }
    run.new_phase(scenario, plan.samples, -1.0);
    run.evaluate_pending(scenario, plan.samples);

    // Which static slope scales each coefficient (fixed by the static model, not the samples).
    std::array<StaticSlope, 6> slope;
    for (std::size_t j = 0; j < 6; ++j) {
        double sa = 0.0, sb = 0.0;
        StaticSlope by_alpha{static_model, j, false}, by_beta{static_model, j, true};
        for (const double a : plan.alpha)
            for (const double m : plan.mach) {
                sa = std::max(sa, std::abs(by_alpha(a, m)));
                sb = std::max(sb, std::abs(by_beta(a, m)));
            }
        slope[j] = sa >= sb ? by_alpha : by_beta;
    }
    const double dmax = std::max(std::abs(grid.box.lo[2]), std::abs(grid.box.hi[2]));

    std::shared_ptr<ControlModel::Impl> impl;
    double cv = 0.0;
    for (;;) {
        std::vector<Sample> done;
        int failed = 0;
        for (const Sample& s : store.samples(scenario)) {
            if (s.status == SampleStatus::done) done.push_back(s);
            if (s.status == SampleStatus::failed) ++failed;
        }
        if (done.size() < 4)
            throw ConvergenceError(fmt::format(
                "tables: the {} scenario has {} done samples; at least 4 are needed for the "
                "increment model (see samples.csv; --retry-failed evaluates failed samples again)",
                scenario, done.size()));
        const auto n = static_cast<Eigen::Index>(done.size());
        Matrix X(n, 3);
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto& q = done[static_cast<std::size_t>(i)].query;
            X.row(i) = grid.box.unit(q.alpha, q.mach, get_control(q, plan.control));
        }
        impl = std::make_shared<ControlModel::Impl>();
        impl->control = plan.control;
        impl->box = grid.box;
        report.loo.clear();
        report.rho.clear();
        cv = 0.0;
        for (std::size_t j = 0; j < 6; ++j) {
            // Increment samples over the static model at (alpha, M, beta = 0), per radian.
            Vector dc(n), g(n), r(n);
            for (Eigen::Index i = 0; i < n; ++i) {
                const Sample& s = done[static_cast<std::size_t>(i)];
                const double d = get_control(s.query, plan.control);
                dc[i] = coefficient(s.result, static_cast<int>(j)) -
                        static_model->predict(s.query.alpha, s.query.mach, 0.0)[j].mean;
                g[i] = dc[i] / d;
                r[i] = slope[j](s.query.alpha, s.query.mach);
            }
            LooError e{coefficient_names[j], 0.0, dc.maxCoeff() - dc.minCoeff(), 0.0};
            double gain = 0.0;
            if (is_constant(g)) {
                impl->constant[j] = g.mean();
            } else {
                surrogate::KrigingOptions o = run.campaign_.static_table.kriging;
                o.theta_min = std::max(o.theta_min, control_theta_min);
                o.theta_max = std::max(o.theta_max, 10 * o.theta_min);
                // Universal trend 1, alpha, M, delta (constant with few samples), plus the
                // static slope where it varies over the samples.
                o.trend = n >= 7 ? surrogate::Trend::linear : surrogate::Trend::constant;
                const bool use_slope = !is_constant(r) && n >= 5;
                if (use_slope) {
                    const Box3 box = grid.box;
                    o.extra_regressors = [f = slope[j], box](const Vector& x) {
                        Vector v(1);
                        v[0] = f(box.from_unit(0, x[0]), box.from_unit(1, x[1]));
                        return v;
                    };
                }
                const surrogate::Kriging& k =
                    impl->ratio[j].emplace(surrogate::Kriging::fit(X, g, o));
                if (use_slope) gain = k.trend_coefficients()[k.trend_coefficients().size() - 1];
                // LOO error of the increment: delta_i times the LOO residual of g.
                const Vector res = k.loo_residuals();
                double ss = 0.0;
                for (Eigen::Index i = 0; i < n; ++i) {
                    const double d = grid.box.from_unit(2, X(i, 2));
                    ss += d * d * res[i] * res[i];
                }
                e.rmse = std::sqrt(ss / static_cast<double>(n));
            }
            e.relative = e.range > 0.0 ? e.rmse / e.range : 0.0;
            cv = std::max(cv, e.relative);
            report.loo.push_back(e);
            report.rho.push_back(gain);
        }
        run.new_phase(scenario, plan.samples, cv);

        const int used = static_cast<int>(done.size()) + failed;
        if (used >= plan.samples) {
            report.stop_reason = "budget";
            break;
        }
        // Infill: the free deflected entries of largest increment MSE, delta^2 mse_g(x) over
        // the process variance of g (delta scaled by the largest |delta|), summed over the
        // coefficients; q = batch per round, the later ones by the Kriging believer (the pick
        // joins the data at its predicted value, the MSE drops around it).
        std::vector<bool> taken(grid.size(), false);
        for (const Sample& s : store.samples(scenario)) {
            const long e =
                grid.find(s.query.alpha, s.query.mach, get_control(s.query, plan.control));
            if (e >= 0) taken[static_cast<std::size_t>(e)] = true;
        }
        std::vector<std::size_t> free;
        for (std::size_t e = 0; e < grid.size(); ++e)
            if (!taken[e] && grid.value(e, 2) != 0.0) free.push_back(e);
        if (free.empty()) {
            report.stop_reason = "grid";
            break;
        }
        const int q = std::min({batch, plan.samples - used, static_cast<int>(free.size())});
        std::array<std::optional<surrogate::Kriging>, 6> believer = impl->ratio;
        std::vector<std::size_t> chosen;
        for (int k = 0; k < q; ++k) {
            double best = -1.0;
            std::size_t pick = free.front();
            for (const std::size_t e : free) {
                if (std::find(chosen.begin(), chosen.end(), e) != chosen.end()) continue;
                const Vector x = grid.unit.row(static_cast<Eigen::Index>(e)).transpose();
                const double w = grid.value(e, 2) / dmax;
                double c = 0.0;
                for (const auto& m : believer)
                    if (m) c += w * w * m->predict_with_mse(x).mse / m->process_variance();
                if (c > best) {
                    best = c;
                    pick = e;
                }
            }
            chosen.push_back(pick);
            if (k + 1 == q) break;
            const Vector x = grid.unit.row(static_cast<Eigen::Index>(pick)).transpose();
            for (auto& m : believer) {
                if (!m) continue;
                Matrix Xa(m->points().rows() + 1, 3);
                Xa << m->points(), x.transpose();
                Vector ya(m->values().size() + 1);
                ya << m->values(), m->predict(x);
                m = surrogate::Kriging::with_hyperparameters(Xa, ya, m->options(),
                                                             m->hyperparameters());
            }
        }
        std::vector<aero::AeroQuery<double>> pts;
        for (const std::size_t e : chosen) pts.push_back(query_of(e));
        store.schedule(scenario, pts);
        run.evaluate_pending(scenario, plan.samples);
    }
    model_out = std::make_shared<const ControlModel>(impl);

    TableWithSigma t;
    t.table.name = name;
    t.table.kind = aero::TableKind::control;
    t.table.axes = {{aero::Axis::alpha, plan.alpha},
                    {aero::Axis::mach, plan.mach},
                    {plan.control, plan.deflection}};
    t.table.columns = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    t.table.values.assign(grid.size() * 6, 0.0);
    t.sigma.assign(grid.size() * 6, 0.0);
    for (std::size_t e = 0; e < grid.size(); ++e) {
        const auto p = model_out->increment(grid.value(e, 0), grid.value(e, 1), grid.value(e, 2));
        for (std::size_t j = 0; j < 6; ++j) {
            t.table.values[e * 6 + j] = p[j].mean;
            t.sigma[e * 6 + j] = std::sqrt(std::max(0.0, p[j].mse));
        }
    }
    count_samples(store.samples(scenario), report);
    report.scenario = scenario;
    report.reused = reused;
    return t;
}

/// Dynamic derivatives by central differences in each non-dimensional rate.
TableWithSigma run_dynamic(Runner& run, const DynamicPlan& plan, ScenarioReport& report) {
    const std::string scenario = "dynamic";
    SampleStore& store = run.store_;
    if (run.options_.retry_failed) store.reset_failed(scenario);
    const int reused = done_count(store, scenario);
    const double h = plan.rate_step;
    std::vector<aero::AeroQuery<double>> points;
    for (const double a : plan.alpha)
        for (const double m : plan.mach)
            for (int rate = 0; rate < 3; ++rate)
                for (const double sign : {1.0, -1.0}) {
                    aero::AeroQuery<double> q = query_at(a, m, 0.0);
                    (rate == 0 ? q.p_hat : rate == 1 ? q.q_hat : q.r_hat) = sign * h;
                    points.push_back(q);
                }
    const std::vector<std::int64_t> ids = store.schedule(scenario, points);
    const int total = static_cast<int>(points.size());
    run.new_phase(scenario, total, -1.0);
    run.evaluate_pending(scenario, total);

    std::map<std::int64_t, Sample> by_id;
    for (Sample& s : store.samples(scenario)) by_id.emplace(s.id, std::move(s));
    TableWithSigma t;
    t.table.name = "dynamic";
    t.table.kind = aero::TableKind::dynamic;
    t.table.axes = {{aero::Axis::alpha, plan.alpha}, {aero::Axis::mach, plan.mach}};
    const char* rates[3] = {"p", "q", "r"};
    for (int j = 0; j < 6; ++j)
        for (int r = 0; r < 3; ++r)
            t.table.columns.push_back(fmt::format("{}_{}", coefficient_names[j], rates[r]));
    const std::size_t nc = t.table.columns.size();
    const std::size_t n_points = plan.alpha.size() * plan.mach.size();
    t.table.values.assign(n_points * nc, 0.0);
    t.sigma.assign(n_points * nc, 0.0);
    for (std::size_t g = 0; g < n_points; ++g) {
        for (int r = 0; r < 3; ++r) {
            const Sample& plus = by_id.at(ids[g * 6 + static_cast<std::size_t>(2 * r)]);
            const Sample& minus = by_id.at(ids[g * 6 + static_cast<std::size_t>(2 * r + 1)]);
            for (const Sample* s : {&plus, &minus})
                if (s->status != SampleStatus::done)
                    throw ConvergenceError(fmt::format(
                        "tables: dynamic sample {} (alpha {:.4f} rad, M {:g}, rates {:g} {:g} "
                        "{:g}) failed: {}; run again with --retry-failed",
                        s->id, s->query.alpha, s->query.mach, s->query.p_hat, s->query.q_hat,
                        s->query.r_hat, s->error));
            for (int j = 0; j < 6; ++j)
                t.table.values[g * nc + static_cast<std::size_t>(j * 3 + r)] =
                    (coefficient(plus.result, j) - coefficient(minus.result, j)) / (2.0 * h);
        }
    }
    count_samples(store.samples(scenario), report);
    report.scenario = scenario;
    report.reused = reused;
    report.stop_reason = "grid";
    return t;
}

}  // namespace

CampaignResult run_campaign(const Campaign& campaign, const aero::AeroSource& source,
                            SampleStore& store, const RunOptions& options) {
    Runner run(campaign, source, store, options);
    CampaignResult result;
    // Batch size: the campaign's, else the one recorded by an earlier run of this store (so a
    // resumed campaign proposes the same points), else the number of jobs.
    int batch = campaign.static_table.batch;
    if (batch <= 0) {
        const auto stored = store.meta("static.batch");
        batch = stored ? std::max(1, std::atoi(stored->c_str())) : std::max(1, options.jobs);
    }
    store.set_meta("static.batch", std::to_string(batch));
    result.batch = batch;
    int reused_total = 0;
    for (const Sample& s : store.samples())
        if (s.status == SampleStatus::done) ++reused_total;

    ScenarioReport sr;
    result.tables.push_back(run_static(run, batch, sr, result.static_model));
    result.reports.push_back(sr);
    for (const ControlPlan& plan : campaign.controls) {
        ScenarioReport cr;
        std::shared_ptr<const ControlModel> m;
        result.tables.push_back(run_control(run, plan, batch, result.static_model, cr, m));
        result.control_models.push_back(m);
        result.reports.push_back(cr);
    }
    if (campaign.dynamic) {
        ScenarioReport dr;
        result.tables.push_back(run_dynamic(run, *campaign.dynamic, dr));
        result.reports.push_back(dr);
    }
    result.evaluated = run.evaluated();
    for (const Sample& s : store.samples())
        if (s.status == SampleStatus::failed) ++result.failed;
    // Per-scenario counts of this run: done now minus reused.
    for (auto& r : result.reports)
        r.evaluated = std::max(0, r.samples_done + r.samples_failed - r.reused);
    result.reused = reused_total;
    result.wall_time_s = run.elapsed();
    return result;
}

aero::AeroDatabase make_database(const Campaign& campaign, const CampaignResult& result,
                                 const std::string& source_name) {
    aero::DatabaseInfo info;
    info.name = campaign.name;
    info.source = source_name;
    std::string d = fmt::format("manta tables: static table from {} samples",
                                result.reports.empty() ? 0 : result.reports.front().samples_done);
    for (std::size_t i = 1; i < result.reports.size(); ++i) {
        const auto& r = result.reports[i];
        if (r.scenario == "dynamic")
            d += fmt::format("; dynamic derivatives by central differences ({} samples)",
                             r.samples_done);
        else
            d += fmt::format("; {} increments fused with the static model ({} samples)",
                             r.scenario.substr(8), r.samples_done);
    }
    info.description = d;
    std::vector<aero::Table> tables;
    for (const auto& t : result.tables) tables.push_back(t.table);
    return aero::AeroDatabase(info, aero::ForceAxes::wind, campaign.output.extrapolation,
                              std::move(tables));
}

TableWithSigma brute_force_static(const StaticPlan& plan, const aero::AeroSource& source,
                                  const RunOptions& options) {
    const Grid3 grid(plan.alpha, plan.mach, plan.beta);
    TableWithSigma t = empty_static_table(plan, grid.size());
    std::atomic<std::size_t> next{0};
    std::mutex error_mutex;
    std::string error;
    auto work = [&] {
        for (;;) {
            const std::size_t e = next.fetch_add(1);
            if (e >= grid.size()) return;
            try {
                const auto q = query_at(grid.value(e, 0), grid.value(e, 1), grid.value(e, 2));
                const aero::FlowConditions fc =
                    options.conditions ? options.conditions(q.mach) : aero::FlowConditions{};
                const aero::SourceResult r = source.evaluate(q, fc);
                for (int j = 0; j < 6; ++j)
                    t.table.values[e * 6 + static_cast<std::size_t>(j)] = coefficient(r, j);
            } catch (const std::exception& ex) {
                const std::lock_guard lock(error_mutex);
                if (error.empty()) error = ex.what();
            }
        }
    };
    std::vector<std::thread> threads;
    for (int k = 1; k < std::max(1, options.jobs); ++k) threads.emplace_back(work);
    work();
    for (auto& th : threads) th.join();
    if (!error.empty()) throw NumericalError("tables: brute-force table: " + error);
    return t;
}

}  // namespace manta::tables
