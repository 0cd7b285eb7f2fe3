#pragma once
/// @file source.hpp
/// The vortex-lattice method as an `aero::AeroSource`: steady coefficients at any flight state
/// and control setting (solvers cached per Mach number: one influence matrix and factorisation
/// each; trailing legs along the free stream, TrailingLegs::freestream, the steady limit of the
/// unsteady lattice that `replay` and `start_unsteady` run), the viscous drag build-up added when
/// the aircraft's shape is known and a Reynolds number is given, and the unsteady lattice along a
/// motion.

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "manta/aero/source.hpp"
#include "manta/geometry/aircraft_geometry.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/model.hpp"
#include "manta/vlm/steady.hpp"
#include "manta/vlm/unsteady.hpp"
#include "manta/vlm/viscous.hpp"

namespace manta::vlm {

/// The trailing legs a source uses unless told: along the free stream for a model built from a
/// MANTA aircraft geometry (the steady limit of the unsteady lattice's convected wake, so tables
/// and replays agree in steady flight); along body x for a model without one (an AVL file: AVL's
/// own convention, and its flat-plate fuselages lie in the wing plane, where bent legs pass
/// centimetres from the plate; docs/vlm.md, "Trailing legs").
[[nodiscard]] inline TrailingLegs default_trailing_legs(bool has_geometry) {
    return has_geometry ? TrailingLegs::freestream : TrailingLegs::body_axis;
}

class VlmSource : public aero::AeroSource {
public:
    /// `geometry`, if given, feeds the viscous build-up (else only Model::profile_drag is added).
    /// The steady solvers' trailing legs: `legs`, or by default default_trailing_legs(geometry).
    explicit VlmSource(Model model, std::optional<geometry::AircraftGeometry> geometry = {},
                       ViscousDragOptions viscous = {},
                       std::optional<TrailingLegs> legs = std::nullopt);
    /// As above on a lattice built beforehand from `model` (build_lattice, possibly altered;
    /// InputError if check_lattice refuses it).
    VlmSource(Model model, Lattice lattice, std::optional<geometry::AircraftGeometry> geometry = {},
              ViscousDragOptions viscous = {}, std::optional<TrailingLegs> legs = std::nullopt);

    [[nodiscard]] std::string name() const override { return "vlm"; }
    [[nodiscard]] std::string fingerprint() const override;
    [[nodiscard]] aero::SourceResult evaluate(const aero::AeroQuery<double>& q,
                                              const aero::FlowConditions& c) const override;
    [[nodiscard]] bool unsteady() const override { return true; }
    /// The unsteady vortex lattice along `motion` (UnsteadyOptions of the source; the motion's
    /// v0 and Mach metadata unless the options set them). The profile drag is the model's only.
    [[nodiscard]] aero::CoefficientHistory replay(
        const aero::Motion& motion, const aero::ProgressCallback& progress) const override;
    /// A steppable unsteady-lattice run along `motion` (UnsteadyOptions of the source, its dt
    /// replaced by `settings.dt` when that is > 0; the motion's v0 and Mach metadata unless the
    /// options set them). With a geometry and `settings.conditions.reynolds_per_metre` > 0 the
    /// viscous profile drag of `evaluate` at the run's Mach is added to every step (as a drag
    /// along the instantaneous air velocity), so a replay and a table made by `evaluate` mean the
    /// same thing. save/restore: UnsteadySolver::save_state / restore_state in a file.
    [[nodiscard]] std::unique_ptr<aero::UnsteadyRun> start_unsteady(
        const aero::Motion& motion, const aero::UnsteadySettings& settings) const override;
    /// Options of `replay` and `start_unsteady` (default: UnsteadyOptions with the wake whose
    /// steady limit is this source's steady lattice: WakeModel::planar with body-axis legs).
    void set_unsteady_options(const UnsteadyOptions& o) { unsteady_options_ = o; }
    [[nodiscard]] const UnsteadyOptions& unsteady_options() const { return unsteady_options_; }

    [[nodiscard]] const Model& model() const { return model_; }
    /// Where the steady solvers' trailing legs go (part of the fingerprint).
    [[nodiscard]] TrailingLegs trailing_legs() const { return trailing_legs_; }
    [[nodiscard]] const Lattice& lattice() const { return lattice_; }
    /// The solver at Mach `mach` (built on first use, then cached).
    [[nodiscard]] std::shared_ptr<const SteadySolver> solver(double mach) const;
    /// Flow state of a query: the elevator, aileron and rudder values set on the lattice controls
    /// of those names (others zero).
    [[nodiscard]] FlowState flow_state(const aero::AeroQuery<double>& q) const;
    /// Viscous drag at Mach `mach` and Re/l (nullopt without a geometry or with Re/l = 0).
    [[nodiscard]] std::optional<ViscousDrag> viscous(double mach, double reynolds_per_metre) const;

private:
    void init();  ///< trailing legs, default unsteady wake, lattice check, fingerprint
    Model model_;
    Lattice lattice_;
    std::optional<geometry::AircraftGeometry> geometry_;
    ViscousDragOptions viscous_options_;
    TrailingLegs trailing_legs_ = TrailingLegs::freestream;
    UnsteadyOptions unsteady_options_;
    std::string fingerprint_;
    mutable std::mutex mutex_;
    mutable std::map<double, std::shared_ptr<const SteadySolver>> solvers_;
};

}  // namespace manta::vlm
