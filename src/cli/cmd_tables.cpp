/// `manta tables`: generate aerodynamic tables from an aero source by sampling and Kriging, with
/// a resumable SQLite sample store (docs/tables.md).

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/aircraft/aircraft.hpp"
#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/process.hpp"
#include "manta/core/units.hpp"
#include "manta/core/version.hpp"
#include "manta/euler/launched_source.hpp"
#include "manta/euler/source.hpp"
#include "manta/flightdyn/atmosphere.hpp"
#include "manta/meshgen/meshgen.hpp"
#include "manta/tables/analytic_source.hpp"
#include "manta/tables/campaign.hpp"
#include "manta/tables/export.hpp"
#include "manta/tables/generator.hpp"
#include "manta/tables/store.hpp"
#include "manta/vlm/source.hpp"
#include "manta/vlm/viscous.hpp"
#include "subprocess.hpp"
#include "svg_plot.hpp"

namespace manta::cli {

namespace {

struct TablesArgs {
    std::string campaign;
    std::string out;
    int jobs = 1;
    bool restart = false;
    bool accept_changed_source = false;
    bool retry_failed = false;
    bool json = false;
    double progress_interval = 2.0;
};

std::string clock_text(double s) {
    if (!(s >= 0.0)) return "?";
    const long t = std::lround(s);
    return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, (t / 60) % 60, t % 60)
                     : fmt::format("{:02}:{:02}", t / 60, t % 60);
}

/// Slice plots of the static table: each coefficient against alpha at one Mach and sideslip,
/// the Kriging mean with its +-2 sigma band and the samples at the nearest table Mach and beta.
std::string static_slice_svg(const tables::Campaign& c, const tables::StaticModel& model,
                             const std::vector<tables::Sample>& samples, double mach, double beta) {
    const auto& pa = c.static_table.alpha;
    auto nearest = [](const std::vector<double>& v, double x) {
        double best = v.front();
        for (const double y : v)
            if (std::abs(y - x) < std::abs(best - x)) best = y;
        return best;
    };
    const double m_grid = nearest(c.static_table.mach, mach);
    const double b_grid = nearest(c.static_table.beta, beta);
    const int n = 121;
    std::vector<double> x(n);
    std::array<std::vector<double>, 6> mean, lo, hi;
    for (int i = 0; i < n; ++i) {
        const double a = pa.front() + (pa.back() - pa.front()) * i / (n - 1);
        x[static_cast<std::size_t>(i)] = a * core::rad_to_deg;
        const auto p = model.predict(a, mach, beta);
        for (std::size_t j = 0; j < 6; ++j) {
            const double s = std::sqrt(std::max(0.0, p[j].mse));
            mean[j].push_back(p[j].mean);
            lo[j].push_back(p[j].mean - 2 * s);
            hi[j].push_back(p[j].mean + 2 * s);
        }
    }
    const std::size_t order[6] = {0, 1, 4, 2, 3, 5};  // CL CD Cm CY Cl Cn, as the paper
    std::vector<XyPanel> panels;
    for (const std::size_t j : order) {
        XyPanel p;
        p.y_label = tables::coefficient_names[j];
        XyCurve curve;
        curve.label = "Kriging, +-2 sigma";
        curve.x = x;
        curve.y = mean[j];
        curve.band_lo = lo[j];
        curve.band_hi = hi[j];
        p.curves.push_back(curve);
        XyPoints pts;
        pts.label =
            fmt::format("samples at M {:g}, beta {:g} deg", m_grid, b_grid * core::rad_to_deg);
        for (const auto& s : samples) {
            if (s.status != tables::SampleStatus::done || s.query.mach != m_grid ||
                s.query.beta != b_grid)
                continue;
            pts.x.push_back(s.query.alpha * core::rad_to_deg);
            const auto& r = s.result;
            const double v[6] = {r.wind.CL, r.wind.CD, r.wind.CY, r.body.Cl, r.body.Cm, r.body.Cn};
            pts.y.push_back(v[j]);
        }
        p.points.push_back(pts);
        panels.push_back(p);
    }
    return svg_xy_panels(fmt::format("{}: static table at M = {:g}, beta = {:g} deg", c.name, mach,
                                     beta * core::rad_to_deg),
                         "alpha [deg]", panels, 3);
}

/// Increment plots of one control: dC against alpha at one Mach for the extreme deflections.
std::string control_svg(const tables::Campaign& c, const tables::ControlPlan& plan,
                        const tables::ControlModel& model, double mach) {
    const int n = 121;
    const char* colours[2] = {"#1f77b4", "#2ca02c"};
    const double deltas[2] = {plan.deflection.front(), plan.deflection.back()};
    const std::size_t order[6] = {0, 1, 4, 2, 3, 5};
    std::vector<XyPanel> panels(6);
    for (std::size_t k = 0; k < 6; ++k)
        panels[k].y_label = std::string("d") + tables::coefficient_names[order[k]];
    for (int d = 0; d < 2; ++d) {
        std::array<XyCurve, 6> curves;
        for (std::size_t k = 0; k < 6; ++k) {
            curves[k].label = fmt::format("{} {:g} deg, +-2 sigma", aero::to_string(plan.control),
                                          deltas[d] * core::rad_to_deg);
            curves[k].colour = colours[d];
        }
        for (int i = 0; i < n; ++i) {
            const double a =
                plan.alpha.front() + (plan.alpha.back() - plan.alpha.front()) * i / (n - 1);
            const auto p = model.increment(a, mach, deltas[d]);
            for (std::size_t k = 0; k < 6; ++k) {
                const auto& q = p[order[k]];
                const double s = std::sqrt(std::max(0.0, q.mse));
                curves[k].x.push_back(a * core::rad_to_deg);
                curves[k].y.push_back(q.mean);
                curves[k].band_lo.push_back(q.mean - 2 * s);
                curves[k].band_hi.push_back(q.mean + 2 * s);
            }
        }
        for (std::size_t k = 0; k < 6; ++k) panels[k].curves.push_back(curves[k]);
    }
    return svg_xy_panels(
        fmt::format("{}: {} increments at M = {:g}", c.name, aero::to_string(plan.control), mach),
        "alpha [deg]", panels, 3);
}

nlohmann::json report_json(const tables::ScenarioReport& r) {
    nlohmann::json j;
    j["scenario"] = r.scenario;
    j["samples_done"] = r.samples_done;
    j["samples_failed"] = r.samples_failed;
    j["evaluated"] = r.evaluated;
    j["reused"] = r.reused;
    j["sample_wall_time_s"] = r.sample_wall_time_s;
    j["stop_reason"] = r.stop_reason;
    if (!r.loo.empty()) {
        nlohmann::json loo;
        for (const auto& e : r.loo)
            loo[e.coefficient] = {{"rmse", e.rmse}, {"range", e.range}, {"relative", e.relative}};
        j["loo"] = loo;
    }
    if (!r.rho.empty()) {
        nlohmann::json rho;
        for (std::size_t k = 0; k < r.rho.size(); ++k) rho[tables::coefficient_names[k]] = r.rho[k];
        j["rho"] = rho;
    }
    return j;
}

/// ConfigError naming the campaign key where a control table's deflections leave the aircraft
/// file's control limits.
void check_campaign_control_limits(const tables::Campaign& campaign,
                                   const aircraft::AircraftDefinition& def) {
    for (const auto& plan : campaign.controls) {
        const auto& lim = plan.control == aero::Axis::elevator  ? def.limits.elevator
                          : plan.control == aero::Axis::aileron ? def.limits.aileron
                                                                : def.limits.rudder;
        tables::check_control_limits(plan, lim[0], lim[1]);
    }
}

/// The mesh of an Euler source with `mesh: {model, level}`: OUT/mesh/<aircraft>_<model>_<level>.su2
/// with its companion, generated from the aircraft file on the first run and reused while the
/// stamp beside it (the aircraft file's text, model and level) is unchanged.
std::filesystem::path campaign_mesh(const tables::SourceSpec& spec,
                                    const std::filesystem::path& out) {
    if (!std::filesystem::exists(spec.aircraft))
        throw ConfigError(fmt::format(
            "{}: aircraft file '{}' does not exist; expected the MANTA aircraft file to mesh",
            spec.where, spec.aircraft.string()));
    const std::filesystem::path dir = out / "mesh";
    const std::filesystem::path mesh =
        dir / fmt::format("{}_{}_{}.su2", spec.aircraft.stem().string(), spec.mesh_model,
                          spec.mesh_level);
    const std::filesystem::path stamp_file = std::filesystem::path(mesh.string() + ".stamp");
    const std::string stamp = fmt::format(
        "model {}\nlevel {}\nsize_factor {}\nmanta {}\n{}", spec.mesh_model, spec.mesh_level,
        core::format_exact(spec.mesh_size_factor), core::version(), core::read_file(spec.aircraft));
    const std::filesystem::path companion =
        mesh.parent_path() / (mesh.stem().string() + ".mesh.yaml");
    if (std::filesystem::exists(mesh) && std::filesystem::exists(companion) &&
        std::filesystem::exists(stamp_file) && core::read_file(stamp_file) == stamp)
        return mesh;
    std::filesystem::create_directories(dir);
    std::fprintf(stderr, "tables: meshing %s (%s model, %s level) into %s\n",
                 spec.aircraft.string().c_str(), spec.mesh_model.c_str(), spec.mesh_level.c_str(),
                 mesh.string().c_str());
    const auto aircraft = aircraft::load_aircraft(spec.aircraft);
    meshgen::MeshOptions opts;
    opts.model = meshgen::parse_model(spec.mesh_model);
    opts.level = meshgen::parse_level(spec.mesh_level);
    opts.size_factor = spec.mesh_size_factor;
    const auto r = meshgen::generate_mesh(aircraft, opts, mesh);
    std::fprintf(stderr, "tables: mesh of %lld nodes in %.1f s\n", r.quality.nodes,
                 r.seconds_total);
    core::write_file_atomic(stamp_file, stamp);
    return mesh;
}

/// The Euler source of a campaign: the mesh and the `manta cfd` configuration, set up as
/// `manta cfd` sets up a case (`euler::EulerSource::from_files`); the flow condition comes from
/// each sample.
std::unique_ptr<aero::AeroSource> make_euler_source(const tables::Campaign& campaign,
                                                    const std::filesystem::path& out) {
    tables::SourceSpec spec = campaign.source;
    if (!spec.mesh_model.empty()) {
        // The aircraft file is known: its control limits bound the tables' deflections, checked
        // before the mesh is built (a missing file is campaign_mesh's error).
        if (std::filesystem::exists(spec.aircraft))
            check_campaign_control_limits(campaign, aircraft::load_aircraft(spec.aircraft));
        spec.mesh = campaign_mesh(spec, out);
    }
    if (!std::filesystem::exists(spec.mesh))
        throw ConfigError(
            fmt::format("{}: mesh file '{}' does not exist; expected a mesh that "
                        "manta cfd reads (SU2, gmsh, CGNS)",
                        spec.where, spec.mesh.string()));
    // Every table of `controls` needs a control surface of its mode, checked before any sample
    // (in process and launched alike).
    const auto check_controls = [&](const auto& source) {
        for (const auto& plan : campaign.controls) {
            const std::string name(aero::to_string(plan.control));
            if (!source.has_control(name))
                throw ConfigError(fmt::format(
                    "{}: {} has no control surface of mode '{}'; expected a control_surfaces "
                    "entry with mode: {} for each table of controls",
                    plan.where,
                    spec.cfd_config.empty()
                        ? std::string("the default CFD configuration (no source.config)")
                        : fmt::format("the CFD configuration '{}'", spec.cfd_config.string()),
                    name, name));
        }
    };
    if (!spec.launched) {
        auto source = euler::EulerSource::from_files(spec.mesh, spec.cfd_config);
        check_controls(*source);
        return source;
    }
    // Each sample a `manta cfd` job through the user's launcher, its run folder under OUT/cfd.
    euler::LaunchOptions o;
    o.launcher = core::split_command(spec.launcher, spec.where + ": launcher");
    o.executable = self_executable();
    o.work_dir = std::filesystem::absolute(out / "cfd");
    auto source = std::make_unique<euler::LaunchedEulerSource>(
        std::filesystem::absolute(spec.mesh),
        spec.cfd_config.empty() ? std::filesystem::path{}
                                : std::filesystem::absolute(spec.cfd_config),
        std::move(o));
    check_controls(*source);
    return source;
}

int run_tables(const TablesArgs& a) {
    if (a.restart && a.accept_changed_source)
        throw InputError("tables: --restart and --accept-changed-source exclude each other");
    const tables::Campaign campaign = tables::read_campaign(a.campaign);
    const std::filesystem::path out(a.out);
    // One command at a time in a run folder: a second one would mix its samples into the store.
    const core::RunFolderLock lock(out, "tables");

    // The source: built here, so the tables module never depends on a solver.
    std::unique_ptr<aero::AeroSource> source;
    if (campaign.source.type == tables::SourceType::analytic) {
        source = std::make_unique<tables::AnalyticSource>(campaign.source.analytic);
    } else if (campaign.source.type == tables::SourceType::euler) {
        source = make_euler_source(campaign, out);
    } else {
        const auto& spec = campaign.source;
        if (!std::filesystem::exists(spec.aircraft))
            throw ConfigError(
                fmt::format("{}: aircraft file '{}' does not exist; expected a MANTA "
                            "aircraft file or an AVL geometry file",
                            spec.where, spec.aircraft.string()));
        vlm::LatticeDensity density;
        density.n_chord = spec.n_chord;
        density.strip_width = spec.strip_width;
        VlmInput in = load_vlm_input(spec.aircraft.string(), density);
        if (in.geometry) {
            check_campaign_control_limits(campaign, aircraft::load_aircraft(spec.aircraft));
        }
        auto vs = std::make_unique<vlm::VlmSource>(std::move(in.model),
                                                   spec.viscous ? in.geometry : std::nullopt);
        for (const auto& plan : campaign.controls) {
            const std::string name(aero::to_string(plan.control));
            if (vs->lattice().control_index(name) < 0)
                throw ConfigError(fmt::format(
                    "{}: the aircraft '{}' has no control '{}'; expected a table only for its "
                    "controls",
                    plan.where, spec.aircraft.string(), name));
        }
        source = std::move(vs);
    }
    // Reynolds number per metre at each Mach number, at the campaign's altitude.
    const auto atm = flightdyn::us1976(campaign.altitude);
    tables::RunOptions ro;
    ro.jobs = std::max(1, a.jobs);
    ro.retry_failed = a.retry_failed;
    ro.conditions = [atm](double mach) {
        aero::FlowConditions c;
        c.reynolds_per_metre =
            vlm::reynolds_per_metre(atm.density, mach * atm.speed_of_sound, atm.dynamic_viscosity);
        return c;
    };
    const std::string fingerprint =
        fmt::format("{}|altitude={}", source->fingerprint(), core::format_exact(campaign.altitude));

    const std::filesystem::path store_file = out / "samples.sqlite";
    tables::StoreOpenOptions so;
    so.restart = a.restart;
    so.accept_changed_source = a.accept_changed_source;
    const auto store = tables::SampleStore::open(store_file, source->name(), fingerprint, so);
    if (!store->replaced_fingerprint().empty())
        std::fprintf(stderr,
                     "manta tables: warning: reusing samples of source fingerprint '%s' with "
                     "source fingerprint '%s' (--accept-changed-source)\n",
                     store->replaced_fingerprint().c_str(), fingerprint.c_str());
    store->set_meta("campaign", campaign.name);
    {
        int done = 0, pending = 0;
        for (const auto& s : store->samples())
            (s.status == tables::SampleStatus::pending ? pending : done) += 1;
        if (done + pending > 0)
            std::fprintf(stderr,
                         "manta tables: resuming from %s: %d finished samples reused, %d pending "
                         "evaluated first\n",
                         store_file.string().c_str(), done, pending);
    }

    // Progress: one status line on stderr at most every progress_interval seconds, and at each
    // change of phase.
    std::mutex pm;
    auto last = std::chrono::steady_clock::now() - std::chrono::hours(1);
    std::string last_phase;
    ro.progress = [&](const tables::Progress& p) {
        const std::lock_guard lock(pm);
        const auto now = std::chrono::steady_clock::now();
        if (p.phase == last_phase &&
            std::chrono::duration<double>(now - last).count() < a.progress_interval &&
            p.done < p.total)
            return;
        last = now;
        last_phase = p.phase;
        std::fprintf(stderr, "[tables] %-17s %4d/%-4d samples  CV %s  elapsed %s  left ~%s\n",
                     p.phase.c_str(), p.done, p.total,
                     p.cv_error >= 0 ? fmt::format("{:.2e}", p.cv_error).c_str() : "-",
                     clock_text(p.elapsed_s).c_str(), clock_text(p.remaining_s).c_str());
    };

    // samples.csv also when the campaign stops with an error: its messages point the user there.
    tables::CampaignResult result;
    try {
        result = tables::run_campaign(campaign, *source, *store, ro);
    } catch (const Error&) {
        core::write_file_atomic(out / "samples.csv", tables::samples_csv(store->samples()));
        throw;
    }
    const aero::AeroDatabase db = tables::make_database(campaign, result, source->name());

    std::vector<std::string> written;
    auto write = [&](const std::string& name, const std::string& text) {
        core::write_file_atomic(out / name, text);
        written.push_back(name);
    };
    db.write(out / "database.yaml");
    written.push_back("database.yaml");
    write("tables.csv", tables::tables_csv(result.tables));
    if (const std::string d = tables::dynamic_csv(result.tables); !d.empty())
        write("dynamic.csv", d);
    const auto samples = store->samples();
    write("samples.csv", tables::samples_csv(samples));
    write("ceasiom_aero.txt",
          tables::ceasiom_aero_table(db, campaign.dynamic ? campaign.dynamic->rate_step : 0.01));
    if (!campaign.controls.empty()) write("ceasiom_control.txt", tables::ceasiom_control_table(db));
    write("jsbsim_aero.xml", tables::jsbsim_aerodynamics(db));
    for (const double m : campaign.output.plot_mach)
        for (const double b : campaign.output.plot_beta)
            write(fmt::format("plot_static_M{:g}_beta{:g}.svg", m, b * core::rad_to_deg),
                  static_slice_svg(campaign, *result.static_model, samples, m, b));
    for (std::size_t k = 0; k < campaign.controls.size(); ++k)
        write(fmt::format("plot_{}.svg", aero::to_string(campaign.controls[k].control)),
              control_svg(campaign, campaign.controls[k], *result.control_models[k],
                          campaign.output.plot_mach.front()));

    nlohmann::json j;
    j["campaign"] = campaign.name;
    j["campaign_file"] = campaign.file.string();
    j["manta_version"] = core::version();
    j["source"] = {{"name", source->name()}, {"fingerprint", fingerprint}};
    if (!store->replaced_fingerprint().empty())
        j["source"]["replaced_fingerprint"] = store->replaced_fingerprint();
    j["store"] = store_file.string();
    j["jobs"] = ro.jobs;
    j["batch"] = result.batch;
    j["samples"] = {{"evaluated", result.evaluated},
                    {"reused", result.reused},
                    {"failed", result.failed},
                    {"total", static_cast<int>(samples.size())}};
    j["wall_time_s"] = result.wall_time_s;
    double sample_time = 0.0;
    for (const auto& s : samples) sample_time += s.wall_time_s;
    j["sample_wall_time_s"] = sample_time;
    j["scenarios"] = nlohmann::json::array();
    for (const auto& r : result.reports) j["scenarios"].push_back(report_json(r));
    nlohmann::json entries;
    for (const auto& t : result.tables) entries[t.table.name] = t.table.n_points();
    j["table_entries"] = entries;
    written.push_back("summary.json");
    j["outputs"] = written;
    core::write_file_atomic(out / "summary.json", j.dump(2) + "\n");

    if (a.json) {
        print_json(j);
    } else {
        std::printf("%s: %d samples evaluated, %d reused, %d failed in %.1f s (store %s)\n",
                    campaign.name.c_str(), result.evaluated, result.reused, result.failed,
                    result.wall_time_s, store_file.string().c_str());
        for (const auto& r : result.reports) {
            std::string loo;
            for (const auto& e : r.loo) loo += fmt::format(" {} {:.2e}", e.coefficient, e.relative);
            std::printf("  %-17s %3d samples (%s)%s%s\n", r.scenario.c_str(), r.samples_done,
                        r.stop_reason.c_str(), loo.empty() ? "" : "  LOO/range:", loo.c_str());
        }
        std::printf("  outputs in %s:", out.string().c_str());
        for (const auto& w : written) std::printf(" %s", w.c_str());
        std::printf("\n");
    }
    return 0;
}

}  // namespace

void add_tables(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "tables",
        "Generate aerodynamic tables (static, control increments, dynamic derivatives) from an\n"
        "aero source by adaptive sampling and Kriging, control increments fused with the static\n"
        "model (recursive co-Kriging form); every sample is kept in a\n"
        "resumable SQLite store (docs/tables.md).");
    auto a = std::make_shared<TablesArgs>();
    cmd->add_option("--campaign", a->campaign, "Campaign file (YAML, docs/formats.md)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--out", a->out, "Output folder (also holds the sample store samples.sqlite)")
        ->required()
        ->check(output_path());
    cmd->add_option("--jobs", a->jobs, "Samples evaluated at once (default 1)")
        ->check(integer_in(1, 1024));
    cmd->add_flag("--restart", a->restart, "Delete the sample store and start from scratch");
    cmd->add_flag("--accept-changed-source", a->accept_changed_source,
                  "Reuse stored samples although the source fingerprint changed");
    cmd->add_flag("--retry-failed", a->retry_failed, "Evaluate failed samples again");
    cmd->add_option("--progress-interval", a->progress_interval,
                    "Seconds between progress lines on stderr (default 2)")
        ->check(real_in(0.0, 3600.0, "s"));
    cmd->add_flag("--json", a->json, "Print the summary as one JSON object");
    cmd->callback([a, &action] { action = [a]() -> int { return run_tables(*a); }; });
}

}  // namespace manta::cli
