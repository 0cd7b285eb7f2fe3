#pragma once
/// @file infill.hpp
/// Infill criteria for adaptive sampling: where to run the next (expensive) evaluations.
///  - maximum MSE: the point where the models are least certain (space filling guided by the data);
///  - Expected Improvement (minimisation) of one model (Jones, Schonlau & Welch 1998);
///  - batches of q points at once for parallel evaluation: after each pick the model is updated as
///    if its own prediction had been observed there ("Kriging believer", same hyper-parameters),
///    which lowers the MSE around the pick, so the q points spread out.
/// Several models (one per output) are combined by summing their MSE normalised by each model's
/// process variance. Candidates are either a given finite set (e.g. the entries of a table) or a
/// box searched by a dense Latin hypercube followed by a local NLopt polish (BOBYQA).
/// All points are in the models' input space (as the models were fitted). Deterministic for a
/// given seed. Theory: docs/cokriging-and-infill.md.

#include <cstdint>
#include <vector>

#include "manta/surrogate/kriging.hpp"

namespace manta::surrogate {

enum class Criterion { max_mse, expected_improvement };

/// Expected improvement below `y_best` (minimisation) of a prediction with s = sqrt(mse):
/// (y_best - mean) Phi(z) + s phi(z), z = (y_best - mean) / s; for s = 0 its limit
/// max(y_best - mean, 0).
[[nodiscard]] double expected_improvement(const Prediction& p, double y_best);

struct InfillOptions {
    Criterion criterion = Criterion::max_mse;
    int batch = 1;             ///< q points per call (>= 1)
    int search_points = 2000;  ///< LHS size when searching a box (>= 1)
    bool polish = true;        ///< local NLopt refinement when searching a box
    std::uint64_t seed = 1;
    double min_separation = 1e-6;  ///< candidates closer than this to a sample are skipped
};

/// Criterion value at each row of `points` (larger is better): the sum over the models of
/// mse / process variance for max_mse; the expected improvement of models.front() below the
/// smallest of its sample values for expected_improvement. InputError if `models` is empty.
[[nodiscard]] Vector criterion_values(const std::vector<const Kriging*>& models,
                                      const Matrix& points, Criterion criterion);

/// Next q points among `candidates` (rows), never a candidate within min_separation of a sample
/// of any model nor one already picked. Expected improvement uses models.front() only. Returns
/// the chosen rows of `candidates`, best first; fewer than q when fewer candidates are eligible.
/// search_points and polish are not used.
[[nodiscard]] std::vector<Eigen::Index> propose_from(const std::vector<const Kriging*>& models,
                                                     const Matrix& candidates,
                                                     const InfillOptions& options);

/// Next q points in the box `bounds` (rows, best first): the best of search_points random Latin
/// hypercube points, then (polish) a bound-constrained BOBYQA from the best few of them.
[[nodiscard]] Matrix propose_in(const std::vector<const Kriging*>& models, const Bounds& bounds,
                                const InfillOptions& options);

}  // namespace manta::surrogate
