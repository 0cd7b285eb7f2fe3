// Tests of the AVL geometry reader: every AVL sample and study case loads, the sample aircraft
// give the values written in their files (after SCALE, TRANSLATE and ANGLE), each keyword does
// what docs/avl-input.md says, and malformed input gives one-line errors naming file and line.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/vlm/avl_reader.hpp"

namespace {

namespace fs = std::filesystem;
using manta::vlm::Model;
using manta::vlm::parse_avl;
using manta::vlm::read_avl;
constexpr double deg = std::numbers::pi / 180.0;

const fs::path avl_dir = fs::path(MANTA_SHARED_DIR) / "reference" / "avl";

#define REQUIRE_AVL_DATA()                                                          \
    do {                                                                            \
        if (!fs::is_directory(avl_dir))                                             \
            GTEST_SKIP() << "AVL reference data not found at " << avl_dir.string(); \
    } while (false)

/// A scratch folder of its own for each test.
class Scratch {
public:
    Scratch() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("manta_avl_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;

    [[nodiscard]] const fs::path& dir() const { return dir_; }
    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path p = dir_ / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }

private:
    fs::path dir_;
};

void expect_parts(const std::string& msg, std::initializer_list<std::string> parts) {
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
    for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
}

/// The header every synthetic file starts with (lines 1 to 5).
const std::string header =
    "Test model\n"
    "0.1\n"
    "0 0 0.0\n"
    "10.0 1.0 10.0\n"
    "0.25 0.0 0.0\n";

/// A plain two-section surface (lines 1 to 4 of the block).
const std::string plain_wing =
    "SURFACE\n"
    "Wing\n"
    "8 1.0 12 1.0\n"
    "SECTION\n"
    "0 0 0 1 0\n"
    "SECTION\n"
    "0 5 0 1 0\n";

Model parse(const std::string& text, std::vector<std::string>* warnings = nullptr,
            const fs::path& base = fs::temp_directory_path()) {
    std::vector<std::string> w;
    Model m = parse_avl(text, "test.avl", base, warnings ? *warnings : w);
    return m;
}

/// InputError message of parsing `text` as "test.avl" (empty if none).
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

std::string io_error(const std::string& text, const fs::path& base) {
    try {
        std::vector<std::string> w;
        (void)parse_avl(text, "test.avl", base, w);
    } catch (const manta::IoError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no IoError for:\n" << text;
    return {};
}

const manta::vlm::Surface& surface(const Model& m, const std::string& name) {
    for (const auto& s : m.surfaces)
        if (s.name == name) return s;
    throw std::runtime_error("no surface " + name);
}

const manta::vlm::SectionControl* control(const manta::vlm::Section& s, const std::string& name) {
    for (const auto& c : s.controls)
        if (c.name == name) return &c;
    return nullptr;
}

// ------------------------------------------------------------------------ reference files

TEST(AvlReader, EverySampleAndCaseParses) {
    REQUIRE_AVL_DATA();
    int n = 0;
    for (const char* folder : {"samples", "cases"}) {
        for (const auto& e : fs::directory_iterator(avl_dir / folder)) {
            if (e.path().extension() != ".avl") continue;
            SCOPED_TRACE(e.path().string());
            std::vector<std::string> warnings;
            Model m;
            EXPECT_NO_THROW(m = read_avl(e.path(), warnings));
            EXPECT_FALSE(m.surfaces.empty());
            for (const auto& s : m.surfaces) {
                EXPECT_GE(s.sections.size(), 2u) << s.name;
                for (const auto& sec : s.sections) EXPECT_GT(sec.chord, 0.0) << s.name;
            }
            ++n;
        }
    }
    EXPECT_GE(n, 20);
}

TEST(AvlReader, AvlSampleAirfoilFilesLoad) {
    REQUIRE_AVL_DATA();
    for (const char* name :
         {"sd7037.dat", "a1.dat", "ag40d.dat", "ag41d.dat", "ag42d.dat", "ag43d.dat"}) {
        SCOPED_TRACE(name);
        Scratch tmp;
        const std::string text = header + "SURFACE\nW\n4 1.0 4 1.0\nSECTION\n0 0 0 1 0\nAFILE\n" +
                                 (avl_dir / "samples" / name).string() + "\nSECTION\n0 1 0 1 0\n";
        const Model m = parse(text);
        ASSERT_TRUE(m.surfaces[0].sections[0].airfoil.has_value());
        const auto& a = *m.surfaces[0].sections[0].airfoil;
        EXPECT_FALSE(a.is_naca());
        EXPECT_GT(a.thickness_ratio(), 0.03);
        EXPECT_LT(a.thickness_ratio(), 0.2);
    }
}

TEST(AvlReader, B737) {
    REQUIRE_AVL_DATA();
    std::vector<std::string> warnings;
    const Model m = read_avl(avl_dir / "samples" / "b737.avl", warnings);
    EXPECT_EQ(m.name, "Boeing 737-800");
    EXPECT_DOUBLE_EQ(m.mach, 0.78);
    EXPECT_EQ(m.y_symmetry, 0);
    EXPECT_EQ(m.z_symmetry, 0);
    EXPECT_DOUBLE_EQ(m.reference.area, 1260.0);
    EXPECT_DOUBLE_EQ(m.reference.chord, 11.0);
    EXPECT_DOUBLE_EQ(m.reference.span, 113.0);
    EXPECT_DOUBLE_EQ(m.reference.point.x(), 60.0);
    EXPECT_DOUBLE_EQ(m.profile_drag, 0.0);

    // 7 defined surfaces, 4 of them duplicated: the 11 surfaces AVL reports.
    ASSERT_EQ(m.surfaces.size(), 7u);
    int duplicated = 0;
    for (const auto& s : m.surfaces) duplicated += s.y_duplicate.has_value() ? 1 : 0;
    EXPECT_EQ(duplicated, 4);
    EXPECT_EQ(m.surfaces.size() + static_cast<std::size_t>(duplicated), 11u);
    for (const auto& s : m.surfaces) EXPECT_EQ(s.component, 1) << s.name;
    EXPECT_TRUE(m.bodies.empty());

    const auto names = m.control_names();
    for (const char* c : {"aileron", "elevator", "rudder", "flap", "slat"})
        EXPECT_NE(std::find(names.begin(), names.end(), c), names.end()) << c;
    EXPECT_EQ(names.size(), 5u);

    const auto& wing = surface(m, "Wing");
    EXPECT_EQ(wing.n_chord, 12);
    EXPECT_DOUBLE_EQ(wing.chord_spacing, 1.0);
    EXPECT_EQ(wing.n_span, 26);
    EXPECT_DOUBLE_EQ(wing.span_spacing, -1.1);
    ASSERT_TRUE(wing.y_duplicate.has_value());
    EXPECT_DOUBLE_EQ(*wing.y_duplicate, 0.0);
    ASSERT_EQ(wing.sections.size(), 7u);
    // Section 2: "2.167 10.0 6.0 18.333 0.0" with SCALE 1 1 0.07 and TRANSLATE 50 0 0.
    const auto& s2 = wing.sections[1];
    EXPECT_NEAR(s2.leading_edge.x(), 52.167, 1e-12);
    EXPECT_NEAR(s2.leading_edge.y(), 10.0, 1e-12);
    EXPECT_NEAR(s2.leading_edge.z(), 0.42, 1e-12);
    EXPECT_NEAR(s2.chord, 18.333, 1e-12);
    EXPECT_NEAR(wing.sections[0].incidence, 5.0 * deg, 1e-12);
    EXPECT_NEAR(wing.sections[2].incidence, 3.0 * deg, 1e-12);
    ASSERT_TRUE(s2.airfoil.has_value());
    EXPECT_EQ(s2.airfoil->name(), "N+3 A1 (visc. decam.)");
    const auto* slat = control(wing.sections[0], "slat");
    ASSERT_NE(slat, nullptr);
    EXPECT_DOUBLE_EQ(slat->gain, -1.0);
    EXPECT_DOUBLE_EQ(slat->hinge_chord_fraction, -0.05);
    EXPECT_TRUE(slat->hinge_axis.isZero());
    EXPECT_DOUBLE_EQ(slat->duplicate_sign, 1.0);
    const auto* aileron = control(wing.sections[3], "aileron");
    ASSERT_NE(aileron, nullptr);
    EXPECT_DOUBLE_EQ(aileron->gain, -1.0);
    EXPECT_DOUBLE_EQ(aileron->hinge_chord_fraction, 0.80);
    EXPECT_DOUBLE_EQ(aileron->duplicate_sign, -1.0);

    // Stab section 2: "2.00 6.0 6.0 11.5 0. 1 0." with SCALE 1 1 0.17, TRANSLATE 110 0 6.
    const auto& stab = surface(m, "Stab");
    const auto& t2 = stab.sections[1];
    EXPECT_NEAR(t2.leading_edge.x(), 112.0, 1e-12);
    EXPECT_NEAR(t2.leading_edge.y(), 6.0, 1e-12);
    EXPECT_NEAR(t2.leading_edge.z(), 6.0 + 6.0 * 0.17, 1e-12);
    EXPECT_EQ(t2.n_span, 1);
    EXPECT_DOUBLE_EQ(t2.span_spacing, 0.0);
    EXPECT_EQ(stab.sections[0].n_span, 0);

    // Nacelle: SCALE 1 4 3.5, TRANSLATE 45 16 -4 on "0.00 0.5 0.866 12.5".
    const auto& nacelle = surface(m, "Nacelle");
    EXPECT_NEAR(nacelle.sections[1].leading_edge.y(), 16.0 + 4.0 * 0.5, 1e-12);
    EXPECT_NEAR(nacelle.sections[1].leading_edge.z(), -4.0 + 3.5 * 0.866, 1e-12);

    const auto& fus = surface(m, "Fuselage H");
    EXPECT_EQ(fus.n_span, 0);
    EXPECT_EQ(fus.sections[0].n_span, 1);
    EXPECT_TRUE(fus.sheds_wake);
    EXPECT_FALSE(surface(m, "Fuselage V Bottom").sheds_wake);
    EXPECT_FALSE(surface(m, "Fin").y_duplicate.has_value());
    EXPECT_TRUE(warnings.empty()) << warnings.front();
}

TEST(AvlReader, Vanilla) {
    REQUIRE_AVL_DATA();
    std::vector<std::string> warnings;
    const Model m = read_avl(avl_dir / "samples" / "vanilla.avl", warnings);
    EXPECT_EQ(m.name, "Plane Vanilla");
    ASSERT_EQ(m.surfaces.size(), 3u);
    EXPECT_EQ(m.control_names(),
              (std::vector<std::string>{"flap", "aileron", "elevator", "rudder"}));
    const auto& wing = surface(m, "Wing");
    for (const auto& sec : wing.sections) {
        EXPECT_DOUBLE_EQ(sec.lift_slope_factor, 1.0);
        EXPECT_NEAR(sec.incidence, 2.0 * deg, 1e-12);  // ANGLE 2.0
        ASSERT_TRUE(sec.airfoil.has_value());
        EXPECT_EQ(sec.airfoil->name(), "SD7037");
    }
    EXPECT_NEAR(wing.sections[1].leading_edge.z(), 1.0, 1e-12);
    const auto& stab = surface(m, "H-stab");
    EXPECT_NEAR(stab.sections[1].leading_edge.x(), 4.14, 1e-12);
    const auto* elevator = control(stab.sections[0], "elevator");
    ASSERT_NE(elevator, nullptr);
    EXPECT_TRUE(elevator->hinge_axis.isApprox(Eigen::Vector3d(0.0, 1.0, 0.0)));
    EXPECT_DOUBLE_EQ(elevator->hinge_chord_fraction, 0.7);
    EXPECT_FALSE(surface(m, "V-stab").y_duplicate.has_value());
    EXPECT_TRUE(warnings.empty());
}

TEST(AvlReader, SupraBodyAndIndex) {
    REQUIRE_AVL_DATA();
    std::vector<std::string> warnings;
    const Model m = read_avl(avl_dir / "samples" / "supra.avl", warnings);
    EXPECT_DOUBLE_EQ(m.profile_drag, 0.015);
    EXPECT_DOUBLE_EQ(m.reference.area, 1034.0);
    EXPECT_DOUBLE_EQ(m.reference.point.z(), 1.5);
    ASSERT_EQ(m.bodies.size(), 1u);
    const auto& body = m.bodies[0];
    EXPECT_EQ(body.name, "Fuse pod");
    ASSERT_EQ(body.axis.size(), body.radius.size());
    ASSERT_GE(body.axis.size(), 50u);
    EXPECT_NEAR(body.axis.front().x(), -16.5, 1e-9);  // nose of fuseSupra.dat
    EXPECT_NEAR(body.axis.back().x(), 51.0, 1e-9);    // end of the boom
    for (std::size_t i = 1; i < body.axis.size(); ++i)
        EXPECT_GT(body.axis[i].x(), body.axis[i - 1].x());
    EXPECT_NEAR(body.radius.back(), 0.25, 1e-9);     // boom: +-0.25
    EXPECT_NEAR(body.axis.back().z(), -1.75, 1e-9);  // TRANSLATE 0 0 -1.75
    const double rmax = *std::max_element(body.radius.begin(), body.radius.end());
    EXPECT_GT(rmax, 1.0);
    EXPECT_LT(rmax, 2.0);

    const auto& inner = surface(m, "Inner Wing");
    const auto& outer = surface(m, "Outer Wing");
    EXPECT_EQ(inner.component, 1);
    EXPECT_EQ(outer.component, 1);
    EXPECT_NE(surface(m, "Stab").component, 1);
    EXPECT_NEAR(inner.sections[0].incidence, 1.0 * deg, 1e-12);  // ANGLE 1.0
    EXPECT_NEAR(outer.sections[1].incidence, 0.5 * deg, 1e-12);  // -0.5 + 1.0
    EXPECT_NEAR(outer.sections[1].leading_edge.z(), 1.37655 + 23.5 * 0.13165, 1e-12);
    EXPECT_EQ(inner.sections[0].airfoil->name(), "AG40d");
    EXPECT_EQ(inner.n_span, 8);
    EXPECT_DOUBLE_EQ(inner.span_spacing, -2.9);
    const auto& fin = surface(m, "Fin");
    EXPECT_NEAR(fin.sections[0].chord, 7.0 * 1.15, 1e-12);
    // DESIGN is read and ignored with one warning.
    ASSERT_EQ(warnings.size(), 1u);
    expect_parts(warnings[0], {"supra.avl:", "DESIGN", "ignored", "times"});
}

TEST(AvlReader, NulBytesAreWhitespace) {
    REQUIRE_AVL_DATA();
    std::ifstream in(avl_dir / "samples" / "vanilla.avl", std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.insert(text.find("SURFACE"), std::string(300, '\0'));
    text += std::string(200, '\0');
    std::vector<std::string> w;
    const Model m = parse_avl(text, "vanilla.avl", avl_dir / "samples", w);
    EXPECT_EQ(m.surfaces.size(), 3u);
}

// ------------------------------------------------------------------------ keywords

TEST(AvlReader, HeaderAndComments) {
    const std::string text =
        "# leading comment\n"
        "\n"
        "My plane ! remark\n"
        "0.3                 Mach\n"
        "  1 -1 -0.5         iYsym iZsym Zsym\n"
        "! comment\n"
        "12.0, 1.5, 8.0\n"
        "0.4 0.1 0.2\n"
        "0.02                CDp\n" +
        plain_wing;
    const Model m = parse(text);
    EXPECT_EQ(m.name, "My plane");
    EXPECT_DOUBLE_EQ(m.mach, 0.3);
    EXPECT_EQ(m.y_symmetry, 1);
    EXPECT_EQ(m.z_symmetry, -1);
    EXPECT_DOUBLE_EQ(m.z_symmetry_plane, -0.5);
    EXPECT_DOUBLE_EQ(m.reference.area, 12.0);
    EXPECT_DOUBLE_EQ(m.reference.chord, 1.5);
    EXPECT_DOUBLE_EQ(m.reference.span, 8.0);
    EXPECT_TRUE(m.reference.point.isApprox(Eigen::Vector3d(0.4, 0.1, 0.2)));
    EXPECT_DOUBLE_EQ(m.profile_drag, 0.02);
    // Without the CDp line it is zero.
    EXPECT_DOUBLE_EQ(parse(header + plain_wing).profile_drag, 0.0);
}

TEST(AvlReader, WindowsLineEndsTabsAndCommaLines) {
    const std::string unix_text = header + ",\t,\n" + "\tSURFACE\t\n" + plain_wing.substr(8);
    std::string text;
    for (char c : unix_text) text += c == '\n' ? std::string("\r\n") : std::string(1, c);
    const Model m = parse(text);
    ASSERT_EQ(m.surfaces.size(), 1u);
    EXPECT_EQ(m.surfaces[0].name, "Wing");
    EXPECT_DOUBLE_EQ(m.surfaces[0].sections[1].leading_edge.y(), 5.0);
}

TEST(AvlReader, SurfaceDefaultsAndKeywordCase) {
    const Model m = parse(header +
                          "surf\n"
                          "Tail plane\n"
                          "6 -2.0 ! 10 1.0 (commented out)\n"
                          "sectIONS  extra words\n"
                          "1 0 0 2 3 4 -1.5\n"
                          "Sect\n"
                          "1 3 0 1 -1 0 0\n");
    ASSERT_EQ(m.surfaces.size(), 1u);
    const auto& s = m.surfaces[0];
    EXPECT_EQ(s.name, "Tail plane");
    EXPECT_EQ(s.n_chord, 6);
    EXPECT_DOUBLE_EQ(s.chord_spacing, -2.0);
    EXPECT_EQ(s.n_span, 0);
    EXPECT_DOUBLE_EQ(s.span_spacing, 0.0);
    EXPECT_TRUE(s.sheds_wake);
    EXPECT_FALSE(s.y_duplicate.has_value());
    EXPECT_EQ(s.component, 1);
    EXPECT_EQ(s.sections[0].n_span, 4);
    EXPECT_DOUBLE_EQ(s.sections[0].span_spacing, -1.5);
    EXPECT_NEAR(s.sections[0].incidence, 3.0 * deg, 1e-15);
    EXPECT_NEAR(s.sections[1].incidence, -1.0 * deg, 1e-15);
    EXPECT_FALSE(s.sections[0].airfoil.has_value());
    EXPECT_DOUBLE_EQ(s.sections[0].lift_slope_factor, 1.0);
}

TEST(AvlReader, ScaleTranslateAngle) {
    // SCALE, TRANSLATE and ANGLE act on the whole surface, wherever they appear in its block.
    const Model m = parse(header +
                          "SURFACE\nWing\n8 1.0 10 1.0\n"
                          "SCALE\n2.0 3.0 0.5\n"
                          "SECTION\n1 2 4 1.5 1.0\n"
                          "SECTION\n2 4 8 0.5 -1.0\n"
                          "TRANSLATE\n10 -1 0.25\n"
                          "ANGLE\n2.5\n");
    const auto& s = m.surfaces[0];
    EXPECT_TRUE(s.sections[0].leading_edge.isApprox(Eigen::Vector3d(12.0, 5.0, 2.25)));
    EXPECT_TRUE(s.sections[1].leading_edge.isApprox(Eigen::Vector3d(14.0, 11.0, 4.25)));
    EXPECT_DOUBLE_EQ(s.sections[0].chord, 3.0);  // chords scale with Xscale
    EXPECT_DOUBLE_EQ(s.sections[1].chord, 1.0);
    EXPECT_NEAR(s.sections[0].incidence, 3.5 * deg, 1e-15);
    EXPECT_NEAR(s.sections[1].incidence, 1.5 * deg, 1e-15);
}

TEST(AvlReader, YduplicateNowakeComponent) {
    std::vector<std::string> warnings;
    const Model m = parse(header + plain_wing +
                              "YDUPLICATE\n0.5\n"
                              "COMPONENT\n3\n"
                              "NOWAKE\n"
                              "NOALBE\n"
                              "NOLOAD\n"
                              "SURFACE\nFin\n4 1.0 4 1.0\n"
                              "INDEX\n3\n"
                              "SECTION\n0 0 0 1 0\nSECTION\n0 0 1 1 0\n",
                          &warnings);
    ASSERT_EQ(m.surfaces.size(), 2u);
    const auto& w = m.surfaces[0];
    ASSERT_TRUE(w.y_duplicate.has_value());
    EXPECT_DOUBLE_EQ(*w.y_duplicate, 0.5);
    EXPECT_EQ(w.component, 3);
    EXPECT_FALSE(w.sheds_wake);
    EXPECT_EQ(m.surfaces[1].component, 3);
    EXPECT_TRUE(m.surfaces[1].sheds_wake);
    ASSERT_EQ(warnings.size(), 2u);
    expect_parts(warnings[0], {"test.avl:18: NOALBE: ignored"});
    expect_parts(warnings[1], {"test.avl:19: NOLOAD: ignored"});
}

TEST(AvlReader, DefaultComponentIsTheSurfaceNumber) {
    // As in AVL, mirror copies count: the third surface follows a duplicated one.
    const Model m = parse(header + plain_wing + plain_wing + "YDUPLICATE\n0\n" + plain_wing);
    EXPECT_EQ(m.surfaces[0].component, 1);
    EXPECT_EQ(m.surfaces[1].component, 2);
    EXPECT_EQ(m.surfaces[2].component, 4);
}

TEST(AvlReader, Naca) {
    const Model m = parse(header +
                          "SURFACE\nWing\n8 1.0 12 1.0\n"
                          "SECTION\n0 0 0 1 0\nNACA\n4412\n"
                          "SECTION\n0 5 0 1 0\nNACA\n4300\n"
                          "SECTION\n0 6 0 1 0\nNACA 0.0 0.5\n2412\n");
    const auto& s = m.surfaces[0].sections;
    ASSERT_TRUE(s[0].airfoil.has_value());
    EXPECT_TRUE(s[0].airfoil->is_naca());
    EXPECT_EQ(s[0].airfoil->designation().text, "NACA 4412");
    EXPECT_NEAR(s[0].airfoil->camber(0.4), 0.04, 1e-12);
    // Zero thickness (AVL's own example) is accepted; the mean line is that of 43xx.
    EXPECT_NEAR(s[1].airfoil->camber(0.3), 0.04, 1e-12);
    // x/c range 0..0.5 of a 2412: the front half, stretched to a unit chord.
    ASSERT_TRUE(s[2].airfoil.has_value());
    const auto ref = manta::geometry::Airfoil::naca("NACA 2412");
    EXPECT_NEAR(s[2].airfoil->camber(0.8), ref.camber(0.4) / 0.5, 2e-4);
    EXPECT_NEAR(s[2].airfoil->camber_slope(0.4), ref.camber_slope(0.2), 2e-3);
}

TEST(AvlReader, InlineAirfoilIsNormalisedAndOriented) {
    // A NACA 2412 contour at twice the chord, shifted, and listed lower surface first: AVL
    // accepts it, so must the reader.
    const auto ref = manta::geometry::Airfoil::naca("NACA 2412");
    auto pts = ref.coordinates(41);
    std::string text = header +
                       "SURFACE\nWing\n8 1.0 12 1.0\n"
                       "SECTION\n0 0 0 1 0\n"
                       "AIRFOIL\n";
    for (auto it = pts.rbegin(); it != pts.rend(); ++it)
        text +=
            std::to_string(2.0 * it->x() + 0.3) + " " + std::to_string(2.0 * it->y() - 0.1) + "\n";
    text += "CLAF\n1.1\nSECTION\n0 5 0 1 0\n";
    const Model m = parse(text);
    const auto& s = m.surfaces[0].sections;
    ASSERT_EQ(s.size(), 2u);  // the coordinates end at the next keyword
    ASSERT_TRUE(s[0].airfoil.has_value());
    for (double x : {0.1, 0.3, 0.5, 0.8})
        EXPECT_NEAR(s[0].airfoil->camber_slope(x), ref.camber_slope(x), 0.01) << x;
    EXPECT_NEAR(s[0].airfoil->thickness_ratio(), 0.12, 0.005);
    EXPECT_DOUBLE_EQ(s[0].lift_slope_factor, 1.1);
}

TEST(AvlReader, AfileRelativeToTheFileAndNormalisedWhenNeeded) {
    Scratch tmp;
    fs::create_directories(tmp.dir() / "foils");
    // Chord 3 with the leading edge at x = -1: the Airfoil parser wants unit chords, AVL does not.
    const auto ref = manta::geometry::Airfoil::naca("NACA 4412");
    std::string foil = "Big 4412\n";
    for (const auto& p : ref.coordinates(41))
        foil += std::to_string(3.0 * p.x() - 1.0) + " " + std::to_string(3.0 * p.y()) + "\n";
    tmp.write("foils/big.dat", foil);
    const auto avl = tmp.write("model.avl", header +
                                                "SURFACE\nWing\n8 1.0 12 1.0\n"
                                                "SECTION\n0 0 0 1 0\nAFILE\nfoils/big.dat\n"
                                                "SECTION\n0 5 0 1 0\nAFILE 0.5 1.0\n"
                                                "\"foils/big.dat\"\n");
    std::vector<std::string> warnings;
    const Model m = read_avl(avl, warnings);
    const auto& s = m.surfaces[0].sections;
    ASSERT_TRUE(s[0].airfoil.has_value());
    EXPECT_EQ(s[0].airfoil->name(), "Big 4412");
    EXPECT_NEAR(s[0].airfoil->camber(0.4), 0.04, 1e-3);
    ASSERT_TRUE(s[1].airfoil.has_value());
    EXPECT_NEAR(s[1].airfoil->camber_slope(0.5), ref.camber_slope(0.75), 5e-3);
    EXPECT_TRUE(warnings.empty());
}

TEST(AvlReader, Control) {
    const Model m = parse(header +
                          "SURFACE\nWing\n8 1.0 12 1.0\n"
                          "SECTION\n0 0 0 1 0\n"
                          "CONTROL\nFlap  0.5 0.7 0 1 0 1  ! name gain Xhinge XYZhvec SgnDup\n"
                          "CONTROL\nAileron -1.0 0.75 0. 0. 0. -1\n"
                          "CONTROL\nslat -1 -0.1\n"
                          "SECTION\n0 5 0 1 0\n"
                          "CONTROL\nwarp\n");
    const auto& s = m.surfaces[0].sections;
    ASSERT_EQ(s[0].controls.size(), 3u);
    const auto& flap = s[0].controls[0];
    EXPECT_EQ(flap.name, "flap");
    EXPECT_DOUBLE_EQ(flap.gain, 0.5);
    EXPECT_DOUBLE_EQ(flap.hinge_chord_fraction, 0.7);
    EXPECT_TRUE(flap.hinge_axis.isApprox(Eigen::Vector3d(0, 1, 0)));
    EXPECT_DOUBLE_EQ(flap.duplicate_sign, 1.0);
    EXPECT_EQ(s[0].controls[1].name, "aileron");
    EXPECT_DOUBLE_EQ(s[0].controls[1].duplicate_sign, -1.0);
    EXPECT_DOUBLE_EQ(s[0].controls[2].hinge_chord_fraction, -0.1);
    EXPECT_TRUE(s[0].controls[2].hinge_axis.isZero());
    EXPECT_DOUBLE_EQ(s[0].controls[2].duplicate_sign, 1.0);
    // Only a name: AVL's defaults (gain 1, hinge at the leading edge, SgnDup 1).
    const auto& warp = s[1].controls.at(0);
    EXPECT_DOUBLE_EQ(warp.gain, 1.0);
    EXPECT_DOUBLE_EQ(warp.hinge_chord_fraction, 0.0);
    EXPECT_EQ(m.control_names(), (std::vector<std::string>{"flap", "aileron", "slat", "warp"}));
}

TEST(AvlReader, IgnoredKeywordsWarnOncePerKeyword) {
    std::vector<std::string> warnings;
    const Model m = parse(header +
                              "SURFACE\nWing\n8 1.0 12 1.0\n"
                              "SECTION\n0 0 0 1 0\n"
                              "CDCL\n-0.5 0.02 0.3 0.01 1.2 0.03\n"
                              "DESIGN\ntwist 1.0\n"
                              "CLAF\n2.5\n"
                              "SECTION\n0 5 0 1 0\n"
                              "CDCL\n-0.5 0.02 0.3 0.01 1.2 0.03\n"
                              "DESIGN\ntwist 0.5\n",
                          &warnings);
    EXPECT_DOUBLE_EQ(m.surfaces[0].sections[0].lift_slope_factor, 1.0);
    ASSERT_EQ(warnings.size(), 3u);
    expect_parts(warnings[0], {"test.avl:16: CLAF", "(0, 2)"});
    expect_parts(warnings[1], {"test.avl:11: CDCL: ignored (2 times"});
    expect_parts(warnings[2], {"test.avl:13: DESIGN: ignored (2 times"});
}

TEST(AvlReader, OtherWarnings) {
    std::vector<std::string> warnings;
    const Model m = parse(
        "T\n0\n1 0 0\n0 1 1\n0 0 0\n"
        "SURFACE\nWing\n8 1.0 6\n"
        "YDUPLICATE\n0\n"
        "SECTION\n0 0 0 1 0 4 1.0\n"
        "SECTION\n0 5 0 1 0 4\n",
        &warnings);
    EXPECT_DOUBLE_EQ(m.reference.area, 1.0);  // Sref 0 replaced, as AVL does
    EXPECT_EQ(m.y_symmetry, 1);
    EXPECT_EQ(m.surfaces[0].n_span, 0);
    ASSERT_EQ(warnings.size(), 4u);
    expect_parts(warnings[0], {"test.avl:4: header: Sref = 0"});
    expect_parts(warnings[1], {"test.avl:8: SURFACE: Nspan given without Sspace"});
    expect_parts(warnings[2], {"test.avl:9: YDUPLICATE:", "IYsym"});
    expect_parts(warnings[3], {"test.avl:14: SECTION: Nspan given without Sspace"});
}

TEST(AvlReader, BodyFromBfile) {
    Scratch tmp;
    // A side view: nose at x = 0, tail at x = 4, centre line at z = 0.5, radius 1 at x = 2.
    tmp.write("pod.dat", "pod\n4 0.6\n2 1.5\n0 0.5\n2 -0.5\n4 0.4\n");
    const Model m = parse(header +
                              "BODY\nPod\n20 1.0\n"
                              "SCALE\n2 1 1\nTRANSLATE\n1 0 -1\nYDUPLICATE\n3.0\n"
                              "BFILE\npod.dat\n" +
                              plain_wing,
                          nullptr, tmp.dir());
    ASSERT_EQ(m.bodies.size(), 1u);
    const auto& b = m.bodies[0];
    EXPECT_EQ(b.name, "Pod");
    ASSERT_EQ(b.axis.size(), 3u);
    EXPECT_TRUE(b.axis[0].isApprox(Eigen::Vector3d(1.0, 0.0, -0.5)));
    EXPECT_TRUE(b.axis[1].isApprox(Eigen::Vector3d(5.0, 0.0, -0.5)));
    EXPECT_TRUE(b.axis[2].isApprox(Eigen::Vector3d(9.0, 0.0, -0.5)));
    EXPECT_DOUBLE_EQ(b.radius[0], 0.0);
    EXPECT_DOUBLE_EQ(b.radius[1], 1.0);
    EXPECT_DOUBLE_EQ(b.radius[2], 0.1);
    ASSERT_TRUE(b.y_duplicate.has_value());
    EXPECT_DOUBLE_EQ(*b.y_duplicate, 3.0);
    EXPECT_EQ(m.surfaces.size(), 1u);
}

// ------------------------------------------------------------------------ errors

TEST(AvlReaderErrors, SectionNumbers) {
    // Line 10 is the SECTION data line.
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0\nSECTION\nabc 0 0 1 0\n"),
                 {"test.avl:10: SECTION: expected 5 numbers (Xle Yle Zle Chord Ainc", "'abc'"});
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0\nSECTION\n0 0 0 1\n"),
                 {"test.avl:10: SECTION:", "got 4 in '0 0 0 1'"});
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0\nSECTION\n"),
                 {"test.avl:9: SECTION:", "end of the file"});
}

TEST(AvlReaderErrors, SurfaceShape) {
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0 4 1.0\nSECTION\n0 0 0 1 0\n"),
                 {"test.avl:6: SURFACE: 'Wing' has 1 SECTION; expected at least 2"});
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0 4 1.0\nSECTION\n0 0 0 0 0\n"
                                      "SECTION\n0 1 0 1 0\n"),
                 {"test.avl:10: SECTION: Chord = 0; expected a chord > 0"});
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0 4 1.0\nSECTION\n0 0 0 -2 0\n"
                                      "SECTION\n0 1 0 1 0\n"),
                 {"test.avl:10: SECTION: Chord = -2"});
    expect_parts(input_error(header + "SURFACE\nWing\n0 1.0 4 1.0\n"),
                 {"test.avl:8: SURFACE: Nchord = 0; expected at least 1"});
    expect_parts(input_error(header + "SURFACE\nWing\n2.5 1.0 4 1.0\n"),
                 {"test.avl:8: SURFACE: Nchord = 2.5", "expected an integer"});
    expect_parts(input_error(header + "SURFACE\nWing\n8 4.0 4 1.0\n"),
                 {"test.avl:8: SURFACE: Cspace = 4", "[-3, 3]"});
    // No spanwise count anywhere.
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0\nSECTION\n0 0 0 1 0\n"
                                      "SECTION\n0 1 0 1 0\n"),
                 {"test.avl:9: SECTION: no spanwise vortex count", "Nspan"});
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0 4 1.0\nSCALE\n0 1 1\n"),
                 {"test.avl:10: SCALE: Xscale = 0"});
}

TEST(AvlReaderErrors, KeywordsAndPlacement) {
    expect_parts(input_error(header + plain_wing + "WINGLET\n1\n"),
                 {"test.avl:13: keyword: unknown keyword 'WINGLET'", "SURFACE"});
    expect_parts(input_error(header + "SECTION\n0 0 0 1 0\n"),
                 {"test.avl:6: SECTION: outside a SURFACE block"});
    expect_parts(input_error(header + "SURFACE\nWing\n8 1.0 4 1.0\nCONTROL\nflap 1 0.7\n"),
                 {"test.avl:9: CONTROL: before the first SECTION of SURFACE 'Wing'"});
    expect_parts(input_error(header + "BODY\nPod\n10 1.0\nNOWAKE\n"),
                 {"test.avl:9: NOWAKE: inside BODY 'Pod'"});
    expect_parts(input_error(header + plain_wing + "BFILE\npod.dat\n"),
                 {"test.avl:13: BFILE: outside a BODY block"});
    expect_parts(input_error(header + "BODY\nPod\n10 1.0\n" + plain_wing),
                 {"test.avl:6: BODY: 'Pod' has no BFILE"});
    expect_parts(input_error(header), {"test.avl:5: end of file: no SURFACE"});
    expect_parts(input_error(""), {"test.avl:1: header: the file is empty"});
}

TEST(AvlReaderErrors, Values) {
    expect_parts(input_error("T\nfast\n0 0 0\n1 1 1\n0 0 0\n" + plain_wing),
                 {"test.avl:2: header: expected 1 number (Mach), got 'fast'"});
    expect_parts(input_error("T\n0\n0 0\n1 1 1\n0 0 0\n" + plain_wing),
                 {"test.avl:3: header: expected 3 numbers (IYsym IZsym Zsym)"});
    expect_parts(input_error(header + plain_wing + "YDUPLICATE\nzero\n"),
                 {"test.avl:14: YDUPLICATE: expected 1 number (Ydupl), got 'zero'"});
    expect_parts(input_error(header + plain_wing + "TRANSLATE\n1 2\n"),
                 {"test.avl:14: TRANSLATE: expected 3 numbers (dX dY dZ)"});
    expect_parts(input_error(header + plain_wing + "NACA\n12345\n"),
                 {"test.avl:14: NACA: '12345' is not a NACA 4-digit designation"});
    expect_parts(input_error(header + plain_wing + "NACA\n2012\n"),
                 {"test.avl:14: NACA:", "NACA 2012"});
    expect_parts(input_error(header + plain_wing + "NACA\n2412 0.5 0.2\n"),
                 {"test.avl:14: NACA: x/c range 0.5 to 0.2"});
    expect_parts(input_error(header + plain_wing + "CONTROL\nflap 1 1.5\n"),
                 {"test.avl:14: CONTROL: Xhinge = 1.5"});
    expect_parts(input_error(header + plain_wing + "CONTROL\nflap 1 0.7 0 1\n"),
                 {"test.avl:14: CONTROL: the hinge vector has 2 of 3 components"});
    expect_parts(input_error(header + plain_wing + "CONTROL\n1.0 0.7\n"),
                 {"test.avl:14: CONTROL: control name '1.0' is a number"});
    expect_parts(
        input_error(header + plain_wing + "AIRFOIL\n1 0\n0 0\n1 0\n"),
        {"test.avl:13: AIRFOIL: inline coordinates: has 3 coordinate points", "at least 7"});
}

TEST(AvlReaderErrors, MissingFiles) {
    Scratch tmp;
    expect_parts(io_error(header + plain_wing + "AFILE\nnone.dat\n", tmp.dir()),
                 {"test.avl:14: AFILE: cannot read", "none.dat"});
    expect_parts(
        io_error(header + "BODY\nPod\n10 1.0\nBFILE\n\"no body.dat\"\n" + plain_wing, tmp.dir()),
        {"test.avl:10: BFILE: cannot read", "no body.dat"});
    EXPECT_THROW((void)read_avl(tmp.dir() / "absent.avl"), manta::IoError);
    // A coordinate file that is not an airfoil even after normalisation.
    tmp.write("bad.dat", "bad\n0 0\n1 0\nx y\n");
    expect_parts(input_error(header + plain_wing + "AFILE\nbad.dat\n", tmp.dir()),
                 {"test.avl:14: AFILE:", "bad.dat"});
}

}  // namespace
