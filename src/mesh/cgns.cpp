/// @file cgns.cpp
/// CGNS reader through the CGNS mid-level library (CGNS Mid-Level Library manual, v3.4; node
/// order of the SIDS, "Element Numbering Conventions"). Every zone of the first base, structured
/// or unstructured; zones are joined where their exposed nodes coincide.

#include <cgnslib.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "detail/raw.hpp"
#include "manta/core/error.hpp"

namespace manta::mesh {

namespace {

using detail::RawType;

/// Closes the file on every path out.
struct CgnsFile {
    int fn = -1;
    ~CgnsFile() {
        if (fn >= 0) cg_close(fn);
    }
};

/// CGNS element type -> kind; false for types this reader does not take.
bool cgns_type(CGNS_ENUMT(ElementType_t) t, RawType& out) {
    switch (t) {
        case CGNS_ENUMV(BAR_2):
            out = RawType::line;
            return true;
        case CGNS_ENUMV(TRI_3):
            out = RawType::triangle;
            return true;
        case CGNS_ENUMV(QUAD_4):
            out = RawType::quad;
            return true;
        case CGNS_ENUMV(TETRA_4):
            out = RawType::tetra;
            return true;
        case CGNS_ENUMV(PYRA_5):
            out = RawType::pyramid;
            return true;
        case CGNS_ENUMV(PENTA_6):
            out = RawType::prism;
            return true;
        case CGNS_ENUMV(HEXA_8):
            out = RawType::hexa;
            return true;
        default:
            return false;
    }
}

struct Boundary {
    RawType type;
    std::array<Index, 4> nodes;
    std::int64_t element;
    int section;
    int marker = -1;
};

/// The marker of a boundary condition: its FamilyName if it has one (multi-block grids group
/// the patches of one boundary so), else its own name.
std::string bc_marker(int fn, int Z, int b, const char* bcname) {
    char family[33] = {};
    if (cg_goto(fn, 1, "Zone_t", Z, "ZoneBC_t", 1, "BC_t", b, "end") == CG_OK &&
        cg_famname_read(family) == CG_OK && family[0] != '\0')
        return family;
    return bcname;
}

/// Add one structured zone (cells as hexahedra or, in 2-D, quadrilaterals; boundary conditions
/// given as point ranges or point lists, as faces) to `raw`; cells are numbered on from
/// `serial` (i fastest), which is advanced past them.
void add_structured_zone(int fn, int Z, int cell_dim, int phys_dim, const std::string& src,
                         detail::RawMesh& raw, std::int64_t& serial) {
    const auto check = [&src](int rc, const std::string& where) {
        if (rc != CG_OK) throw InputError(fmt::format("{}: {}: {}", src, where, cg_get_error()));
    };
    char zname[33] = {};
    cgsize_t size[9] = {};
    check(cg_zone_read(fn, 1, Z, zname, size), fmt::format("zone {}", Z));
    const std::string zone = fmt::format("zone '{}'", zname);
    std::array<cgsize_t, 3> nv{1, 1, 1};
    for (int d = 0; d < cell_dim; ++d) {
        nv[d] = size[d];
        if (nv[d] < 2)
            throw InputError(
                fmt::format("{}: {} has {} vertices in direction {}; expected at "
                            "least 2",
                            src, zone, nv[d], d + 1));
    }
    const cgsize_t total = nv[0] * nv[1] * nv[2];
    if (total + static_cast<cgsize_t>(raw.x.size() / 3) > std::numeric_limits<Index>::max())
        throw InputError(fmt::format("{}: {} makes the mesh too large", src, zone));
    const auto offset = static_cast<Index>(raw.x.size() / 3);
    raw.x.resize(raw.x.size() + 3 * static_cast<std::size_t>(total), 0.0);
    {
        std::vector<double> c(static_cast<std::size_t>(total));
        cgsize_t rmin[3] = {1, 1, 1}, rmax[3] = {nv[0], nv[1], nv[2]};
        const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
        for (int k = 0; k < std::min(phys_dim, 3); ++k) {
            check(cg_coord_read(fn, 1, Z, names[k], CGNS_ENUMV(RealDouble), rmin, rmax, c.data()),
                  fmt::format("{} {}", zone, names[k]));
            for (cgsize_t i = 0; i < total; ++i) raw.x[3 * (offset + i) + k] = c[i];
        }
    }
    const auto id = [&](cgsize_t i, cgsize_t j, cgsize_t k) {
        return offset + static_cast<Index>(i + nv[0] * (j + nv[1] * k));
    };
    const auto p = [&raw](Index n) {
        return Eigen::Vector3d(raw.x[3 * n], raw.x[3 * n + 1], raw.x[3 * n + 2]);
    };
    // Handedness of the (i, j, k) system from the first cell: left-handed blocks are reversed.
    const Eigen::Vector3d ei = p(id(1, 0, 0)) - p(id(0, 0, 0));
    const Eigen::Vector3d ej = p(id(0, 1, 0)) - p(id(0, 0, 0));
    const bool left = cell_dim == 3 ? ei.cross(ej).dot(p(id(0, 0, 1)) - p(id(0, 0, 0))) < 0.0
                                    : ei.cross(ej).z() < 0.0;
    for (cgsize_t k = 0; k < std::max<cgsize_t>(nv[2] - 1, 1); ++k)
        for (cgsize_t j = 0; j < nv[1] - 1; ++j)
            for (cgsize_t i = 0; i < nv[0] - 1; ++i) {
                ++serial;
                if (cell_dim == 3) {
                    std::array<Index, 8> h{id(i, j, k),
                                           id(i + 1, j, k),
                                           id(i + 1, j + 1, k),
                                           id(i, j + 1, k),
                                           id(i, j, k + 1),
                                           id(i + 1, j, k + 1),
                                           id(i + 1, j + 1, k + 1),
                                           id(i, j + 1, k + 1)};
                    if (left) {
                        std::swap(h[1], h[3]);
                        std::swap(h[5], h[7]);
                    }
                    raw.cells.add(RawType::hexa, h.data(), serial);
                } else {
                    std::array<Index, 4> q{id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0),
                                           id(i, j + 1, 0)};
                    raw.cells.add(RawType::quad, q.data(), serial);
                }
            }
    // Nodes of the block-face element with lower corner q (q[fixed] the plane's vertex index):
    // a quadrilateral, or in 2-D an edge along the other direction.
    const auto face_nodes = [&](int fixed, const std::array<cgsize_t, 3>& q,
                                std::array<Index, 4>& out) -> int {
        if (cell_dim == 2) {
            std::array<cgsize_t, 3> q1 = q;
            q1[fixed == 0 ? 1 : 0] += 1;
            out = {id(q[0], q[1], 0), id(q1[0], q1[1], 0), 0, 0};
            return 2;
        }
        const int a = (fixed + 1) % 3, c = (fixed + 2) % 3;
        std::array<cgsize_t, 3> q1 = q, q2 = q, q3 = q;
        q1[a] += 1;
        q2[a] += 1;
        q2[c] += 1;
        q3[c] += 1;
        out = {id(q[0], q[1], q[2]), id(q1[0], q1[1], q1[2]), id(q2[0], q2[1], q2[2]),
               id(q3[0], q3[1], q3[2])};
        return 4;
    };
    const auto add_face = [&](int fixed, const std::array<cgsize_t, 3>& q, int marker) {
        std::array<Index, 4> f{};
        const int n = face_nodes(fixed, q, f);
        raw.faces.add(n == 2 ? RawType::line : RawType::quad, f.data(), 0, marker);
    };
    // Number of cells in direction d (one across the third direction of a 2-D zone).
    const auto ncell = [&](int d) { return d < cell_dim ? nv[d] - 1 : cgsize_t{1}; };

    int nbc = 0;
    check(cg_nbocos(fn, 1, Z, &nbc), zone + " boundary conditions");
    for (int b = 1; b <= nbc; ++b) {
        char bcname[33] = {};
        CGNS_ENUMT(BCType_t) bctype{};
        CGNS_ENUMT(PointSetType_t) ptype{};
        cgsize_t npnts = 0, nlist = 0;
        int normal_index[3] = {};
        CGNS_ENUMT(DataType_t) ndt{};
        int ndataset = 0;
        const std::string where = fmt::format("{} boundary condition {}", zone, b);
        check(cg_boco_info(fn, 1, Z, b, bcname, &bctype, &ptype, &npnts, normal_index, &nlist, &ndt,
                           &ndataset),
              where);
        CGNS_ENUMT(GridLocation_t) loc = CGNS_ENUMV(Vertex);
        check(cg_boco_gridlocation_read(fn, 1, Z, b, &loc), where);
        const bool vertex = loc == CGNS_ENUMV(Vertex);
        if (ptype == CGNS_ENUMV(PointList)) {
            // I/J/KFaceCenter lists name faces (the plane's vertex index, the other two cell
            // indices); vertex lists name vertices, and every block-face element whose nodes
            // are all listed is taken.
            const int face_dir = loc == CGNS_ENUMV(IFaceCenter)   ? 0
                                 : loc == CGNS_ENUMV(JFaceCenter) ? 1
                                 : loc == CGNS_ENUMV(KFaceCenter) ? 2
                                                                  : -1;
            if (!vertex && (face_dir < 0 || face_dir >= cell_dim))
                throw InputError(
                    fmt::format("{}: {} '{}': a point list at location {}; expected Vertex, "
                                "IFaceCenter, JFaceCenter or KFaceCenter on a structured zone",
                                src, where, bcname, cg_GridLocationName(loc)));
            if (npnts < 1 || npnts > total)
                throw InputError(fmt::format("{}: {} '{}': {} points; expected 1 to {}", src, where,
                                             bcname, npnts, total));
            std::vector<cgsize_t> pts(static_cast<std::size_t>(cell_dim * npnts));
            check(cg_boco_read(fn, 1, Z, b, pts.data(), nullptr), where);
            const int marker = raw.marker(bc_marker(fn, Z, b, bcname));
            if (vertex) {
                std::vector<char> in(static_cast<std::size_t>(total), 0);
                for (cgsize_t p = 0; p < npnts; ++p) {
                    std::array<cgsize_t, 3> q{0, 0, 0};
                    for (int d = 0; d < cell_dim; ++d) {
                        q[d] = pts[cell_dim * p + d] - 1;
                        if (q[d] < 0 || q[d] >= nv[d])
                            throw InputError(
                                fmt::format("{}: {} '{}': point {} has index {} in direction {}; "
                                            "expected 1 to {}",
                                            src, where, bcname, p + 1, q[d] + 1, d + 1, nv[d]));
                    }
                    in[static_cast<std::size_t>(id(q[0], q[1], q[2]) - offset)] = 1;
                }
                for (int d = 0; d < cell_dim; ++d)
                    for (cgsize_t plane : {cgsize_t{0}, nv[d] - 1}) {
                        const int a = (d + 1) % 3, c = (d + 2) % 3;
                        for (cgsize_t u = 0; u < ncell(a); ++u)
                            for (cgsize_t v = 0; v < ncell(c); ++v) {
                                std::array<cgsize_t, 3> q{};
                                q[d] = plane;
                                q[a] = u;
                                q[c] = v;
                                std::array<Index, 4> fv{};
                                const int n = face_nodes(d, q, fv);
                                bool all = true;
                                for (int k = 0; k < n; ++k)
                                    all = all && in[static_cast<std::size_t>(fv[k] - offset)];
                                if (all) add_face(d, q, marker);
                            }
                    }
            } else {
                for (cgsize_t p = 0; p < npnts; ++p) {
                    std::array<cgsize_t, 3> q{0, 0, 0};
                    for (int d = 0; d < cell_dim; ++d) {
                        q[d] = pts[cell_dim * p + d] - 1;
                        const cgsize_t top = d == face_dir ? nv[d] - 1 : nv[d] - 2;
                        if (q[d] < 0 || q[d] > top)
                            throw InputError(
                                fmt::format("{}: {} '{}': face {} has index {} in direction {}; "
                                            "expected 1 to {}",
                                            src, where, bcname, p + 1, q[d] + 1, d + 1, top + 1));
                    }
                    if (q[face_dir] != 0 && q[face_dir] != nv[face_dir] - 1)
                        throw InputError(
                            fmt::format("{}: {} '{}': face {} lies inside the zone (index {} in "
                                        "direction {}); expected a block face (1 or {})",
                                        src, where, bcname, p + 1, q[face_dir] + 1, face_dir + 1,
                                        nv[face_dir]));
                    add_face(face_dir, q, marker);
                }
            }
            continue;
        }
        if (ptype != CGNS_ENUMV(PointRange) || npnts != 2)
            throw InputError(
                fmt::format("{}: {} '{}' is a {} of {} points; expected a PointRange of 2 "
                            "points or a PointList on a structured zone",
                            src, where, bcname, cg_PointSetTypeName(ptype), npnts));
        std::array<cgsize_t, 6> r{};
        check(cg_boco_read(fn, 1, Z, b, r.data(), nullptr), where);
        // Constant direction; vertex ranges span vertices, face-centre ranges span cells.
        int fixed = -1;
        std::array<cgsize_t, 3> lo{}, hi{};
        for (int d = 0; d < cell_dim; ++d) {
            lo[d] = std::min(r[d], r[cell_dim + d]) - 1;
            hi[d] = std::max(r[d], r[cell_dim + d]) - 1;
            if (lo[d] == hi[d] && fixed < 0) fixed = d;
        }
        if (fixed < 0)
            throw InputError(
                fmt::format("{}: {} '{}': the range has no constant index; expected "
                            "a block face",
                            src, where, bcname));
        for (int d = 0; d < cell_dim; ++d) {
            if (d == fixed) {
                if (lo[d] < 0 || lo[d] >= nv[d] + (vertex ? 0 : 1))
                    throw InputError(
                        fmt::format("{}: {} '{}': index {} in direction {} is "
                                    "outside the zone (1 to {})",
                                    src, where, bcname, lo[d] + 1, d + 1, nv[d]));
                lo[d] = std::min(lo[d], nv[d] - 1);
                hi[d] = lo[d] + 1;
                continue;
            }
            if (vertex) hi[d] -= 1;  // vertex range -> cell range
            hi[d] += 1;              // exclusive
            if (lo[d] < 0 || hi[d] > nv[d] - 1)
                throw InputError(
                    fmt::format("{}: {} '{}': range {} to {} in direction {} is "
                                "outside the zone ({} vertices)",
                                src, where, bcname, lo[d] + 1, hi[d], d + 1, nv[d]));
        }
        if (cell_dim == 2) {
            lo[2] = 0;
            hi[2] = 1;
        }
        const int marker = raw.marker(bc_marker(fn, Z, b, bcname));
        const int a = (fixed + 1) % 3, c = (fixed + 2) % 3;
        for (cgsize_t u = lo[a]; u < hi[a]; ++u)
            for (cgsize_t v = lo[c]; v < hi[c]; ++v) {
                std::array<cgsize_t, 3> q{};
                q[fixed] = lo[fixed];
                q[a] = u;
                q[c] = v;
                add_face(fixed, q, marker);
            }
    }
}

/// Add one unstructured zone (cells; face elements, marked by the boundary conditions that
/// name them, else by their section's name) to `raw`. A cell's source number is `serial` plus
/// its CGNS element number; returns the zone's largest element number.
std::int64_t add_unstructured_zone(int fn, int Z, int cell_dim, int phys_dim,
                                   const std::string& src, detail::RawMesh& raw,
                                   std::int64_t serial) {
    const auto check = [&src](int rc, const std::string& where) {
        if (rc != CG_OK) throw InputError(fmt::format("{}: {}: {}", src, where, cg_get_error()));
    };
    char zname[33] = {};
    cgsize_t size[9] = {};
    check(cg_zone_read(fn, 1, Z, zname, size), fmt::format("zone {}", Z));
    const std::string zone = fmt::format("zone '{}'", zname);
    const cgsize_t nv = size[0];
    if (nv <= 0 || nv > std::numeric_limits<Index>::max())
        throw InputError(fmt::format("{}: {} has {} vertices; expected 1 to {}", src, zone, nv,
                                     std::numeric_limits<Index>::max()));

    if (nv + static_cast<cgsize_t>(raw.x.size() / 3) > std::numeric_limits<Index>::max())
        throw InputError(fmt::format("{}: {} makes the mesh too large", src, zone));
    const auto offset = static_cast<Index>(raw.x.size() / 3);
    raw.x.resize(raw.x.size() + 3 * static_cast<std::size_t>(nv), 0.0);
    {
        std::vector<double> c(static_cast<std::size_t>(nv));
        const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
        cgsize_t rmin = 1, rmax = nv;
        for (int k = 0; k < std::min(phys_dim, 3); ++k) {
            check(cg_coord_read(fn, 1, Z, names[k], CGNS_ENUMV(RealDouble), &rmin, &rmax, c.data()),
                  fmt::format("{} {}", zone, names[k]));
            for (cgsize_t i = 0; i < nv; ++i) raw.x[3 * (offset + i) + k] = c[i];
        }
    }

    int nsec = 0;
    check(cg_nsections(fn, 1, Z, &nsec), zone + " sections");
    std::vector<std::string> section_names(nsec + 1);
    std::vector<Boundary> bnd;
    std::unordered_map<std::int64_t, std::size_t> bnd_of_element;
    std::vector<cgsize_t> conn, offs;
    std::int64_t last = 0;
    for (int s = 1; s <= nsec; ++s) {
        char sname[33] = {};
        CGNS_ENUMT(ElementType_t) stype{};
        cgsize_t start = 0, end = 0;
        int nbndry = 0, parent_flag = 0;
        check(cg_section_read(fn, 1, Z, s, sname, &stype, &start, &end, &nbndry, &parent_flag),
              fmt::format("{} section {}", zone, s));
        section_names[s] = sname;
        last = std::max<std::int64_t>(last, end);
        const std::string where = fmt::format("{} section '{}'", zone, sname);
        if (start < 1 || end < start)
            throw InputError(fmt::format("{}: {}: element range {}..{}; expected 1 <= start <= end",
                                         src, where, start, end));
        // Read exactly the announced range (a file whose arrays disagree with it cannot make
        // the library write past the buffers).
        cgsize_t data_size = 0;
        check(cg_ElementPartialSize(fn, 1, Z, s, start, end, &data_size), where);
        conn.resize(static_cast<std::size_t>(std::max<cgsize_t>(data_size, 1)));
        const bool mixed = stype == CGNS_ENUMV(MIXED);
        if (mixed) {
            offs.resize(static_cast<std::size_t>(end - start + 2));
            check(cg_poly_elements_partial_read(fn, 1, Z, s, start, end, conn.data(), offs.data(),
                                                nullptr),
                  where);
        } else {
            check(cg_elements_partial_read(fn, 1, Z, s, start, end, conn.data(), nullptr), where);
        }
        std::size_t pos = 0;
        for (cgsize_t e = start; e <= end; ++e) {
            CGNS_ENUMT(ElementType_t) et = stype;
            if (mixed) {
                if (pos >= conn.size())
                    throw InputError(fmt::format(
                        "{}: {} element {}: connectivity ends early; expected an element type", src,
                        where, e));
                et = static_cast<CGNS_ENUMT(ElementType_t)>(conn[pos++]);
            }
            RawType t{};
            if (et == CGNS_ENUMV(NODE)) {
                pos += 1;
                continue;
            }
            if (!cgns_type(et, t))
                throw InputError(
                    fmt::format("{}: {} element {}: element type {} is not "
                                "supported; expected first-order BAR_2, TRI_3, "
                                "QUAD_4, TETRA_4, PYRA_5, PENTA_6 or HEXA_8",
                                src, where, e, cg_ElementTypeName(et)));
            const int nn = detail::raw_node_count(t);
            if (pos + static_cast<std::size_t>(nn) > conn.size())
                throw InputError(
                    fmt::format("{}: {} element {}: connectivity ends early; "
                                "expected {} nodes",
                                src, where, e, nn));
            std::array<Index, 8> n{};
            for (int k = 0; k < nn; ++k) {
                const cgsize_t v = conn[pos + k];
                if (v < 1 || v > nv)
                    throw InputError(
                        fmt::format("{}: {} element {}: node {}; expected 1 to {} "
                                    "(1-based)",
                                    src, where, e, v, nv));
                n[k] = offset + static_cast<Index>(v - 1);
            }
            pos += static_cast<std::size_t>(nn);
            if (t == RawType::prism) {  // CGNS PENTA_6: (1,2,3) normal toward (4,5,6); VTK: away
                std::swap(n[1], n[2]);
                std::swap(n[4], n[5]);
            }
            const int d = detail::raw_dim(t);
            if (d == cell_dim) {
                raw.cells.add(t, n.data(), serial + e);
            } else if (d == cell_dim - 1) {
                Boundary b{t, {n[0], n[1], n[2], n[3]}, e, s};
                bnd_of_element[e] = bnd.size();
                bnd.push_back(b);
            }
        }
    }

    // Boundary conditions name the faces: by element numbers, or by their vertices.
    int nbc = 0;
    check(cg_nbocos(fn, 1, Z, &nbc), zone + " boundary conditions");
    for (int b = 1; b <= nbc; ++b) {
        char bcname[33] = {};
        CGNS_ENUMT(BCType_t) bctype{};
        CGNS_ENUMT(PointSetType_t) ptype{};
        cgsize_t npnts = 0, nlist = 0;
        int normal_index[3] = {};
        CGNS_ENUMT(DataType_t) ndt{};
        int ndataset = 0;
        const std::string where = fmt::format("{} boundary condition {}", zone, b);
        check(cg_boco_info(fn, 1, Z, b, bcname, &bctype, &ptype, &npnts, normal_index, &nlist, &ndt,
                           &ndataset),
              where);
        CGNS_ENUMT(GridLocation_t) loc = CGNS_ENUMV(Vertex);
        check(cg_boco_gridlocation_read(fn, 1, Z, b, &loc), where);
        std::vector<cgsize_t> pts(static_cast<std::size_t>(std::max<cgsize_t>(npnts, 1)));
        check(cg_boco_read(fn, 1, Z, b, pts.data(), nullptr), where);
        const int marker = raw.marker(bc_marker(fn, Z, b, bcname));
        const bool range = ptype == CGNS_ENUMV(PointRange) || ptype == CGNS_ENUMV(ElementRange);
        const bool by_element = ptype == CGNS_ENUMV(ElementRange) ||
                                ptype == CGNS_ENUMV(ElementList) || loc != CGNS_ENUMV(Vertex);
        std::vector<std::int64_t> ids;
        if (range) {
            if (npnts != 2)
                throw InputError(fmt::format("{}: {} '{}': a range with {} values; expected 2", src,
                                             where, bcname, npnts));
            for (cgsize_t i = pts[0]; i <= pts[1]; ++i) ids.push_back(i);
        } else {
            ids.assign(pts.begin(), pts.begin() + npnts);
        }
        if (by_element) {
            for (auto id : ids) {
                const auto it = bnd_of_element.find(id);
                if (it == bnd_of_element.end())
                    throw InputError(
                        fmt::format("{}: {} '{}' names element {}, which is not a "
                                    "boundary element; expected face elements",
                                    src, where, bcname, id));
                bnd[it->second].marker = marker;
            }
        } else {
            std::vector<char> in(static_cast<std::size_t>(nv), 0);
            for (auto id : ids) {
                if (id < 1 || id > nv)
                    throw InputError(fmt::format("{}: {} '{}': vertex {}; expected 1 to {}", src,
                                                 where, bcname, id, nv));
                in[id - 1] = 1;
            }
            for (auto& bf : bnd) {
                bool all = true;
                for (int k = 0; k < detail::raw_node_count(bf.type); ++k)
                    all = all && in[bf.nodes[k] - offset];
                if (all && bf.marker < 0) bf.marker = marker;
            }
        }
    }
    for (auto& bf : bnd) {
        if (bf.marker < 0) bf.marker = raw.marker(section_names[bf.section]);
        raw.faces.add(bf.type, bf.nodes.data(), serial + bf.element, bf.marker);
    }
    return last;
}

}  // namespace

Mesh read_cgns(const std::filesystem::path& file, const ReadOptions& options) {
    const std::string src = file.string();
    if (!std::filesystem::exists(file))
        throw IoError(fmt::format("{}: cannot open the mesh file for reading (no such file)", src));
    CgnsFile f;
    if (cg_open(src.c_str(), CG_MODE_READ, &f.fn) != CG_OK) {
        f.fn = -1;
        throw IoError(
            fmt::format("{}: cannot open as CGNS ({}); expected a CGNS file", src, cg_get_error()));
    }
    const auto check = [&src](int rc, const std::string& where) {
        if (rc != CG_OK) throw InputError(fmt::format("{}: {}: {}", src, where, cg_get_error()));
    };
    int nbases = 0;
    check(cg_nbases(f.fn, &nbases), "reading the bases");
    if (nbases < 1) throw InputError(fmt::format("{}: no CGNS base; expected one", src));
    char bname[33] = {};
    int cell_dim = 0, phys_dim = 0;
    check(cg_base_read(f.fn, 1, bname, &cell_dim, &phys_dim), "base 1");
    if (cell_dim != 2 && cell_dim != 3)
        throw InputError(fmt::format("{}: base '{}' has cell dimension {}; expected 2 or 3", src,
                                     bname, cell_dim));
    int nzones = 0;
    check(cg_nzones(f.fn, 1, &nzones), "reading the zones");
    if (nzones < 1) throw InputError(fmt::format("{}: base '{}' has no zone", src, bname));
    std::vector<bool> structured(static_cast<std::size_t>(nzones) + 1, false);
    for (int z = 1; z <= nzones; ++z) {
        CGNS_ENUMT(ZoneType_t) t{};
        check(cg_zone_type(f.fn, 1, z, &t), fmt::format("zone {}", z));
        if (t != CGNS_ENUMV(Structured) && t != CGNS_ENUMV(Unstructured))
            throw InputError(
                fmt::format("{}: zone {} has zone type {}; expected Structured or "
                            "Unstructured",
                            src, z, cg_ZoneTypeName(t)));
        structured[z] = t == CGNS_ENUMV(Structured);
    }

    detail::RawMesh raw;
    raw.source = src;
    raw.dim = cell_dim;
    if (nzones == 1 && !structured[1]) {
        // One unstructured zone: read as it is (coincident nodes stay apart).
        char zname[33] = {};
        cgsize_t size[9] = {};
        check(cg_zone_read(f.fn, 1, 1, zname, size), "zone 1");
        raw.where_label = fmt::format("zone '{}' element", zname);
        (void)add_unstructured_zone(f.fn, 1, cell_dim, phys_dim, src, raw, 0);
        return detail::build_mesh(std::move(raw), options);
    }
    // Several zones, or structured blocks: each zone's cells and boundary faces, then the
    // nodes on exposed faces that coincide (zone interfaces, block cuts) merged, and boundary
    // faces that became interior (interface sections or conditions) dropped.
    raw.where_label = nzones == 1 ? "structured cell (i fastest)"
                                  : "element (numbered over the zones in file order, each "
                                    "zone's numbers after the previous zone's last)";
    std::int64_t serial = 0;
    for (int z = 1; z <= nzones; ++z) {
        if (structured[z])
            add_structured_zone(f.fn, z, cell_dim, phys_dim, src, raw, serial);
        else
            serial += add_unstructured_zone(f.fn, z, cell_dim, phys_dim, src, raw, serial);
    }
    const Index merged =
        detail::merge_coincident(raw, detail::exposed_nodes(raw), detail::merge_tolerance(raw));
    if (merged > 0) detail::drop_interior_faces(raw);
    return detail::build_mesh(std::move(raw), options);
}

}  // namespace manta::mesh
