/// @file flap_meshes.cpp
/// Test meshes with a flap marker (flap_meshes.hpp).

#include "flap_meshes.hpp"

#include <fmt/format.h>
#include <gmsh.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "manta/core/error.hpp"
#include "manta/mesh/readers.hpp"

// gmsh 4.8 keeps a few small allocations to the end of the process (LeakSanitizer in
// `make test-asan`, all inside libgmsh).
extern "C" const char* __lsan_default_suppressions() {
    return "leak:libgmsh\n";
}

namespace manta::test {
namespace {

namespace fs = std::filesystem;

/// One quiet single-threaded gmsh session, finalised on scope exit.
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

mesh::Mesh write_and_read(const std::string& source) {
    const fs::path dir =
        fs::temp_directory_path() / fmt::format("manta-meshmotion-{}", static_cast<long>(getpid()));
    fs::create_directories(dir);
    const fs::path file = dir / "mesh.msh";
    gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
    gmsh::option::setNumber("Mesh.Binary", 0);
    gmsh::option::setNumber("Mesh.SaveAll", 0);
    gmsh::write(file.string());
    const std::string text = mesh::read_maybe_gzipped(file);
    std::error_code ec;
    fs::remove_all(dir, ec);
    return mesh::parse_gmsh(text, source, {});
}

void physical(int dim, const std::vector<int>& tags, const std::string& name) {
    const int g = gmsh::model::addPhysicalGroup(dim, tags);
    gmsh::model::setPhysicalName(dim, g, name);
}

}  // namespace

double naca0012_thickness(double x) {
    if (!(x >= 0.0 && x <= 1.0))
        throw InputError(fmt::format("naca0012_thickness: x = {}; expected [0, 1]", x));
    return 0.6 * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x -
                  0.1036 * x * x * x * x);
}

mesh::Mesh flap_wing(double size) {
    if (!(size >= 0.2 && size <= 2.0))
        throw InputError(fmt::format("flap_wing: size {}; expected 0.2 to 2", size));
    const FlapGeometry fg;
    const double f = size;
    const double h_le = 0.02 * f, h_te = 0.04 * f, h_mid = 0.08 * f, h_flap = 0.03 * f,
                 h_far = 2.5 * f;
    const double span = 3.0, x_split = 0.3;

    GmshSession gmsh_session("flap_wing");
    namespace geo = gmsh::model::geo;
    constexpr int n_ctrl = 30;
    auto spline = [&](int from, int to, double xa, double xb, double sign) {
        std::vector<int> ctrl{from};
        for (int i = 1; i < n_ctrl; ++i) {
            const double t = 0.5 * (1.0 - std::cos(std::numbers::pi * i / n_ctrl));
            const double x =
                xa +
                (xb - xa) * (xa == 0.0 ? 1.0 - std::cos(0.5 * std::numbers::pi * i / n_ctrl) : t);
            ctrl.push_back(geo::addPoint(x, 0.0, sign * naca0012_thickness(x), h_mid));
        }
        ctrl.push_back(to);
        return geo::addSpline(ctrl);
    };
    const int p_le = geo::addPoint(0.0, 0.0, 0.0, h_le);
    const int p_te = geo::addPoint(1.0, 0.0, 0.0, h_te);
    const double xh = fg.hinge_x;
    const int p_up = geo::addPoint(x_split, 0.0, naca0012_thickness(x_split), h_mid);
    const int p_lo = geo::addPoint(x_split, 0.0, -naca0012_thickness(x_split), h_mid);
    const int h_up = geo::addPoint(xh, 0.0, naca0012_thickness(xh), h_flap);
    const int h_lo = geo::addPoint(xh, 0.0, -naca0012_thickness(xh), h_flap);
    // Root curves: upper LE-0.3, 0.3-hinge, hinge-TE, then the lower ones.
    std::vector<int> curves{
        spline(p_le, p_up, 0.0, x_split, 1.0), spline(p_up, h_up, x_split, xh, 1.0),
        spline(h_up, p_te, xh, 1.0, 1.0),      spline(p_le, p_lo, 0.0, x_split, -1.0),
        spline(p_lo, h_lo, x_split, xh, -1.0), spline(h_lo, p_te, xh, 1.0, -1.0)};
    const std::vector<int> root = curves;
    std::vector<int> wing_surfaces, flap_surfaces;
    const std::array<double, 3> dy{fg.y_in, fg.y_out - fg.y_in, span - fg.y_out};
    gmsh::vectorpair ext;
    for (int seg = 0; seg < 3; ++seg)
        for (std::size_t k = 0; k < curves.size(); ++k) {
            geo::extrude({{1, curves[k]}}, 0.0, dy[static_cast<std::size_t>(seg)], 0.0, ext);
            curves[k] = ext.at(0).second;
            const bool flap = seg == 1 && (k == 2 || k == 5);
            (flap ? flap_surfaces : wing_surfaces).push_back(ext.at(1).second);
        }
    const int tip_loop =
        geo::addCurveLoop({curves[0], curves[1], curves[2], -curves[5], -curves[4], -curves[3]});
    wing_surfaces.push_back(geo::addPlaneSurface({tip_loop}));
    const int root_loop =
        geo::addCurveLoop({root[0], root[1], root[2], -root[5], -root[4], -root[3]});

    const double xa = -10.0, xb = 11.0, yb = 10.0, za = -10.0, zb = 10.0;
    auto pt = [&](double x, double y, double z) { return geo::addPoint(x, y, z, h_far); };
    const std::array<int, 8> b{pt(xa, 0, za),  pt(xb, 0, za),  pt(xb, 0, zb),  pt(xa, 0, zb),
                               pt(xa, yb, za), pt(xb, yb, za), pt(xb, yb, zb), pt(xa, yb, zb)};
    auto line = [&](int i, int j) { return geo::addLine(b[i], b[j]); };
    const int l01 = line(0, 1), l12 = line(1, 2), l23 = line(2, 3), l30 = line(3, 0);
    const int l45 = line(4, 5), l56 = line(5, 6), l67 = line(6, 7), l74 = line(7, 4);
    const int l04 = line(0, 4), l15 = line(1, 5), l26 = line(2, 6), l37 = line(3, 7);
    const int symmetry = geo::addPlaneSurface({geo::addCurveLoop({l01, l12, l23, l30}), root_loop});
    const std::vector<int> farfield{
        geo::addPlaneSurface({geo::addCurveLoop({l45, l56, l67, l74})}),
        geo::addPlaneSurface({geo::addCurveLoop({l01, l15, -l45, -l04})}),
        geo::addPlaneSurface({geo::addCurveLoop({l23, l37, -l67, -l26})}),
        geo::addPlaneSurface({geo::addCurveLoop({l30, l04, -l74, -l37})}),
        geo::addPlaneSurface({geo::addCurveLoop({l12, l26, -l56, -l15})}),
    };
    std::vector<int> all{symmetry};
    all.insert(all.end(), farfield.begin(), farfield.end());
    all.insert(all.end(), wing_surfaces.begin(), wing_surfaces.end());
    all.insert(all.end(), flap_surfaces.begin(), flap_surfaces.end());
    const int volume = geo::addVolume({geo::addSurfaceLoop(all)});
    geo::synchronize();

    namespace field = gmsh::model::mesh::field;
    const std::string d_box =
        "Sqrt(Max(Max(-x, x - 1), 0)^2 + Max(y - 3, 0)^2 + Max(Fabs(z) - 0.06, 0)^2)";
    field::add("MathEval", 1);
    field::setString(1, "F", fmt::format("Min({}, {} + {} * {})", h_far, 0.1 * f, 0.2 * f, d_box));
    field::setAsBackgroundMesh(1);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);

    physical(2, wing_surfaces, "wing");
    physical(2, flap_surfaces, "flap");
    physical(2, {symmetry}, "symmetry");
    physical(2, farfield, "farfield");
    physical(3, {volume}, "fluid");
    gmsh::model::mesh::generate(3);
    return write_and_read(fmt::format("flap_wing(size {})", size));
}

mesh::Mesh flap_plate(int n_x, int n_y, int n_z, bool prisms) {
    if (n_x < 3 || n_x % 3 != 0 || n_y < 4 || n_y % 4 != 0 || n_z < 1)
        throw InputError(fmt::format(
            "flap_plate: {} x {} x {}; expected n_x a multiple of 3, n_y a multiple of 4", n_x, n_y,
            n_z));
    using mesh::Index;
    mesh::Mesh m(fmt::format("flap_plate({}x{}x{})", n_x, n_y, n_z));
    auto id = [&](int i, int j, int k) {
        return static_cast<Index>(i + (n_x + 1) * (j + (n_y + 1) * k));
    };
    for (int k = 0; k <= n_z; ++k)
        for (int j = 0; j <= n_y; ++j)
            for (int i = 0; i <= n_x; ++i)
                m.add_node(Eigen::Vector3d(3.0 * i / n_x, 1.0 * j / n_y, 1.0 * k / n_z));
    const int wall = m.add_marker("wall"), flap = m.add_marker("flap"),
              far = m.add_marker("farfield");
    for (int k = 0; k < n_z; ++k)
        for (int j = 0; j < n_y; ++j)
            for (int i = 0; i < n_x; ++i) {
                const std::array<Index, 8> c{id(i, j, k),
                                             id(i + 1, j, k),
                                             id(i + 1, j + 1, k),
                                             id(i, j + 1, k),
                                             id(i, j, k + 1),
                                             id(i + 1, j, k + 1),
                                             id(i + 1, j + 1, k + 1),
                                             id(i, j + 1, k + 1)};
                if (prisms) {
                    // Split along the diagonal (0, 2): (0, 1, 2) and (0, 2, 3) over z; the VTK
                    // wedge's (0, 1, 2) has its normal away from (3, 4, 5).
                    m.add_cell(mesh::CellType::prism,
                               std::array<Index, 6>{c[0], c[2], c[1], c[4], c[6], c[5]});
                    m.add_cell(mesh::CellType::prism,
                               std::array<Index, 6>{c[0], c[3], c[2], c[4], c[7], c[6]});
                } else {
                    m.add_cell(mesh::CellType::hexa, c);
                }
            }
    auto quad = [&](Index a, Index b, Index c, Index d, int marker) {
        if (prisms && marker != far) {
            m.add_face(mesh::FaceType::triangle, std::array<Index, 3>{a, b, c}, marker);
            m.add_face(mesh::FaceType::triangle, std::array<Index, 3>{a, c, d}, marker);
        } else {
            m.add_face(mesh::FaceType::quad, std::array<Index, 4>{a, b, c, d}, marker);
        }
    };
    for (int j = 0; j < n_y; ++j)
        for (int i = 0; i < n_x; ++i) {
            quad(id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0),
                 3 * i >= n_x && 3 * i < 2 * n_x && 4 * j >= n_y && 4 * j < 3 * n_y ? flap : wall);
            const int k = n_z;
            if (prisms) {
                m.add_face(mesh::FaceType::triangle,
                           std::array<Index, 3>{id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k)},
                           far);
                m.add_face(mesh::FaceType::triangle,
                           std::array<Index, 3>{id(i, j, k), id(i + 1, j + 1, k), id(i, j + 1, k)},
                           far);
            } else {
                quad(id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), far);
            }
        }
    for (int k = 0; k < n_z; ++k) {
        for (int i = 0; i < n_x; ++i) {
            quad(id(i, 0, k), id(i + 1, 0, k), id(i + 1, 0, k + 1), id(i, 0, k + 1), far);
            quad(id(i, n_y, k), id(i + 1, n_y, k), id(i + 1, n_y, k + 1), id(i, n_y, k + 1), far);
        }
        for (int j = 0; j < n_y; ++j) {
            quad(id(0, j, k), id(0, j + 1, k), id(0, j + 1, k + 1), id(0, j, k + 1), far);
            quad(id(n_x, j, k), id(n_x, j + 1, k), id(n_x, j + 1, k + 1), id(n_x, j, k + 1), far);
        }
    }
    m.finalize();
    return m;
}

}  // namespace manta::test
