// `manta mesh`: the options and the one-line errors with exit 2 for geometry that cannot be built
// (the meshing itself is tested in tests/meshgen).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string ranger = std::string(MANTA_SOURCE_DIR) + "/examples/ranger2000/aircraft.yaml";

struct Outcome {
    int code = -1;
    std::string out, err;
};

std::string read(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string quote(const std::string& s) {
    std::string q = "'";
    for (const char c : s) {
        if (c == '\'')
            q.append("'\\''");
        else
            q.push_back(c);
    }
    return q + "'";
}

fs::path work_dir() {
    const fs::path dir = fs::temp_directory_path() / "manta_test_cli_mesh";
    fs::create_directories(dir);
    return dir;
}

Outcome mesh(const std::vector<std::string>& args) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string stem = (work_dir() / info->name()).string();
    std::string cmd = quote(MANTA_EXE) + " mesh";
    for (const auto& a : args) cmd.append(" ").append(quote(a));
    cmd.append(" >" + quote(stem + ".out") + " 2>" + quote(stem + ".err"));
    const int status = std::system(cmd.c_str());
    Outcome r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read(stem + ".out");
    r.err = read(stem + ".err");
    return r;
}

/// The Ranger's file with `from` replaced by `to`, written into the work folder.
std::string variant(const std::string& from, const std::string& to) {
    std::string text = read(ranger);
    const auto p = text.find(from);
    if (p == std::string::npos)
        ADD_FAILURE() << "no '" << from << "' in the Ranger's file";
    else
        text.replace(p, from.size(), to);
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path file = work_dir() / (std::string(info->name()) + ".yaml");
    std::ofstream(file) << text;
    return file.string();
}

#define EXPECT_HAS(text, what) \
    EXPECT_NE((text).find(what), std::string::npos) << "'" << (what) << "' not in: " << (text)

void expect_one_line_error(const Outcome& r) {
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace

TEST(CliMesh, Help) {
    const Outcome r = mesh({"--help"});
    EXPECT_EQ(r.code, 0);
    for (const char* o : {"--aircraft", "--model", "--level", "--out", "--json"})
        EXPECT_HAS(r.out, o);
}

TEST(CliMesh, BadOptions) {
    const std::string out = (work_dir() / "x.su2").string();
    EXPECT_EQ(mesh({"--aircraft", ranger, "--model", "quarter", "--out", out}).code, 2);
    EXPECT_EQ(mesh({"--aircraft", ranger, "--level", "finest", "--out", out}).code, 2);
    const Outcome r = mesh({"--aircraft", ranger, "--out", (work_dir() / "x.vtk").string()});
    expect_one_line_error(r);
    EXPECT_HAS(r.err, "--out");
    EXPECT_HAS(r.err, ".su2, .msh or .cgns");
}

TEST(CliMesh, SectionsOutOfOrder) {
    const Outcome r =
        mesh({"--aircraft", variant("[4.6546, 5.23, 0.27409]", "[4.6546, -1.0, 0.27409]"), "--out",
              (work_dir() / "x.su2").string()});
    expect_one_line_error(r);
    EXPECT_HAS(r.err, "geometry.lifting_surfaces[0].sections[1]");
}

TEST(CliMesh, ControlSurfaceInsideTheFuselage) {
    const Outcome r =
        mesh({"--aircraft", variant("span_fraction: [0.55, 0.95]", "span_fraction: [0.0, 0.08]"),
              "--out", (work_dir() / "x.su2").string(), "--json"});
    expect_one_line_error(r);
    EXPECT_HAS(r.err, "geometry.control_surfaces[1].span_fraction");
    EXPECT_HAS(r.err, "'[0, 0.08]'");
    EXPECT_HAS(r.err, "inside the fuselage");
    EXPECT_FALSE(fs::exists(work_dir() / "x.su2"));
}
