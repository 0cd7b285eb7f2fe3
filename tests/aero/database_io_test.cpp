// AeroDatabase native text format: exact round trip, atomic write/read, located errors.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <numbers>

#include "aero_test_util.hpp"
#include "manta/aero/database.hpp"
#include "manta/core/error.hpp"

namespace manta::aero {
namespace {

using test::make_table;

void expect_bitwise_equal(const AeroDatabase& a, const AeroDatabase& b) {
    EXPECT_EQ(a.info().name, b.info().name);
    EXPECT_EQ(a.info().source, b.info().source);
    EXPECT_EQ(a.info().description, b.info().description);
    EXPECT_EQ(a.force_axes(), b.force_axes());
    EXPECT_EQ(a.extrapolation(), b.extrapolation());
    ASSERT_EQ(a.tables().size(), b.tables().size());
    for (std::size_t t = 0; t < a.tables().size(); ++t) {
        const Table& x = a.tables()[t];
        const Table& y = b.tables()[t];
        EXPECT_EQ(x.name, y.name);
        EXPECT_EQ(x.kind, y.kind);
        EXPECT_EQ(x.columns, y.columns);
        ASSERT_EQ(x.axes.size(), y.axes.size());
        for (std::size_t k = 0; k < x.axes.size(); ++k) {
            EXPECT_EQ(x.axes[k].axis, y.axes[k].axis);
            ASSERT_EQ(x.axes[k].breakpoints.size(), y.axes[k].breakpoints.size());
            for (std::size_t j = 0; j < x.axes[k].breakpoints.size(); ++j) {
                EXPECT_EQ(std::bit_cast<std::uint64_t>(x.axes[k].breakpoints[j]),
                          std::bit_cast<std::uint64_t>(y.axes[k].breakpoints[j]));
            }
        }
        ASSERT_EQ(x.values.size(), y.values.size());
        for (std::size_t j = 0; j < x.values.size(); ++j) {
            EXPECT_EQ(std::bit_cast<std::uint64_t>(x.values[j]),
                      std::bit_cast<std::uint64_t>(y.values[j]))
                << x.name << " value " << j << ": " << x.values[j] << " vs " << y.values[j];
        }
    }
}

TEST(AeroDatabaseFormat, RoundTripIsExact) {
    const AeroDatabase db = test::ranger_like(Extrapolation::linear);
    const std::string text = db.to_text();
    const AeroDatabase back = AeroDatabase::from_text(text, "ranger.yaml");
    expect_bitwise_equal(db, back);
    EXPECT_EQ(back.to_text(), text);
}

TEST(AeroDatabaseFormat, AwkwardNumbersAndStringsSurvive) {
    // Values chosen to break naive printing: 0.1, 1/3, pi, the plausible extremes (+-100),
    // subnormals, -0.0.
    const std::vector<double> awkward = {0.1,
                                         1.0 / 3.0,
                                         std::numbers::pi,
                                         1e-300,
                                         -99.999999999999986,  // coefficients stay within
                                         100.0,                // [-100, 100] (issue 16)
                                         1.0 / 7.0,
                                         std::numeric_limits<double>::min(),
                                         std::numeric_limits<double>::denorm_min(),
                                         -4.9406564584124654e-320,
                                         -0.0,
                                         0.0,
                                         12.345678901234568,
                                         2.2250738585072009e-308,
                                         0.30000000000000004,
                                         -1.0000000000000002};
    std::vector<Table> tables;
    Table t;
    t.name = "static: \"quoted\" #1";
    t.kind = TableKind::static_table;
    t.axes = {{Axis::alpha, {-0.1, 1e-300, 0.1 + 0.2}}, {Axis::mach, {0.0, 1.0 / 3.0}}};
    t.columns = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    for (std::size_t k = 0; k < 36; ++k) t.values.push_back(awkward[k % awkward.size()]);
    tables.push_back(t);
    tables.push_back(
        make_table("null", TableKind::control, {{Axis::elevator, {-0.2, 0.2}}}, {"Cm"},
                   [](const std::vector<double>& p) { return std::vector<double>{-p[0]}; }));
    DatabaseInfo info{
        "Ranger 2000 (linear derivatives)",
        "line one\nline two: with colon # and hash\ttab \\ backslash \"quotes\" ünïcödé",
        " leading space"};
    const AeroDatabase db(info, ForceAxes::wind, Extrapolation::clamp, tables);
    const std::string text = db.to_text();
    const AeroDatabase back = AeroDatabase::from_text(text, "awkward.yaml");
    expect_bitwise_equal(db, back);
    EXPECT_TRUE(std::signbit(back.tables()[0].values[10]));  // -0.0 keeps its sign
    EXPECT_EQ(back.to_text(), text);
    // Plain names stay plain.
    EXPECT_NE(text.find("  name: Ranger 2000 (linear derivatives)\n"), std::string::npos) << text;
    EXPECT_NE(text.find("  - name: \"null\"\n"), std::string::npos) << text;
    EXPECT_NE(text.find("{name: alpha, values: [-0.1, 1e-300, 0.30000000000000004]}"),
              std::string::npos)
        << text;
}

TEST(AeroDatabaseFormat, WriteIsAtomicAndReadsBack) {
    const auto dir = std::filesystem::temp_directory_path() / "manta_aero_io_test";
    std::filesystem::remove_all(dir);
    const auto file = dir / "sub" / "ranger.yaml";
    const AeroDatabase db = test::ranger_like();
    db.write(file);
    const AeroDatabase back = AeroDatabase::read(file);
    expect_bitwise_equal(db, back);
    // Overwrite in place; no temporary left behind.
    back.write(file);
    std::size_t n_files = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir / "sub"))
        ++n_files;
    EXPECT_EQ(n_files, 1u);
    std::filesystem::remove_all(dir);
    EXPECT_THROW((void)AeroDatabase::read(dir / "missing.yaml"), IoError);
}

const char* const small_file = R"(manta_aero_database: 1
info:
  name: small
  source: hand
  description: a hand-written example
force_axes: wind
extrapolation: linear
tables:
  - name: static
    kind: static
    axes:
      - {name: alpha, values_deg: [-4, 0, 4]}
      - {name: mach, values: [0.1, 0.3]}
    columns: [CL, CD, Cm]
    data:
      - [-0.1, 0.02, 0.01]
      - [-0.1, 0.021, 0.01]
      - [0.2, 0.02, 0.0]
      - [0.2, 0.021, 0.0]
      - [0.5, 0.03, -0.01]
      - [0.5, 0.031, -0.01]
  - name: elevator
    kind: control
    axes:
      - {name: elevator, values: [-0.2, 0.2]}
    columns: [CL, Cm]
    data:
      - [-0.08, 0.2]
      - [0.08, -0.2]
  - name: dynamic
    kind: dynamic
    axes: []
    columns: [Cm_q, CL_alphadot]
    data:
      - [-12, 1.5]
)";

TEST(AeroDatabaseFormat, ReadsHandWrittenFile) {
    const AeroDatabase db = AeroDatabase::from_text(small_file, "small.yaml");
    EXPECT_EQ(db.info().name, "small");
    EXPECT_EQ(db.info().description, "a hand-written example");
    EXPECT_EQ(db.extrapolation(), Extrapolation::linear);
    ASSERT_EQ(db.tables().size(), 3u);
    EXPECT_DOUBLE_EQ(db.tables()[0].axes[0].breakpoints[0], -4 * std::numbers::pi / 180);
    EXPECT_EQ(db.tables()[2].n_points(), 1u);
    AeroQuery<double> q;
    q.alpha = 2 * std::numbers::pi / 180;
    q.mach = 0.2;
    q.elevator = 0.1;
    q.q_hat = 0.01;
    const auto c = db.evaluate(q, Interpolation::multilinear);
    EXPECT_NEAR(c.Cm, -0.005 - 0.1 - 0.12, 1e-15);  // static + elevator + Cm_q q
    const auto w = wind_from_body(c.CX, c.CY, c.CZ, q.alpha, q.beta);
    EXPECT_NEAR(w.CL, 0.35 + 0.04, 1e-14);
    EXPECT_NEAR(w.CD, 0.0255, 1e-14);
}

/// The InputError message from_text throws for `text`.
std::string read_error(const std::string& text) {
    try {
        (void)AeroDatabase::from_text(text, "db.yaml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

/// `small_file` with the first occurrence of `from` replaced by `to`.
std::string edited(std::string_view from, std::string_view to) {
    std::string s = small_file;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
    return s;
}

void expect_contains(const std::string& message, std::initializer_list<std::string_view> parts) {
    for (const auto part : parts)
        EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
}

TEST(AeroDatabaseFormatErrors, Version) {
    expect_contains(read_error(edited("manta_aero_database: 1", "manta_aero_database: 2")),
                    {"db.yaml:1:", "manta_aero_database",
                     "value '2' is an unsupported format version", "expected 1"});
    expect_contains(read_error(edited("manta_aero_database: 1\n", "")),
                    {"db.yaml:1", "not an aero database: missing key 'manta_aero_database'"});
    expect_contains(read_error("- just\n- a list\n"), {"db.yaml:1", "is not an aero database"});
    expect_contains(read_error("manta_aero_database: [1\n"), {"db.yaml:", "YAML syntax error"});
}

TEST(AeroDatabaseFormatErrors, UnknownNamesSuggestTheClosest) {
    expect_contains(read_error(edited("kind: static", "kind: statc")),
                    {"db.yaml:10:", "tables[0].kind", "'statc' is not a valid choice",
                     "did you mean 'static'?"});
    expect_contains(read_error(edited("{name: mach,", "{name: mahc,")),
                    {"db.yaml:13:", "tables[0].axes[1].name", "'mahc' is not an axis name",
                     "did you mean 'mach'?"});
    expect_contains(
        read_error(edited("columns: [CL, CD, Cm]", "columns: [CL, CD, Cmm]")),
        {"db.yaml:14:", "tables[0].columns[2]", "unknown column 'Cmm' (did you mean 'Cm'?)"});
    expect_contains(read_error(edited("[Cm_q, CL_alphadot]", "[Cm_q, CL_alphadt]")),
                    {"db.yaml:33:", "tables[2].columns[1]",
                     "unknown column 'CL_alphadt' (did you mean 'CL_alphadot'?)"});
    expect_contains(read_error(edited("force_axes: wind", "force_axes: wnd")),
                    {"db.yaml:6:", "did you mean 'wind'?"});
    expect_contains(read_error(edited("    columns: [CL, CD, Cm]", "    colums: [CL, CD, Cm]")),
                    {"db.yaml:", "missing required key 'tables[0].columns'"});
    expect_contains(
        read_error(edited("extrapolation: linear", "extrapolation: linear\nextrapolate: clamp")),
        {"db.yaml:8:", "unknown key 'extrapolate'", "did you mean 'extrapolation'?"});
    expect_contains(read_error(edited("{name: mach, values:", "{name: mach, valeus:")),
                    {"db.yaml:13:", "axis 'mach' has no breakpoints; expected key 'values'"});
}

TEST(AeroDatabaseFormatErrors, DataShape) {
    expect_contains(
        read_error(edited("      - [-0.1, 0.021, 0.01]\n", "      - [-0.1, 0.021]\n")),
        {"db.yaml:17:", "tables[0].data[1]",
         "table 'static' data row 1 has 2 entries; expected a list of 3 numbers", "(CL, CD, Cm)"});
    expect_contains(read_error(edited("      - [0.5, 0.031, -0.01]\n", "")),
                    {"db.yaml:15:", "tables[0].data",
                     "table 'static' has 5 data rows; expected 6 = 3 alpha x 2 mach"});
    expect_contains(read_error(edited("[0.2, 0.021, 0.0]", "[0.2, 0.021, abc]")),
                    {"db.yaml:19:", "tables[0].data[3][2]", "value 'abc' is not a number"});
    expect_contains(read_error(edited("[0.2, 0.021, 0.0]", "[0.2, 0.021, .inf]")),
                    {"db.yaml:19:", "value '.inf' is not"});
    expect_contains(read_error(edited("[0.2, 0.021, 0.0]", "[0.2, 0.021, 1e999]")),
                    {"db.yaml:19:", "value '1e999' is out of the range of a double"});
}

TEST(AeroDatabaseFormatErrors, Axes) {
    expect_contains(
        read_error(edited("values_deg: [-4, 0, 4]", "values_deg: [-4, 5, 4]")),
        {"db.yaml:12:", "tables[0].axes[0].values_deg[2]",
         "axis 'alpha' breakpoint [2] = 4 deg is not greater than breakpoint [1] = 5 deg",
         "strictly increasing"});
    expect_contains(read_error(edited("values: [0.1, 0.3]", "values: [0.3, 0.3]")),
                    {"db.yaml:13:", "tables[0].axes[1].values[1]",
                     "axis 'mach' breakpoint [1] = 0.3 is not greater than breakpoint [0] = 0.3;"});
    expect_contains(read_error(edited("values_deg: [-4, 0, 4]", "values: [-4, 0, 10]")),
                    {"db.yaml:12:", "tables[0].axes[0].values[2]", "breakpoint [2] = 10 rad",
                     "looks like degrees"});
    expect_contains(read_error(edited("{name: mach, values: [0.1, 0.3]}",
                                      "{name: mach, values_deg: [0.1, 0.3]}")),
                    {"db.yaml:13:", "tables[0].axes[1].values_deg",
                     "is given for 'mach', which is not an angle"});
    expect_contains(
        read_error(edited("values_deg: [-4, 0, 4]}", "values_deg: [-4, 0, 4], values: [1, 2, 3]}")),
        {"db.yaml:12:", "duplicates 'values'"});
    expect_contains(
        read_error(
            edited("{name: elevator, values: [-0.2, 0.2]}", "{name: alpha, values: [-0.2, 0.2]}")),
        {"db.yaml:22:", "tables[1]", "control table 'elevator' has 0 control axes (axes: alpha)"});
}

TEST(AeroDatabaseFormatErrors, TableSet) {
    expect_contains(read_error(edited("kind: control", "kind: static")),
                    {"db.yaml:22:", "tables[1]",
                     "table 'elevator' is a second static table (the first is 'static')"});
    expect_contains(read_error(edited("  - name: elevator", "  - name: static")),
                    {"db.yaml:22:", "tables[1].name", "table [1] name 'static' repeats table [0]"});
    expect_contains(read_error(edited("kind: static", "kind: dynamic")),
                    {"db.yaml:14:", "tables[0].columns[0]", "unknown column 'CL'",
                     "dynamic columns are <coef>_<rate>"});
}

}  // namespace
}  // namespace manta::aero
