/// Exports of a generated table set: the native database round trip (and it flies: evaluate),
/// the CEASIOM/SDSA columns of the paper's Table 5, the JSBSim XML (well formed, the expected
/// axes, functions and 3-D tables), the CSV files.

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "manta/tables/analytic_source.hpp"
#include "manta/tables/export.hpp"
#include "manta/tables/generator.hpp"

using namespace manta;
using namespace manta::tables;

namespace {

struct Fixture {
    Campaign campaign;
    CampaignResult result;
    std::vector<Sample> samples;
};

const Fixture& fixture() {
    static const Fixture f = [] {
        Fixture x;
        x.campaign = parse_campaign(
            "schema_version: 1\nname: export test\nsource: {type: analytic}\n"
            "static: {alpha_deg: {min: -4, max: 12, count: 5}, mach: [0.2, 0.4, 0.6], "
            "beta_deg: [-5, 0, 5], budget: 20, batch: 4, initial_design: {size: 10}}\n"
            "controls:\n  elevator: {deflection_deg: [-10, 0, 10], samples: 6}\n"
            "  aileron: {deflection_deg: [-10, 0, 10], samples: 6}\n"
            "dynamic: {alpha_deg: [0, 8], mach: [0.2, 0.6]}\n",
            "export.yaml");
        const AnalyticSource src;
        const auto dir = std::filesystem::temp_directory_path() / "manta_tables_export";
        std::filesystem::remove_all(dir);
        auto store = SampleStore::open(dir / "samples.sqlite", src.name(), src.fingerprint());
        x.result = run_campaign(x.campaign, src, *store, {});
        x.samples = store->samples();
        return x;
    }();
    return f;
}

std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> out;
    std::istringstream in(s);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

/// Minimal XML well-formedness: every start tag closed in order, attributes quoted.
bool well_formed(const std::string& xml, std::string& why) {
    std::vector<std::string> stack;
    const std::regex tag(R"(<(/?)([A-Za-z_][\w.-]*)((?:\s+[\w-]+="[^"<]*")*)\s*(/?)>)");
    std::size_t pos = 0;
    while ((pos = xml.find('<', pos)) != std::string::npos) {
        if (xml.compare(pos, 4, "<!--") == 0) {
            pos = xml.find("-->", pos);
            if (pos == std::string::npos) return why = "open comment", false;
            continue;
        }
        if (xml.compare(pos, 2, "<?") == 0) {
            pos = xml.find("?>", pos);
            continue;
        }
        std::smatch m;
        const std::string rest = xml.substr(pos, 400);
        if (!std::regex_search(rest, m, tag) || m.position(0) != 0)
            return why = "bad tag at " + std::to_string(pos), false;
        if (m[1] == "/") {
            if (stack.empty() || stack.back() != m[2])
                return why = "mismatched " + m[2].str(), false;
            stack.pop_back();
        } else if (m[4] != "/") {
            stack.push_back(m[2]);
        }
        pos += static_cast<std::size_t>(m.length(0));
    }
    if (!stack.empty()) return why = "unclosed " + stack.back(), false;
    return true;
}

std::size_t count(const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
    return n;
}

}  // namespace

TEST(Export, NativeDatabaseRoundTripsAndEvaluates) {
    const auto& f = fixture();
    const aero::AeroDatabase db = make_database(f.campaign, f.result, "analytic");
    ASSERT_EQ(db.tables().size(), 4u);  // static, elevator, aileron, dynamic
    const std::string text = db.to_text();
    const aero::AeroDatabase back = aero::AeroDatabase::from_text(text, "db.yaml");
    EXPECT_EQ(back.to_text(), text);
    // At a static sample entry the database returns the source's value (sampled entries exact).
    const AnalyticSource src;
    for (const Sample& s : f.samples) {
        if (s.scenario != "static" || s.status != SampleStatus::done) continue;
        const auto c = back.evaluate(s.query, aero::Interpolation::multilinear);
        EXPECT_NEAR(c.Cm, s.result.body.Cm, 1e-12);
        EXPECT_NEAR(c.Cl, s.result.body.Cl, 1e-12);
    }
}

TEST(Export, CeasiomTablesHaveTheColumnsOfTable5) {
    const auto& f = fixture();
    const aero::AeroDatabase db = make_database(f.campaign, f.result, "analytic");
    const auto aero_lines = lines(ceasiom_aero_table(db, 0.01));
    std::vector<std::string> data;
    std::string header;
    for (const auto& l : aero_lines) {
        if (l.rfind("#", 0) == 0) continue;
        if (header.empty())
            header = l;
        else
            data.push_back(l);
    }
    EXPECT_TRUE(std::regex_search(
        header,
        std::regex(R"(alpha\s+Mach\s+beta\s+p_hat\s+q_hat\s+r_hat\s+CL\s+CD\s+Cm\s+CY\s+Cl\s+Cn)")))
        << header;
    EXPECT_EQ(data.size(), 5u * 3 * 3 + 2 * 2 * 3);  // static entries + 3 rate rows per (alpha, M)
    std::istringstream row(data.front());
    std::vector<double> v;
    for (double x; row >> x;) v.push_back(x);
    ASSERT_EQ(v.size(), 12u);
    EXPECT_EQ(v[0], -4.0);  // degrees
    EXPECT_EQ(v[2], -5.0);

    const auto ctl = lines(ceasiom_control_table(db));
    std::size_t n = 0;
    for (const auto& l : ctl)
        if (l.rfind("#", 0) != 0) ++n;
    EXPECT_EQ(n, 1u + 2 * 5 * 3 * 3);
    bool found = false;
    for (const auto& l : ctl)
        if (std::regex_search(
                l,
                std::regex(
                    R"(alpha\s+Mach\s+delta_e\s+delta_r\s+delta_a\s+dCL\s+dCD\s+dCm\s+dCY\s+dCl\s+dCn)")))
            found = true;
    EXPECT_TRUE(found);
}

TEST(Export, JsbsimXmlIsWellFormedWithTheExpectedTables) {
    const auto& f = fixture();
    const aero::AeroDatabase db = make_database(f.campaign, f.result, "analytic");
    const std::string xml = jsbsim_aerodynamics(db);
    std::string why;
    EXPECT_TRUE(well_formed(xml, why)) << why;
    for (const char* axis : {"LIFT", "DRAG", "SIDE", "ROLL", "PITCH", "YAW"})
        EXPECT_EQ(count(xml, std::string("<axis name=\"") + axis + "\">"), 1u) << axis;
    // Static: 6 functions with 3 tableData blocks (beta); controls: 2 x 6 with 3 (deflection);
    // dynamic: 18 2-D tables.
    EXPECT_EQ(count(xml, "<tableData breakPoint="), 6u * 3 + 2 * 6 * 3);
    EXPECT_EQ(count(xml, "<function "), 6u + 12 + 18);
    EXPECT_EQ(count(xml, "<independentVar lookup=\"table\">aero/beta-rad</independentVar>"), 6u);
    EXPECT_EQ(count(xml, "fcs/elevator-pos-rad"), 6u);
    EXPECT_EQ(count(xml, "fcs/left-aileron-pos-rad"), 6u);
    EXPECT_EQ(count(xml, "<property>aero/qbar-psf</property>"), 36u);
    EXPECT_EQ(count(xml, "<property>metrics/cbarw-ft</property>"), 1u + 2 + 3);
    EXPECT_EQ(count(xml, "velocities/q-aero-rad_sec"), 6u);
    EXPECT_NE(xml.find("aero/coefficient/manta/Cm_q"), std::string::npos);
}

TEST(Export, CsvFilesHoldEveryEntryAndSample) {
    const auto& f = fixture();
    const auto t = lines(tables_csv(f.result.tables));
    EXPECT_EQ(t.size(), 2u + 45 + 2 * 45);  // comment, header, static and control entries
    EXPECT_EQ(t[1].substr(0, 40), "table,alpha_deg,mach,beta_deg,delta_deg,");
    const auto d = lines(dynamic_csv(f.result.tables));
    EXPECT_EQ(d.size(), 2u + 4);
    const auto s = lines(samples_csv(f.samples));
    EXPECT_EQ(s.size(), 1u + f.samples.size());
}
