#include "manta/vlm/source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/version.hpp"

namespace manta::vlm {

namespace {

/// FNV-1a over the bytes of every number that defines the lattice and the options.
struct Hasher {
    std::uint64_t h = 1469598103934665603ULL;
    void bytes(const void* p, std::size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) {
            h ^= c[i];
            h *= 1099511628211ULL;
        }
    }
    void num(double x) { bytes(&x, sizeof x); }
    void vec(const Eigen::Vector3d& v) {
        num(v.x());
        num(v.y());
        num(v.z());
    }
    void str(const std::string& s) { bytes(s.data(), s.size()); }
};

/// The unsteady lattice as an aero::UnsteadyRun.
class VlmUnsteadyRun final : public aero::UnsteadyRun {
public:
    VlmUnsteadyRun(const Model& model, const Lattice& lattice, const UnsteadyOptions& options,
                   const aero::Motion& motion, double profile_cd0)
        : solver_(model, lattice, options), motion_(motion), cd0_(profile_cd0) {
        convert(solver_.start(motion_));
    }
    [[nodiscard]] const aero::UnsteadySample& current() const override { return sample_; }
    const aero::UnsteadySample& step() override {
        convert(solver_.step());
        return sample_;
    }
    [[nodiscard]] bool finished() const override { return solver_.finished(); }
    [[nodiscard]] int n_steps() const override { return solver_.n_steps(); }
    [[nodiscard]] double dt() const override { return solver_.dt(); }
    void save(const std::filesystem::path& file) const override {
        core::write_file_atomic(file, solver_.save_state());
    }
    void restore(const std::filesystem::path& file) override {
        convert(solver_.restore_state(motion_, core::read_file(file)));
    }

private:
    void convert(const UnsteadyStep& st) {
        aero::UnsteadySample& o = sample_;
        o.index = st.index;
        o.t = st.t;
        o.body = st.body;
        o.wind = {st.CL, st.CD, st.CY};
        o.alpha = st.alpha;
        o.beta = st.beta;
        o.airspeed = st.airspeed;
        if (cd0_ != 0.0) {
            // Profile drag along the air velocity (as add_profile_drag for the steady solver).
            o.wind.CD += cd0_;
            const double ca = std::cos(st.alpha), sa = std::sin(st.alpha);
            const double cb = std::cos(st.beta), sb = std::sin(st.beta);
            o.body.CX -= cd0_ * ca * cb;
            o.body.CY -= cd0_ * sb;
            o.body.CZ -= cd0_ * sa * cb;
        }
    }
    UnsteadySolver solver_;
    aero::Motion motion_;
    double cd0_ = 0.0;
    aero::UnsteadySample sample_;
};

}  // namespace

VlmSource::VlmSource(Model model, std::optional<geometry::AircraftGeometry> geometry,
                     ViscousDragOptions viscous, std::optional<TrailingLegs> legs)
    : model_(std::move(model)),
      lattice_(build_lattice(model_)),
      geometry_(std::move(geometry)),
      viscous_options_(std::move(viscous)),
      trailing_legs_(legs.value_or(default_trailing_legs(geometry_.has_value()))) {
    init();
}

VlmSource::VlmSource(Model model, Lattice lattice,
                     std::optional<geometry::AircraftGeometry> geometry, ViscousDragOptions viscous,
                     std::optional<TrailingLegs> legs)
    : model_(std::move(model)),
      lattice_(std::move(lattice)),
      geometry_(std::move(geometry)),
      viscous_options_(std::move(viscous)),
      trailing_legs_(legs.value_or(default_trailing_legs(geometry_.has_value()))) {
    init();
}

void VlmSource::init() {
    // The unsteady lattice's default wake has the steady lattice's legs as its steady limit.
    if (trailing_legs_ == TrailingLegs::body_axis) unsteady_options_.wake = WakeModel::planar;
    check_lattice(model_, lattice_);
    Hasher h;
    h.str(core::version());
    h.num(model_.reference.area);
    h.num(model_.reference.span);
    h.num(model_.reference.chord);
    h.vec(model_.reference.point);
    h.num(model_.profile_drag);
    for (int i = 0; i < lattice_.size(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        h.vec(lattice_.a[k]);
        h.vec(lattice_.b[k]);
        h.vec(lattice_.control_point[k]);
        h.vec(lattice_.normal[k]);
        for (const auto& c : lattice_.controls[k]) {
            h.num(c.control);
            h.num(c.gain);
            h.vec(c.axis);
        }
    }
    for (const auto& n : lattice_.control_names) h.str(n);
    h.num(geometry_ ? 1.0 : 0.0);
    h.str(trailing_legs_ == TrailingLegs::freestream ? "legs:freestream" : "legs:body_axis");
    h.num(viscous_options_.laminar_fraction_surfaces);
    h.num(viscous_options_.laminar_fraction_fuselage);
    h.num(viscous_options_.interference_wing);
    h.num(viscous_options_.interference_tail);
    h.num(viscous_options_.interference_fuselage);
    h.num(viscous_options_.leakage_protuberance_fraction);
    fingerprint_ = fmt::format("vlm:{:016x}:{}", h.h, lattice_.size());
}

std::string VlmSource::fingerprint() const {
    return fingerprint_;
}

std::shared_ptr<const SteadySolver> VlmSource::solver(double mach) const {
    {
        const std::lock_guard lock(mutex_);
        const auto it = solvers_.find(mach);
        if (it != solvers_.end()) return it->second;
    }
    // Built outside the lock (seconds for large lattices); a concurrent duplicate is harmless.
    // Trailing legs as chosen at construction (default_trailing_legs).
    SteadyOptions o;
    o.trailing_legs = trailing_legs_;
    auto s = std::make_shared<const SteadySolver>(model_, lattice_, mach, o);
    const std::lock_guard lock(mutex_);
    if (solvers_.size() >= 16) solvers_.erase(solvers_.begin());
    return solvers_.emplace(mach, std::move(s)).first->second;
}

FlowState VlmSource::flow_state(const aero::AeroQuery<double>& q) const {
    FlowState s;
    s.alpha = q.alpha;
    s.beta = q.beta;
    s.p_hat = q.p_hat;
    s.q_hat = q.q_hat;
    s.r_hat = q.r_hat;
    s.deflection = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(lattice_.control_names.size()));
    auto set = [&](const char* name, double v) {
        const int k = lattice_.control_index(name);
        if (k >= 0) s.deflection[k] = v;
    };
    set("elevator", q.elevator);
    set("aileron", q.aileron);
    set("rudder", q.rudder);
    return s;
}

std::optional<ViscousDrag> VlmSource::viscous(double mach, double reynolds_per_metre) const {
    if (!geometry_ || !(reynolds_per_metre > 0.0)) return std::nullopt;
    return viscous_drag(*geometry_, model_.reference.area, mach, reynolds_per_metre,
                        viscous_options_);
}

aero::SourceResult VlmSource::evaluate(const aero::AeroQuery<double>& q,
                                       const aero::FlowConditions& c) const {
    const FlowState s = flow_state(q);
    SteadyResult r = solver(q.mach)->solve(s);
    if (const auto v = viscous(q.mach, c.reynolds_per_metre))
        add_profile_drag(r, v->cd0, s.alpha, s.beta);
    aero::SourceResult out;
    out.body = r.body;
    out.wind = {r.CL, r.CD, r.CY};
    out.CD_induced = r.CD_induced;
    out.CD_profile = r.CD_profile;
    return out;
}

std::unique_ptr<aero::UnsteadyRun> VlmSource::start_unsteady(
    const aero::Motion& motion, const aero::UnsteadySettings& settings) const {
    UnsteadyOptions o = unsteady_options_;
    if (!o.mach && motion.metadata.mach) o.mach = motion.metadata.mach;
    if (settings.dt > 0.0) o.dt = settings.dt;
    const double mach = o.mach ? *o.mach : model_.mach;
    double cd0 = 0.0;
    if (const auto v = viscous(mach, settings.conditions.reynolds_per_metre)) cd0 = v->cd0;
    return std::make_unique<VlmUnsteadyRun>(model_, lattice_, o, motion, cd0);
}

aero::CoefficientHistory VlmSource::replay(const aero::Motion& motion,
                                           const aero::ProgressCallback& progress) const {
    UnsteadyOptions o = unsteady_options_;
    if (!o.mach && motion.metadata.mach) o.mach = motion.metadata.mach;
    UnsteadySolver solver(model_, lattice_, o);
    const UnsteadyHistory h = solver.run(motion, [&](const UnsteadySolver& s) {
        if (progress) progress(static_cast<double>(s.current().index) / std::max(1, s.n_steps()));
    });
    aero::CoefficientHistory out;
    for (const UnsteadyStep& st : h.steps) {
        out.t.push_back(st.t);
        out.body.push_back(st.body);
        out.wind.push_back({st.CL, st.CD, st.CY});
    }
    return out;
}

}  // namespace manta::vlm
