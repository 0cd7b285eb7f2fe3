/// `manta vlm`: steady vortex-lattice solution and derivatives of an aircraft file (MANTA YAML
/// or AVL geometry).

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/vlm/avl_mass.hpp"
#include "manta/vlm/avl_reader.hpp"
#include "manta/vlm/avl_run.hpp"
#include "manta/vlm/output.hpp"
#include "manta/vlm/source.hpp"
#include "manta/vlm/steady.hpp"
#include "manta/vlm/viscous.hpp"

namespace manta::cli {

VlmInput load_vlm_input(const std::string& file, const vlm::LatticeDensity& density) {
    VlmInput in;
    const std::filesystem::path path(file);
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".avl") {
        in.model = vlm::read_avl(path);
        in.label = "AVL geometry file";
        in.default_mach = in.model.mach;
        return in;
    }
    const aircraft::AircraftDefinition def = aircraft::load_aircraft(path);
    vlm::Reference ref;
    ref.area = def.reference.area;
    ref.span = def.reference.span;
    ref.chord = def.reference.chord;
    ref.point = def.moment_reference_geom;
    in.model = vlm::from_geometry(def.geometry, ref, density, def.name);
    in.geometry = def.geometry;
    in.label = "MANTA aircraft file";
    return in;
}

namespace {

struct VlmArgs {
    std::string aircraft;
    double alpha_deg = 0.0, beta_deg = 0.0;
    std::optional<double> mach;
    double p_hat = 0.0, q_hat = 0.0, r_hat = 0.0;
    double elevator_deg = 0.0, aileron_deg = 0.0, rudder_deg = 0.0;
    std::vector<std::string> controls;  // NAME=DEG
    double altitude = 0.0;
    std::optional<double> speed;
    bool no_viscous = false;
    int n_chord = vlm::LatticeDensity{}.n_chord;
    double strip_width = vlm::LatticeDensity{}.strip_width;
    std::string vtu, span_csv;
    bool json = false;
    // AVL users' files (AVL geometry only) and the moment reference point.
    std::string mass_file, run_file;
    int run_case = 1;
    std::vector<double> xref;            // X Y Z
    std::string trailing_legs = "auto";  // auto | freestream | body-axis
};

/// The trailing legs of `--trailing-legs`: `auto` is vlm::default_trailing_legs (free stream for
/// MANTA aircraft files, as the tables and the replay; body x for AVL files, as AVL).
vlm::TrailingLegs trailing_legs_of(const std::string& choice, bool has_geometry) {
    if (choice == "freestream") return vlm::TrailingLegs::freestream;
    if (choice == "body-axis") return vlm::TrailingLegs::body_axis;
    return vlm::default_trailing_legs(has_geometry);
}

/// The options of AVL's mass and run-case files and of the moment reference point; the run case
/// sets the flight state, so it excludes the state options.
void add_reference_options(CLI::App& cmd, VlmArgs& a) {
    cmd.add_option("--mass", a.mass_file,
                   "AVL mass file (.mass): its centre of gravity is the moment "
                   "reference point (AVL geometry only)")
        ->check(CLI::ExistingFile);
    auto* run = cmd.add_option("--run", a.run_file,
                               "AVL run-case file (.run): the case's constraints (trim), Mach, "
                               "CDo and X_cg Y_cg Z_cg (AVL geometry only)")
                    ->check(CLI::ExistingFile);
    cmd.add_option("--case", a.run_case, "Run case of --run (default 1)")
        ->check(integer_in(1, 1000000))
        ->needs(run);
    cmd.add_option("--xref", a.xref,
                   "Moment reference point X Y Z (geometry axes; AVL files: the .avl length unit, "
                   "MANTA files: m); overrides --run, --mass and the aircraft file")
        ->expected(3)
        ->check(real_in(-1e6, 1e6));
    for (const char* o : {"--alpha-deg", "--beta-deg", "--p-hat", "--q-hat", "--r-hat",
                          "--elevator-deg", "--aileron-deg", "--rudder-deg", "--control"})
        run->excludes(cmd.get_option(o));
}

/// {CL CD CY Cl Cm Cn} column as JSON keyed by coefficient.
nlohmann::json coefficient_column(const Eigen::Matrix<double, 6, Eigen::Dynamic>& m,
                                  Eigen::Index col) {
    static const char* names[6] = {"CL", "CD", "CY", "Cl", "Cm", "Cn"};
    nlohmann::json j;
    for (int r = 0; r < 6; ++r) j[names[r]] = m(r, col);
    return j;
}

void run_vlm(const VlmArgs& a) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    vlm::LatticeDensity density;
    density.n_chord = a.n_chord;
    density.strip_width = a.strip_width;
    VlmInput in = load_vlm_input(a.aircraft, density);
    // AVL's mass and run-case files, and the moment reference point (docs/avl-input.md).
    std::optional<vlm::AvlMass> mass;
    std::optional<vlm::RunCase> run_case;
    if (in.geometry && (!a.mass_file.empty() || !a.run_file.empty()))
        throw InputError(fmt::format(
            "vlm: --mass and --run read AVL's mass and run-case files; expected them with an AVL "
            "geometry file (.avl), not with the MANTA aircraft file '{}'",
            a.aircraft));
    if (!a.mass_file.empty()) mass = vlm::read_avl_mass(a.mass_file);
    if (!a.run_file.empty()) {
        run_case = vlm::find_run_case(vlm::read_avl_run(a.run_file), a.run_case, a.run_file);
        vlm::apply_run_case(in.model, *run_case);
        in.default_mach = in.model.mach;
    }
    std::optional<Eigen::Vector3d> xref;
    if (a.xref.size() == 3) xref = Eigen::Vector3d(a.xref[0], a.xref[1], a.xref[2]);
    vlm::ReferenceChoice reference;
    if (in.geometry) {
        reference.point = xref.value_or(in.model.reference.point);
        reference.from = xref ? "--xref" : "the aircraft file";
    } else {
        reference = vlm::choose_reference_point(in.model, mass ? &*mass : nullptr,
                                                run_case ? &*run_case : nullptr, xref);
    }
    in.model.reference.point = reference.point;
    const double mach = a.mach.value_or(in.default_mach);
    const vlm::Lattice lattice = vlm::build_lattice(in.model);
    const auto t1 = clock::now();
    vlm::SteadyOptions solver_options;
    solver_options.trailing_legs = trailing_legs_of(a.trailing_legs, in.geometry.has_value());
    const bool legs_freestream = solver_options.trailing_legs == vlm::TrailingLegs::freestream;
    const vlm::SteadySolver solver(in.model, lattice, mach, solver_options);
    const auto t2 = clock::now();

    vlm::FlowState s;
    vlm::Derivatives d;
    int run_iterations = 0;
    if (run_case) {
        vlm::RunCaseSolution sol = vlm::solve_run_case(solver, *run_case);
        s = sol.state;
        d = std::move(sol.derivatives);
        run_iterations = sol.iterations;
    } else {
        s.alpha = a.alpha_deg * core::deg_to_rad;
        s.beta = a.beta_deg * core::deg_to_rad;
        s.p_hat = a.p_hat;
        s.q_hat = a.q_hat;
        s.r_hat = a.r_hat;
        s.deflection =
            Eigen::VectorXd::Zero(static_cast<Eigen::Index>(lattice.control_names.size()));
        auto set_control = [&](const std::string& name, double deg, bool required) {
            const int k = lattice.control_index(name);
            if (k < 0) {
                if (!required && deg == 0.0) return;
                std::string known;
                for (const auto& n : lattice.control_names)
                    known += (known.empty() ? "" : ", ") + n;
                throw InputError(
                    fmt::format("vlm: control '{}' is not on this aircraft; its controls are: {}",
                                name, known.empty() ? "(none)" : known));
            }
            s.deflection[k] = deg * core::deg_to_rad;
        };
        set_control("elevator", a.elevator_deg, false);
        set_control("aileron", a.aileron_deg, false);
        set_control("rudder", a.rudder_deg, false);
        for (const std::string& c : a.controls) {
            const auto eq = c.find('=');
            double v = 0.0;
            try {
                if (eq == std::string::npos) throw std::invalid_argument("no '='");
                std::size_t used = 0;
                v = std::stod(c.substr(eq + 1), &used);
                if (used != c.size() - eq - 1) throw std::invalid_argument("trailing text");
            } catch (const std::exception&) {
                throw InputError(fmt::format(
                    "vlm: --control '{}'; expected NAME=DEGREES, e.g. --control flap=10", c));
            }
            if (!(std::abs(v) <= range::max_angle_deg))
                throw InputError(fmt::format(
                    "--control: value '{}' of '{}' is not a deflection; expected NAME=DEGREES "
                    "with DEGREES a number in [-90, 90]",
                    c.substr(eq + 1), c.substr(0, eq)));
            set_control(c.substr(0, eq), v, true);
        }

        d = solver.derivatives(s);
    }
    vlm::SteadyResult r = d.state;
    const auto t3 = clock::now();

    // Viscous drag from the shape (MANTA aircraft files) at the Reynolds number of the flight
    // condition: speed given, or Mach times the speed of sound at the altitude.
    std::optional<vlm::ViscousDrag> visc;
    const auto atm = flightdyn::us1976(a.altitude);
    const double speed = a.speed.value_or(mach * atm.speed_of_sound);
    if (in.geometry && !a.no_viscous) {
        if (!(speed > 0.0))
            throw InputError(
                "vlm: the viscous drag needs a speed: give --mach > 0 or --speed (or "
                "--no-viscous)");
        const double re = vlm::reynolds_per_metre(atm.density, speed, atm.dynamic_viscosity);
        visc = vlm::viscous_drag(*in.geometry, in.model.reference.area, mach, re);
        vlm::add_profile_drag(r, visc->cd0, s.alpha, s.beta);
    }
    if (!a.vtu.empty()) vlm::write_panels_vtu(a.vtu, in.model, lattice, r);
    if (!a.span_csv.empty()) vlm::write_span_loading_csv(a.span_csv, in.model, lattice, r);
    auto ms = [](auto x, auto y) {
        return std::chrono::duration<double, std::milli>(y - x).count();
    };

    if (a.json) {
        nlohmann::json j;
        j["aircraft"] = a.aircraft;
        j["model"] = in.model.name;
        j["input"] = in.label;
        j["alpha"] = s.alpha;
        j["alpha_deg"] = run_case ? s.alpha * core::rad_to_deg : a.alpha_deg;
        j["beta"] = s.beta;
        j["beta_deg"] = run_case ? s.beta * core::rad_to_deg : a.beta_deg;
        j["reference_point"] = {reference.point.x(), reference.point.y(), reference.point.z()};
        j["reference_point_from"] = reference.from;
        j["trailing_legs"] = legs_freestream ? "freestream" : "body-axis";
        if (mass)
            j["mass_file"] = {{"file", a.mass_file},
                              {"items", mass->items},
                              {"mass", mass->mass},
                              {"cg", {mass->cg.x(), mass->cg.y(), mass->cg.z()}},
                              {"length_unit", mass->length_unit},
                              {"length_unit_name", mass->length_unit_name},
                              {"mass_unit", mass->mass_unit},
                              {"mass_unit_name", mass->mass_unit_name}};
        if (run_case) {
            nlohmann::json cons = nlohmann::json::array();
            for (const auto& c : run_case->constraints)
                cons.push_back({{"variable", c.variable},
                                {"constraint", c.constraint},
                                {"value", c.value},
                                {"line", c.line}});
            j["run_case"] = {{"file", a.run_file},
                             {"number", run_case->number},
                             {"name", run_case->name},
                             {"constraints", cons},
                             {"newton_iterations", run_iterations}};
        }
        j["mach"] = mach;
        j["p_hat"] = s.p_hat;
        j["q_hat"] = s.q_hat;
        j["r_hat"] = s.r_hat;
        nlohmann::json defl;
        for (std::size_t k = 0; k < lattice.control_names.size(); ++k)
            defl[lattice.control_names[k]] = s.deflection[static_cast<Eigen::Index>(k)];
        j["controls"] = defl;
        j["CL"] = r.CL;
        j["CD"] = r.CD;
        j["CY"] = r.CY;
        j["Cl"] = r.body.Cl;
        j["Cm"] = r.body.Cm;
        j["Cn"] = r.body.Cn;
        j["CX"] = r.body.CX;
        j["CZ"] = r.body.CZ;
        j["CD_induced"] = r.CD_induced;
        j["CD_near_field"] = r.CD_near_field;
        j["CD_profile"] = r.CD_profile;
        j["span_efficiency"] = r.span_efficiency;
        if (visc) {
            nlohmann::json v;
            v["reynolds_per_metre"] = visc->reynolds_per_metre;
            v["CD0"] = visc->cd0;
            for (const auto& c : visc->components)
                v["components"][c.name] = {{"CD0", c.cd0},
                                           {"reynolds", c.reynolds},
                                           {"skin_friction", c.skin_friction},
                                           {"form_factor", c.form_factor},
                                           {"wetted_area", c.wetted_area}};
            j["viscous"] = v;
        }
        const char* vars[5] = {"alpha", "beta", "p_hat", "q_hat", "r_hat"};
        for (int k = 0; k < 5; ++k) {
            j["derivatives"]["body"][vars[k]] = coefficient_column(d.body, k);
            j["derivatives"]["stability"][vars[k]] = coefficient_column(d.stability, k);
        }
        for (std::size_t k = 0; k < lattice.control_names.size(); ++k) {
            const auto col = static_cast<Eigen::Index>(k);
            j["derivatives"]["body"][lattice.control_names[k]] = coefficient_column(d.control, col);
            j["derivatives"]["stability"][lattice.control_names[k]] =
                coefficient_column(d.control_stability, col);
        }
        j["x_neutral_point"] = d.x_neutral_point;
        j["static_margin"] = d.static_margin;
        j["lattice"] = {{"vortices", lattice.size()},
                        {"strips", lattice.strips.size()},
                        {"surfaces", in.model.surfaces.size()}};
        j["time_ms"] = {{"lattice", ms(t0, t1)},
                        {"factorisation", ms(t1, t2)},
                        {"solution_and_derivatives", ms(t2, t3)}};
        print_json(j);
        return;
    }
    fmt::print("{} ({}): {} vortices on {} strips, {} surfaces\n", in.model.name, in.label,
               lattice.size(), lattice.strips.size(), in.model.surfaces.size());
    if (run_case)
        fmt::print("run case {} '{}' of {}: {} constraints met in {} Newton iterations\n",
                   run_case->number, run_case->name, a.run_file, run_case->constraints.size(),
                   run_iterations);
    fmt::print("moments about ({:g}, {:g}, {:g}) from {}\n", reference.point.x(),
               reference.point.y(), reference.point.z(), reference.from);
    fmt::print("trailing legs {}\n", legs_freestream ? "along the free stream" : "along body x");
    fmt::print("alpha {:.4f} deg  beta {:.4f} deg  Mach {:.3f}  p^ {:.4f}  q^ {:.4f}  r^ {:.4f}\n",
               s.alpha * core::rad_to_deg, s.beta * core::rad_to_deg, mach, s.p_hat, s.q_hat,
               s.r_hat);
    for (std::size_t k = 0; k < lattice.control_names.size(); ++k)
        fmt::print("  {:<10} {:8.3f} deg\n", lattice.control_names[k],
                   s.deflection[static_cast<Eigen::Index>(k)] * core::rad_to_deg);
    fmt::print("\nCL {:9.5f}  CD {:9.5f} (induced {:.5f}, profile {:.5f})  CY {:9.5f}\n", r.CL,
               r.CD, r.CD_induced, r.CD_profile, r.CY);
    fmt::print("Cl {:9.5f}  Cm {:9.5f}  Cn {:9.5f}   span efficiency {:.4f}\n", r.body.Cl,
               r.body.Cm, r.body.Cn, r.span_efficiency);
    fmt::print("\nStability-axis derivatives (per rad, per non-dimensional rate):\n");
    fmt::print("{:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "", "CL", "CD", "CY", "Cl",
               "Cm", "Cn");
    const char* vars[5] = {"alpha", "beta", "p_hat", "q_hat", "r_hat"};
    for (int k = 0; k < 5; ++k) {
        fmt::print("{:>10}", vars[k]);
        for (int c = 0; c < 6; ++c) fmt::print(" {:10.5f}", d.stability(c, k));
        fmt::print("\n");
    }
    for (std::size_t k = 0; k < lattice.control_names.size(); ++k) {
        fmt::print("{:>10}", lattice.control_names[k]);
        for (int c = 0; c < 6; ++c)
            fmt::print(" {:10.5f}", d.control_stability(c, static_cast<Eigen::Index>(k)));
        fmt::print("\n");
    }
    fmt::print("\nneutral point x = {:.4f} {}, static margin {:.2f} % of c_ref\n",
               d.x_neutral_point, in.geometry ? "m" : "(length unit of the .avl file)",
               100.0 * d.static_margin);
    fmt::print(
        "time: lattice {:.0f} ms, factorisation {:.0f} ms, solution and derivatives {:.0f} ms\n",
        ms(t0, t1), ms(t1, t2), ms(t2, t3));
}

}  // namespace

void add_vlm(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "vlm",
        "Steady vortex-lattice solution of an aircraft (MANTA YAML or AVL .avl file): the six\n"
        "coefficients, induced and profile drag, stability and control derivatives, neutral\n"
        "point (docs/vlm.md).");
    auto a = std::make_shared<VlmArgs>();
    cmd->add_option("--aircraft", a->aircraft, "Aircraft file: MANTA YAML or AVL geometry (.avl)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--alpha-deg", a->alpha_deg, "Angle of attack [deg] (default 0)")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    cmd->add_option("--beta-deg", a->beta_deg, "Sideslip angle [deg] (default 0)")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    cmd->add_option("--mach", a->mach, "Mach number (default: the AVL file's, else 0)")
        ->check(real_in(0.0, 0.95));
    cmd->add_option("--p-hat", a->p_hat, "Roll rate p b / 2V (body axes, default 0)")
        ->check(real_in(-1.0, 1.0));
    cmd->add_option("--q-hat", a->q_hat, "Pitch rate q c / 2V (default 0)")
        ->check(real_in(-1.0, 1.0));
    cmd->add_option("--r-hat", a->r_hat, "Yaw rate r b / 2V (body axes, default 0)")
        ->check(real_in(-1.0, 1.0));
    cmd->add_option("--elevator-deg", a->elevator_deg, "Elevator [deg], trailing edge down +")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    cmd->add_option("--aileron-deg", a->aileron_deg, "Aileron [deg], left trailing edge down +")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    cmd->add_option("--rudder-deg", a->rudder_deg, "Rudder [deg], trailing edge left +")
        ->check(real_in(-range::max_angle_deg, range::max_angle_deg, "deg"));
    cmd->add_option("--control", a->controls, "Any control by name: NAME=DEG (repeatable)");
    cmd->add_option("--altitude", a->altitude,
                    "Altitude [m] for the Reynolds number of the viscous drag (default 0)")
        ->check(altitude());
    cmd->add_option("--speed", a->speed, "True airspeed [m/s] (default: Mach x speed of sound)")
        ->check(real_positive(range::max_speed, "m/s"));
    cmd->add_flag("--no-viscous", a->no_viscous, "No viscous drag build-up");
    cmd->add_option("--n-chord", a->n_chord, "Chordwise vortices per strip (MANTA files)")
        ->check(integer_in(1, 100));
    cmd->add_option("--strip-width", a->strip_width,
                    "Strip width as a fraction of the span (MANTA files)")
        ->check(real_in(1e-4, 0.5));
    cmd->add_option("--vtu", a->vtu, "Write the panel loads as VTU (ParaView)")
        ->check(output_path());
    cmd->add_option("--span-csv", a->span_csv, "Write the span loading as CSV")
        ->check(output_path());
    cmd->add_option("--trailing-legs", a->trailing_legs,
                    "Trailing legs behind the trailing edge: freestream, body-axis, or auto "
                    "(freestream for MANTA files, as the tables and replay; body-axis for AVL "
                    "files, as AVL)")
        ->check(CLI::IsMember({"auto", "freestream", "body-axis"}))
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object (SI units, radians)");
    add_reference_options(*cmd, *a);
    cmd->callback([a, &action] {
        action = [a]() -> int {
            run_vlm(*a);
            return 0;
        };
    });
}

}  // namespace manta::cli
