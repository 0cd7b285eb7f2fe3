/// @file fuzz_cgns.cpp
/// libFuzzer target for the CGNS reader: the input bytes are written to a scratch file (the
/// CGNS library reads only files) and given to `mesh::read_cgns`, which must either give a
/// finalized mesh or a `manta::Error` (docs/fuzzing.md).
///
/// Two modes, by the input's first bytes:
/// - an input starting with the HDF5 signature is written as it is: the raw container (libcgns
///   and Debian's HDF5, not instrumented, parse it; mutations of a binary HDF5 file rarely get
///   past HDF5's own checks, so this mode mostly tests that failures there come back as
///   errors). Other raw inputs (ADF, garbage) reach the library only with MANTA_FUZZ_CGNS_ANY=1:
///   the library may crash inside itself on them, which MANTA cannot guard.
/// - any other input is decoded (FuzzedDataProvider) into the *content* of a CGNS file that
///   libcgns then writes as a well-formed container: a base of cell dimension 2 or 3, one or two
///   zones, structured or unstructured, with hostile sizes, coordinates, element sections
///   (types, ranges, node numbers), boundary conditions (point ranges and lists, locations) and
///   family names. This reaches MANTA's reader logic with coverage feedback.

#include <unistd.h>

#include <cgnslib.h>
#include <fuzzer/FuzzedDataProvider.h>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fuzz_mesh_check.hpp"
#include "manta/core/error.hpp"
#include "manta/mesh/readers.hpp"

// libcgns 3.4 and HDF5 1.10 keep small allocations when cg_open fails on a damaged file (the
// library's own error path, after MANTA's reader has closed what it opened); not MANTA's leaks.
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libcgns\nleak:libhdf5\n";
}

namespace {

/// Scratch file of this fuzzing process (libFuzzer's -jobs/-fork workers are processes).
const std::filesystem::path& scratch_file() {
    static const std::filesystem::path file = [] {
        const std::filesystem::path shm("/dev/shm");
        const auto dir =
            std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
        return dir / ("manta-fuzz-cgns-" + std::to_string(static_cast<long>(getpid())) + ".cgns");
    }();
    return file;
}

/// The 8-byte HDF5 superblock signature at offset 0 (HDF5 File Format Specification, sec. II.A;
/// files with a user block put it at 512, 1024, ... which CGNS never writes).
bool has_hdf5_signature(const std::uint8_t* data, std::size_t size) {
    static constexpr char signature[] = "\x89HDF\r\n\x1a\n";
    return size >= 8 && std::memcmp(data, signature, 8) == 0;
}

/// Closes the CGNS file being written on every path.
struct Writer {
    int fn = -1;
    ~Writer() {
        if (fn >= 0) cg_close(fn);
    }
};

/// Write a CGNS file whose content is decoded from the fuzzer's bytes; false if libcgns itself
/// refuses the content (nothing to read then).
bool write_decoded(FuzzedDataProvider& in, const std::string& file) {
    Writer w;
    if (cg_open(file.c_str(), CG_MODE_WRITE, &w.fn) != CG_OK) return false;
    const int cell_dim = in.ConsumeIntegralInRange(1, 3);
    int B = 0;
    if (cg_base_write(w.fn, "Base", cell_dim, 3, &B) != CG_OK) return false;
    const bool structured = in.ConsumeBool();
    const int n_zones = in.ConsumeIntegralInRange(1, 2);
    for (int zi = 0; zi < n_zones; ++zi) {
        int Z = 0, C = 0;
        std::vector<cgsize_t> size;
        cgsize_t n_nodes = 1;
        if (structured) {
            std::vector<cgsize_t> n(static_cast<std::size_t>(cell_dim));
            for (auto& v : n) {
                v = in.ConsumeIntegralInRange<cgsize_t>(1, 5);
                n_nodes *= v;
            }
            size = n;
            for (auto v : n)
                size.push_back(v > 1 ? v - 1 : in.ConsumeIntegralInRange<cgsize_t>(0, 1));
            for (std::size_t d = 0; d < n.size(); ++d) size.push_back(0);
        } else {
            n_nodes = in.ConsumeIntegralInRange<cgsize_t>(1, 40);
            size = {n_nodes, in.ConsumeIntegralInRange<cgsize_t>(0, 40), 0};
        }
        const std::string zname = "Zone" + std::to_string(zi + 1);
        if (cg_zone_write(w.fn, B, zname.c_str(), size.data(),
                          structured ? CGNS_ENUMV(Structured) : CGNS_ENUMV(Unstructured),
                          &Z) != CG_OK)
            return false;
        // Coordinates on a coarse lattice (coincident and degenerate nodes likely), sometimes
        // one axis missing.
        const char* axes[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
        const int n_axes = in.ConsumeIntegralInRange(1, 3);
        for (int a = 0; a < n_axes; ++a) {
            std::vector<double> x(static_cast<std::size_t>(n_nodes));
            for (auto& v : x) v = 0.5 * in.ConsumeIntegralInRange(-4, 4);
            if (in.ConsumeIntegralInRange(0, 15) == 0) x[0] = in.ConsumeFloatingPoint<double>();
            if (cg_coord_write(w.fn, B, Z, CGNS_ENUMV(RealDouble), axes[a], x.data(), &C) != CG_OK)
                return false;
        }
        if (!structured) {
            static constexpr CGNS_ENUMT(ElementType_t) types[] = {
                CGNS_ENUMV(NODE),     CGNS_ENUMV(BAR_2),  CGNS_ENUMV(TRI_3),   CGNS_ENUMV(QUAD_4),
                CGNS_ENUMV(TETRA_4),  CGNS_ENUMV(PYRA_5), CGNS_ENUMV(PENTA_6), CGNS_ENUMV(HEXA_8),
                CGNS_ENUMV(TETRA_10), CGNS_ENUMV(MIXED)};
            const int n_sections = in.ConsumeIntegralInRange(0, 3);
            cgsize_t next = 1;
            for (int si = 0; si < n_sections; ++si) {
                const auto type = in.PickValueInArray(types);
                const cgsize_t start =
                    in.ConsumeBool() ? next : in.ConsumeIntegralInRange<cgsize_t>(-1, 50);
                const cgsize_t count = in.ConsumeIntegralInRange<cgsize_t>(1, 12);
                const cgsize_t end = start + count - 1;
                next = end + 1;
                std::vector<cgsize_t> conn, offsets{0};
                for (cgsize_t e = 0; e < count; ++e) {
                    auto t = type;
                    if (type == CGNS_ENUMV(MIXED)) {
                        t = in.PickValueInArray(types);
                        if (t == CGNS_ENUMV(MIXED)) t = CGNS_ENUMV(TETRA_4);
                        conn.push_back(t);
                    }
                    int npe = 0;
                    if (cg_npe(t, &npe) != CG_OK || npe <= 0) return false;
                    for (int k = 0; k < npe; ++k)
                        conn.push_back(in.ConsumeIntegralInRange<cgsize_t>(0, n_nodes + 1));
                    offsets.push_back(static_cast<cgsize_t>(conn.size()));
                }
                const std::string sname = "Section" + std::to_string(si + 1);
                int S = 0;
                const int rc = type == CGNS_ENUMV(MIXED)
                                   ? cg_poly_section_write(w.fn, B, Z, sname.c_str(), type, start,
                                                           end, 0, conn.data(), offsets.data(), &S)
                                   : cg_section_write(w.fn, B, Z, sname.c_str(), type, start, end,
                                                      0, conn.data(), &S);
                if (rc != CG_OK) return false;
            }
        }
        // Boundary conditions: point ranges or lists of vertices, faces or elements.
        const int n_bocos = in.ConsumeIntegralInRange(0, 4);
        for (int bi = 0; bi < n_bocos; ++bi) {
            const bool range = in.ConsumeBool();
            const int n_index = structured ? cell_dim : 1;
            const cgsize_t n_points = range ? 2 : in.ConsumeIntegralInRange<cgsize_t>(1, 8);
            std::vector<cgsize_t> pts(static_cast<std::size_t>(n_points * n_index));
            for (auto& v : pts) v = in.ConsumeIntegralInRange<cgsize_t>(-1, 8);
            const std::string bname = "bc" + std::to_string(bi + 1);
            int BC = 0;
            if (cg_boco_write(w.fn, B, Z, bname.c_str(), CGNS_ENUMV(BCWall),
                              range ? CGNS_ENUMV(PointRange) : CGNS_ENUMV(PointList), n_points,
                              pts.data(), &BC) != CG_OK)
                return false;
            static constexpr CGNS_ENUMT(GridLocation_t) locations[] = {
                CGNS_ENUMV(Vertex),      CGNS_ENUMV(FaceCenter),  CGNS_ENUMV(IFaceCenter),
                CGNS_ENUMV(JFaceCenter), CGNS_ENUMV(KFaceCenter), CGNS_ENUMV(CellCenter)};
            if (in.ConsumeBool() &&
                cg_boco_gridlocation_write(w.fn, B, Z, BC, in.PickValueInArray(locations)) != CG_OK)
                return false;
            if (in.ConsumeBool()) {
                if (cg_goto(w.fn, B, "Zone_t", Z, "ZoneBC_t", 1, "BC_t", BC, "end") != CG_OK)
                    return false;
                const std::string family = in.ConsumeBool() ? "" : "family";
                if (cg_famname_write(family.c_str()) != CG_OK) return false;
            }
        }
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool any = std::getenv("MANTA_FUZZ_CGNS_ANY") != nullptr;
    if (has_hdf5_signature(data, size) || any) {
        std::ofstream out(scratch_file(), std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    } else {
        FuzzedDataProvider in(data, size);
        if (!write_decoded(in, scratch_file().string())) return 0;
    }
    try {
        manta::fuzz::check_mesh(manta::mesh::read_cgns(scratch_file()));
    } catch (const manta::Error&) {
        // A one-line input error: the expected outcome for malformed input.
    }
    return 0;
}
