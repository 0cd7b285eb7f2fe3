/// Sample store: round trip of every field, uniqueness of (scenario, inputs), pending samples
/// across reopening, fingerprint mismatch, accepting a changed source, restart, failed samples.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "manta/core/error.hpp"
#include "manta/tables/store.hpp"

using namespace manta;
using namespace manta::tables;

namespace {

std::filesystem::path fresh(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "manta_tables_store" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir / "samples.sqlite";
}

aero::AeroQuery<double> point(double alpha, double mach, double beta) {
    aero::AeroQuery<double> q;
    q.alpha = alpha;
    q.mach = mach;
    q.beta = beta;
    return q;
}

}  // namespace

TEST(SampleStore, RoundTripsEveryField) {
    const auto file = fresh("roundtrip");
    auto store = SampleStore::open(file, "analytic", "fp-1");
    aero::AeroQuery<double> q = point(0.1, 0.3, -0.05);
    q.p_hat = 0.01;
    q.q_hat = -1.0 / 3.0;
    q.r_hat = 1e-300;
    q.elevator = 0.2;
    q.aileron = -0.1;
    q.rudder = 0.07;
    const auto ids = store->schedule("static", {q});
    ASSERT_EQ(ids.size(), 1u);
    aero::SourceResult r;
    r.wind = {0.1, 1.0 / 3.0, -2.5e-17};
    r.body = {-0.01, 0.02, -0.9, 1e-5, -0.123456789012345678, 0.3};
    r.CD_induced = 0.01;
    r.CD_profile = 1.0 / 3.0 - 0.01;
    store->record_done(ids[0], r, 1.25);
    store.reset();

    store = SampleStore::open(file, "analytic", "fp-1");
    const auto s = store->samples();
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s[0].scenario, "static");
    EXPECT_EQ(s[0].status, SampleStatus::done);
    EXPECT_EQ(s[0].query.q_hat, q.q_hat);  // bit for bit
    EXPECT_EQ(s[0].query.r_hat, q.r_hat);
    EXPECT_EQ(s[0].query.rudder, q.rudder);
    EXPECT_EQ(s[0].result.wind.CD, r.wind.CD);
    EXPECT_EQ(s[0].result.wind.CY, r.wind.CY);
    EXPECT_EQ(s[0].result.body.Cm, r.body.Cm);
    EXPECT_EQ(s[0].result.body.Cl, r.body.Cl);
    EXPECT_EQ(s[0].result.wind.CL, r.wind.CL);
    EXPECT_EQ(s[0].result.CD_profile, r.CD_profile);
    EXPECT_EQ(s[0].wall_time_s, 1.25);
    EXPECT_EQ(s[0].fingerprint, "fp-1");
    EXPECT_EQ(s[0].source, "analytic");
    EXPECT_FALSE(s[0].created_at.empty());
    EXPECT_FALSE(s[0].finished_at.empty());
}

TEST(SampleStore, SchedulingTheSamePointTwiceKeepsOneRecord) {
    auto store = SampleStore::open(fresh("unique"), "analytic", "fp");
    const auto a = store->schedule("static", {point(0.1, 0.2, 0.0), point(0.2, 0.2, 0.0)});
    const auto b = store->schedule("static", {point(0.2, 0.2, 0.0), point(0.3, 0.2, 0.0)});
    EXPECT_EQ(a[1], b[0]);
    EXPECT_NE(b[1], a[0]);
    // The same inputs in another scenario are another sample.
    const auto c = store->schedule("dynamic", {point(0.1, 0.2, 0.0)});
    EXPECT_NE(c[0], a[0]);
    EXPECT_EQ(store->samples().size(), 4u);
    EXPECT_EQ(store->samples("static").size(), 3u);
    // -0 and +0 are the same point.
    const auto z1 = store->schedule("static", {point(-0.0, 0.2, 0.0)});
    const auto z2 = store->schedule("static", {point(0.0, 0.2, 0.0)});
    EXPECT_EQ(z1[0], z2[0]);
}

TEST(SampleStore, PendingSamplesSurviveReopening) {
    const auto file = fresh("pending");
    {
        auto store = SampleStore::open(file, "analytic", "fp");
        const auto ids = store->schedule("static", {point(0.1, 0.2, 0.0), point(0.2, 0.2, 0.0)});
        store->record_done(ids[0], {}, 0.5);
        // "killed" here: the second sample stays pending
    }
    auto store = SampleStore::open(file, "analytic", "fp");
    const auto s = store->samples("static");
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0].status, SampleStatus::done);
    EXPECT_EQ(s[1].status, SampleStatus::pending);
    EXPECT_TRUE(s[1].finished_at.empty());
}

TEST(SampleStore, ChangedFingerprintIsRefusedWithBothFingerprints) {
    const auto file = fresh("fingerprint");
    {
        auto store = SampleStore::open(file, "analytic", "analytic:aaaa");
        (void)store->schedule("static", {point(0.1, 0.2, 0.0)});
    }
    try {
        (void)SampleStore::open(file, "analytic", "analytic:bbbb");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(file.string()), std::string::npos) << m;
        EXPECT_NE(m.find("analytic:aaaa"), std::string::npos) << m;
        EXPECT_NE(m.find("analytic:bbbb"), std::string::npos) << m;
        EXPECT_NE(m.find("--accept-changed-source"), std::string::npos) << m;
        EXPECT_NE(m.find("--restart"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << "one line";
    }
    {
        StoreOpenOptions o;
        o.accept_changed_source = true;
        auto store = SampleStore::open(file, "analytic", "analytic:bbbb", o);
        EXPECT_EQ(store->replaced_fingerprint(), "analytic:aaaa");
        EXPECT_EQ(store->samples().size(), 1u);
    }
    // Accepted once: the store now belongs to the new fingerprint.
    EXPECT_NO_THROW((void)SampleStore::open(file, "analytic", "analytic:bbbb"));
    StoreOpenOptions r;
    r.restart = true;
    auto store = SampleStore::open(file, "analytic", "analytic:cccc", r);
    EXPECT_TRUE(store->samples().empty());
}

TEST(SampleStore, FailedSamplesKeepTheirErrorAndCanBeReset) {
    auto store = SampleStore::open(fresh("failed"), "analytic", "fp");
    const auto ids = store->schedule("static", {point(0.1, 0.2, 0.0), point(0.2, 0.2, 0.0)});
    store->record_failed(ids[1], "solver diverged, residual 1e3", 2.0);
    auto s = store->samples();
    EXPECT_EQ(s[1].status, SampleStatus::failed);
    EXPECT_EQ(s[1].error, "solver diverged, residual 1e3");
    EXPECT_EQ(store->reset_failed("dynamic"), 0);
    EXPECT_EQ(store->reset_failed("static"), 1);
    s = store->samples();
    EXPECT_EQ(s[1].status, SampleStatus::pending);
}

TEST(SampleStore, NotAStoreIsAnIoError) {
    const auto file = fresh("garbage");
    {
        std::FILE* f = std::fopen(file.string().c_str(), "w");
        std::fputs("this is not a database, just text long enough to be read as a header....", f);
        std::fclose(f);
    }
    EXPECT_THROW((void)SampleStore::open(file, "analytic", "fp"), IoError);
}
