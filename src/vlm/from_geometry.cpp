#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "manta/core/error.hpp"
#include "manta/vlm/model.hpp"

namespace manta::vlm {

namespace {

/// Section of `ls` at semi-span fraction eta (linear between its defining sections; the airfoil
/// of the nearer defining section, inboard on ties).
Section section_at(const geometry::LiftingSurface& ls, double eta) {
    Section s;
    s.leading_edge = ls.leading_edge_at(eta);
    s.chord = ls.chord_at(eta);
    // Incidence interpolated between the bounding defining sections.
    const double x = ls.spanwise(ls.sections.front()) + eta * ls.semi_span();
    std::size_t j = 0;
    while (j + 2 < ls.sections.size() && ls.spanwise(ls.sections[j + 1]) < x) ++j;
    const auto& A = ls.sections[j];
    const auto& B = ls.sections[j + 1];
    const double u = std::clamp((x - ls.spanwise(A)) / (ls.spanwise(B) - ls.spanwise(A)), 0.0, 1.0);
    s.incidence = A.twist + u * (B.twist - A.twist);
    s.airfoil = u <= 0.5 ? A.airfoil : B.airfoil;
    return s;
}

}  // namespace

Model from_geometry(const geometry::AircraftGeometry& g, const Reference& reference,
                    const LatticeDensity& density, std::string name) {
    if (density.n_chord < 1 || density.n_chord > 100)
        throw InputError(
            fmt::format("vlm: {} chordwise vortices; expected 1 to 100", density.n_chord));
    if (!(density.strip_width > 0.0 && density.strip_width <= 0.5))
        throw InputError(
            fmt::format("vlm: strip width {} of the reference span; expected 0 < width <= 0.5",
                        density.strip_width));
    Model m;
    m.name = std::move(name);
    m.reference = reference;
    for (const auto& ls : g.surfaces) {
        // Span fractions of the defining sections and of every control-surface edge.
        std::vector<double> etas;
        for (const auto& sec : ls.sections) etas.push_back(ls.eta_of(ls.spanwise(sec)));
        std::vector<const geometry::ControlSurface*> controls;
        for (const auto& cs : g.control_surfaces) {
            if (cs.surface != ls.name) continue;
            const auto [e0, e1] = cs.span_fraction;
            if (!(e0 >= 0.0 && e1 <= 1.0 && e0 < e1))
                throw InputError(
                    fmt::format("vlm: control surface '{}' spans {}..{} of '{}'; expected 0 <= "
                                "start < end <= 1 "
                                "(inside its lifting surface)",
                                cs.name, e0, e1, ls.name));
            etas.push_back(e0);
            etas.push_back(e1);
            controls.push_back(&cs);
        }
        std::sort(etas.begin(), etas.end());
        etas.erase(std::unique(etas.begin(), etas.end(),
                               [](double a, double b) { return std::abs(a - b) < 1e-9; }),
                   etas.end());
        Surface s;
        s.name = ls.name;
        s.n_chord = density.n_chord;
        s.chord_spacing = density.chord_spacing;
        s.n_span = 0;
        // Each lifting surface is its own component (as AVL numbers surfaces by default; joined
        // surfaces are merged below), so the wing's trailing legs seen from the tail get the
        // inter-component core.
        s.component = static_cast<int>(m.surfaces.size()) + 1;
        if (ls.symmetric) s.y_duplicate = 0.0;
        const double semi = ls.semi_span();
        for (std::size_t k = 0; k < etas.size(); ++k) {
            Section sec = section_at(ls, etas[k]);
            if (k + 1 < etas.size()) {
                const double width = (etas[k + 1] - etas[k]) * semi;
                sec.n_span = std::max(
                    2,
                    static_cast<int>(std::lround(width / (density.strip_width * reference.span))));
                sec.span_spacing = density.span_spacing;
            }
            for (const auto* cs : controls) {
                const double eta = etas[k];
                if (eta < cs->span_fraction[0] - 1e-9 || eta > cs->span_fraction[1] + 1e-9)
                    continue;
                SectionControl c;
                c.name = cs->control == geometry::Control::none
                             ? cs->name
                             : std::string(geometry::to_string(cs->control));
                c.hinge_chord_fraction = cs->hinge_chord_fraction;
                // Local deflection: trailing edge down on horizontal surfaces (a right-handed
                // rotation about the root-to-tip hinge line); trailing edge toward -y on fins,
                // the opposite of a right-handed rotation about the upward hinge line.
                c.gain = ls.vertical ? -cs->gain : cs->gain;
                if (ls.symmetric) {
                    if (cs->gain == 0.0 && cs->mirror_gain != 0.0)
                        throw InputError(fmt::format(
                            "vlm: control surface '{}': gain 0 on the defined side and {} on the "
                            "mirror side; the lattice needs a non-zero defined-side gain",
                            cs->name, cs->mirror_gain));
                    c.duplicate_sign = cs->gain != 0.0 ? cs->mirror_gain / cs->gain : 1.0;
                }
                sec.controls.push_back(c);
            }
            s.sections.push_back(std::move(sec));
        }
        m.surfaces.push_back(std::move(s));
    }
    // Surfaces that touch (a T-tail's fin and tailplane) are one component, so each sees the
    // other's vortices without the inter-component core: union of surfaces with section leading
    // or trailing edges closer than 5 % of the smaller chord there.
    const std::size_t n = m.surfaces.size();
    std::vector<std::size_t> root(n);
    for (std::size_t i = 0; i < n; ++i) root[i] = i;
    auto find = [&](std::size_t i) {
        while (root[i] != i) i = root[i] = root[root[i]];
        return i;
    };
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            for (const Section& a : m.surfaces[i].sections)
                for (const Section& b : m.surfaces[j].sections) {
                    const Eigen::Vector3d ta = a.leading_edge + a.chord * Eigen::Vector3d::UnitX();
                    const Eigen::Vector3d tb = b.leading_edge + b.chord * Eigen::Vector3d::UnitX();
                    const double tol = 0.05 * std::min(a.chord, b.chord);
                    if ((a.leading_edge - b.leading_edge).norm() < tol || (ta - tb).norm() < tol)
                        root[find(j)] = find(i);
                }
    for (std::size_t i = 0; i < n; ++i) m.surfaces[i].component = static_cast<int>(find(i)) + 1;
    return m;
}

}  // namespace manta::vlm
