// Tests of the configuration validation layer (src/core/config.cpp): every error path, each
// asserting that the one-line message names the file, the line, the key path, the value and what
// was expected.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <string>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"

namespace {

using manta::ConfigError;
using manta::core::ConfigMap;
using manta::core::ConfigNode;
using manta::core::NumberSpec;

ConfigMap root(const std::string& text) {
    return ConfigMap(ConfigNode::parse_string(text, "test.yaml"));
}

/// Message of the ConfigError thrown by `f` (a test failure if none is thrown).
std::string config_error(const std::function<void()>& f) {
    try {
        f();
    } catch (const ConfigError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected ConfigError, got: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected ConfigError, nothing thrown";
    return {};
}

/// The message is one line and contains every part.
void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

// ------------------------------------------------------------------------------------ success
// paths

TEST(Config, ReadsEveryKindOfValue) {
    auto m = root(
        "area: 15.5\n"
        "n: 3\n"
        "flag: true\n"
        "off: no\n"
        "name: Ranger\n"
        "p: [1, 2, 3]\n"
        "twist_deg: 2\n"
        "sweep: 0.1\n"
        "limits_deg: [-25, 15]\n"
        "kind: lapse\n"
        "sub: {a: 1}\n"
        "list: [{x: 1}]\n");
    EXPECT_DOUBLE_EQ(m.number("area", NumberSpec::positive("m^2")), 15.5);
    EXPECT_EQ(m.integer("n", NumberSpec::positive("-")), 3);
    EXPECT_TRUE(m.boolean_or("flag", false));
    EXPECT_FALSE(m.boolean_or("off", true));
    EXPECT_TRUE(m.boolean_or("absent", true));
    EXPECT_EQ(m.string("name"), "Ranger");
    const auto p = m.vec3("p", NumberSpec::any("m"));
    EXPECT_DOUBLE_EQ(p[2], 3.0);
    EXPECT_NEAR(m.angle("twist", NumberSpec::any("rad")), 2.0 * std::numbers::pi / 180.0, 1e-15);
    EXPECT_DOUBLE_EQ(m.angle("sweep", NumberSpec::any("rad")), 0.1);
    EXPECT_DOUBLE_EQ(m.angle_or("dihedral", 0.25, NumberSpec::any("rad")), 0.25);
    const auto lim = m.angle_range("limits", NumberSpec::any("rad"));
    EXPECT_NEAR(lim[0], -25.0 * std::numbers::pi / 180.0, 1e-15);
    EXPECT_NEAR(lim[1], 15.0 * std::numbers::pi / 180.0, 1e-15);
    EXPECT_EQ(m.choice("kind", {"lapse", "table"}), "lapse");
    EXPECT_EQ(m.choice_or("other", "table", {"lapse", "table"}), "table");
    EXPECT_DOUBLE_EQ(m.number_or("missing", 7.0, NumberSpec::any("-")), 7.0);
    auto sub = m.map("sub");
    EXPECT_DOUBLE_EQ(sub.number("a", NumberSpec::any("-")), 1.0);
    sub.finish();
    const ConfigNode list = m.sequence("list");
    EXPECT_EQ(list.size(), 1u);
    EXPECT_EQ(list.element(0).key_path(), "list[0]");
    EXPECT_EQ(list.element(0).line(), 12);
    EXPECT_NO_THROW(m.finish());
}

TEST(Config, LinesAndPathsOfNestedNodes) {
    auto m = root("a:\n  b:\n    - c: 1\n    - c: 2\n");
    const ConfigNode b = m.map("a").sequence("b");
    const ConfigNode c = b.element(1).child("c");
    EXPECT_EQ(c.key_path(), "a.b[1].c");
    EXPECT_EQ(c.line(), 4);
    EXPECT_EQ(c.where(), "test.yaml:4: key 'a.b[1].c'");
    EXPECT_EQ(c.value_text(), "2");
}

// ------------------------------------------------------------------------------------ error paths

TEST(ConfigErrors, MissingKey) {
    auto m = root("reference:\n  span: 10.46\n");
    auto r = m.map("reference");
    const auto msg = config_error([&] { (void)r.number("area", NumberSpec::positive("m^2")); });
    expect_parts(msg, {"test.yaml:1", "missing required key 'reference.area'"});
}

TEST(ConfigErrors, MissingKeyAtTopLevel) {
    auto m = root("name: x\n");
    expect_parts(config_error([&] { (void)m.string("schema"); }),
                 {"test.yaml:1", "missing required key 'schema'"});
}

TEST(ConfigErrors, MissingKeyPointsAtTheMisspelling) {
    auto m = root("reference:\n  span: 10.46\n  aera: 15.5\n");
    auto r = m.map("reference");
    (void)r.number("span", NumberSpec::positive("m"));
    const auto msg = config_error([&] { (void)r.number("area", NumberSpec::positive("m^2")); });
    expect_parts(
        msg, {"test.yaml:1", "missing required key 'reference.area'", "found 'aera' at line 3"});
}

TEST(ConfigErrors, MissingKeyPointsAtTheKeyWithAUnitSuffix) {
    auto m = root("a: 1\nceiling_ft: 31000\n");
    const auto msg = config_error([&] { (void)m.number("ceiling", NumberSpec::positive("m")); });
    expect_parts(msg, {"test.yaml:1", "missing required key 'ceiling'",
                       "found 'ceiling_ft' at line 2", "MANTA reads 'ceiling' in SI units"});
}

TEST(ConfigErrors, UnknownKeyWithSuggestion) {
    auto m = root("area: 1\nchrod: 2\n");
    (void)m.number("area", NumberSpec::any("m^2"));
    (void)m.number_or("chord", 1.0, NumberSpec::any("m"));
    const auto msg = config_error([&] { m.finish(); });
    expect_parts(msg, {"test.yaml:2", "unknown key 'chrod'", "did you mean 'chord'?",
                       "valid keys here: area, chord"});
}

TEST(ConfigErrors, UnknownKeyWithoutCloseMatchListsValidKeys) {
    auto m = root("sub:\n  area: 1\n  zzzzzz: 2\n");
    auto s = m.map("sub");
    (void)s.number("area", NumberSpec::any("m^2"));
    const auto msg = config_error([&] { s.finish(); });
    expect_parts(
        msg, {"test.yaml:3", "key 'sub.zzzzzz'", "unknown key 'zzzzzz'", "valid keys here: area"});
    EXPECT_EQ(msg.find("did you mean"), std::string::npos) << msg;
}

TEST(ConfigErrors, UnknownKeyWithForeignUnitSuffix) {
    auto m = root("span_ft: 34.3\n");
    (void)m.number_or("span", 10.0, NumberSpec::positive("m"));
    const auto msg = config_error([&] { m.finish(); });
    expect_parts(msg, {"test.yaml:1", "unknown key 'span_ft'", "MANTA reads 'span' in SI units",
                       "convert the value"});
}

TEST(ConfigErrors, UnknownAngleKeyWithRadianSuffixPointsToDegrees) {
    auto m = root("twist_rad: 0.1\n");
    (void)m.angle_or("twist", 0.0, NumberSpec::any("rad"));
    const auto msg = config_error([&] { m.finish(); });
    expect_parts(
        msg, {"test.yaml:1", "unknown key 'twist_rad'", "'twist'", "or 'twist_deg' in degrees"});
}

TEST(ConfigErrors, WrongTypeTextForNumber) {
    auto m = root("a: 1\nmass: heavy\n");
    const auto msg = config_error([&] { (void)m.number("mass", NumberSpec::positive("kg")); });
    expect_parts(msg, {"test.yaml:2", "key 'mass'", "value 'heavy'", "is not a number",
                       "expected a number > 0 [kg]"});
}

TEST(ConfigErrors, WrongTypeMapForNumber) {
    auto m = root("mass:\n  value: 1\n");
    const auto msg = config_error([&] { (void)m.number("mass", NumberSpec::positive("kg")); });
    expect_parts(msg, {"test.yaml:1", "key 'mass'", "value '<mapping>'", "is not a number",
                       "a number > 0 [kg]"});
}

TEST(ConfigErrors, WrongTypeScalarForList) {
    auto m = root("cases: 3\n");
    const auto msg = config_error([&] { (void)m.sequence("cases"); });
    expect_parts(msg,
                 {"test.yaml:1", "key 'cases'", "value '3'", "is not a list", "expected a list"});
}

TEST(ConfigErrors, WrongTypeScalarForNumberList) {
    auto m = root("a: 1\nx: 5\n");
    const auto msg = config_error([&] { (void)m.numbers("x", 0, NumberSpec::any("m")); });
    expect_parts(msg, {"test.yaml:2", "key 'x'", "value '5'", "is not a list",
                       "a list of numbers, each a number [m]"});
}

TEST(ConfigErrors, OptionalKeysAreValidatedWhenPresent) {
    auto m = root("n: 2.5\nx: -1\nkind: tabel\nt_deg: 99\n");
    expect_parts(config_error([&] { (void)m.integer_or("n", 1, NumberSpec::any("-")); }),
                 {"test.yaml:1", "key 'n'", "value '2.5'", "is not an integer"});
    expect_parts(config_error([&] { (void)m.number_or("x", 1.0, NumberSpec::positive("m")); }),
                 {"test.yaml:2", "key 'x'", "value '-1'", "a number > 0 [m]"});
    expect_parts(config_error([&] {
                     (void)m.choice_or("kind", "lapse", {"lapse", "table"});
                 }),
                 {"test.yaml:3", "key 'kind'", "value 'tabel'", "did you mean 'table'?"});
    expect_parts(
        config_error([&] { (void)m.angle_or("t", 0.0, NumberSpec::range(-1.0, 1.0, "rad")); }),
        {"test.yaml:4", "key 't_deg'", "value '99'", "is out of range", "[deg]"});
    EXPECT_EQ(m.integer_or("absent", 4, NumberSpec::any("-")), 4);
    EXPECT_FALSE(m.optional_child("absent").has_value());
    EXPECT_TRUE(m.optional_child("n").has_value());
    EXPECT_EQ(m.string_or("absent", "z"), "z");
}

TEST(ConfigErrors, MissingChildMapAndSequence) {
    auto m = root("a: 1\n");
    expect_parts(config_error([&] { (void)m.map("geometry"); }),
                 {"test.yaml:1", "missing required key 'geometry'"});
    expect_parts(config_error([&] { (void)m.sequence("cases"); }),
                 {"missing required key 'cases'"});
    expect_parts(config_error([&] { (void)m.child("aero"); }), {"missing required key 'aero'"});
}

TEST(ConfigErrors, WrongTypeListForText) {
    auto m = root("name: [a, b]\n");
    const auto msg = config_error([&] { (void)m.string("name"); });
    expect_parts(msg, {"test.yaml:1", "key 'name'", "value '<sequence>'", "is not a text value",
                       "expected a text value"});
}

TEST(ConfigErrors, WrongTypeScalarForMap) {
    auto m = root("reference: 3\n");
    const auto msg = config_error([&] { (void)m.map("reference"); });
    expect_parts(
        msg, {"test.yaml:1", "key 'reference'", "value '3'", "is not a mapping", "'key: value'"});
}

TEST(ConfigErrors, EmptyValue) {
    auto m = root("mass:\n");
    const auto msg = config_error([&] { (void)m.number("mass", NumberSpec::positive("kg")); });
    expect_parts(
        msg, {"test.yaml:1", "key 'mass'", "value '<empty>'", "is missing", "a number > 0 [kg]"});
}

TEST(ConfigErrors, OutOfRange) {
    auto m = root("x: 1\nmass: -3\n");
    const auto msg = config_error([&] { (void)m.number("mass", NumberSpec::positive("kg")); });
    expect_parts(msg, {"test.yaml:2", "key 'mass'", "value '-3'", "is out of range",
                       "expected a number > 0 [kg]"});
}

TEST(ConfigErrors, OutOfClosedRange) {
    auto m = root("f: 1.5\n");
    const auto msg = config_error([&] { (void)m.number("f", NumberSpec::range(0.0, 1.0, "-")); });
    expect_parts(msg, {"test.yaml:1", "key 'f'", "value '1.5'", "is out of range",
                       "a number in [0, 1] [-]"});
}

TEST(ConfigErrors, ExclusiveBounds) {
    const NumberSpec open{0.0, 1.0, true, true, "-"};
    for (const char* bad : {"0", "1"}) {
        auto m = root(std::string("f: ") + bad + "\n");
        const auto msg = config_error([&] { (void)m.number("f", open); });
        expect_parts(msg, {"test.yaml:1", "key 'f'", std::string("value '") + bad + "'",
                           "is out of range", "a number in (0, 1) [-]"});
    }
    auto ok = root("f: 0.5\ng: 0\nh: 1\n");
    EXPECT_DOUBLE_EQ(ok.number("f", open), 0.5);
    // The same bounds inclusive accept the end points.
    EXPECT_DOUBLE_EQ(ok.number("g", NumberSpec::range(0.0, 1.0, "-")), 0.0);
    EXPECT_DOUBLE_EQ(ok.number("h", NumberSpec::range(0.0, 1.0, "-")), 1.0);
    auto lower = root("f: 0\n");
    expect_parts(config_error([&] { (void)lower.number("f", NumberSpec::positive("m")); }),
                 {"a number > 0 [m]"});
    auto upper = root("f: 2\n");
    expect_parts(config_error([&] {
                     (void)upper.number("f", NumberSpec{std::nullopt, 2.0, false, true, "m"});
                 }),
                 {"value '2'", "a number < 2 [m]"});
}

TEST(ConfigErrors, NumberCarryingAUnit) {
    auto m = root("area: 15.5 m2\n");
    const auto msg = config_error([&] { (void)m.number("area", NumberSpec::positive("m^2")); });
    expect_parts(msg,
                 {"test.yaml:1", "key 'area'", "value '15.5 m2'", "carries a unit in the value",
                  "a number > 0 [m^2] written as a plain number"});
}

TEST(ConfigErrors, NumberCarryingAUnitWithoutSpace) {
    auto m = root("twist: 10deg\n");
    const auto msg = config_error([&] { (void)m.angle("twist", NumberSpec::any("rad")); });
    expect_parts(msg,
                 {"test.yaml:1", "key 'twist'", "value '10deg'", "carries a unit in the value"});
}

TEST(ConfigErrors, NotFinite) {
    auto m = root("a: nan\nb: inf\n");
    expect_parts(config_error([&] { (void)m.number("a", NumberSpec::any("m")); }),
                 {"test.yaml:1", "key 'a'", "value 'nan'", "is not finite", "a number [m]"});
    expect_parts(config_error([&] { (void)m.number("b", NumberSpec::any("m")); }),
                 {"test.yaml:2", "key 'b'", "value 'inf'", "is not finite"});
}

TEST(ConfigErrors, RadianAngleThatLooksLikeDegrees) {
    auto m = root("twist: 25\n");
    const auto msg =
        config_error([&] { (void)m.angle("twist", NumberSpec::range(-0.5, 0.5, "rad")); });
    expect_parts(msg, {"test.yaml:1", "key 'twist'", "value '25'",
                       "is in radians but looks like degrees", "write it as 'twist_deg'"});
}

TEST(ConfigErrors, AngleOutOfRangeInDegrees) {
    auto m = root("twist_deg: 45\n");
    const auto msg = config_error([&] {
        (void)m.angle("twist", NumberSpec::range(-0.5235987755982988, 0.5235987755982988, "rad"));
    });
    expect_parts(msg, {"test.yaml:1", "key 'twist_deg'", "value '45'", "is out of range",
                       "a number in [-30, 30] [deg]"});
}

TEST(ConfigErrors, AngleOutOfRangeInRadians) {
    auto m = root("twist: 1\n");
    const auto msg =
        config_error([&] { (void)m.angle("twist", NumberSpec::range(-0.5, 0.5, "rad")); });
    expect_parts(msg, {"test.yaml:1", "key 'twist'", "value '1'", "is out of range",
                       "a number in [-0.5, 0.5] [rad]"});
}

TEST(ConfigErrors, MissingAngle) {
    auto m = root("a: 1\n");
    const auto msg = config_error([&] { (void)m.angle("twist", NumberSpec::any("rad")); });
    expect_parts(msg, {"test.yaml:1", "missing required key 'twist' (or 'twist_deg' in degrees)"});
}

TEST(ConfigErrors, BothKeyAndKeyDeg) {
    auto m = root("twist: 0.1\ntwist_deg: 5\n");
    const auto msg = config_error([&] { (void)m.angle("twist", NumberSpec::any("rad")); });
    expect_parts(msg, {"test.yaml:2", "key 'twist_deg'", "value '5'", "duplicates 'twist'",
                       "either 'twist' (radians) or 'twist_deg' (degrees), not both"});
}

TEST(ConfigErrors, BothKeyAndKeyDegInARange) {
    auto m = root("limits: [-0.4, 0.2]\nlimits_deg: [-25, 15]\n");
    const auto msg = config_error([&] { (void)m.angle_range("limits", NumberSpec::any("rad")); });
    expect_parts(msg, {"test.yaml:2", "key 'limits_deg'", "duplicates 'limits'", "not both"});
}

TEST(ConfigErrors, AngleRangeReversed) {
    auto m = root("elevator_deg: [15, -25]\n");
    const auto msg = config_error([&] { (void)m.angle_range("elevator", NumberSpec::any("rad")); });
    expect_parts(msg, {"test.yaml:1", "key 'elevator_deg'", "value '<sequence>'",
                       "has its lower bound above its upper bound", "[lower, upper]"});
}

TEST(ConfigErrors, AngleRangeInRadiansThatLooksLikeDegrees) {
    // Reported as a unit mistake even though the values are also outside the bounds.
    auto m = root("elevator: [-25, 15]\n");
    const auto msg =
        config_error([&] { (void)m.angle_range("elevator", NumberSpec::range(-1.5, 1.5, "rad")); });
    expect_parts(msg, {"test.yaml:1", "key 'elevator'", "is in radians but looks like degrees",
                       "'elevator_deg'"});
}

TEST(ConfigErrors, AngleRangeElementOutOfRange) {
    auto m = root("elevator_deg: [-95, 15]\n");
    const auto msg = config_error([&] {
        (void)m.angle_range("elevator",
                            NumberSpec::range(-1.5707963267948966, 1.5707963267948966, "rad"));
    });
    expect_parts(msg, {"test.yaml:1", "key 'elevator_deg[0]'", "value '-95'", "is out of range",
                       "a number in [-90, 90] [deg]"});
}

TEST(ConfigErrors, MissingAngleRange) {
    auto m = root("a: 1\nelevatr_deg: [-25, 15]\n");
    const auto msg = config_error([&] { (void)m.angle_range("elevator", NumberSpec::any("rad")); });
    expect_parts(msg,
                 {"test.yaml:1", "missing required key 'elevator' (or 'elevator_deg' in degrees)",
                  "found 'elevatr_deg' at line 2"});
}

TEST(ConfigErrors, ChoiceNotInListWithSuggestion) {
    auto m = root("type: lapes\n");
    const auto msg = config_error([&] { (void)m.choice("type", {"lapse", "table"}); });
    expect_parts(msg, {"test.yaml:1", "key 'type'", "value 'lapes'", "is not a valid choice",
                       "one of lapse, table", "did you mean 'lapse'?"});
}

TEST(ConfigErrors, ChoiceNotInListWithoutSuggestion) {
    auto m = root("type: rocket\n");
    const auto msg = config_error([&] { (void)m.choice("type", {"lapse", "table"}); });
    expect_parts(msg, {"value 'rocket'", "one of lapse, table"});
    EXPECT_EQ(msg.find("did you mean"), std::string::npos);
}

TEST(ConfigErrors, YamlSyntaxErrorWithLine) {
    const auto msg =
        config_error([] { (void)ConfigNode::parse_string("a: 1\nb: [1, 2\nc: 3\n", "test.yaml"); });
    expect_parts(msg, {"test.yaml:", "YAML syntax error"});
    // The line is the one yaml-cpp reports for the unterminated flow sequence (2 or later).
    const auto colon = msg.find(':');
    const int line = std::stoi(msg.substr(colon + 1));
    EXPECT_GE(line, 2) << msg;
    EXPECT_LE(line, 4) << msg;
}

TEST(ConfigErrors, YamlBadIndentationWithLine) {
    const auto msg =
        config_error([] { (void)ConfigNode::parse_string("a:\n  b: 1\n c: 2\n", "test.yaml"); });
    expect_parts(msg, {"test.yaml:3:", "YAML syntax error"});
}

TEST(ConfigErrors, DuplicateKey) {
    const auto msg =
        config_error([] { (void)ConfigNode::parse_string("a:\n  b: 1\n  b: 2\n", "test.yaml"); });
    expect_parts(msg,
                 {"test.yaml:3", "key 'a.b'", "appears twice", "first at line 2", "each key once"});
}

TEST(ConfigErrors, ListOfWrongLength) {
    auto m = root("cg: [4.9, 0.0]\n");
    const auto msg = config_error([&] { (void)m.vec3("cg", NumberSpec::any("m")); });
    expect_parts(msg, {"test.yaml:1", "key 'cg'", "value '<sequence>'", "has 2 entries",
                       "a list of 3 numbers, each a number [m]"});
}

TEST(ConfigErrors, ListElementNotANumber) {
    auto m = root("cg: [4.9, y, 0]\n");
    const auto msg = config_error([&] { (void)m.vec3("cg", NumberSpec::any("m")); });
    expect_parts(msg,
                 {"test.yaml:1", "key 'cg[1]'", "value 'y'", "is not a number", "a number [m]"});
}

TEST(ConfigErrors, EmptyList) {
    auto m = root("x: []\ncases: []\n");
    expect_parts(config_error([&] { (void)m.numbers("x", 0, NumberSpec::any("m")); }),
                 {"test.yaml:1", "key 'x'", "value '<sequence>'", "is empty", "a list of numbers"});
    expect_parts(config_error([&] { (void)m.sequence("cases"); }),
                 {"test.yaml:2", "key 'cases'", "is empty", "at least one entry"});
    EXPECT_NO_THROW((void)m.sequence("cases", true));
}

TEST(ConfigErrors, IntegerNotIntegral) {
    auto m = root("schema_version: 1.5\n");
    const auto msg =
        config_error([&] { (void)m.integer("schema_version", NumberSpec::positive("-")); });
    expect_parts(msg, {"test.yaml:1", "key 'schema_version'", "value '1.5'", "is not an integer",
                       "an integer"});
}

TEST(ConfigErrors, IntegerTooLarge) {
    auto m = root("n: 1e30\n");
    const auto msg = config_error([&] { (void)m.integer("n", NumberSpec::any("-")); });
    expect_parts(msg, {"test.yaml:1", "key 'n'", "value '1e30'", "is too large"});
}

TEST(ConfigErrors, Boolean) {
    auto m = root("symmetric: maybe\nflag: [1]\n");
    expect_parts(
        config_error([&] { (void)m.boolean_or("symmetric", true); }),
        {"test.yaml:1", "key 'symmetric'", "value 'maybe'", "is not a boolean", "true or false"});
    expect_parts(config_error([&] { (void)m.boolean_or("flag", true); }),
                 {"test.yaml:2", "key 'flag'", "value '<sequence>'", "is not a boolean"});
    auto ok = root("a: true\nb: True\nc: yes\nd: false\ne: False\nf: no\n");
    for (const char* k : {"a", "b", "c"}) EXPECT_TRUE(ok.boolean_or(k, false)) << k;
    for (const char* k : {"d", "e", "f"}) EXPECT_FALSE(ok.boolean_or(k, true)) << k;
}

TEST(ConfigErrors, NotAMapping) {
    const auto msg =
        config_error([] { (void)ConfigMap(ConfigNode::parse_string("- a\n- b\n", "test.yaml")); });
    expect_parts(msg, {"test.yaml:1", "value '<sequence>'", "is not a mapping", "'key: value'"});
    const auto empty =
        config_error([] { (void)ConfigMap(ConfigNode::parse_string("", "empty.yaml")); });
    expect_parts(empty, {"empty.yaml:1", "value '<empty>'", "is not a mapping"});
}

TEST(ConfigErrors, ExplicitFail) {
    auto m = root("a: 1\nmass: 5\n");
    const auto msg = config_error([&] { m.fail("mass", "is too light", "at least 10 kg"); });
    expect_parts(
        msg, {"test.yaml:2", "key 'mass'", "value '5'", "is too light", "expected at least 10 kg"});
}

TEST(ConfigErrors, FileMissing) {
    try {
        (void)ConfigNode::parse_file("/nonexistent/dir/aircraft.yaml");
        FAIL() << "no error";
    } catch (const manta::IoError& e) {
        expect_parts(e.what(), {"/nonexistent/dir/aircraft.yaml", "cannot open"});
        EXPECT_EQ(e.exit_code(), 2);
    }
}

TEST(ConfigErrors, FileIsADirectory) {
    EXPECT_THROW((void)ConfigNode::parse_file(MANTA_SOURCE_DIR), manta::IoError);
}

TEST(ConfigErrors, ExitCodeIsBadInput) {
    try {
        auto m = root("a: x\n");
        (void)m.number("a", NumberSpec::any("m"));
    } catch (const manta::Error& e) {
        EXPECT_EQ(e.exit_code(), 2);
    }
}

// ------------------------------------------------------------------------------------ helpers

TEST(ConfigHelpers, EditDistance) {
    EXPECT_EQ(manta::core::edit_distance("kitten", "sitting"), 3u);
    EXPECT_EQ(manta::core::edit_distance("", "abc"), 3u);
    EXPECT_EQ(manta::core::edit_distance("Cl_beta", "CL_BETA"), 0u);  // case-insensitive
    EXPECT_EQ(manta::core::edit_distance("chord", "chrod"), 2u);
}

TEST(ConfigHelpers, ClosestMatch) {
    const std::vector<std::string> keys{"area", "span", "chord", "moment_reference"};
    EXPECT_EQ(manta::core::closest_match("aera", keys), "area");
    EXPECT_EQ(manta::core::closest_match("moment_referense", keys), "moment_reference");
    EXPECT_EQ(manta::core::closest_match("xyzzy", keys), "");
    EXPECT_EQ(manta::core::closest_match("x", {}), "");
}

TEST(ConfigHelpers, NumberSpecDescribe) {
    EXPECT_EQ(NumberSpec::positive("m").describe(), "a number > 0 [m]");
    EXPECT_EQ(NumberSpec::non_negative("kg").describe(), "a number >= 0 [kg]");
    EXPECT_EQ(NumberSpec::range(-1, 2.5, "-").describe(), "a number in [-1, 2.5] [-]");
    EXPECT_EQ((NumberSpec{0.0, 1.0, true, false, ""}).describe(), "a number in (0, 1]");
    EXPECT_EQ(NumberSpec::any("").describe(), "a number");
    EXPECT_FALSE(NumberSpec::any("").accepts(std::nan("")));
    EXPECT_FALSE(NumberSpec::any("").accepts(INFINITY));
}

}  // namespace
