/// @file quality.cpp
/// The quality report of a tetrahedral mesh: dihedral angles, the volume ratio of neighbouring
/// cells, slivers, and the checks that the boundary is closed and every volume positive.

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "manta/core/error.hpp"
#include "manta/meshgen/meshgen.hpp"

namespace manta::meshgen {

namespace {

using Key3 = std::array<long long, 3>;
struct Key3Hash {
    std::size_t operator()(const Key3& k) const noexcept {
        std::size_t h = static_cast<std::size_t>(k[0]) * 0x9E3779B97F4A7C15ULL;
        h ^= static_cast<std::size_t>(k[1]) + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
        h ^= static_cast<std::size_t>(k[2]) + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
        return h;
    }
};
Key3 sorted(long long a, long long b, long long c) {
    Key3 k{a, b, c};
    std::sort(k.begin(), k.end());
    return k;
}

}  // namespace

QualityReport assess_quality(const std::vector<double>& xyz,
                             const std::vector<std::array<long long, 4>>& tets,
                             const std::vector<std::array<long long, 3>>& faces,
                             double sliver_min_deg) {
    const long long n = static_cast<long long>(xyz.size() / 3);
    auto node = [&](long long i) {
        if (i < 0 || i >= n) throw InputError("assess_quality: node index out of range");
        return Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    };
    QualityReport q;
    q.nodes = n;
    q.cells = static_cast<long long>(tets.size());
    q.boundary_faces = static_cast<long long>(faces.size());
    q.sliver_min_deg = sliver_min_deg;
    q.min_dihedral_deg = 180.0;
    q.max_dihedral_deg = 0.0;
    q.min_cell_volume = tets.empty() ? 0.0 : std::numeric_limits<double>::infinity();
    q.volume_positive = !tets.empty();
    std::vector<double> vol(tets.size());
    // Local faces opposite each node, and the two faces at each of the six edges.
    static constexpr std::array<std::array<int, 3>, 4> tf{
        {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
    static constexpr std::array<std::array<int, 2>, 6> edge_faces{
        {{2, 3}, {1, 3}, {1, 2}, {0, 3}, {0, 2}, {0, 1}}};  // edges 01, 02, 03, 12, 13, 23
    const double rad = 180.0 / std::numbers::pi;
    for (std::size_t c = 0; c < tets.size(); ++c) {
        std::array<Eigen::Vector3d, 4> p;
        for (int k = 0; k < 4; ++k) p[k] = node(tets[c][k]);
        const double v = (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / 6.0;
        vol[c] = v;
        q.volume += v;
        q.min_cell_volume = std::min(q.min_cell_volume, v);
        if (!(v > 0.0)) q.volume_positive = false;
        // Outward normals of the four faces (for a positive cell).
        std::array<Eigen::Vector3d, 4> nf;
        for (int f = 0; f < 4; ++f) {
            const auto& a = p[tf[f][0]];
            const auto& b = p[tf[f][1]];
            const auto& d = p[tf[f][2]];
            nf[f] = (b - a).cross(d - a);
            const double len = nf[f].norm();
            if (len > 0.0) nf[f] /= len;
        }
        double lo = 180.0, hi = 0.0;
        for (const auto& e : edge_faces) {
            const double cosang = std::clamp(-nf[e[0]].dot(nf[e[1]]), -1.0, 1.0);
            const double ang = std::acos(cosang) * rad;
            lo = std::min(lo, ang);
            hi = std::max(hi, ang);
        }
        q.min_dihedral_deg = std::min(q.min_dihedral_deg, lo);
        q.max_dihedral_deg = std::max(q.max_dihedral_deg, hi);
        if (lo < sliver_min_deg || hi > 180.0 - sliver_min_deg) ++q.slivers;
    }
    // Faces shared by two cells: volume ratio; faces of one cell: exposed.
    std::unordered_map<Key3, long long, Key3Hash> owner;
    owner.reserve(tets.size() * 3);
    std::unordered_map<Key3, int, Key3Hash> exposed;
    q.max_volume_ratio = tets.empty() ? 0.0 : 1.0;
    for (std::size_t c = 0; c < tets.size(); ++c)
        for (const auto& f : tf) {
            const Key3 k = sorted(tets[c][f[0]], tets[c][f[1]], tets[c][f[2]]);
            auto [it, fresh] = owner.emplace(k, static_cast<long long>(c));
            if (!fresh) {
                const double a = std::abs(vol[c]),
                             b = std::abs(vol[static_cast<std::size_t>(it->second)]);
                if (a > 0.0 && b > 0.0)
                    q.max_volume_ratio = std::max(q.max_volume_ratio, std::max(a / b, b / a));
                it->second = -1;  // interior
            }
        }
    long long n_exposed = 0;
    for (const auto& [k, c] : owner)
        if (c >= 0) {
            exposed.emplace(k, 0);
            ++n_exposed;
        }
    long long matched = 0;
    std::unordered_map<Key3, int, Key3Hash> edges;  // (a, b, -1) -> count
    for (const auto& f : faces) {
        const Key3 k = sorted(f[0], f[1], f[2]);
        auto it = exposed.find(k);
        if (it != exposed.end() && it->second == 0) {
            it->second = 1;
            ++matched;
        }
        for (int e = 0; e < 3; ++e) {
            long long a = f[e], b = f[(e + 1) % 3];
            if (a > b) std::swap(a, b);
            ++edges[Key3{a, b, -1}];
        }
    }
    for (const auto& [k, count] : edges)
        if (count != 2) ++q.open_edges;
    q.unmarked_faces = n_exposed - matched;
    q.surface_closed = !faces.empty() && q.open_edges == 0 && q.unmarked_faces == 0 &&
                       matched == static_cast<long long>(faces.size());
    return q;
}

}  // namespace manta::meshgen
