/// @file fuzz_avl.cpp
/// libFuzzer target for the AVL readers: geometry (`vlm::parse_avl`), mass file
/// (`vlm::parse_avl_mass`) and run-case file (`vlm::parse_avl_run`), each on every input
/// (issue 16; docs/fuzzing.md): any bytes must give a result or a `manta::Error`; any other
/// exception, a crash, a hang or a sanitizer report is a finding. A result must hold what
/// docs/avl-input.md promises (else `abort`, a finding): a model with finite numbers, positive
/// reference values and chords, Mach in [0, 1), symmetry flags in {-1, 0, 1}, at least two
/// sections per surface, bodies with as many radii as axis points; a mass file with a positive
/// total mass, finite centre of gravity and a finite symmetric inertia tensor; run cases with
/// finite constraint and parameter values.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_check.hpp"
#include "manta/core/error.hpp"
#include "manta/vlm/avl_mass.hpp"
#include "manta/vlm/avl_reader.hpp"
#include "manta/vlm/avl_run.hpp"

namespace {

using manta::fuzz::check;
using manta::fuzz::finite;

bool flag(int v) {
    return v == -1 || v == 0 || v == 1;
}

void check_model(const manta::vlm::Model& m) {
    const auto& r = m.reference;
    check(finite(r.area) && r.area > 0.0 && finite(r.span) && r.span > 0.0 && finite(r.chord) &&
              r.chord > 0.0,
          "avl: reference area, span and chord finite, > 0");
    check(r.point.allFinite(), "avl: reference point finite");
    check(m.mach >= 0.0 && m.mach < 1.0, "avl: Mach in [0, 1)");
    check(flag(m.y_symmetry) && flag(m.z_symmetry) && finite(m.z_symmetry_plane),
          "avl: symmetry flags in {-1, 0, 1}");
    check(finite(m.profile_drag), "avl: CDp finite");
    for (const auto& s : m.surfaces) {
        check(s.sections.size() >= 2, "avl: a surface has at least two sections");
        check(s.n_chord >= 1 && finite(s.chord_spacing) && s.n_span >= 0 && finite(s.span_spacing),
              "avl: surface lattice counts and spacings");
        check(s.section_scale.allFinite() && (s.section_scale.array() > 0.0).all(),
              "avl: SCALE factors finite, > 0");
        check(!s.y_duplicate || finite(*s.y_duplicate), "avl: YDUPLICATE finite");
        for (const auto& sec : s.sections) {
            check(sec.leading_edge.allFinite(), "avl: section leading edge finite");
            check(finite(sec.chord) && sec.chord > 0.0, "avl: section chord finite, > 0");
            check(finite(sec.incidence), "avl: section incidence finite");
            check(finite(sec.lift_slope_factor) && sec.lift_slope_factor > 0.0,
                  "avl: CLAF factor finite, > 0");
            check(sec.n_span >= 0 && finite(sec.span_spacing), "avl: section strips");
            for (const auto& c : sec.controls)
                check(finite(c.gain) && finite(c.hinge_chord_fraction) &&
                          c.hinge_axis.allFinite() && finite(c.duplicate_sign),
                      "avl: control finite");
        }
    }
    for (const auto& b : m.bodies) {
        check(b.radius.size() == b.axis.size(), "avl: one radius per body axis point");
        for (std::size_t i = 0; i < b.axis.size(); ++i)
            check(b.axis[i].allFinite() && finite(b.radius[i]) && b.radius[i] >= 0.0,
                  "avl: body axis and radii finite");
    }
}

void check_mass(const manta::vlm::AvlMass& m) {
    check(finite(m.length_unit) && m.length_unit > 0.0 && finite(m.mass_unit) &&
              m.mass_unit > 0.0 && finite(m.time_unit) && m.time_unit > 0.0,
          "avl mass: units finite, > 0");
    check(!m.gravity || finite(*m.gravity), "avl mass: g finite");
    check(!m.density || finite(*m.density), "avl mass: rho finite");
    check(m.items >= 1, "avl mass: at least one item");
    check(finite(m.mass) && m.mass > 0.0, "avl mass: total mass finite, > 0");
    check(m.cg.allFinite(), "avl mass: centre of gravity finite");
    check(m.inertia.allFinite(), "avl mass: inertia finite");
    check((m.inertia.array() == m.inertia.transpose().array()).all(),
          "avl mass: inertia symmetric");
    check(finite(m.dimensional_mass()) && m.dimensional_cg().allFinite() &&
              m.dimensional_inertia().allFinite(),
          "avl mass: dimensional values finite");
}

void check_run(const std::vector<manta::vlm::RunCase>& cases) {
    check(!cases.empty(), "avl run: at least one run case");
    for (const auto& c : cases) {
        for (const auto& k : c.constraints)
            check(finite(k.value), "avl run: constraint value finite");
        for (const auto& [name, p] : c.parameters)
            check(finite(p.first), "avl run: parameter value finite");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        std::vector<std::string> warnings;
        check_model(manta::vlm::parse_avl(text, "fuzz.avl", "/nonexistent-fuzz-dir", warnings));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    try {
        check_mass(manta::vlm::parse_avl_mass(text, "fuzz.mass"));
    } catch (const manta::Error&) {
    }
    try {
        check_run(manta::vlm::parse_avl_run(text, "fuzz.run"));
    } catch (const manta::Error&) {
    }
    return 0;
}
