/// @file meshgen.cpp
/// `generate_mesh`: the CAD with gmsh's OpenCASCADE kernel, the markers, the size field, the
/// tetrahedral mesh, the files and the quality report (docs/meshgen.md).

#include <fmt/format.h>
#include <gmsh.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <set>

#include "cgns_writer.hpp"
#include "manta/core/error.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "shapes.hpp"

namespace manta::meshgen {

namespace {

using detail::ControlRegion;
using detail::SectionFrame;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// gmsh keeps one global state: one session at a time, finalised on scope exit.
std::mutex& gmsh_mutex() {
    static std::mutex m;
    return m;
}
class GmshSession {
public:
    explicit GmshSession(int threads) : lock_(gmsh_mutex()) {
        gmsh::initialize(0, nullptr, false);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::option::setNumber("General.Verbosity", 1);
        gmsh::option::setNumber("General.NumThreads", std::max(1, threads));
        gmsh::option::setNumber("Geometry.OCCUnionUnify", 0);  // keep the control-surface seams
        gmsh::option::setNumber("Geometry.OCCParallel", threads > 1 ? 1 : 0);
        gmsh::model::add("aircraft");
    }
    GmshSession(const GmshSession&) = delete;
    GmshSession& operator=(const GmshSession&) = delete;
    ~GmshSession() { gmsh::finalize(); }

private:
    std::lock_guard<std::mutex> lock_;
};

// ------------------------------------------------------------------------------------ size field

/// Distance from p to the segment [a, b].
double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                        const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double l2 = ab.squaredNorm();
    const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return (p - (a + t * ab)).norm();
}

/// Distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
double triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double nn = n.squaredNorm();
    if (nn > 0.0) {
        const Eigen::Vector3d q = p - n * ((p - a).dot(n) / nn);
        const double u = (b - q).cross(c - q).dot(n), v = (c - q).cross(a - q).dot(n),
                     w = (a - q).cross(b - q).dot(n);
        if (u >= 0.0 && v >= 0.0 && w >= 0.0) return (p - q).norm();
    }
    return std::min(
        {segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

/// A place with its own mesh size: h(x) = h0 + growth * max(0, distance(x) - radius).
struct Feature {
    enum Kind { segment, triangle } kind = segment;
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero(),
                    c = Eigen::Vector3d::Zero();
    double radius = 0.0, h0 = 0.0;
};

struct SizeField {
    std::vector<Feature> features;
    double growth = 0.2, h_max = 1.0;
    [[nodiscard]] double operator()(double x, double y, double z) const {
        const Eigen::Vector3d p(x, y, z);
        double h = h_max;
        for (const auto& f : features) {
            const double lower = f.h0;
            if (lower >= h) continue;
            // The distance only matters while h0 + growth * d can undercut h.
            const double d = f.kind == Feature::segment ? segment_distance(p, f.a, f.b)
                                                        : triangle_distance(p, f.a, f.b, f.c);
            h = std::min(h, lower + growth * std::max(0.0, d - f.radius));
        }
        return h;
    }
};

/// Mesh sizes of one level, as fractions of the local chord (lifting surfaces) or of the largest
/// fuselage width.
struct Sizes {
    double le = 0.015, te = 0.015, tip = 0.06, cs = 0.04, surface = 0.07, fuselage = 0.15,
           nose = 0.04, growth = 0.22, farfield = 0.2;  // farfield: fraction of the radius
};

Sizes sizes_for(Level level, double factor) {
    Sizes s;
    // 2.5x the nodes per level: sizes 2.5^(1/3) = 1.357 apart.
    const double f = factor * std::pow(2.5, -static_cast<double>(static_cast<int>(level)) / 3.0);
    s.le *= f;
    s.te *= f;
    s.tip *= f;
    s.cs *= f;
    s.surface *= f;
    s.fuselage *= f;
    s.nose *= f;
    // The far field and the growth keep the level's factor only: a test's coarser factor would
    // facet the sphere and coarsen the volume twice.
    s.farfield *= f / factor;
    s.growth *= f / factor;
    return s;
}

// ------------------------------------------------------------------------------------------ CAD

Eigen::Vector3d mirrored(Eigen::Vector3d p) {
    p.y() = -p.y();
    return p;
}

int add_point(const Eigen::Vector3d& p) {
    return gmsh::model::occ::addPoint(p.x(), p.y(), p.z());
}

/// A closed wire through a section contour placed in its frame.
int section_wire(const SectionFrame& f, const detail::Contour& c) {
    std::vector<int> pts;
    pts.reserve(c.points.size());
    for (const auto& q : c.points) pts.push_back(add_point(f.at(q.x(), q.y())));
    namespace occ = gmsh::model::occ;
    std::vector<int> curves;
    if (c.sharp_trailing_edge) {
        std::vector<int> upper(pts.begin(), pts.begin() + static_cast<long>(c.leading_edge) + 1);
        std::vector<int> lower(pts.begin() + static_cast<long>(c.leading_edge), pts.end());
        lower.push_back(pts.front());
        curves = {occ::addSpline(upper), occ::addSpline(lower)};
    } else {
        // The contour as one spline from the trailing edge round the leading edge (smooth there)
        // and the trailing-edge base as a line.
        curves = {occ::addSpline(pts), occ::addLine(pts.back(), pts.front())};
    }
    return occ::addWire(curves);
}

int volume_of(const gmsh::vectorpair& out, const std::string& what) {
    for (const auto& [d, t] : out)
        if (d == 3) return t;
    throw NumericalError(fmt::format("meshgen: OpenCASCADE made no solid for {}", what));
}

/// A ruled solid through closed polygons (the control-surface regions).
int ruled_box(const std::array<std::array<Eigen::Vector3d, 4>, 2>& corners) {
    namespace occ = gmsh::model::occ;
    std::vector<int> wires;
    for (const auto& q : corners) {
        std::array<int, 4> p{};
        for (int k = 0; k < 4; ++k)
            p[static_cast<std::size_t>(k)] = add_point(q[static_cast<std::size_t>(k)]);
        std::vector<int> lines;
        for (int k = 0; k < 4; ++k)
            lines.push_back(occ::addLine(p[static_cast<std::size_t>(k)],
                                         p[static_cast<std::size_t>((k + 1) % 4)]));
        wires.push_back(occ::addWire(lines));
    }
    gmsh::vectorpair out;
    occ::addThruSections(wires, out, -1, true, true);
    return volume_of(out, "a control-surface region");
}

/// What a solid of the body is.
struct Piece {
    int volume = 0;
    int region = -1;  ///< index into the control regions, -1 for plain wall
};

/// Elliptic fuselage cross-section as a closed periodic spline (seam at the bottom).
int fuselage_wire(const geometry::FuselageStation& s, double w, double h) {
    constexpr int n = 24;
    std::vector<int> pts;
    for (int k = 0; k < n; ++k) {
        const double t = 2.0 * std::numbers::pi * k / n;
        pts.push_back(gmsh::model::occ::addPoint(s.x, 0.5 * w * std::sin(t),
                                                 s.z_centre - 0.5 * h * std::cos(t)));
    }
    pts.push_back(pts.front());
    const int c = gmsh::model::occ::addSpline(pts);
    return gmsh::model::occ::addWire({c});
}

struct Cad {
    std::vector<ControlRegion> regions;
    std::vector<int> fluid;
    std::map<std::string, std::vector<int>> marker_faces;  // marker -> surfaces
    std::vector<std::string> marker_order;
    std::map<std::string, std::string> roles;
    double body_volume = 0.0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = 0.0;
    std::vector<std::string> notes;
};

Cad build_cad(const aircraft::AircraftDefinition& a, const MeshOptions& o) {
    namespace occ = gmsh::model::occ;
    const auto& g = a.geometry;
    const bool half = o.model == Model::half;
    Cad cad;
    std::vector<Piece> pieces;
    for (std::size_t i = 0; i < g.surfaces.size(); ++i) {
        const auto& w = g.surfaces[i];
        std::vector<int> wires;
        for (std::size_t j = 0; j < w.sections.size(); ++j) {
            const auto contour = detail::section_contour(w.sections[j].airfoil);
            if (!contour.note.empty() &&
                std::find(cad.notes.begin(), cad.notes.end(), contour.note) == cad.notes.end())
                cad.notes.push_back(contour.note);
            wires.push_back(section_wire(detail::frame_of(w, j), contour));
        }
        gmsh::vectorpair out;
        try {
            occ::addThruSections(wires, out, -1, true, true);
        } catch (const std::exception& e) {
            detail::fail_key(a, fmt::format("geometry.lifting_surfaces[{}]", i), w.name,
                             fmt::format("cannot be lofted through its sections ({})", e.what()),
                             "sections that make a closed solid");
        }
        const int solid = volume_of(out, w.name);
        // Control-surface regions on this surface (right copy; mirrored copies follow).
        std::vector<int> region_index;
        gmsh::vectorpair boxes;
        for (std::size_t k = 0; k < g.control_surfaces.size(); ++k) {
            if (g.control_surfaces[k].surface != w.name) continue;
            const auto& cs = g.control_surfaces[k];
            cad.regions.push_back(detail::control_region(
                g, k, false, detail::marker_name(cs, w.symmetric, false, half)));
            region_index.push_back(static_cast<int>(cad.regions.size()) - 1);
            boxes.emplace_back(3, ruled_box(cad.regions.back().corners));
        }
        std::vector<Piece> right;
        if (boxes.empty()) {
            right.push_back({solid, -1});
        } else {
            std::vector<gmsh::vectorpair> map;
            occ::fragment({{3, solid}}, boxes, out, map);
            std::set<int> in_solid;
            for (const auto& [d, t] : map.at(0))
                if (d == 3) in_solid.insert(t);
            std::set<int> in_box;
            for (std::size_t b = 0; b < boxes.size(); ++b)
                for (const auto& [d, t] : map.at(b + 1)) {
                    if (d != 3) continue;
                    in_box.insert(t);
                    if (in_solid.count(t)) right.push_back({t, region_index[b]});
                }
            for (int t : in_solid)
                if (!in_box.count(t)) right.push_back({t, -1});
            gmsh::vectorpair spare;
            for (int t : in_box)
                if (!in_solid.count(t)) spare.emplace_back(3, t);
            if (!spare.empty()) occ::remove(spare, true);
        }
        if (w.symmetric) {
            gmsh::vectorpair src;
            for (const auto& p : right) src.emplace_back(3, p.volume);
            gmsh::vectorpair copies;
            occ::copy(src, copies);
            occ::mirror(copies, 0.0, 1.0, 0.0, 0.0);
            std::vector<Piece> left;
            for (std::size_t p = 0; p < right.size(); ++p) {
                int region = right[p].region;
                if (region >= 0) {
                    const auto& r = cad.regions[static_cast<std::size_t>(region)];
                    const auto& cs = g.control_surfaces[r.control_index];
                    cad.regions.push_back(detail::control_region(
                        g, r.control_index, true, detail::marker_name(cs, true, true, half)));
                    region = static_cast<int>(cad.regions.size()) - 1;
                }
                left.push_back({copies.at(p).second, region});
            }
            // The plain parts of both copies fused, so that no face lies on y = 0.
            std::vector<Piece> merged;
            gmsh::vectorpair plain_r, plain_l;
            for (const auto& p : right)
                if (p.region < 0)
                    plain_r.emplace_back(3, p.volume);
                else
                    merged.push_back(p);
            for (const auto& p : left)
                if (p.region < 0)
                    plain_l.emplace_back(3, p.volume);
                else
                    merged.push_back(p);
            std::vector<gmsh::vectorpair> map;
            occ::fuse(plain_r, plain_l, out, map);
            for (const auto& [d, t] : out)
                if (d == 3) merged.push_back({t, -1});
            right = merged;
        }
        pieces.insert(pieces.end(), right.begin(), right.end());
    }
    if (!g.fuselage.empty()) {
        const auto& st = g.fuselage.stations;
        double wmax = 0.0;
        for (const auto& s : st) wmax = std::max({wmax, s.width, s.height});
        std::vector<int> wires;
        for (std::size_t j = 0; j < st.size(); ++j) {
            double wj = st[j].width, hj = st[j].height;
            if (!(wj > 0.0) || !(hj > 0.0)) {
                // A pointed end: a small ellipse (1 % of the largest size) shaped like the next.
                const auto& nb = st[j == 0 ? 1 : j - 1];
                const double s = 0.01 * wmax / std::max(nb.width, nb.height);
                wj = std::max(nb.width * s, 1e-4);
                hj = std::max(nb.height * s, 1e-4);
            }
            wires.push_back(fuselage_wire(st[j], wj, hj));
        }
        gmsh::vectorpair out;
        try {
            occ::addThruSections(wires, out, -1, true, false);
        } catch (const std::exception& e) {
            detail::fail_key(a, "geometry.fuselage", "stations",
                             fmt::format("cannot be lofted ({})", e.what()),
                             "stations that make a closed solid");
        }
        pieces.push_back({volume_of(out, "the fuselage"), -1});
    }
    occ::synchronize();
    // Fuse the parts into one body; the control-surface pieces keep their faces.
    gmsh::vectorpair object{{3, pieces.front().volume}}, tools;
    for (std::size_t p = 1; p < pieces.size(); ++p) tools.emplace_back(3, pieces[p].volume);
    gmsh::vectorpair body;
    if (!tools.empty()) {
        std::vector<gmsh::vectorpair> map;
        try {
            occ::fuse(object, tools, body, map);
        } catch (const std::exception& e) {
            throw NumericalError(
                fmt::format("meshgen: the fusion of the aircraft's parts failed "
                            "({}); the parts may self-intersect",
                            e.what()));
        }
    } else {
        body = object;
    }
    occ::synchronize();
    double xmin = 0, ymin = 0, zmin = 0, xmax = 0, ymax = 0, zmax = 0;
    double bx0 = 1e300, by0 = 1e300, bz0 = 1e300, bx1 = -1e300, by1 = -1e300, bz1 = -1e300;
    for (const auto& [d, t] : body) {
        if (d != 3) continue;
        occ::getBoundingBox(3, t, xmin, ymin, zmin, xmax, ymax, zmax);
        bx0 = std::min(bx0, xmin), by0 = std::min(by0, ymin), bz0 = std::min(bz0, zmin);
        bx1 = std::max(bx1, xmax), by1 = std::max(by1, ymax), bz1 = std::max(bz1, zmax);
        double m = 0.0;
        occ::getMass(3, t, m);
        cad.body_volume += m;
    }
    if (half) cad.body_volume *= 0.5;  // symmetric body
    cad.centre = Eigen::Vector3d(0.5 * (bx0 + bx1), 0.0, 0.5 * (bz0 + bz1));
    cad.radius = o.farfield_spans * a.reference.span;
    const double size = std::max({bx1 - bx0, by1 - by0, bz1 - bz0});
    if (!(cad.radius > 1.5 * size))
        throw InputError(
            fmt::format("meshgen: far-field radius {} m ({} spans) is not beyond the "
                        "aircraft ({} m across); expected more spans",
                        cad.radius, o.farfield_spans, size));
    const int domain =
        occ::addSphere(cad.centre.x(), 0.0, cad.centre.z(), cad.radius, -1, -std::numbers::pi / 2,
                       std::numbers::pi / 2, half ? std::numbers::pi : 2 * std::numbers::pi);
    gmsh::vectorpair fluid;
    {
        std::vector<gmsh::vectorpair> map;
        try {
            occ::cut({{3, domain}}, body, fluid, map);
        } catch (const std::exception& e) {
            throw NumericalError(
                fmt::format("meshgen: cutting the body from the far field failed ({})", e.what()));
        }
    }
    occ::synchronize();
    for (const auto& [d, t] : fluid)
        if (d == 3) cad.fluid.push_back(t);
    if (cad.fluid.empty()) throw NumericalError("meshgen: no fluid volume left after the cut");

    // Remove what is left of the construction (section wires, points) outside the fluid's
    // closure, so that nothing but the fluid is meshed.
    gmsh::vectorpair faces;
    gmsh::vectorpair fl;
    for (int t : cad.fluid) fl.emplace_back(3, t);
    gmsh::model::getBoundary(fl, faces, true, false, false);
    {
        std::set<std::pair<int, int>> keep(fl.begin(), fl.end());
        gmsh::vectorpair level;
        for (const auto& [d, t] : faces) level.emplace_back(d, std::abs(t));
        for (int dim = 2; dim >= 0 && !level.empty(); --dim) {
            for (const auto& e : level) keep.insert({e.first, std::abs(e.second)});
            gmsh::vectorpair next;
            if (dim > 0) gmsh::model::getBoundary(level, next, false, false, false);
            level.clear();
            for (const auto& [d, t] : next) level.emplace_back(d, std::abs(t));
        }
        gmsh::vectorpair stray;
        for (int dim = 3; dim >= 0; --dim) {
            gmsh::vectorpair all;
            gmsh::model::getEntities(all, dim);
            for (const auto& e : all)
                if (!keep.count(e)) stray.push_back(e);
        }
        if (!stray.empty()) {
            occ::remove(stray, false);
            occ::synchronize();
        }
    }
    // Classify the fluid's boundary faces.
    const double tol_far = 2.0 * size;
    for (const auto& r : cad.regions) {
        if (std::find(cad.marker_order.begin(), cad.marker_order.end(), r.marker) ==
            cad.marker_order.end())
            cad.marker_order.push_back(r.marker);
    }
    cad.marker_order.insert(cad.marker_order.begin(), "wall");
    cad.marker_order.push_back("farfield");
    if (half) cad.marker_order.push_back("symmetry");
    for (const auto& m : cad.marker_order)
        cad.roles[m] = m == "farfield" ? "farfield" : m == "symmetry" ? "symmetry" : "wall";
    for (const auto& [d, t] : faces) {
        const int tag = std::abs(t);
        gmsh::model::getBoundingBox(2, tag, xmin, ymin, zmin, xmax, ymax, zmax);
        const double extent = std::max({xmax - xmin, ymax - ymin, zmax - zmin});
        std::string marker = "wall";
        if (extent > tol_far) {
            marker =
                (half && std::abs(ymin) < 1e-7 * cad.radius && std::abs(ymax) < 1e-7 * cad.radius)
                    ? "symmetry"
                    : "farfield";
        } else {
            double cx = 0, cy = 0, cz = 0;
            occ::getCenterOfMass(2, tag, cx, cy, cz);
            const Eigen::Vector3d p(cx, cy, cz);
            for (const auto& r : cad.regions)
                if (r.contains(p, 0.0)) {
                    marker = r.marker;
                    break;
                }
        }
        cad.marker_faces[marker].push_back(tag);
    }
    // Every control surface of the model must have wetted faces.
    for (const auto& r : cad.regions) {
        if (half && r.mirrored) continue;
        if (!cad.marker_faces.count(r.marker)) {
            const auto& cs = g.control_surfaces[r.control_index];
            detail::fail_key(
                a, fmt::format("geometry.control_surfaces[{}].span_fraction", r.control_index),
                fmt::format("[{}, {}]", cs.span_fraction[0], cs.span_fraction[1]),
                fmt::format("puts control surface '{}' where it has no wetted face "
                            "(inside other parts of the aircraft, or outside its "
                            "surface '{}')",
                            cs.name, cs.surface),
                "a span range on the exposed part of its surface");
        }
    }
    // Drop markers without faces (the left copies in the half model).
    std::vector<std::string> kept;
    for (const auto& m : cad.marker_order)
        if (cad.marker_faces.count(m)) kept.push_back(m);
    cad.marker_order = kept;
    return cad;
}

SizeField size_field(const aircraft::AircraftDefinition& a, const Cad& cad, const Sizes& s,
                     bool half) {
    SizeField f;
    f.growth = s.growth;
    f.h_max = s.farfield * cad.radius;
    const auto& g = a.geometry;
    auto seg = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q, double h, double r = 0.0) {
        Feature ft;
        ft.kind = Feature::segment;
        ft.a = p;
        ft.b = q;
        ft.h0 = h;
        ft.radius = r;
        f.features.push_back(ft);
    };
    auto tri = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r,
                   double h) {
        Feature ft;
        ft.kind = Feature::triangle;
        ft.a = p;
        ft.b = q;
        ft.c = r;
        ft.h0 = h;
        f.features.push_back(ft);
    };
    for (const auto& w : g.surfaces) {
        for (int copy = 0; copy < w.n_copies(); ++copy) {
            if (half && copy == 1) continue;
            auto place = [&](Eigen::Vector3d p) { return copy == 1 ? mirrored(p) : p; };
            for (std::size_t j = 0; j + 1 < w.sections.size(); ++j) {
                const auto f0 = detail::frame_of(w, j), f1 = detail::frame_of(w, j + 1);
                const double c = std::min(f0.chord, f1.chord);
                const Eigen::Vector3d le0 = place(f0.at(0, 0)), le1 = place(f1.at(0, 0));
                const Eigen::Vector3d te0 = place(f0.at(1, 0)), te1 = place(f1.at(1, 0));
                seg(le0, le1, s.le * c);
                seg(te0, te1, s.te * c);
                tri(le0, le1, te1, s.surface * c);
                tri(le0, te1, te0, s.surface * c);
            }
            const auto ft = detail::frame_of(w, w.sections.size() - 1);
            seg(place(ft.at(0, 0)), place(ft.at(1, 0)), s.tip * ft.chord);
        }
    }
    for (const auto& r : cad.regions) {
        if (half && r.mirrored) continue;
        for (const auto* fr : {&r.frame0, &r.frame1}) {
            const double c = fr->chord;
            seg(fr->at(r.hinge_fraction, 0), fr->at(1, 0), s.cs * c);
        }
        seg(r.frame0.at(r.hinge_fraction, 0), r.frame1.at(r.hinge_fraction, 0),
            s.cs * std::min(r.frame0.chord, r.frame1.chord));
    }
    const auto& st = g.fuselage.stations;
    if (!st.empty()) {
        const double wmax = std::max(g.fuselage.max_width(), g.fuselage.max_height());
        for (std::size_t j = 0; j + 1 < st.size(); ++j) {
            const double r = 0.5 * std::min(std::max(st[j].width, st[j].height),
                                            std::max(st[j + 1].width, st[j + 1].height));
            seg(Eigen::Vector3d(st[j].x, 0, st[j].z_centre),
                Eigen::Vector3d(st[j + 1].x, 0, st[j + 1].z_centre), s.fuselage * wmax, r);
        }
        const Eigen::Vector3d nose(st.front().x, 0, st.front().z_centre);
        seg(nose, nose, s.nose * wmax);
        const Eigen::Vector3d tail(st.back().x, 0, st.back().z_centre);
        seg(tail, tail, s.nose * wmax, 0.5 * std::max(st.back().width, st.back().height));
    }
    return f;
}

void physical(int dim, const std::vector<int>& tags, const std::string& name) {
    const int gtag = gmsh::model::addPhysicalGroup(dim, tags);
    gmsh::model::setPhysicalName(dim, gtag, name);
}

/// Hinge of one copy ordered for meshmotion's sign convention (see CompanionControlSurface).
CompanionControlSurface companion_entry(const geometry::AircraftGeometry& g,
                                        const ControlRegion& r) {
    const auto& cs = g.control_surfaces[r.control_index];
    const auto& w = g.surface(cs.surface);
    CompanionControlSurface e;
    e.mode = std::string(geometry::to_string(cs.control));
    e.marker = r.marker;
    e.control_surface = cs.name;
    e.side = w.symmetric ? (r.mirrored ? "left" : "right") : "";
    auto h = g.hinge_line(cs);
    if (r.mirrored) {
        h[0] = mirrored(h[0]);
        h[1] = mirrored(h[1]);
    }
    // Horizontal: toward +y (trailing edge down); fins: toward -z (trailing edge toward -y).
    const bool swap = w.vertical ? (h[1].z() > h[0].z()) : (h[1].y() < h[0].y());
    if (swap) std::swap(h[0], h[1]);
    e.hinge = h;
    e.gain = r.mirrored ? cs.mirror_gain : cs.gain;
    return e;
}

}  // namespace

MeshResult generate_mesh(const aircraft::AircraftDefinition& a, const MeshOptions& o,
                         const std::filesystem::path& out) {
    const auto t0 = Clock::now();
    if (!(o.farfield_spans > 0.0) || !(o.size_factor > 0.0) || !std::isfinite(o.size_factor))
        throw InputError(
            fmt::format("meshgen: farfield_spans {} and size_factor {}; expected "
                        "positive numbers",
                        o.farfield_spans, o.size_factor));
    const std::string ext = out.extension().string();
    if (ext != ".su2" && ext != ".msh" && ext != ".cgns")
        throw InputError(
            fmt::format("--out: value '{}' has no mesh extension; expected a name "
                        "ending in .su2, .msh or .cgns",
                        out.string()));
    check_buildable(a);
    const bool half = o.model == Model::half;
    MeshResult res;
    GmshSession session(o.threads);
    Cad cad;
    try {
        cad = build_cad(a, o);
    } catch (const Error&) {
        throw;
    } catch (...) {
        std::string last;
        gmsh::logger::getLastError(last);
        throw NumericalError(fmt::format("meshgen: OpenCASCADE could not build the aircraft ({})",
                                         last.empty() ? "no message" : last));
    }
    res.notes = cad.notes;
    res.body_volume = cad.body_volume;
    res.seconds_cad = seconds_since(t0);

    for (const auto& m : cad.marker_order) physical(2, cad.marker_faces.at(m), m);
    physical(3, cad.fluid, "fluid");

    const Sizes sizes = sizes_for(o.level, o.size_factor);
    const SizeField field = size_field(a, cad, sizes, half);
    gmsh::model::mesh::setSizeCallback(
        [field](int, int, double x, double y, double z) { return field(x, y, z); });
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::option::setNumber("Mesh.MeshSizeMax", field.h_max);
    gmsh::option::setNumber("Mesh.Algorithm", 6);
    gmsh::option::setNumber("Mesh.Algorithm3D", 1);
    gmsh::option::setNumber("Mesh.Optimize", 1);
    const auto tm = Clock::now();
    try {
        gmsh::model::mesh::generate(3);
    } catch (const std::exception& e) {
        throw NumericalError(
            fmt::format("meshgen: gmsh failed to mesh the aircraft ({})", e.what()));
    } catch (...) {
        throw NumericalError("meshgen: gmsh failed to mesh the aircraft (unknown error)");
    }
    res.seconds_mesh = seconds_since(tm);

    // Gather the mesh: nodes, tetrahedra, marker triangles.
    std::vector<std::size_t> node_tags;
    std::vector<double> coords, param;
    gmsh::model::mesh::getNodes(node_tags, coords, param, -1, -1, false, false);
    std::size_t max_tag = 0;
    for (auto t : node_tags) max_tag = std::max(max_tag, t);
    std::vector<long long> index(max_tag + 1, -1);
    for (std::size_t i = 0; i < node_tags.size(); ++i)
        index[node_tags[i]] = static_cast<long long>(i);
    std::vector<std::array<long long, 4>> tets;
    for (int v : cad.fluid) {
        std::vector<std::size_t> et, nt;
        gmsh::model::mesh::getElementsByType(4, et, nt, v);
        for (std::size_t e = 0; e + 3 < nt.size(); e += 4)
            tets.push_back({index[nt[e]], index[nt[e + 1]], index[nt[e + 2]], index[nt[e + 3]]});
    }
    std::vector<std::array<long long, 3>> tris;
    for (const auto& m : cad.marker_order) {
        MarkerSummary ms;
        ms.name = m;
        ms.role = cad.roles.at(m);
        std::set<long long> nodes;
        for (int s : cad.marker_faces.at(m)) {
            std::vector<std::size_t> et, nt;
            gmsh::model::mesh::getElementsByType(2, et, nt, s);
            for (std::size_t e = 0; e + 2 < nt.size(); e += 3) {
                const std::array<long long, 3> f{index[nt[e]], index[nt[e + 1]], index[nt[e + 2]]};
                tris.push_back(f);
                ++ms.faces;
                Eigen::Vector3d p[3];
                for (int k = 0; k < 3; ++k) {
                    nodes.insert(f[static_cast<std::size_t>(k)]);
                    const auto q = static_cast<std::size_t>(f[static_cast<std::size_t>(k)]);
                    p[k] = Eigen::Vector3d(coords[3 * q], coords[3 * q + 1], coords[3 * q + 2]);
                }
                ms.area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
            }
        }
        ms.nodes = static_cast<long long>(nodes.size());
        if (ms.role == "wall") res.wetted_area += ms.area;
        res.markers.push_back(ms);
    }
    res.quality = assess_quality(coords, tets, tris);

    // Write the mesh atomically: a scratch name with the same extension, then a rename.
    std::error_code ec;
    const auto dir = out.has_parent_path() ? out.parent_path() : std::filesystem::path(".");
    std::filesystem::create_directories(dir, ec);
    const auto tmp =
        dir / fmt::format(".{}.tmp{}{}", out.stem().string(), static_cast<long>(getpid()), ext);
    gmsh::option::setNumber("Mesh.SaveAll", 0);
    gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
    gmsh::option::setNumber("Mesh.Binary", 0);
    try {
        if (ext == ".cgns") {
            std::vector<std::pair<std::string, long long>> counts;
            std::vector<std::string> roles;
            for (const auto& m : res.markers) {
                counts.emplace_back(m.name, m.faces);
                roles.push_back(m.role);
            }
            detail::write_cgns(tmp, coords, tets, tris, counts, roles);
        } else {
            gmsh::write(tmp.string());
        }
    } catch (const Error&) {
        std::filesystem::remove(tmp, ec);
        throw;
    } catch (...) {
        std::filesystem::remove(tmp, ec);
        std::string last;
        gmsh::logger::getLastError(last);
        throw IoError(fmt::format("{}: cannot write the mesh ({})", out.string(),
                                  last.empty() ? "gmsh gave no reason" : last));
    }
    if (!std::filesystem::exists(tmp, ec))
        throw IoError(fmt::format("{}: gmsh wrote no file", out.string()));
    std::filesystem::rename(tmp, out, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw IoError(fmt::format("{}: cannot write the mesh ({})", out.string(), ec.message()));
    }
    res.mesh_file = out;

    // Companion file.
    Companion& c = res.companion;
    c.mesh = out.filename().string();
    c.aircraft = a.file.string();
    c.aircraft_name = a.name;
    c.model = std::string(to_string(o.model));
    c.level = std::string(to_string(o.level));
    for (const auto& m : cad.marker_order) c.markers.push_back({m, cad.roles.at(m)});
    c.reference.aircraft_area = a.reference.area;
    c.reference.area = half ? 0.5 * a.reference.area : a.reference.area;
    c.reference.chord = a.reference.chord;
    c.reference.span = a.reference.span;
    c.reference.moment_point = a.moment_reference_geom;
    const auto& mc = a.mass_case();
    c.reference.cg_case = mc.name;
    c.reference.cg = mc.cg_geom;
    for (const auto& r : cad.regions) {
        if (half && r.mirrored) continue;
        if (a.geometry.control_surfaces[r.control_index].control == geometry::Control::none)
            continue;
        if (!cad.marker_faces.count(r.marker)) continue;
        c.control_surfaces.push_back(companion_entry(a.geometry, r));
    }
    res.companion_file = companion_path(out);
    write_companion(res.companion_file, c);
    res.seconds_total = seconds_since(t0);
    return res;
}

}  // namespace manta::meshgen
