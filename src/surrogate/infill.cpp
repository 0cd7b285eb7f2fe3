#include "manta/surrogate/infill.hpp"

#include <fmt/format.h>
#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "manta/core/error.hpp"
#include "manta/surrogate/design.hpp"

namespace manta::surrogate {

double expected_improvement(const Prediction& p, double y_best) {
    const double improvement = y_best - p.mean;
    const double s = std::sqrt(std::max(p.mse, 0.0));
    if (!(s > 0.0)) return std::max(improvement, 0.0);
    const double z = improvement / s;
    const double cdf = 0.5 * std::erfc(-z / std::numbers::sqrt2);
    const double pdf = std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
    // The closed form can round to a tiny negative value far below y_best.
    return std::max(improvement * cdf + s * pdf, 0.0);
}

namespace {

void check_models(const std::vector<const Kriging*>& models, const char* where) {
    if (models.empty())
        throw InputError(fmt::format("{}: no model given; expected at least one", where));
    const Eigen::Index d = models.front() != nullptr ? models.front()->points().cols() : 0;
    for (std::size_t m = 0; m < models.size(); ++m) {
        if (models[m] == nullptr) {
            throw InputError(
                fmt::format("{}: model {} is null; expected a fitted Kriging", where, m));
        }
        if (models[m]->points().cols() != d) {
            throw InputError(
                fmt::format("{}: model {} has {} inputs, model 0 has {}; expected the same", where,
                            m, models[m]->points().cols(), d));
        }
    }
}

/// The models as the batch goes on: copies updated by the Kriging believer, the fixed weights
/// (1 / process variance of the models as given) and the points that may not be proposed again.
class Working {
public:
    Working(const std::vector<const Kriging*>& models, Criterion criterion)
        : criterion_(criterion) {
        // Expected improvement needs models.front() only; the others still block their samples.
        const std::size_t used = criterion == Criterion::max_mse ? models.size() : 1;
        Eigen::Index n_taken = 0;
        for (const Kriging* m : models) n_taken += m->points().rows();
        taken_.resize(n_taken, models.front()->points().cols());
        Eigen::Index row = 0;
        for (std::size_t m = 0; m < models.size(); ++m) {
            const Matrix& X = models[m]->points();
            taken_.middleRows(row, X.rows()) = X;
            row += X.rows();
            if (m >= used) continue;
            models_.push_back(*models[m]);
            const double s2 = models[m]->process_variance();
            // A model with no variance has no uncertainty to reduce (and MSE 0 everywhere).
            weights_.push_back(s2 > 0.0 && std::isfinite(s2) ? 1.0 / s2 : 0.0);
        }
        y_best_ = models_.front().values().minCoeff();
    }

    [[nodiscard]] Eigen::Index dim() const { return taken_.cols(); }

    /// Criterion at each row of P.
    [[nodiscard]] Vector values(const Matrix& P) const {
        Vector total = Vector::Zero(P.rows());
        Vector mean, mse;
        if (criterion_ == Criterion::max_mse) {
            for (std::size_t m = 0; m < models_.size(); ++m) {
                models_[m].predict(P, mean, &mse);
                total += weights_[m] * mse.cwiseMax(0.0);
            }
        } else {
            models_.front().predict(P, mean, &mse);
            for (Eigen::Index i = 0; i < P.rows(); ++i) {
                total(i) = expected_improvement({mean(i), mse(i)}, y_best_);
            }
        }
        return total;
    }

    [[nodiscard]] double value(const Vector& x) const {
        if (criterion_ == Criterion::max_mse) {
            double total = 0.0;
            for (std::size_t m = 0; m < models_.size(); ++m) {
                total += weights_[m] * std::max(models_[m].predict_with_mse(x).mse, 0.0);
            }
            return total;
        }
        return expected_improvement(models_.front().predict_with_mse(x), y_best_);
    }

    /// Whether x is at least `separation` away from every sample and every pick so far.
    [[nodiscard]] bool eligible(const Vector& x, double separation) const {
        if (taken_.rows() == 0) return true;
        const double d2 = (taken_.rowwise() - x.transpose()).rowwise().squaredNorm().minCoeff();
        return d2 >= separation * separation;
    }

    /// Kriging believer: each model refitted, same hyper-parameters, with its own prediction at x
    /// added as an observation.
    void believe(const Vector& x) {
        for (Kriging& model : models_) {
            const Eigen::Index n = model.points().rows();
            Matrix X(n + 1, dim());
            X.topRows(n) = model.points();
            X.row(n) = x.transpose();
            Vector y(n + 1);
            y.head(n) = model.values();
            y(n) = model.predict(x);
            model = Kriging::with_hyperparameters(X, y, model.options(), model.hyperparameters());
        }
        if (criterion_ == Criterion::expected_improvement) {
            y_best_ = models_.front().values().minCoeff();
        }
        taken_.conservativeResize(taken_.rows() + 1, Eigen::NoChange);
        taken_.row(taken_.rows() - 1) = x.transpose();
    }

private:
    Criterion criterion_;
    std::vector<Kriging> models_;
    std::vector<double> weights_;
    double y_best_ = 0.0;
    Matrix taken_;
};

/// Rows of P that are eligible, by decreasing criterion value (ties: lower row first).
std::vector<Eigen::Index> ranked(const Working& w, const Matrix& P, double separation) {
    const Vector v = w.values(P);
    std::vector<Eigen::Index> order;
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
        if (std::isfinite(v(i)) && w.eligible(P.row(i).transpose(), separation)) order.push_back(i);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&v](Eigen::Index a, Eigen::Index b) { return v(a) > v(b); });
    return order;
}

void check_options(const InfillOptions& o, const char* where) {
    if (o.batch < 1) {
        throw InputError(fmt::format("{}: batch = {}; expected at least 1", where, o.batch));
    }
    if (!(o.min_separation >= 0.0)) {
        throw InputError(
            fmt::format("{}: min_separation = {}; expected >= 0", where, o.min_separation));
    }
}

/// Local maximisation of the criterion from x0 within the bounds (BOBYQA, derivative free).
struct Polish {
    const Working* working;
    double best_value;
    std::vector<double> best_x;
};

double polish_objective(const std::vector<double>& x, std::vector<double>& /*grad*/, void* data) {
    auto* p = static_cast<Polish*>(data);
    const Vector xv = Eigen::Map<const Vector>(x.data(), static_cast<Eigen::Index>(x.size()));
    const double v = p->working->value(xv);
    if (std::isfinite(v) && v > p->best_value) {
        p->best_value = v;
        p->best_x = x;
    }
    return std::isfinite(v) ? v : -std::numeric_limits<double>::max();
}

/// Best point (and its value) reached by BOBYQA from x0; x0 itself if nothing better is found.
std::pair<Vector, double> polish(const Working& w, const Bounds& b, const Vector& x0, double step) {
    const auto d = static_cast<unsigned>(x0.size());
    Polish data{&w, w.value(x0), std::vector<double>(x0.data(), x0.data() + x0.size())};
    nlopt::opt opt(nlopt::LN_BOBYQA, d);
    opt.set_lower_bounds(std::vector<double>(b.lower.data(), b.lower.data() + d));
    opt.set_upper_bounds(std::vector<double>(b.upper.data(), b.upper.data() + d));
    opt.set_max_objective(polish_objective, &data);
    std::vector<double> steps(d);
    for (unsigned k = 0; k < d; ++k) steps[k] = step * (b.upper(k) - b.lower(k));
    opt.set_initial_step(steps);
    opt.set_maxeval(static_cast<int>(60 * d + 40));
    opt.set_xtol_rel(1e-6);
    std::vector<double> x = data.best_x;
    double v = 0.0;
    try {
        opt.optimize(x, v);
    } catch (const std::exception&) {
        // Roundoff or a failed step: the best point evaluated so far is kept (data.best_x).
    }
    return {Eigen::Map<const Vector>(data.best_x.data(), d), data.best_value};
}

}  // namespace

Vector criterion_values(const std::vector<const Kriging*>& models, const Matrix& points,
                        Criterion criterion) {
    check_models(models, "infill criterion");
    if (points.cols() != models.front()->points().cols()) {
        throw InputError(fmt::format("infill criterion: points have {} columns; expected {}",
                                     points.cols(), models.front()->points().cols()));
    }
    return Working(models, criterion).values(points);
}

std::vector<Eigen::Index> propose_from(const std::vector<const Kriging*>& models,
                                       const Matrix& candidates, const InfillOptions& options) {
    check_models(models, "infill (candidates)");
    check_options(options, "infill (candidates)");
    if (candidates.cols() != models.front()->points().cols()) {
        throw InputError(fmt::format("infill (candidates): candidates have {} columns; expected {}",
                                     candidates.cols(), models.front()->points().cols()));
    }
    Working w(models, options.criterion);
    std::vector<Eigen::Index> picks;
    for (int k = 0; k < options.batch; ++k) {
        const std::vector<Eigen::Index> order = ranked(w, candidates, options.min_separation);
        if (order.empty()) break;
        picks.push_back(order.front());
        if (k + 1 < options.batch) w.believe(candidates.row(order.front()).transpose());
    }
    return picks;
}

Matrix propose_in(const std::vector<const Kriging*>& models, const Bounds& bounds,
                  const InfillOptions& options) {
    check_models(models, "infill (box)");
    check_options(options, "infill (box)");
    const Eigen::Index d = models.front()->points().cols();
    if (bounds.lower.size() != d || bounds.upper.size() != d) {
        throw InputError(fmt::format("infill (box): bounds of dimension {} and {}; expected {}",
                                     bounds.lower.size(), bounds.upper.size(), d));
    }
    for (Eigen::Index k = 0; k < d; ++k) {
        if (!(bounds.lower(k) < bounds.upper(k))) {
            throw InputError(
                fmt::format("infill (box): bounds [{}, {}] in dimension {}; expected "
                            "lower < upper",
                            bounds.lower(k), bounds.upper(k), k));
        }
    }
    if (options.search_points < 1) {
        throw InputError(fmt::format("infill (box): search_points = {}; expected at least 1",
                                     options.search_points));
    }
    // A plain random LHS (no maximin iterations): dense enough that its spacing matters more
    // than its uniformity, and cheap to draw.
    const Matrix search = to_bounds(
        latin_hypercube(options.search_points, static_cast<int>(d), options.seed, 0), bounds);
    // Polish from the best few search points: the criteria are multimodal (one bump per gap
    // between samples). Initial BOBYQA step: about the spacing of the search points.
    constexpr std::size_t n_starts = 3;
    const double step = std::clamp(
        std::pow(static_cast<double>(options.search_points), -1.0 / static_cast<double>(d)), 1e-3,
        0.25);
    Working w(models, options.criterion);
    Matrix picks(0, d);
    for (int k = 0; k < options.batch; ++k) {
        const std::vector<Eigen::Index> order = ranked(w, search, options.min_separation);
        if (order.empty()) break;
        Vector best = search.row(order.front()).transpose();
        if (options.polish) {
            double best_value = w.value(best);
            for (std::size_t s = 0; s < std::min(n_starts, order.size()); ++s) {
                auto [x, v] = polish(w, bounds, search.row(order[s]).transpose(), step);
                if (v > best_value && w.eligible(x, options.min_separation)) {
                    best = x;
                    best_value = v;
                }
            }
        }
        picks.conservativeResize(picks.rows() + 1, Eigen::NoChange);
        picks.row(picks.rows() - 1) = best.transpose();
        if (k + 1 < options.batch) w.believe(best);
    }
    return picks;
}

}  // namespace manta::surrogate
