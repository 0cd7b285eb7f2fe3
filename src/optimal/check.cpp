/// @file check.cpp
/// Finite-difference check of the NLP derivatives, and hp refinement at control jumps.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "detail/check.hpp"
#include "detail/transcription.hpp"
#include "manta/core/error.hpp"
#include "manta/optimal/refine.hpp"
#include "manta/optimal/solve.hpp"

namespace manta::optimal {

DerivativeCheck check_derivatives(const Model& model, const Mesh& mesh, const Guess& guess,
                                  double perturbation, unsigned seed) {
    detail::Transcription tr(model, mesh);
    std::vector<double> z(static_cast<std::size_t>(tr.n_vars()));
    tr.initial_point(guess, z.data());
    return detail::check_nlp(tr, std::move(z), perturbation, seed);
}

Mesh refine_at_control_jumps(const Solution& sol, int nodes_per_segment, double threshold) {
    if (sol.segments.empty()) throw InputError("hp refinement: the solution has no segments");
    if (nodes_per_segment < 2) {
        throw InputError("hp refinement: " + std::to_string(nodes_per_segment) +
                         " nodes per segment, expected >= 2");
    }
    const double t0 = sol.initial_time;
    const double dt = sol.final_time - sol.initial_time;
    if (!(dt > 0.0)) throw InputError("hp refinement: the solution has zero duration");
    const int K = static_cast<int>(sol.segments.size());
    const std::vector<double> fr = control_jumps(sol, threshold);
    // existing breaks are kept; a new one within one node spacing of a kept one is dropped
    std::vector<double> old(static_cast<std::size_t>(K) + 1);
    for (int k = 0; k <= K; ++k) old[k] = (sol.breaks[k] - t0) / dt;
    old.front() = 0.0;
    old.back() = 1.0;
    auto old_segment = [&](double f) {
        int k = 0;
        while (k + 1 < K && f >= old[k + 1]) ++k;
        return k;
    };
    auto spacing_at = [&](double f) {
        const int k = old_segment(f);
        return (old[k + 1] - old[k]) / static_cast<double>(sol.segments[k].time.size() - 1);
    };
    std::vector<double> breaks = old;
    for (const double f : fr) {
        const auto it = std::lower_bound(breaks.begin(), breaks.end(), f);
        const double h = spacing_at(f);
        const bool near_next = it != breaks.end() && *it - f < h;
        const bool near_prev = it != breaks.begin() && f - *(it - 1) < h;
        if (!near_next && !near_prev) breaks.insert(it, f);
    }
    Mesh mesh;
    mesh.breaks = breaks;
    // Never coarser than the solution: each new segment has at least the points per unit time
    // of every old segment it overlaps (so at least as many points in all), and at least
    // nodes_per_segment.
    for (std::size_t q = 0; q + 1 < breaks.size(); ++q) {
        const double a = breaks[q], b = breaks[q + 1];
        double density = 0.0;
        for (int k = 0; k < K; ++k) {
            if (old[k + 1] <= a || old[k] >= b) continue;
            density = std::max(
                density, static_cast<double>(sol.segments[k].time.size()) / (old[k + 1] - old[k]));
        }
        const int need = static_cast<int>(std::ceil(density * (b - a) - 1e-9));
        mesh.nodes.push_back(std::max(nodes_per_segment, need));
    }
    mesh.free_breaks = mesh.nodes.size() > 1;
    double shortest = 1.0;
    for (std::size_t q = 0; q + 1 < breaks.size(); ++q)
        shortest = std::min(shortest, breaks[q + 1] - breaks[q]);
    mesh.min_segment_fraction = std::min(1e-3, 0.5 * shortest);
    mesh.validate();
    return mesh;
}

}  // namespace manta::optimal
