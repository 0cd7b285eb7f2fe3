// Gzip-compressed meshes (issue 16, defect 6): an 8.7 MB .su2.gz once grew to 9.3 GB because
// the reader decompressed the whole file into memory before parsing. The SU2 reader now
// streams: it holds one chunk and the current line, stops at the first bad line, and a header's
// count is capped by what the compressed bytes left could hold. Whole-file reads
// (read_maybe_gzipped, the gmsh reader) refuse a compression ratio over 100 past 256 MiB.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <string>

#include "manta/core/error.hpp"
#include "manta/mesh/readers.hpp"

namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / ("manta_gz_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir / name;
}

/// Write `head`, then `blank_mb` MiB of newlines, then `tail`, gzip-compressed.
void write_gz(const fs::path& file, const std::string& head, std::size_t blank_mb,
              const std::string& tail = {}) {
    gzFile g = gzopen(file.string().c_str(), "wb9");
    ASSERT_NE(g, nullptr);
    gzwrite(g, head.data(), static_cast<unsigned>(head.size()));
    const std::string mb(1u << 20, '\n');
    for (std::size_t i = 0; i < blank_mb; ++i)
        gzwrite(g, mb.data(), static_cast<unsigned>(mb.size()));
    if (!tail.empty()) gzwrite(g, tail.data(), static_cast<unsigned>(tail.size()));
    gzclose(g);
}

long peak_rss_mb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss / 1024;
}

std::string error_of(const fs::path& file) {
    try {
        (void)manta::mesh::read_su2(file);
    } catch (const manta::Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "read " << file;
    return {};
}

const std::string small_su2 =
    "NDIME= 2\n"
    "NELEM= 2\n"
    "5 0 1 2 0\n"
    "5 0 2 3 1\n"
    "NPOIN= 4\n"
    "0 0 0\n1 0 1\n1 1 2\n0 1 3\n"
    "NMARK= 1\n"
    "MARKER_TAG= wall\n"
    "MARKER_ELEMS= 4\n"
    "3 0 1\n3 1 2\n3 2 3\n3 3 0\n";

TEST(GzipStream, CompressedMeshReadsAsThePlainOne) {
    const fs::path gz = temp_file("square.su2.gz");
    write_gz(gz, small_su2, 0);
    const auto a = manta::mesh::read_su2(gz);
    const auto b = manta::mesh::parse_su2(small_su2, "square.su2");
    EXPECT_EQ(a.n_cells(), b.n_cells());
    EXPECT_EQ(a.n_nodes(), b.n_nodes());
    // A plain file goes through the same stream.
    const fs::path plain = temp_file("square.su2");
    {
        gzFile g = gzopen(plain.string().c_str(), "wT");  // 'T': written without compression
        gzwrite(g, small_su2.data(), static_cast<unsigned>(small_su2.size()));
        gzclose(g);
    }
    EXPECT_EQ(manta::mesh::read_su2(plain).n_cells(), b.n_cells());
}

TEST(GzipStream, StopsAtTheFirstBadLineWithoutHoldingTheFile) {
    // A bad line 2, then 200 MiB of blank lines (0.2 MB compressed). Before the fix the reader
    // held all 200 MiB before it looked at line 2.
    const fs::path gz = temp_file("bomb.su2.gz");
    write_gz(gz, "NDIME= 3\nthis is not SU2\n", 200);
    const long before = peak_rss_mb();
    const std::string msg = error_of(gz);
    const long grown = peak_rss_mb() - before;
    EXPECT_NE(msg.find("bomb.su2.gz: line 2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("unexpected line 'this is not SU2'"), std::string::npos) << msg;
    EXPECT_LT(grown, 128) << "peak memory grew by " << grown << " MiB reading a 200 MiB stream";
}

TEST(GzipStream, HeaderCountCappedByTheCompressedBytesLeft) {
    // A few hundred compressed bytes cannot hold 10^9 point lines (deflate expands at most
    // 1032 to 1).
    const fs::path gz = temp_file("count.su2.gz");
    write_gz(gz, "NDIME= 3\nNPOIN= 1000000000\n0 0 0\n", 0);
    const std::string msg = error_of(gz);
    EXPECT_NE(msg.find("count.su2.gz: line 2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("NPOIN= = 1000000000, but only"), std::string::npos) << msg;
}

TEST(GzipStream, TruncatedStreamIsAnError) {
    const fs::path gz = temp_file("cut.su2.gz");
    write_gz(gz, small_su2, 0);
    const auto size = fs::file_size(gz);
    fs::resize_file(gz, size - 12);  // drop the gzip trailer and some data
    const std::string msg = error_of(gz);
    EXPECT_NE(msg.find("cut.su2.gz"), std::string::npos) << msg;
}

TEST(GzipStream, WholeFileReadRefusesACompressionBomb) {
    const fs::path gz = temp_file("bomb.msh.gz");
    write_gz(gz, "$MeshFormat\n", 270);
    try {
        (void)manta::mesh::read_maybe_gzipped(gz);
        ADD_FAILURE() << "a 270 MiB expansion of 0.3 MB was read whole";
    } catch (const manta::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("ratio over 100"), std::string::npos) << e.what();
    }
    fs::remove_all(gz.parent_path());
}

}  // namespace
