/// @file deflection.cpp
/// Steady control deflections of a mesh (deflection.hpp), shared by the Euler source and the
/// case driver.

#include "manta/euler/deflection.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "manta/aero/motion.hpp"
#include "manta/core/error.hpp"

namespace manta::euler {

namespace {

constexpr double deg_per_rad = 57.29577951308232;

/// The motion the steady deformation is built with: two samples of zeros, one mode column per
/// mode of the surfaces (elevator, aileron and rudder always).
aero::Motion still_motion(const std::vector<meshmotion::ControlSurfaceSpec>& surfaces) {
    aero::Motion m;
    m.t = {0.0, 1.0};
    for (auto& c : m.position) c = {0.0, 0.0};
    for (auto& c : m.angles) c = {0.0, 0.0};
    std::vector<std::string> names(deflection_modes.begin(), deflection_modes.end());
    for (const auto& s : surfaces)
        if (std::find(names.begin(), names.end(), s.mode) == names.end()) names.push_back(s.mode);
    for (auto& n : names) m.add_mode(n, {0.0, 0.0});
    return m;
}

/// "elevator 5 deg, rudder -2 deg": the components of `d` other than 0.
std::string deflection_text(const ModeDeflections& d, const DeflectionNaming& naming) {
    std::string s;
    for (std::size_t k = 0; k < d.size(); ++k)
        if (d[k] != 0.0)
            s += fmt::format("{}{} {:.6g}{}", s.empty() ? "" : ", ", naming.names[k],
                             d[k] * deg_per_rad, naming.unit);
    return s;
}

}  // namespace

bool deflects(const ModeDeflections& d) noexcept {
    return std::any_of(d.begin(), d.end(), [](double v) { return v != 0.0; });
}

meshmotion::DeformationOptions motion_deformation(const mesh::Mesh& mesh,
                                                  const std::vector<BoundaryKind>& roles,
                                                  meshmotion::BodyMotion body, double rigid_radius,
                                                  double fixed_radius) {
    meshmotion::DeformationOptions options;
    options.body = body;
    options.rigid_radius = rigid_radius;
    options.fixed_radius = fixed_radius;
    for (std::size_t m = 0; m < roles.size() && m < mesh.markers().size(); ++m) {
        if (roles[m] == BoundaryKind::wall)
            options.wall_markers.push_back(mesh.markers()[m]);
        else if (roles[m] == BoundaryKind::symmetry)
            options.symmetry_markers.push_back(mesh.markers()[m]);
    }
    return options;
}

std::unique_ptr<meshmotion::MeshMotion> deflection_motion(
    const mesh::Mesh& mesh, const std::vector<BoundaryKind>& roles,
    const Eigen::Vector3d& moment_point,
    const std::vector<meshmotion::ControlSurfaceSpec>& surfaces, const std::string& config) {
    if (surfaces.empty()) return nullptr;
    meshmotion::MotionPlacement placement;
    placement.reference_point = moment_point;
    placement.motion_source = config;
    // Rigid body: the wall markers are not used, the symmetry planes slide.
    return std::make_unique<meshmotion::MeshMotion>(
        mesh, still_motion(surfaces), placement, surfaces,
        motion_deformation(mesh, roles, meshmotion::BodyMotion::rigid, 0.0, 0.0));
}

std::string surface_modes(const std::vector<meshmotion::ControlSurfaceSpec>& surfaces) {
    std::vector<std::string> modes;
    for (const auto& s : surfaces)
        if (std::find(modes.begin(), modes.end(), s.mode) == modes.end()) modes.push_back(s.mode);
    if (modes.empty()) return "none";
    std::string text;
    for (const auto& m : modes) text += (text.empty() ? "" : ", ") + m;
    return text;
}

std::vector<double> surface_deflections(const std::vector<meshmotion::ControlSurfaceSpec>& surfaces,
                                        const ModeDeflections& d, const DeflectionNaming& naming) {
    std::vector<double> delta(surfaces.size(), 0.0);
    for (std::size_t k = 0; k < d.size(); ++k) {
        if (d[k] == 0.0) continue;
        if (!std::isfinite(d[k]))
            throw InputError(fmt::format("{}: {} {}{}; expected a finite angle", naming.who,
                                         naming.names[k], d[k] * deg_per_rad, naming.unit));
        bool found = false;
        for (std::size_t s = 0; s < surfaces.size(); ++s)
            if (surfaces[s].mode == deflection_modes[k]) {
                delta[s] = surfaces[s].gain * d[k];
                found = true;
            }
        if (!found)
            throw InputError(fmt::format(
                "{}: {} {:.6g}{}: {} has no control surface of mode '{}' (the modes of its "
                "control surfaces: {}); expected a control_surfaces entry with mode: {}",
                naming.who, naming.names[k], d[k] * deg_per_rad, naming.unit, naming.config,
                deflection_modes[k], surface_modes(surfaces), deflection_modes[k]));
    }
    return delta;
}

void deflect_mesh(mesh::Mesh& mesh, mesh::DualMetrics& dual, const meshmotion::MeshMotion* motion,
                  const std::vector<meshmotion::ControlSurfaceSpec>& surfaces,
                  const ModeDeflections& d, const DeflectionNaming& naming,
                  std::span<const mesh::Index> node_numbers) {
    const std::vector<double> delta = surface_deflections(surfaces, d, naming);
    if (!deflects(d)) return;
    if (!motion)  // surface_deflections found a surface for every mode that deflects
        throw InputError(fmt::format("{}: {}: the control surfaces of {} are not set up",
                                     naming.who, deflection_text(d, naming), naming.config));
    Eigen::Matrix3Xd x;
    motion->deformed(delta, x);
    mesh.set_coordinates(std::span<const double>(x.data(), static_cast<std::size_t>(x.size())));
    mesh::update_dual_metrics(mesh, dual);
    const auto& v = dual.dual_volumes;
    const auto bad = std::min_element(v.begin(), v.end());
    if (bad != v.end() && !(*bad > 0.0)) {
        const auto node = static_cast<std::size_t>(bad - v.begin());
        throw InputError(fmt::format(
            "{}: {} fold{} the mesh at node {} (dual volume {:.3g} m^3); expected deflections "
            "the control surfaces of {} can take",
            naming.who, deflection_text(d, naming),
            std::count_if(d.begin(), d.end(), [](double a) { return a != 0.0; }) > 1 ? "" : "s",
            node < node_numbers.size() ? node_numbers[node] : static_cast<mesh::Index>(node), *bad,
            naming.config));
    }
}

}  // namespace manta::euler
