// UnsteadySolver::save_state / restore_state: a run restored from its state and stepped on gives
// bit for bit what the uninterrupted run gives (the checkpoint/resume of `manta replay`,
// docs/replay.md), for every wake model; a state of another run is refused.

#include <gtest/gtest.h>

#include <cmath>

#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"
#include "manta/vlm/source.hpp"
#include "manta/vlm/unsteady.hpp"

namespace {

using namespace manta;
using Eigen::Vector3d;

vlm::Model wing_and_tail() {
    vlm::Model m;
    m.name = "wing-tail";
    m.reference = {6.0, 6.0, 1.0, Vector3d(0.25, 0, 0)};
    vlm::Surface w;
    w.name = "wing";
    w.n_chord = 3;
    w.n_span = 6;
    w.y_duplicate = 0.0;
    w.component = 1;
    vlm::Section r, t;
    r.chord = 1.0;
    t.chord = 1.0;
    t.leading_edge = Vector3d(0, 3, 0);
    w.sections = {r, t};
    vlm::Surface h;
    h.name = "tail";
    h.n_chord = 2;
    h.n_span = 3;
    h.y_duplicate = 0.0;
    h.component = 2;
    vlm::Section hr, ht;
    hr.leading_edge = Vector3d(4, 0, 0.3);
    hr.chord = 0.5;
    ht.leading_edge = Vector3d(4, 1, 0.3);
    ht.chord = 0.5;
    vlm::SectionControl e;
    e.name = "elevator";
    e.hinge_chord_fraction = 0.7;
    hr.controls = {e};
    ht.controls = {e};
    h.sections = {hr, ht};
    m.surfaces = {w, h};
    return m;
}

/// A pitch-and-plunge motion with elevator, 60 steps.
aero::Motion test_motion() {
    aero::Motion m;
    const int n = 61;
    for (int i = 0; i < n; ++i) m.t.push_back(0.01 * i);
    for (auto& c : m.position) c.assign(n, 0.0);
    for (auto& c : m.angles) c.assign(n, 0.0);
    std::vector<double> el(n, 0.0), ail(n, 0.0), rud(n, 0.0);
    for (int i = 0; i < n; ++i) {
        const double t = m.t[static_cast<std::size_t>(i)];
        m.angles[1][static_cast<std::size_t>(i)] = 0.05 + 0.03 * std::sin(10.0 * t);
        m.angles[0][static_cast<std::size_t>(i)] = 0.1 * std::sin(7.0 * t);
        m.position[2][static_cast<std::size_t>(i)] = 0.05 * std::sin(5.0 * t);
        el[static_cast<std::size_t>(i)] = 0.02 * std::sin(12.0 * t);
    }
    m.add_mode("elevator", el);
    m.add_mode("aileron", ail);
    m.add_mode("rudder", rud);
    m.metadata.v0 = 30.0;
    return m;
}

void expect_same(const vlm::UnsteadyStep& a, const vlm::UnsteadyStep& b) {
    EXPECT_EQ(a.index, b.index);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.CL, b.CL);
    EXPECT_EQ(a.CD, b.CD);
    EXPECT_EQ(a.CY, b.CY);
    EXPECT_EQ(a.body.Cl, b.body.Cl);
    EXPECT_EQ(a.body.Cm, b.body.Cm);
    EXPECT_EQ(a.body.Cn, b.body.Cn);
    EXPECT_EQ(a.alpha, b.alpha);
}

class Checkpoint : public ::testing::TestWithParam<vlm::WakeModel> {};

TEST_P(Checkpoint, ResumedRunEqualsUninterruptedBitForBit) {
    const vlm::Model model = wing_and_tail();
    vlm::UnsteadyOptions o;
    o.dt = 0.01;
    o.wake = GetParam();
    o.wake_length = 4.0;  // rows are dropped before the end: the truncation state is saved too
    const aero::Motion motion = test_motion();
    vlm::UnsteadySolver full(model, vlm::build_lattice(model), o);
    const vlm::UnsteadyHistory ref = full.run(motion);

    vlm::UnsteadySolver first(model, vlm::build_lattice(model), o);
    first.start(motion);
    for (int k = 0; k < 23; ++k) first.step();
    const std::string state = first.save_state();
    vlm::UnsteadySolver second(model, vlm::build_lattice(model), o);
    expect_same(second.restore_state(motion, state), ref.steps[23]);
    while (!second.finished()) {
        const vlm::UnsteadyStep& s = second.step();
        expect_same(s, ref.steps[static_cast<std::size_t>(s.index)]);
    }
    EXPECT_EQ(second.current().index, static_cast<int>(ref.steps.size()) - 1);
}

INSTANTIATE_TEST_SUITE_P(WakeModels, Checkpoint,
                         ::testing::Values(vlm::WakeModel::prescribed, vlm::WakeModel::free,
                                           vlm::WakeModel::planar));

TEST(CheckpointErrors, StateOfAnotherRunIsRefused) {
    const vlm::Model model = wing_and_tail();
    vlm::UnsteadyOptions o;
    o.dt = 0.01;
    const aero::Motion motion = test_motion();
    vlm::UnsteadySolver a(model, vlm::build_lattice(model), o);
    EXPECT_THROW((void)a.save_state(), InputError);  // before start
    a.start(motion);
    a.step();
    const std::string state = a.save_state();
    vlm::UnsteadyOptions o2 = o;
    o2.dt = 0.02;
    vlm::UnsteadySolver b(model, vlm::build_lattice(model), o2);
    EXPECT_THROW(b.restore_state(motion, state), InputError);  // other time step
    EXPECT_THROW(b.restore_state(motion, state.substr(0, state.size() / 2)), InputError);
    EXPECT_THROW(b.restore_state(motion, "garbage"), InputError);
}

TEST(CheckpointSource, VlmRunSavesAndRestoresThroughFiles) {
    const vlm::VlmSource src(wing_and_tail());
    const aero::Motion motion = test_motion();
    aero::UnsteadySettings s;
    s.dt = 0.01;
    const auto ref = src.start_unsteady(motion, s);
    std::vector<double> cl{ref->current().wind.CL};
    while (!ref->finished()) cl.push_back(ref->step().wind.CL);
    const auto a = src.start_unsteady(motion, s);
    for (int k = 0; k < 10; ++k) a->step();
    const auto file = std::filesystem::temp_directory_path() / "manta_uvlm_checkpoint_test.bin";
    a->save(file);
    const auto b = src.start_unsteady(motion, s);
    b->restore(file);
    EXPECT_EQ(b->current().index, 10);
    while (!b->finished()) {
        const auto& x = b->step();
        EXPECT_EQ(x.wind.CL, cl[static_cast<std::size_t>(x.index)]);
    }
    std::filesystem::remove(file);
    // The default replay() runs on the steppable interface (default settings: the source's dt).
    const aero::CoefficientHistory h = src.aero::AeroSource::replay(motion, {});
    EXPECT_EQ(h.t.size(), static_cast<std::size_t>(src.start_unsteady(motion, {})->n_steps()) + 1);
    EXPECT_EQ(h.t.front(), 0.0);
}

}  // namespace
