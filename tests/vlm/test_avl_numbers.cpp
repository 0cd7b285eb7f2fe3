// Defect 7 of issue 16: every numeric field of an AVL geometry file rejects NaN, infinity, numbers
// beyond the range of a double and implausible magnitudes with a one-line InputError naming the
// file, the line, the keyword and the value. Before the fix a NaN in an optional field ended the
// list of numbers there, so "CONTROL / flap 1 nan" put the hinge at the leading edge (the whole
// chord deflected, exit 0), and "ANGLE / -1e308" was taken as given.

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/vlm/avl_reader.hpp"

namespace {

namespace fs = std::filesystem;
using manta::vlm::parse_avl;

/// Lines 1 to 5.
const std::string header =
    "Test model\n"
    "0.1\n"
    "0 0 0.0\n"
    "10.0 1.0 10.0\n"
    "0.25 0.0 0.0\n";

/// Lines 6 to 12: a plain wing; the line after it is 13, its data line 14.
const std::string wing =
    "SURFACE\n"
    "Wing\n"
    "8 1.0 12 1.0\n"
    "SECTION\n"
    "0 0 0 1 0\n"
    "SECTION\n"
    "0 5 0 1 0\n";

std::string input_error(const std::string& text, const fs::path& base = fs::temp_directory_path()) {
    try {
        std::vector<std::string> w;
        (void)parse_avl(text, "test.avl", base, w);
    } catch (const manta::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return {};
}

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
    for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

struct Case {
    std::string text;
    std::string where;  // "test.avl:LINE: KEYWORD"
    std::string value;  // the offending word as written
};

/// Every non-finite spelling in every numeric field of the file.
TEST(AvlReaderNumbers, NonFiniteValuesAreErrors) {
    const std::string sec1 = "SURFACE\nWing\n8 1.0 12 1.0\nSECTION\n";  // data line 10
    const std::string sec2 = "SECTION\n0 5 0 1 0\n";
    std::vector<Case> cases = {
        // header
        {"T\nnan\n0 0 0\n10 1 10\n0 0 0\n" + wing, "test.avl:2: header", "'nan'"},
        {"T\n0\n0 0 inf\n10 1 10\n0 0 0\n" + wing, "test.avl:3: header", "'inf'"},
        {"T\n0\n0 0 0\nNaN 1 10\n0 0 0\n" + wing, "test.avl:4: header", "'NaN'"},
        {"T\n0\n0 0 0\n10 1 -Infinity\n0 0 0\n" + wing, "test.avl:4: header", "'-Infinity'"},
        {"T\n0\n0 0 0\n10 1 10\n0.25 nan 0\n" + wing, "test.avl:5: header", "'nan'"},
        {"T\n0\n0 0 0\n10 1 10\n0.25 0 0\nnan\n" + wing, "test.avl:6: header", "'nan'"},
        {"T\n0\n0 0 0\n10 1 10\n0.25 0 0\n1e999\n" + wing, "test.avl:6: header", "'1e999'"},
        // SURFACE counts and spacings
        {header + "SURFACE\nWing\nnan 1.0 12 1.0\n", "test.avl:8: SURFACE", "'nan'"},
        {header + "SURFACE\nWing\n8 1.0 12 nan\n", "test.avl:8: SURFACE", "'nan'"},
        {header + "SURFACE\nWing\n8 1.0 inf 1.0\n", "test.avl:8: SURFACE", "'inf'"},
        // SECTION: coordinates, chord, incidence and the optional Nspan Sspace
        {header + sec1 + "nan 0 0 1 0\n" + sec2, "test.avl:10: SECTION", "'nan'"},
        {header + sec1 + "0 0 0 inf 0\n" + sec2, "test.avl:10: SECTION", "'inf'"},
        {header + sec1 + "0 0 0 1 nan\n" + sec2, "test.avl:10: SECTION", "'nan'"},
        {header + sec1 + "0 0 0 1 0 nan 1\n" + sec2, "test.avl:10: SECTION", "'nan'"},
        {header + sec1 + "0 0 0 1 0 8 -inf\n" + sec2, "test.avl:10: SECTION", "'-inf'"},
        {header + sec1 + "0 0 0 1 0 8 1D999\n" + sec2, "test.avl:10: SECTION", "'1D999'"},
        // CONTROL: gain, Xhinge, hinge vector, SgnDup (the defect's example first)
        {header + wing + "CONTROL\nflap 1 nan\n", "test.avl:14: CONTROL", "'nan'"},
        {header + wing + "CONTROL\nflap nan 0.7\n", "test.avl:14: CONTROL", "'nan'"},
        {header + wing + "CONTROL\nflap 1 0.7 nan 0 0 1\n", "test.avl:14: CONTROL", "'nan'"},
        {header + wing + "CONTROL\nflap 1 0.7 0 inf 0 1\n", "test.avl:14: CONTROL", "'inf'"},
        {header + wing + "CONTROL\nflap 1 0.7 0 0 0 nan\n", "test.avl:14: CONTROL", "'nan'"},
        {header + wing + "CONTROL\nflap 1 0.7 0 0 0 -inf\n", "test.avl:14: CONTROL", "'-inf'"},
        // surface keywords
        {header + wing + "ANGLE\nnan\n", "test.avl:14: ANGLE", "'nan'"},
        {header + wing + "SCALE\n1 nan 1\n", "test.avl:14: SCALE", "'nan'"},
        {header + wing + "TRANSLATE\n0 inf 0\n", "test.avl:14: TRANSLATE", "'inf'"},
        {header + wing + "YDUPLICATE\nnan\n", "test.avl:14: YDUPLICATE", "'nan'"},
        {header + wing + "COMPONENT\nnan\n", "test.avl:14: COMPONENT", "'nan'"},
        // section keywords
        {header + wing + "CLAF\nnan\n", "test.avl:14: CLAF", "'nan'"},
        {header + wing + "CDCL\n0 0.01 nan 0.01 1 0.02\n", "test.avl:14: CDCL", "'nan'"},
        {header + wing + "DESIGN\ntwist nan\n", "test.avl:14: DESIGN", "'nan'"},
        {header + wing + "NACA 0 nan\n2412\n", "test.avl:13: NACA", "'nan'"},
        {header + wing + "NACA\n2412 0 inf\n", "test.avl:14: NACA", "'inf'"},
        {header + wing + "AIRFOIL\n1 0\n0.5 nan\n0 0\n0.5 -0.01\n1 0\n", "test.avl:15: AIRFOIL",
         "'nan'"},
        // BODY
        {header + "BODY\nPod\nnan 1.0\n", "test.avl:8: BODY", "'nan'"},
        {header + "BODY\nPod\n10 inf\n", "test.avl:8: BODY", "'inf'"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        expect_parts(input_error(c.text), {c.where, c.value, "not a finite number"});
    }
}

/// Finite numbers far outside what the field can mean.
TEST(AvlReaderNumbers, ImplausibleMagnitudesAreErrors) {
    const std::string sec1 = "SURFACE\nWing\n8 1.0 12 1.0\nSECTION\n";
    const std::string sec2 = "SECTION\n0 5 0 1 0\n";
    const std::vector<Case> cases = {
        {header + wing + "ANGLE\n-1e308\n", "test.avl:14: ANGLE", "dAinc = -1e+308"},
        {header + wing + "ANGLE\n720\n", "test.avl:14: ANGLE", "dAinc = 720"},
        {header + sec1 + "0 0 0 1 400\n" + sec2, "test.avl:10: SECTION", "Ainc = 400"},
        {header + sec1 + "1e300 0 0 1 0\n" + sec2, "test.avl:10: SECTION", "Xle = 1e+300"},
        {header + sec1 + "0 0 -1e9 1 0\n" + sec2, "test.avl:10: SECTION", "Zle = -1e+09"},
        {header + sec1 + "0 0 0 1e300 0\n" + sec2, "test.avl:10: SECTION", "Chord = 1e+300"},
        {header + sec1 + "0 0 0 1 0 100000 1\n" + sec2, "test.avl:10: SECTION", "Nspan = 100000"},
        {header + "SURFACE\nWing\n1000000 1.0\n", "test.avl:8: SURFACE", "Nchord = 1000000"},
        {header + "SURFACE\nWing\n8 1.0 50000 1.0\n", "test.avl:8: SURFACE", "Nspan = 50000"},
        {header + wing + "CONTROL\nflap 1e300 0.7\n", "test.avl:14: CONTROL", "gain = 1e+300"},
        {header + wing + "CONTROL\nflap 1 0.7 1e300 0 0\n", "test.avl:14: CONTROL",
         "Xhvec = 1e+300"},
        {header + wing + "CONTROL\nflap 1 0.7 0 0 0 -1e300\n", "test.avl:14: CONTROL",
         "SgnDup = -1e+300"},
        {header + wing + "SCALE\n1 1e300 1\n", "test.avl:14: SCALE", "Yscale = 1e+300"},
        {header + wing + "TRANSLATE\n0 0 1e300\n", "test.avl:14: TRANSLATE", "dZ = 1e+300"},
        {header + wing + "YDUPLICATE\n1e300\n", "test.avl:14: YDUPLICATE", "Ydupl = 1e+300"},
        {header + wing + "CLAF\n1e300\n", "test.avl:14: CLAF", "CLaf = 1e+300"},
        {header + wing + "CDCL\n0 0.01 0.5 1e300 1 0.02\n", "test.avl:14: CDCL", "CD2 = 1e+300"},
        {header + wing + "DESIGN\ntwist 1e300\n", "test.avl:14: DESIGN", "Wdes = 1e+300"},
        {"T\n0\n0 0 1e300\n10 1 10\n0 0 0\n" + wing, "test.avl:3: header", "Zsym = 1e+300"},
        {"T\n0\n0 0 0\n1e300 1 10\n0 0 0\n" + wing, "test.avl:4: header", "Sref = 1e+300"},
        {"T\n0\n0 0 0\n10 1e300 10\n0 0 0\n" + wing, "test.avl:4: header", "Cref = 1e+300"},
        {"T\n0\n0 0 0\n10 1 10\n-1e300 0 0\n" + wing, "test.avl:5: header", "Xref = -1e+300"},
        {"T\n0\n0 0 0\n10 1 10\n0 0 0\n1e300\n" + wing, "test.avl:6: header", "CDp = 1e+300"},
        {header + "BODY\nPod\n100000 1.0\n", "test.avl:8: BODY", "Nbody = 100000"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        expect_parts(input_error(c.text), {c.where, c.value, "expected"});
    }
}

/// Coordinate files named by AFILE and BFILE: the error names that file and its line.
TEST(AvlReaderNumbers, CoordinateFilesRejectNonFiniteValues) {
    const fs::path dir =
        fs::temp_directory_path() / ("manta_avl_numbers_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "nan.dat") << "Bad foil\n1 0\n0.5 0.05\n0 nan\n0.5 -0.02\n1 0\n";
    std::ofstream(dir / "inf_body.dat") << "Pod\n10 0\n5 1\n0 inf\n5 -1\n10 0\n";
    expect_parts(input_error(header + wing + "AFILE\nnan.dat\n", dir),
                 {"nan.dat:4", "'nan'", "not a finite number"});
    expect_parts(input_error(header + "BODY\nPod\n10 1.0\nBFILE\ninf_body.dat\n" + wing, dir),
                 {"inf_body.dat:4", "'inf'", "not a finite number"});
    std::error_code ec;
    fs::remove_all(dir, ec);
}

/// The bounds leave every value of AVL's own samples (b737 in feet, supra in inches) inside.
TEST(AvlReaderNumbers, PlausibleValuesStillRead) {
    std::vector<std::string> w;
    const auto m = parse_avl(header +
                                 "SURFACE\nWing\n8 1.0 12 1.0\nANGLE\n-179\nSCALE\n1000 1 1\n"
                                 "SECTION\n-99999 0 0 50000 10 20 1\n"
                                 "CONTROL\nflap -2 0.7 0 1 0 -1\n"
                                 "SECTION\n0 5 0 1 0\n",
                             "test.avl", fs::temp_directory_path(), w);
    ASSERT_EQ(m.surfaces.size(), 1u);
    EXPECT_EQ(m.surfaces[0].sections[0].n_span, 20);
    EXPECT_DOUBLE_EQ(m.surfaces[0].sections[0].controls.at(0).gain, -2.0);
}

}  // namespace
