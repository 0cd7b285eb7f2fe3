/// @file cmd_mesh.cpp
/// `manta mesh`: an aircraft's tetrahedral mesh and its companion file (docs/meshgen.md). The
/// module meshgen does the work; this file parses and prints.

#include <fmt/format.h>

#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/meshgen/meshgen.hpp"

namespace manta::cli {

namespace {

nlohmann::json vec(const Eigen::Vector3d& v) {
    return {v.x(), v.y(), v.z()};
}

nlohmann::json to_json(const meshgen::MeshResult& r) {
    const auto& q = r.quality;
    nlohmann::json markers = nlohmann::json::array();
    for (const auto& m : r.markers)
        markers.push_back({{"name", m.name},
                           {"role", m.role},
                           {"faces", m.faces},
                           {"nodes", m.nodes},
                           {"area", m.area}});
    nlohmann::json hinges = nlohmann::json::array();
    for (const auto& c : r.companion.control_surfaces)
        hinges.push_back({{"mode", c.mode},
                          {"marker", c.marker},
                          {"hinge", {vec(c.hinge[0]), vec(c.hinge[1])}},
                          {"gain", c.gain}});
    const auto& ref = r.companion.reference;
    return {{"mesh", r.mesh_file.string()},
            {"companion", r.companion_file.string()},
            {"model", r.companion.model},
            {"level", r.companion.level},
            {"quality",
             {{"nodes", q.nodes},
              {"cells", q.cells},
              {"boundary_faces", q.boundary_faces},
              {"min_dihedral_deg", q.min_dihedral_deg},
              {"max_dihedral_deg", q.max_dihedral_deg},
              {"max_volume_ratio", q.max_volume_ratio},
              {"slivers", q.slivers},
              {"sliver_definition",
               fmt::format("a cell with a dihedral angle below {0} deg or above {1} deg",
                           q.sliver_min_deg, 180.0 - q.sliver_min_deg)},
              {"surface_closed", q.surface_closed},
              {"open_edges", q.open_edges},
              {"unmarked_faces", q.unmarked_faces},
              {"volume_positive", q.volume_positive},
              {"volume", q.volume},
              {"min_cell_volume", q.min_cell_volume}}},
            {"markers", markers},
            {"wetted_area", r.wetted_area},
            {"body_volume", r.body_volume},
            {"reference",
             {{"area", ref.area},
              {"aircraft_area", ref.aircraft_area},
              {"chord", ref.chord},
              {"span", ref.span},
              {"moment_point", vec(ref.moment_point)}}},
            {"control_surfaces", hinges},
            {"notes", r.notes},
            {"seconds",
             {{"cad", r.seconds_cad}, {"mesh", r.seconds_mesh}, {"total", r.seconds_total}}}};
}

void print_text(const meshgen::MeshResult& r) {
    const auto& q = r.quality;
    fmt::print("mesh       {} ({} model, {} level)\n", r.mesh_file.string(), r.companion.model,
               r.companion.level);
    fmt::print("companion  {}\n", r.companion_file.string());
    fmt::print("nodes {}  cells {}  boundary faces {}\n", q.nodes, q.cells, q.boundary_faces);
    fmt::print("dihedral angles {:.2f} .. {:.2f} deg, largest neighbour volume ratio {:.1f}\n",
               q.min_dihedral_deg, q.max_dihedral_deg, q.max_volume_ratio);
    fmt::print("slivers (a dihedral angle below {} or above {} deg): {}\n", q.sliver_min_deg,
               180.0 - q.sliver_min_deg, q.slivers);
    fmt::print(
        "surface closed: {} ({} open edges, {} unmarked faces)   volume positive: {} "
        "(smallest cell {:.3g} m^3)\n",
        q.surface_closed ? "yes" : "NO", q.open_edges, q.unmarked_faces,
        q.volume_positive ? "yes" : "NO", q.min_cell_volume);
    fmt::print("{:<16} {:<9} {:>9} {:>9} {:>12}\n", "marker", "role", "faces", "nodes", "area m^2");
    for (const auto& m : r.markers)
        fmt::print("{:<16} {:<9} {:>9} {:>9} {:>12.4f}\n", m.name, m.role, m.faces, m.nodes,
                   m.area);
    fmt::print("wetted area {:.3f} m^2, body volume {:.3f} m^3\n", r.wetted_area, r.body_volume);
    for (const auto& n : r.notes) fmt::print("note: {}\n", n);
    fmt::print("time: CAD {:.1f} s, meshing {:.1f} s, total {:.1f} s\n", r.seconds_cad,
               r.seconds_mesh, r.seconds_total);
}

}  // namespace

void add_mesh(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("mesh",
                                   "Tetrahedral mesh of an aircraft file's shape, with its "
                                   "companion file (markers, hinge lines, reference values)");
    struct Opts {
        std::string aircraft, model = "half", level = "coarse", out;
        int threads = 1;
        bool json = false;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("--aircraft", o->aircraft, "Aircraft file (YAML)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--model", o->model, "half (symmetry plane at y = 0) or full")
        ->check(CLI::IsMember({"half", "full"}));
    cmd->add_option("--level", o->level, "coarse, medium or fine (about 2.5x apart in nodes)")
        ->check(CLI::IsMember({"coarse", "medium", "fine"}));
    cmd->add_option("--out", o->out,
                    "Mesh file: .su2, .msh or .cgns; the companion file is "
                    "written beside it as NAME.mesh.yaml")
        ->required();
    cmd->add_option("--threads", o->threads, "Threads gmsh may use")->check(CLI::Range(1, 64));
    cmd->add_flag("--json", o->json, "Print one JSON object");
    cmd->callback([o, &action] {
        action = [o]() -> int {
            const auto aircraft = aircraft::load_aircraft(o->aircraft);
            meshgen::MeshOptions opts;
            opts.model = meshgen::parse_model(o->model);
            opts.level = meshgen::parse_level(o->level);
            opts.threads = o->threads;
            const auto r = meshgen::generate_mesh(aircraft, opts, o->out);
            if (o->json)
                print_json(to_json(r));
            else
                print_text(r);
            return 0;
        };
    });
}

}  // namespace manta::cli
