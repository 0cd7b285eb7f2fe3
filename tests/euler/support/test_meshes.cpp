/// @file test_meshes.cpp
/// The Euler test meshes (test_meshes.hpp): gmsh builds the geometry and the mesh (or, for the
/// bump channel, takes a structured mesh as a discrete entity), writes MSH 4.1 ASCII into a
/// scratch directory, and `mesh::parse_gmsh` reads it back (extruding 2-D meshes into a slab).

#include "test_meshes.hpp"

#include <fmt/format.h>
#include <gmsh.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/mesh/readers.hpp"

// gmsh 4.8 keeps a few small allocations to the end of the process (LeakSanitizer in
// `make test-asan`, all inside libgmsh; as in tests/mesh/gmsh_fixtures.hpp).
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libgmsh\n";
}

namespace manta::test {
namespace {

namespace fs = std::filesystem;

/// One gmsh session: initialised quietly on one thread, finalised on scope exit (also when an
/// exception leaves the mesh function).
class GmshSession {
public:
    explicit GmshSession(const std::string& model) {
        gmsh::initialize(0, nullptr, false);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::option::setNumber("General.Verbosity", 0);
        gmsh::option::setNumber("General.NumThreads", 1);
        gmsh::model::add(model);
    }
    GmshSession(const GmshSession&) = delete;
    GmshSession& operator=(const GmshSession&) = delete;
    ~GmshSession() { gmsh::finalize(); }
};

/// Write the current gmsh model as MSH 4.1 ASCII to `file`.
void write_msh(const fs::path& file) {
    gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
    gmsh::option::setNumber("Mesh.Binary", 0);
    gmsh::option::setNumber("Mesh.SaveAll", 0);
    gmsh::write(file.string());
}

/// Write the current gmsh model as MSH 4.1 ASCII into a per-process scratch file, read it back
/// with MANTA's reader under the name `source`, and delete the file.
mesh::Mesh write_and_read(const std::string& source, const mesh::ReadOptions& options) {
    const fs::path dir = fs::temp_directory_path() /
                         fmt::format("manta-test-meshes-{}", static_cast<long>(getpid()));
    fs::create_directories(dir);
    const fs::path file = dir / "mesh.msh";
    write_msh(file);
    const std::string text = mesh::read_maybe_gzipped(file);
    std::error_code ec;
    fs::remove_all(dir, ec);
    return mesh::parse_gmsh(text, source, options);
}

/// A named physical group of entities of dimension `dim`.
void physical(int dim, const std::vector<int>& tags, const std::string& name) {
    const int g = gmsh::model::addPhysicalGroup(dim, tags);
    gmsh::model::setPhysicalName(dim, g, name);
}

/// NACA 0012 surface sampled finely: x, y (upper surface, y >= 0) and arc length s from the
/// leading edge, uniform in the angle theta with x = (1 - cos theta) / 2, in which the section
/// is smooth (sqrt(x) = sin(theta / 2)).
struct Section {
    std::vector<double> x, y, s;
};

const Section& section() {
    static const Section sec = [] {
        constexpr int n = 20000;
        Section r;
        r.x.resize(n + 1);
        r.y.resize(n + 1);
        r.s.resize(n + 1);
        for (int i = 0; i <= n; ++i) {
            const double theta = std::numbers::pi * i / n;
            r.x[i] = 0.5 * (1.0 - std::cos(theta));
            r.y[i] = naca0012_half_thickness(r.x[i]);
            r.s[i] =
                i == 0 ? 0.0 : r.s[i - 1] + std::hypot(r.x[i] - r.x[i - 1], r.y[i] - r.y[i - 1]);
        }
        return r;
    }();
    return sec;
}

/// `n` + 1 points on one surface from the leading edge (first) to the trailing edge (last),
/// spaced inversely to the point density w(s) = 1 + 8 exp(-s / 0.03) + 3 exp(-(S - s) / 0.03)
/// + a exp(-((x - x_shock) / 0.15)^2): leading- and trailing-edge clustering plus a band
/// around the expected shock. Returns (x, y >= 0).
std::vector<std::array<double, 2>> surface_points(int n, double a_shock, double x_shock,
                                                  double x_snap = 0.0) {
    const Section& sec = section();
    const std::size_t m = sec.x.size();
    const double total = sec.s.back();
    std::vector<double> w_cum(m, 0.0);
    auto density = [&](std::size_t i) {
        const double dx = (sec.x[i] - x_shock) / 0.15;
        return 1.0 + 8.0 * std::exp(-sec.s[i] / 0.03) + 3.0 * std::exp(-(total - sec.s[i]) / 0.03) +
               a_shock * std::exp(-dx * dx);
    };
    for (std::size_t i = 1; i < m; ++i)
        w_cum[i] = w_cum[i - 1] + 0.5 * (density(i) + density(i - 1)) * (sec.s[i] - sec.s[i - 1]);
    std::vector<std::array<double, 2>> pts;
    pts.push_back({0.0, 0.0});
    std::size_t j = 1;
    for (int k = 1; k < n; ++k) {
        const double target = w_cum.back() * k / n;
        while (w_cum[j] < target) ++j;
        const double t = (target - w_cum[j - 1]) / (w_cum[j] - w_cum[j - 1]);
        // Interpolate the chord position, then put the point on the exact section.
        const double x = sec.x[j - 1] + t * (sec.x[j] - sec.x[j - 1]);
        pts.push_back({x, naca0012_half_thickness(x)});
    }
    pts.push_back({1.0, 0.0});
    if (x_snap > 0.0) {
        // The interior point nearest to x_snap moves onto it (the flap's hinge station).
        std::size_t k = 1;
        for (std::size_t i = 1; i + 1 < pts.size(); ++i)
            if (std::abs(pts[i][0] - x_snap) < std::abs(pts[k][0] - x_snap)) k = i;
        pts[k] = {x_snap, naca0012_half_thickness(x_snap)};
    }
    return pts;
}

/// The gmsh model of the NACA 0012 of `naca0012_slab` (2-D, meshed), wall split at
/// `flap_hinge` when it is in (0, 1).
void naca0012_model(int level, double flap_hinge) {
    if (level < 0 || level > 2)
        throw InputError(fmt::format("naca0012_slab: level {}; expected 0, 1 or 2", level));
    if (!(flap_hinge == 0.0 || (flap_hinge >= 0.05 && flap_hinge <= 0.95)))
        throw InputError(fmt::format(
            "naca0012_slab: flap hinge x/c = {}; expected 0 (no flap) or a value in [0.05, 0.95]",
            flap_hinge));
    const double f = std::ldexp(1.0, -level);  // size factor
    const int n_side = 80 << level;            // intervals per surface
    const auto upper = surface_points(n_side, 1.0, 0.6, flap_hinge);
    const auto lower = surface_points(n_side, 0.5, 0.4, flap_hinge);

    namespace geo = gmsh::model::geo;
    // Closed polygon through the surface points: leading edge, upper surface to the trailing
    // edge, lower surface back. Each point carries its local spacing as mesh size.
    std::vector<std::array<double, 2>> ring(upper.begin(), upper.end());
    for (auto it = lower.rbegin() + 1; it + 1 != lower.rend(); ++it)
        ring.push_back({(*it)[0], -(*it)[1]});
    const std::size_t np = ring.size();
    std::vector<int> pts(np);
    for (std::size_t i = 0; i < np; ++i) {
        const auto& p = ring[i];
        const auto& a = ring[(i + np - 1) % np];
        const auto& b = ring[(i + 1) % np];
        const double h =
            0.5 * (std::hypot(p[0] - a[0], p[1] - a[1]) + std::hypot(b[0] - p[0], b[1] - p[1]));
        pts[i] = geo::addPoint(p[0], p[1], 0.0, h);
    }
    std::vector<int> wall(np);
    for (std::size_t i = 0; i < np; ++i) {
        wall[i] = geo::addLine(pts[i], pts[(i + 1) % np]);
        geo::mesh::setTransfiniteCurve(wall[i], 2);  // the wall nodes are exactly these points
    }

    const double radius = 50.0, xc = 0.5;
    const double h_far = 6.0 * f;
    const int c = geo::addPoint(xc, 0.0, 0.0, h_far);
    std::array<int, 4> q{};
    for (int k = 0; k < 4; ++k) {
        const double t = 0.5 * std::numbers::pi * k;
        q[k] = geo::addPoint(xc + radius * std::cos(t), radius * std::sin(t), 0.0, h_far);
    }
    std::vector<int> far(4);
    for (int k = 0; k < 4; ++k) far[k] = geo::addCircleArc(q[k], c, q[(k + 1) % 4]);
    const int outer = geo::addCurveLoop(far);
    const int inner = geo::addCurveLoop(wall);
    const int s = geo::addPlaneSurface({outer, inner});
    geo::synchronize();
    gmsh::model::removeEntities({{0, c}});

    namespace field = gmsh::model::mesh::field;
    field::add("Distance", 1);
    field::setNumbers(1, "CurvesList", std::vector<double>(wall.begin(), wall.end()));
    field::setNumber(1, "NumPointsPerCurve", 4);
    field::add("MathEval", 2);
    field::setString(2, "F", fmt::format("min({}, {} + {} * F1)", h_far, 0.02 * f, 0.12 * f));
    field::setAsBackgroundMesh(2);
    gmsh::option::setNumber("Mesh.Algorithm", 6);  // Frontal-Delaunay: regular triangles

    if (flap_hinge > 0.0) {
        std::vector<int> fixed, flap;
        for (std::size_t i = 0; i < np; ++i) {
            const double x_aft = std::min(ring[i][0], ring[(i + 1) % np][0]);
            (x_aft >= flap_hinge ? flap : fixed).push_back(wall[i]);
        }
        physical(1, fixed, "airfoil");
        physical(1, flap, "flap");
    } else {
        physical(1, wall, "airfoil");
    }
    physical(1, far, "farfield");
    physical(2, {s}, "fluid");
    gmsh::model::mesh::generate(2);
}

}  // namespace

double naca0012_half_thickness(double x) {
    if (!(x >= 0.0 && x <= 1.0))
        throw InputError(
            fmt::format("naca0012_half_thickness: x = {}; expected a chord fraction in [0, 1]", x));
    return 0.6 * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x -
                  0.1036 * x * x * x * x);
}

double naca0012_perimeter() {
    return 2.0 * section().s.back();
}

mesh::Mesh naca0012_slab(int level, double slab_thickness, double flap_hinge) {
    GmshSession gmsh_session("naca0012");
    naca0012_model(level, flap_hinge);
    mesh::ReadOptions options;
    options.slab_thickness = slab_thickness;
    return write_and_read(fmt::format("naca0012_slab(level {})", level), options);
}

void write_naca0012_msh(int level, const std::filesystem::path& file, double flap_hinge) {
    GmshSession gmsh_session("naca0012");
    naca0012_model(level, flap_hinge);
    write_msh(file);
}

mesh::Mesh turn_y_up_to_z_up(const mesh::Mesh& m) {
    mesh::Mesh r(m.source());
    r.reserve(m.n_nodes(), m.n_cells(), m.n_faces());
    for (mesh::Index i = 0; i < m.n_nodes(); ++i) {
        const Eigen::Vector3d x = m.node(i);
        r.add_node({x.x(), -x.z(), x.y()});
    }
    for (mesh::Index c = 0; c < m.n_cells(); ++c) r.add_cell(m.cell_type(c), m.cell(c));
    for (const std::string& name : m.markers()) r.add_marker(name);
    for (mesh::Index f = 0; f < m.n_faces(); ++f)
        r.add_face(m.face_type(f), m.face(f), m.face_marker(f));
    r.finalize();
    return r;
}

double bump_lower_wall(double x) {
    return 0.0625 * std::exp(-25.0 * x * x);
}

mesh::Mesh bump_channel(int level, double slab_thickness) {
    if (level < 0 || level > 3)
        throw InputError(fmt::format("bump_channel: level {}; expected 0 to 3", level));
    const int nx = 24 << level, ny = 8 << level;
    const double x0 = -1.5, x1 = 1.5, top = 0.8;

    GmshSession gmsh_session("bump");
    // The structured mesh as discrete entities: one surface and its four sides.
    const int surface = gmsh::model::addDiscreteEntity(2);
    const int inflow = gmsh::model::addDiscreteEntity(1);
    const int outflow = gmsh::model::addDiscreteEntity(1);
    const int lower = gmsh::model::addDiscreteEntity(1);
    const int upper = gmsh::model::addDiscreteEntity(1);
    auto node = [&](int i, int j) { return static_cast<std::size_t>(1 + i + (nx + 1) * j); };
    std::vector<std::size_t> tags;
    std::vector<double> xyz;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const double x = x0 + (x1 - x0) * i / nx;
            const double yw = bump_lower_wall(x);
            tags.push_back(node(i, j));
            xyz.insert(xyz.end(), {x, yw + (top - yw) * j / ny, 0.0});
        }
    gmsh::model::mesh::addNodes(2, surface, tags, xyz);
    std::vector<std::size_t> quads;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            quads.insert(quads.end(),
                         {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)});
    constexpr int msh_quad = 3, msh_line = 1;
    gmsh::model::mesh::addElementsByType(surface, msh_quad, {}, quads);
    std::vector<std::size_t> in_lines, out_lines, low_lines, up_lines;
    for (int j = 0; j < ny; ++j) {
        in_lines.insert(in_lines.end(), {node(0, j), node(0, j + 1)});
        out_lines.insert(out_lines.end(), {node(nx, j), node(nx, j + 1)});
    }
    for (int i = 0; i < nx; ++i) {
        low_lines.insert(low_lines.end(), {node(i, 0), node(i + 1, 0)});
        up_lines.insert(up_lines.end(), {node(i, ny), node(i + 1, ny)});
    }
    gmsh::model::mesh::addElementsByType(inflow, msh_line, {}, in_lines);
    gmsh::model::mesh::addElementsByType(outflow, msh_line, {}, out_lines);
    gmsh::model::mesh::addElementsByType(lower, msh_line, {}, low_lines);
    gmsh::model::mesh::addElementsByType(upper, msh_line, {}, up_lines);
    physical(1, {inflow}, "inflow");
    physical(1, {outflow}, "outflow");
    physical(1, {lower}, "lower");
    physical(1, {upper}, "upper");
    physical(2, {surface}, "fluid");
    mesh::ReadOptions options;
    options.slab_thickness = slab_thickness;
    return write_and_read(fmt::format("bump_channel(level {})", level), options);
}

mesh::Mesh wing_box(int level) {
    if (level < 0 || level > 1)
        throw InputError(fmt::format("wing_box: level {}; expected 0 or 1", level));
    const double f = level == 0 ? 1.0 : 0.75;
    const double h_le = 0.02 * f, h_te = 0.04 * f, h_mid = 0.08 * f, h_far = 2.5 * f;
    const double span = 3.0, x_split = 0.3;

    GmshSession gmsh_session("wing");
    namespace geo = gmsh::model::geo;
    // Root section in the x-z plane (y = 0): two splines per surface, split at x_split so the
    // mid-chord size can differ from the edges'.
    constexpr int n_ctrl = 40;
    const int p_le = geo::addPoint(0.0, 0.0, 0.0, h_le);
    const int p_te = geo::addPoint(1.0, 0.0, 0.0, h_te);
    auto spline = [&](int from, int to, double xa, double xb, double sign) {
        std::vector<int> ctrl{from};
        for (int i = 1; i < n_ctrl; ++i) {
            // cosine spacing in the chord fraction between xa and xb
            const double t = 0.5 * (1.0 - std::cos(std::numbers::pi * i / n_ctrl));
            const double x =
                xa +
                (xb - xa) * (xa == 0.0 ? 1.0 - std::cos(0.5 * std::numbers::pi * i / n_ctrl) : t);
            ctrl.push_back(geo::addPoint(x, 0.0, sign * naca0012_half_thickness(x), h_mid));
        }
        ctrl.push_back(to);
        return geo::addSpline(ctrl);
    };
    const int p_up = geo::addPoint(x_split, 0.0, naca0012_half_thickness(x_split), h_mid);
    const int p_lo = geo::addPoint(x_split, 0.0, -naca0012_half_thickness(x_split), h_mid);
    const std::array<int, 4> root{
        spline(p_le, p_up, 0.0, x_split, 1.0), spline(p_up, p_te, x_split, 1.0, 1.0),
        spline(p_le, p_lo, 0.0, x_split, -1.0), spline(p_lo, p_te, x_split, 1.0, -1.0)};
    gmsh::vectorpair ext;
    std::vector<int> wing_surfaces;
    std::array<int, 4> tip{};
    for (int k = 0; k < 4; ++k) {
        geo::extrude({{1, root[k]}}, 0.0, span, 0.0, ext);
        tip[k] = ext.at(0).second;  // the copy of the curve at y = span
        wing_surfaces.push_back(ext.at(1).second);
    }
    const int tip_loop = geo::addCurveLoop({tip[0], tip[1], -tip[3], -tip[2]});
    wing_surfaces.push_back(geo::addPlaneSurface({tip_loop}));
    const int root_loop = geo::addCurveLoop({root[0], root[1], -root[3], -root[2]});

    // Far-field box.
    const double xa = -10.0, xb = 11.0, yb = 10.0, za = -10.0, zb = 10.0;
    auto pt = [&](double x, double y, double z) { return geo::addPoint(x, y, z, h_far); };
    const std::array<int, 8> b{pt(xa, 0, za),  pt(xb, 0, za),  pt(xb, 0, zb),  pt(xa, 0, zb),
                               pt(xa, yb, za), pt(xb, yb, za), pt(xb, yb, zb), pt(xa, yb, zb)};
    // Lines of the box, shared between faces.
    auto line = [&](int i, int j) { return geo::addLine(b[i], b[j]); };
    const int l01 = line(0, 1), l12 = line(1, 2), l23 = line(2, 3), l30 = line(3, 0);
    const int l45 = line(4, 5), l56 = line(5, 6), l67 = line(6, 7), l74 = line(7, 4);
    const int l04 = line(0, 4), l15 = line(1, 5), l26 = line(2, 6), l37 = line(3, 7);
    const int sym_loop = geo::addCurveLoop({l01, l12, l23, l30});
    const int symmetry = geo::addPlaneSurface({sym_loop, root_loop});
    const std::vector<int> farfield{
        geo::addPlaneSurface({geo::addCurveLoop({l45, l56, l67, l74})}),    // y = yb
        geo::addPlaneSurface({geo::addCurveLoop({l01, l15, -l45, -l04})}),  // z = za
        geo::addPlaneSurface({geo::addCurveLoop({l23, l37, -l67, -l26})}),  // z = zb
        geo::addPlaneSurface({geo::addCurveLoop({l30, l04, -l74, -l37})}),  // x = xa
        geo::addPlaneSurface({geo::addCurveLoop({l12, l26, -l56, -l15})}),  // x = xb
    };
    std::vector<int> all{symmetry};
    all.insert(all.end(), farfield.begin(), farfield.end());
    all.insert(all.end(), wing_surfaces.begin(), wing_surfaces.end());
    const int volume = geo::addVolume({geo::addSurfaceLoop(all)});
    geo::synchronize();

    namespace field = gmsh::model::mesh::field;
    // Size growing with the distance from the wing's bounding box (analytic: gmsh 4.8's
    // Distance field samples surfaces far too densely and takes seconds).
    const std::string d_box =
        "Sqrt(Max(Max(-x, x - 1), 0)^2 + Max(y - 3, 0)^2 + Max(Fabs(z) - 0.06, 0)^2)";
    field::add("MathEval", 2);
    field::setString(2, "F", fmt::format("Min({}, {} + 0.2 * {})", h_far, 0.1 * f, d_box));
    field::setAsBackgroundMesh(2);

    physical(2, wing_surfaces, "wing");
    physical(2, {symmetry}, "symmetry");
    physical(2, farfield, "farfield");
    physical(3, {volume}, "fluid");
    gmsh::model::mesh::generate(3);
    return write_and_read(fmt::format("wing_box(level {})", level), {});
}

mesh::Mesh irregular_box(int n, double perturbation, std::uint32_t seed) {
    if (n < 2) throw InputError(fmt::format("irregular_box: n = {}; expected at least 2", n));
    if (!(perturbation >= 0.0 && perturbation <= 0.15))
        throw InputError(
            fmt::format("irregular_box: perturbation = {}; expected 0 to 0.15", perturbation));
    using mesh::CellType;
    using mesh::FaceType;
    using mesh::Index;
    // std::mt19937 is fully specified, so the mesh is the same on every platform; the
    // distributions of <random> are not, hence the explicit conversion.
    std::mt19937 rng(seed);
    auto uniform = [&rng] { return static_cast<double>(rng()) / 4294967296.0; };  // [0, 1)
    const double h = 1.0 / n;
    const int m = n + 1;
    mesh::Mesh result("irregular_box");
    auto grid = [m](int i, int j, int k) { return static_cast<Index>(i + m * (j + m * k)); };
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) result.add_node(Eigen::Vector3d(i * h, j * h, k * h));

    // Sub-cube kinds and which of the grid's faces are split into two triangles: a face is split
    // if a tetrahedral cube touches it, or it is the top or bottom of a prism cube. A hexahedron
    // or prism cube that then meets a split face it cannot have becomes a pyramid cube, which
    // fits any pattern, so one pass settles everything.
    enum class Kind { hexa, prisms, tetras, pyramids };
    std::vector<Kind> kind(static_cast<std::size_t>(n) * n * n);
    for (auto& c : kind) {  // weighted toward hexahedra and prisms, which tetrahedra displace
        const auto r = rng() % 20;
        c = r < 9 ? Kind::hexa : r < 15 ? Kind::prisms : r < 17 ? Kind::tetras : Kind::pyramids;
    }
    auto cube = [n](int i, int j, int k) { return static_cast<std::size_t>(i + n * (j + n * k)); };
    // Face (axis, i, j, k): the face normal to `axis` at grid position i (or j, k) along it,
    // with the cube (i, j, k) above it.
    auto face_id = [m](int axis, int i, int j, int k) {
        return static_cast<std::size_t>(axis + 3 * (i + m * (j + m * k)));
    };
    std::vector<char> split(static_cast<std::size_t>(3) * m * m * m, 0);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const Kind c = kind[cube(i, j, k)];
                for (int axis = 0; axis < 3; ++axis)
                    for (int side = 0; side < 2; ++side) {
                        const bool must = c == Kind::tetras || (c == Kind::prisms && axis == 2);
                        if (must)
                            split[face_id(axis, i + (axis == 0 ? side : 0),
                                          j + (axis == 1 ? side : 0), k + (axis == 2 ? side : 0))] =
                                1;
                    }
            }
    auto is_split = [&](int i, int j, int k, int axis, int side) {
        return split[face_id(axis, i + (axis == 0 ? side : 0), j + (axis == 1 ? side : 0),
                             k + (axis == 2 ? side : 0))] != 0;
    };
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                Kind& c = kind[cube(i, j, k)];
                for (int axis = 0; axis < 3; ++axis)
                    for (int side = 0; side < 2; ++side)
                        if (is_split(i, j, k, axis, side) &&
                            (c == Kind::hexa || (c == Kind::prisms && axis != 2)))
                            c = Kind::pyramids;
            }

    // Cells with their orientation fixed from the unperturbed coordinates (the perturbation
    // below is too small to invert any of them).
    auto x = [&](Index v) { return result.node(v); };
    auto add_tetra = [&](std::array<Index, 4> v) {
        if ((x(v[1]) - x(v[0])).cross(x(v[2]) - x(v[0])).dot(x(v[3]) - x(v[0])) < 0.0)
            std::swap(v[1], v[2]);
        result.add_cell(CellType::tetra, v);
    };
    auto add_pyramid = [&](std::array<Index, 5> v) {
        const Eigen::Vector3d normal = (x(v[2]) - x(v[0])).cross(x(v[3]) - x(v[1]));
        if (normal.dot(x(v[4]) - x(v[0])) < 0.0) std::swap(v[1], v[3]);
        result.add_cell(CellType::pyramid, v);
    };
    auto add_prism = [&](std::array<Index, 6> v) {
        // VTK wedge: (0, 1, 2) has its normal away from (3, 4, 5).
        const Eigen::Vector3d normal = (x(v[1]) - x(v[0])).cross(x(v[2]) - x(v[0]));
        if (normal.dot(x(v[3]) - x(v[0])) > 0.0) {
            std::swap(v[1], v[2]);
            std::swap(v[4], v[5]);
        }
        result.add_cell(CellType::prism, v);
    };
    for (const char* name : {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"})
        result.add_marker(name);

    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                // Corner b = dx + 2 dy + 4 dz of the cube.
                std::array<Index, 8> c{};
                for (int b = 0; b < 8; ++b)
                    c[b] = grid(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2));
                // The face normal to `axis` on `side` as a cycle (c00, c10, c11, c01) in the two
                // other axes, so (c00, c11) is its lowest-to-highest diagonal.
                auto face = [&](int axis, int side) {
                    const int u = axis == 0 ? 1 : 0, w = axis == 2 ? 1 : 2;
                    const int base = side << axis;
                    return std::array<Index, 4>{c[base], c[base | 1 << u],
                                                c[base | 1 << u | 1 << w], c[base | 1 << w]};
                };
                switch (kind[cube(i, j, k)]) {
                    case Kind::hexa:
                        result.add_cell(
                            CellType::hexa,
                            std::array<Index, 8>{c[0], c[1], c[3], c[2], c[4], c[5], c[7], c[6]});
                        break;
                    case Kind::prisms:  // split by the vertical plane through (0,0)-(1,1)
                        add_prism({c[0], c[1], c[3], c[4], c[5], c[7]});
                        add_prism({c[0], c[3], c[2], c[4], c[7], c[6]});
                        break;
                    case Kind::tetras:  // Kuhn: the paths 0 -> e_a -> e_a + e_b -> 7
                        for (const auto& [a, b2] : std::array<std::array<int, 2>, 6>{
                                 {{1, 2}, {1, 4}, {2, 1}, {2, 4}, {4, 1}, {4, 2}}})
                            add_tetra({c[0], c[a], c[a | b2], c[7]});
                        break;
                    case Kind::pyramids: {
                        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
                        for (Index v : c) centre += x(v) / 8.0;
                        const Index apex = result.add_node(centre);
                        for (int axis = 0; axis < 3; ++axis)
                            for (int side = 0; side < 2; ++side) {
                                const auto q = face(axis, side);
                                if (is_split(i, j, k, axis, side)) {
                                    add_tetra({q[0], q[1], q[2], apex});
                                    add_tetra({q[0], q[2], q[3], apex});
                                } else {
                                    add_pyramid({q[0], q[1], q[2], q[3], apex});
                                }
                            }
                        break;
                    }
                }
                // Boundary faces of this cube.
                const std::array<int, 3> at{i, j, k};
                for (int axis = 0; axis < 3; ++axis)
                    for (int side = 0; side < 2; ++side) {
                        if (at[axis] + side != (side == 0 ? 0 : n)) continue;
                        const int marker = 2 * axis + side;
                        const auto q = face(axis, side);
                        if (is_split(i, j, k, axis, side)) {
                            result.add_face(FaceType::triangle,
                                            std::array<Index, 3>{q[0], q[1], q[2]}, marker);
                            result.add_face(FaceType::triangle,
                                            std::array<Index, 3>{q[0], q[2], q[3]}, marker);
                        } else {
                            result.add_face(FaceType::quad, q, marker);
                        }
                    }
            }

    // Perturb the interior grid nodes and the cube centres (added after the grid nodes).
    mesh::Mesh moved("irregular_box");
    for (Index v = 0; v < result.n_nodes(); ++v) {
        Eigen::Vector3d p = result.node(v);
        const bool interior =
            v >= m * m * m || ((p.array() > 0.5 * h).all() && (p.array() < 1.0 - 0.5 * h).all());
        if (interior)
            for (int d = 0; d < 3; ++d) p[d] += (2.0 * uniform() - 1.0) * perturbation * h;
        moved.add_node(p);
    }
    for (Index cidx = 0; cidx < result.n_cells(); ++cidx)
        moved.add_cell(result.cell_type(cidx), result.cell(cidx));
    for (const auto& name : result.markers()) moved.add_marker(name);
    for (Index f = 0; f < result.n_faces(); ++f)
        moved.add_face(result.face_type(f), result.face(f), result.face_marker(f));
    moved.finalize();
    return moved;
}

}  // namespace manta::test
