// Hostile YAML input to the configuration layer (issue 16, defects 3 and 4): alias expansion
// ("billion laughs") must cost time in proportion to the text, and text that is not UTF-8 must
// be refused where it is read, naming file, line, key and byte offset.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "manta/core/config.hpp"
#include "manta/core/error.hpp"
#include "manta/core/utf8.hpp"

namespace {

using manta::ConfigError;
using manta::InputError;
using manta::core::ConfigMap;
using manta::core::ConfigNode;

std::string parse_error(const std::string& text) {
    try {
        (void)ConfigNode::parse_string(text, "hostile.yaml");
    } catch (const ConfigError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected ConfigError for:\n" << text;
    return {};
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << p << " | " << msg;
}

// Ten levels of ten aliases each: 10^10 nodes after expansion from about 100 written. Before the
// fix the duplicate-key check walked every expanded node (minutes); now each node once.
std::string billion_laughs(int levels) {
    std::string s = "l0: &l0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]\n";
    for (int i = 1; i <= levels; ++i) {
        const std::string name = std::to_string(i), prev = std::to_string(i - 1);
        s.append("l").append(name).append(": &l").append(name).append(" [");
        for (int k = 0; k < 10; ++k) s.append(k ? ", *l" : "*l").append(prev);
        s.append("]\n");
    }
    return s;
}

TEST(ConfigHostile, BillionLaughsIsRefusedQuickly) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string msg = parse_error(billion_laughs(10));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    expect_parts(msg, {"hostile.yaml", "aliases", "expand the document", "at most 1000000"});
    // Not a timing test: the old walk took minutes; a linear one takes milliseconds. The bound
    // only catches the exponential walk coming back.
    EXPECT_LT(seconds, 10.0);
}

TEST(ConfigHostile, ModestAliasesAreRead) {
    // Three levels: 1000 expanded scalars, a reasonable use of anchors.
    const ConfigNode n = ConfigNode::parse_string(billion_laughs(3), "ok.yaml");
    EXPECT_EQ(n.child("l3").size(), 10u);
    EXPECT_EQ(n.child("l3").element(9).element(9).element(9).element(0).to_string(), "lol");
    // The same anchor used twice in one mapping is not a repeated key.
    const ConfigNode m =
        ConfigNode::parse_string("base: &b {x: 1, y: 2}\na: *b\nc: *b\n", "ok.yaml");
    EXPECT_EQ(m.child("c").child("y").to_double(), 2.0);
}

TEST(ConfigHostile, RepeatedKeyStillRefusedUnderAnAlias) {
    expect_parts(parse_error("base: &b {x: 1, x: 2}\na: *b\n"),
                 {"hostile.yaml:1", "key 'base.x' appears twice"});
}

TEST(ConfigHostile, NonTextKeyRefused) {
    expect_parts(parse_error("? [a, b]\n: 1\n"), {"hostile.yaml", "list as a key"});
}

TEST(ConfigHostile, Latin1ValueRefusedWithKeyLineAndOffset) {
    // "Caf\xE9" in ISO 8859-1: the 'name' value on line 2; the byte is at file offset 18.
    const std::string text = "mass: 1.0\nname: Caf\xE9\n";
    expect_parts(parse_error(text), {"hostile.yaml:2", "key 'name'", "not valid UTF-8", "0xE9",
                                     "byte offset 3 of the value", "byte offset 19 of the file"});
}

TEST(ConfigHostile, InvalidKeyRefused) {
    expect_parts(parse_error("top:\n  na\xFFme: 1\n"),
                 {"hostile.yaml:2", "key 'top.na\\xFFme'", "not valid UTF-8", "0xFF"});
}

TEST(ConfigHostile, EscapedSurrogateRefused) {
    // Valid ASCII text whose escape names an unpaired surrogate (not encodable in UTF-8):
    // yaml-cpp refuses it itself.
    expect_parts(parse_error("name: \"a\\uD800b\"\n"), {"hostile.yaml:1", "invalid unicode"});
}

TEST(ConfigHostile, InvalidCommentRefused) {
    expect_parts(parse_error("a: 1\n# caf\xE9\n"),
                 {"hostile.yaml:2", "not valid UTF-8", "byte offset 10 of the file"});
}

TEST(ConfigHostile, Utf8TextAccepted) {
    const ConfigNode n = ConfigNode::parse_string("name: Caf\xC3\xA9 \xE2\x82\xAC\n", "ok.yaml");
    EXPECT_EQ(n.child("name").to_string(), "Caf\xC3\xA9 \xE2\x82\xAC");
}

// RFC 3629 and the Unicode Standard, table 3-7: the well-formed sequences.
TEST(Utf8, AcceptsWellFormedAndRejectsTheRest) {
    using manta::core::utf8_invalid_offset;
    constexpr auto npos = std::string_view::npos;
    EXPECT_EQ(utf8_invalid_offset(""), npos);
    EXPECT_EQ(utf8_invalid_offset("plain ascii"), npos);
    EXPECT_EQ(utf8_invalid_offset("\xC3\xA9\xE2\x82\xAC\xF0\x9F\x98\x80\xF4\x8F\xBF\xBF"), npos);
    EXPECT_EQ(utf8_invalid_offset("ab\x80"), 2u);            // lone continuation byte
    EXPECT_EQ(utf8_invalid_offset("\xC0\xAF"), 0u);          // overlong '/'
    EXPECT_EQ(utf8_invalid_offset("\xE0\x80\xAF"), 0u);      // overlong
    EXPECT_EQ(utf8_invalid_offset("x\xED\xA0\x80"), 1u);     // surrogate U+D800
    EXPECT_EQ(utf8_invalid_offset("\xF4\x90\x80\x80"), 0u);  // above U+10FFFF
    EXPECT_EQ(utf8_invalid_offset("\xF5\x80\x80\x80"), 0u);  // invalid lead
    EXPECT_EQ(utf8_invalid_offset("ok\xE2\x82"), 2u);        // truncated at the end
    EXPECT_EQ(utf8_invalid_offset(std::string_view("a\0b", 3)), npos);
    EXPECT_EQ(manta::core::utf8_escaped("Caf\xE9!"), "Caf\\xE9!");
}

TEST(Utf8, RequireNamesLineAndOffset) {
    try {
        manta::core::require_utf8_text("t,x\n1,2\n# caf\xE9\n", "m.csv");
        ADD_FAILURE() << "expected InputError";
    } catch (const InputError& e) {
        expect_parts(e.what(), {"m.csv:3", "0xE9", "byte offset 13"});
    }
}

}  // namespace
