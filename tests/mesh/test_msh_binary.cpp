/// @file test_msh_binary.cpp
/// Binary gmsh MSH files: boxes written by the gmsh API in binary MSH 4.1 and 2.2 read to the
/// same mesh as the ASCII file; a tetrahedron encoded here (gmsh reference manual, "MSH file
/// format", binary layout of version 4.1) in both byte orders and with 4- and 8-byte size_t;
/// truncated and inconsistent binary files give one-line errors naming the byte offset.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "gmsh_fixtures.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/mesh/readers.hpp"
#include "metrics_checks.hpp"

namespace manta::mesh {
namespace {

namespace fs = std::filesystem;

std::string box_name(test::BoxKind k) {
    return k == test::BoxKind::tets ? "tets" : k == test::BoxKind::prisms ? "prisms" : "hexes";
}

class BinaryBox : public ::testing::TestWithParam<test::BoxKind> {};

TEST_P(BinaryBox, BinaryAndAsciiGiveTheSameMesh) {
    const fs::path dir = test::scratch_dir("msh-binary");
    const double lx = 1.0, ly = 0.75, lz = 0.5, h = 0.25;
    test::make_box(GetParam(), lx, ly, lz, h, {dir / "a41.msh"});
    test::make_box(GetParam(), lx, ly, lz, h, {dir / "b41.msh"}, 4.1, true);
    test::make_box(GetParam(), lx, ly, lz, h, {dir / "b22.msh"}, 2.2, true);
    ASSERT_EQ(core::read_file(dir / "b41.msh").substr(12, 8), "4.1 1 8\n");  // really binary
    const Mesh a = read_mesh(dir / "a41.msh");
    for (const char* name : {"b41.msh", "b22.msh"}) {
        SCOPED_TRACE(name);
        const Mesh b = read_mesh(dir / name);
        ASSERT_EQ(b.n_nodes(), a.n_nodes());
        EXPECT_EQ(b.n_cells(), a.n_cells());
        EXPECT_EQ(b.n_faces(), a.n_faces());
        // Same markers with the same faces (MSH 2.2 lists the groups in another order).
        std::map<std::string, int> fa, fb;
        for (Index f = 0; f < a.n_faces(); ++f) ++fa[a.markers()[a.face_marker(f)]];
        for (Index f = 0; f < b.n_faces(); ++f) ++fb[b.markers()[b.face_marker(f)]];
        EXPECT_EQ(fb, fa);
        double dmax = 0.0;  // ASCII writes 16 significant digits
        for (Index i = 0; i < a.n_nodes(); ++i)
            dmax = std::max(dmax, (b.node(i) - a.node(i)).norm());
        EXPECT_LT(dmax, 1e-14);
        for (Index c = 0; c < a.n_cells(); ++c)
            ASSERT_TRUE(std::equal(a.cell(c).begin(), a.cell(c).end(), b.cell(c).begin()));
        test::check_dual(b, lx * ly * lz);
    }
}

INSTANTIATE_TEST_SUITE_P(Msh, BinaryBox,
                         ::testing::Values(test::BoxKind::tets, test::BoxKind::prisms,
                                           test::BoxKind::hexes),
                         [](const auto& info) { return box_name(info.param); });

/// Encodes binary MSH 4.1 values in a chosen byte order and size_t width.
struct Encoder {
    bool swap;
    int size_bytes;
    std::string out;

    template <class T>
    void put(T v) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (swap) std::reverse(b, b + sizeof(T));
        out.append(b, sizeof(T));
    }
    void i(int v) { put<std::int32_t>(v); }
    void z(std::uint64_t v) {
        if (size_bytes == 4)
            put<std::uint32_t>(static_cast<std::uint32_t>(v));
        else
            put<std::uint64_t>(v);
    }
    void d(double v) { put<double>(v); }
    void text(const std::string& s) { out += s; }
};

/// The unit tetrahedron (1/6 m^3) with its four faces on the marker "wall", binary MSH 4.1.
std::string tetra_msh41(bool swap, int size_bytes, std::uint64_t nodes_announced = 4) {
    Encoder e{swap, size_bytes, {}};
    e.text("$MeshFormat\n4.1 1 " + std::to_string(size_bytes) + "\n");
    e.i(1);
    e.text("\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"wall\"\n$EndPhysicalNames\n$Entities\n");
    for (std::uint64_t n : {0, 0, 1, 1}) e.z(n);
    for (int dim : {2, 3}) {
        e.i(1);                                          // entity tag
        for (int k = 0; k < 6; ++k) e.d(k < 3 ? 0 : 1);  // bounding box
        e.z(dim == 2 ? 1 : 0);                           // physical tags
        if (dim == 2) e.i(1);
        e.z(0);  // bounding entities
    }
    e.text("\n$EndEntities\n$Nodes\n");
    for (std::uint64_t n : {std::uint64_t{1}, nodes_announced, std::uint64_t{1}, std::uint64_t{4}})
        e.z(n);
    e.i(3);
    e.i(1);
    e.i(0);
    e.z(4);
    for (int t = 1; t <= 4; ++t) e.z(static_cast<std::uint64_t>(t));
    const double x[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto& p : x)
        for (double c : p) e.d(c);
    e.text("\n$EndNodes\n$Elements\n");
    for (std::uint64_t n : {2, 5, 1, 5}) e.z(n);
    e.i(3);
    e.i(1);
    e.i(4);  // tetrahedra
    e.z(1);
    for (std::uint64_t n : {1, 1, 2, 3, 4}) e.z(n);
    e.i(2);
    e.i(1);
    e.i(2);  // triangles
    e.z(4);
    const std::uint64_t tri[4][3] = {{1, 3, 2}, {1, 2, 4}, {2, 3, 4}, {1, 4, 3}};
    for (std::uint64_t t = 0; t < 4; ++t) {
        e.z(t + 2);
        for (auto n : tri[t]) e.z(n);
    }
    e.text("\n$EndElements\n");
    return e.out;
}

TEST(MshBinary, BothByteOrdersAndSizeWidths) {
    for (bool swap : {false, true})
        for (int size_bytes : {4, 8}) {
            SCOPED_TRACE(::testing::Message() << "swap " << swap << " size_t " << size_bytes);
            const Mesh m = parse_gmsh(tetra_msh41(swap, size_bytes), "t.msh");
            EXPECT_EQ(m.n_nodes(), 4);
            EXPECT_EQ(m.n_cells(), 1);
            EXPECT_EQ(m.n_faces(), 4);
            ASSERT_EQ(m.n_markers(), 1);
            EXPECT_EQ(m.markers()[0], "wall");
            EXPECT_NEAR(m.volume(), 1.0 / 6.0, 1e-15);
            test::check_dual(m, 1.0 / 6.0);
        }
}

/// Every prefix of a binary file, and wrong counts, give one-line InputErrors.
TEST(MshBinary, TruncatedAndInconsistentFiles) {
    const fs::path dir = test::scratch_dir("msh-binary");
    test::make_box(test::BoxKind::prisms, 1.0, 0.5, 0.5, 0.25, {dir / "t41.msh"}, 4.1, true);
    test::make_box(test::BoxKind::prisms, 1.0, 0.5, 0.5, 0.25, {dir / "t22.msh"}, 2.2, true);
    for (const std::string& text :
         {tetra_msh41(false, 8), tetra_msh41(true, 4), core::read_file(dir / "t41.msh"),
          core::read_file(dir / "t22.msh")}) {
        int errors = 0, runs = 0;
        for (std::size_t cut = 0; cut + 1 < text.size(); cut += 1 + text.size() / 400) {
            ++runs;
            try {
                (void)parse_gmsh(text.substr(0, cut), "x.msh");
                ADD_FAILURE() << "no error at cut " << cut;
            } catch (const InputError& e) {
                ++errors;
                const std::string w = e.what();
                EXPECT_EQ(w.find('\n'), std::string::npos) << w;
                EXPECT_TRUE(w.starts_with("x.msh: ")) << w;
            }
        }
        EXPECT_EQ(errors, runs);
    }
    // A truncated node section names the byte where the data ran out.
    const std::string t = tetra_msh41(false, 8);
    const std::size_t cut = t.find("$EndNodes") - 20;
    try {
        (void)parse_gmsh(t.substr(0, cut), "x.msh");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("x.msh: byte "), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("truncated file"), std::string::npos) << e.what();
    }
    // A node count larger than the data.
    try {
        (void)parse_gmsh(tetra_msh41(false, 8, 400), "x.msh");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("number of nodes = 400, but only"), std::string::npos)
            << e.what();
    }
    // A header announcing 3 nodes for a block of 4.
    try {
        (void)parse_gmsh(tetra_msh41(false, 8, 3), "x.msh");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(
            std::string(e.what()).find("the node blocks hold 4 nodes; the header announced 3"),
            std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace manta::mesh
