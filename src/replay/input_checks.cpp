/// @file input_checks.cpp
/// A replay's inputs compared with each other before any flow solution starts
/// (input_checks.hpp, docs/replay.md "Bad input").

#include "manta/replay/input_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include "manta/core/error.hpp"
#include "manta/flightdyn/atmosphere.hpp"

namespace manta::replay {

namespace {

constexpr double deg = 180.0 / std::numbers::pi;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

bool close(double a, double b) {
    return std::abs(a - b) <= reference_rel_tol * std::max({std::abs(a), std::abs(b), 1e-12});
}

/// The first reference value (area, chord, span, moment point) that differs, in words ("" when
/// all agree). `area_factor` scales `got`'s area to the aircraft's (2 for a half model's).
std::string reference_difference(const ReferenceFacts& got, double area_factor,
                                 const ReferenceFacts& want) {
    if (!close(got.area * area_factor, want.area))
        return area_factor == 1.0 ? fmt::format("reference area {:g} m^2", got.area)
                                  : fmt::format("reference area {:g} m^2 (x {:g}: {:g} m^2)",
                                                got.area, area_factor, got.area * area_factor);
    if (!close(got.chord, want.chord)) return fmt::format("reference chord {:g} m", got.chord);
    if (!close(got.span, want.span)) return fmt::format("reference span {:g} m", got.span);
    for (std::size_t k = 0; k < 3; ++k)
        if (std::abs(got.moment_point[k] - want.moment_point[k]) >
            reference_rel_tol * std::max(1.0, want.chord))
            return fmt::format("moment point [{:g}, {:g}, {:g}] m", got.moment_point[0],
                               got.moment_point[1], got.moment_point[2]);
    return {};
}

std::string reference_words(const ReferenceFacts& r) {
    return fmt::format(
        "area {:g} m^2, chord {:g} m, span {:g} m, moment point [{:g}, {:g}, {:g}] m", r.area,
        r.chord, r.span, r.moment_point[0], r.moment_point[1], r.moment_point[2]);
}

ColumnPeak peak(const std::vector<double>& t, const std::vector<double>& v) {
    ColumnPeak p;
    for (std::size_t i = 0; i < v.size(); ++i)
        if (std::abs(v[i]) > std::abs(p.value)) p = {v[i], t[i]};
    return p;
}

const char* const control_names[3] = {"elevator", "aileron", "rudder"};

bool has(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

/// Range [first, last] of the static table's axis, if it has that axis with two breakpoints or
/// more (one breakpoint: constant in that variable, no range to leave).
std::optional<std::array<double, 2>> static_range(const aero::AeroDatabase& db, aero::Axis axis) {
    for (const aero::Table& t : db.tables()) {
        if (t.kind != aero::TableKind::static_table) continue;
        for (const aero::GridAxis& a : t.axes)
            if (a.axis == axis && a.breakpoints.size() >= 2)
                return std::array<double, 2>{a.breakpoints.front(), a.breakpoints.back()};
    }
    return std::nullopt;
}

bool tables_have_axis(const aero::AeroDatabase& db, aero::Axis axis) {
    for (const aero::Table& t : db.tables())
        for (const aero::GridAxis& a : t.axes)
            if (a.axis == axis && a.breakpoints.size() >= 2) return true;
    return false;
}

}  // namespace

std::vector<double> trajectory_mach(const Trajectory& tr) {
    if (!tr.mach.empty()) return tr.mach;
    std::vector<double> m(tr.size());
    for (std::size_t i = 0; i < tr.size(); ++i) {
        const double h = -tr.position[2][i];
        if (!(h >= -5000.0 && h <= 80000.0))
            throw InputError(
                fmt::format("{}:{}, column 'z': altitude {} m; expected -5000 to 80000 m (US 1976 "
                            "atmosphere for the Mach number; or give a 'mach' column)",
                            tr.source, tr.line[i], h));
        m[i] = tr.V[i] / flightdyn::us1976(h).speed_of_sound;
    }
    return m;
}

double entry_mach(const Trajectory& tr) {
    return trajectory_mach(tr).front();
}

std::vector<std::string> check_tables(const TablesFacts& tables, const AircraftFacts& aircraft,
                                      const Trajectory& tr) {
    std::vector<std::string> warnings;
    // The aircraft the trajectory was flown by (`# aircraft:` of manta simulate / optimise).
    // `manta optimise` writes the aircraft file there, often a copy (the demo's inputs/): only a
    // name is compared.
    const std::string flown = tr.meta("aircraft");
    const bool a_file =
        flown.find('/') != std::string::npos || flown.find('\\') != std::string::npos ||
        (flown.size() > 5 &&
         (flown.ends_with(".yaml") || flown.ends_with(".yml") || flown.ends_with(".avl")));
    if (!flown.empty() && !a_file && !aircraft.name.empty() && flown != aircraft.name)
        warnings.push_back(fmt::format(
            "warning: {}: a trajectory of the aircraft '{}' ('# aircraft:'), replayed with the "
            "aircraft file {} ('{}')",
            tr.source, flown, aircraft.file, aircraft.name));
    if (!tables.database) return warnings;
    const aero::AeroDatabase& db = *tables.database;
    const std::string label =
        tables.file.empty() ? aircraft.file + " (its aero model)" : tables.file;
    if (!tables.file.empty()) {
        // A `manta tables` folder of an Euler campaign: the companion of the mesh it made names
        // the aircraft and its reference values.
        for (const CompanionFacts& c : tables.mesh_companions) {
            const std::string d = reference_difference(c.reference, 1.0, aircraft.reference);
            if (!d.empty())
                throw InputError(fmt::format(
                    "{}: tables of the aircraft '{}' (their mesh companion {} has {}); expected "
                    "tables of the aircraft file {} ('{}': {})",
                    tables.file, c.aircraft_name, c.file, d, aircraft.file, aircraft.name,
                    reference_words(aircraft.reference)));
            if (!c.aircraft_name.empty() && c.aircraft_name != aircraft.name)
                warnings.push_back(fmt::format(
                    "warning: {}: tables of the aircraft '{}' (their mesh companion {}), the "
                    "aircraft file {} is '{}' with the same reference values; the comparison "
                    "assumes they are the same aircraft",
                    tables.file, c.aircraft_name, c.file, aircraft.file, aircraft.name));
        }
        const std::string name = db.info().name;
        if (tables.mesh_companions.empty() && !aircraft.name.empty() && !name.empty() &&
            lower(name).find(lower(aircraft.name)) == std::string::npos)
            warnings.push_back(fmt::format(
                "warning: {}: the database '{}' does not name the aircraft '{}' of {}; the "
                "comparison assumes the tables are that aircraft's",
                tables.file, name, aircraft.name, aircraft.file));
    }
    // Mach: far outside the tables is a replay against extrapolated numbers throughout.
    const std::vector<double> mach = trajectory_mach(tr);
    if (const auto r = static_range(db, aero::Axis::mach)) {
        const auto lo = std::min_element(mach.begin(), mach.end());
        const auto hi = std::max_element(mach.begin(), mach.end());  // the first of the largest
        const double below = (*r)[0] - *lo, above = *hi - (*r)[1];
        const double worst = std::max(below, above);
        if (worst > 0.0) {
            const std::size_t i =
                static_cast<std::size_t>((below >= above ? lo : hi) - mach.begin());
            const std::string what = fmt::format(
                "{}: Mach {:.4g} at t = {:.4g} s ({}:{}) is outside the tables' Mach range "
                "{:g} to {:g}",
                tr.source, mach[i], tr.t[i], tr.source, tr.line[i], (*r)[0], (*r)[1]);
            if (worst > mach_margin_error)
                throw InputError(fmt::format(
                    "{} of {} by {:.3g}; expected a trajectory within {:g} of the tables' range "
                    "(tables of this flight's Mach numbers)",
                    what, label, worst, mach_margin_error));
            warnings.push_back(
                fmt::format("warning: {} of {} by {:.3g}; the tables are extrapolated there", what,
                            label, worst));
        }
    }
    // Angles beyond the static table: extrapolated (flagged per step as well).
    const struct {
        aero::Axis axis;
        const std::vector<double>* v;
        const char* name;
    } angles[2] = {{aero::Axis::alpha, &tr.alpha, "alpha"}, {aero::Axis::beta, &tr.beta, "beta"}};
    for (const auto& a : angles)
        if (const auto r = static_range(db, a.axis)) {
            const auto lo = std::min_element(a.v->begin(), a.v->end());
            const auto hi = std::max_element(a.v->begin(), a.v->end());
            if (*lo < (*r)[0] - 1e-12 || *hi > (*r)[1] + 1e-12) {
                const std::size_t i = static_cast<std::size_t>(
                    ((*r)[0] - *lo >= *hi - (*r)[1] ? lo : hi) - a.v->begin());
                warnings.push_back(fmt::format(
                    "warning: {}: {} {:.3g} deg at t = {:.4g} s is outside the tables' range "
                    "{:g} to {:g} deg of {}; the tables are extrapolated there",
                    tr.source, a.name, (*a.v)[i] * deg, tr.t[i], (*r)[0] * deg, (*r)[1] * deg,
                    label));
            }
        }
    // A control the trajectory moves that no table knows: the table prediction leaves it out.
    const aero::Axis control_axes[3] = {aero::Axis::elevator, aero::Axis::aileron,
                                        aero::Axis::rudder};
    for (std::size_t k = 0; k < 3; ++k) {
        const ColumnPeak p = peak(tr.t, tr.controls[k]);
        if (std::abs(p.value) > deflection_tol && !tables_have_axis(db, control_axes[k]))
            warnings.push_back(fmt::format(
                "warning: {}: the {} deflects (up to {:.3g} deg at t = {:.4g} s) and {} has no "
                "{} table; the table prediction leaves the {} out",
                tr.source, control_names[k], p.value * deg, p.t, label, control_names[k],
                control_names[k]));
    }
    return warnings;
}

std::vector<std::string> check_euler_setup(const EulerFacts& e, const AircraftFacts& aircraft,
                                           const Trajectory& tr) {
    std::vector<std::string> warnings;
    // The mesh's companion: the aircraft it was made from.
    if (e.companion) {
        const CompanionFacts& c = *e.companion;
        const std::string d = reference_difference(c.reference, 1.0, aircraft.reference);
        if (!d.empty())
            throw InputError(fmt::format(
                "{}: a mesh of the aircraft '{}' ({} has {}); expected a mesh of the aircraft "
                "file {} ('{}': {}; `manta mesh --aircraft {}`)",
                e.mesh, c.aircraft_name, c.file, d, aircraft.file, aircraft.name,
                reference_words(aircraft.reference), aircraft.file));
        if (!c.aircraft_name.empty() && c.aircraft_name != aircraft.name)
            warnings.push_back(fmt::format(
                "warning: {}: a mesh of the aircraft '{}' ({}), the aircraft file {} is '{}' "
                "with the same reference values; the replay assumes they are the same aircraft",
                e.mesh, c.aircraft_name, c.file, aircraft.file, aircraft.name));
    }
    // The reference the solver divides by: the aircraft's (half its area for a half model).
    {
        const double factor = e.half_model ? 2.0 : 1.0;
        const std::string d = reference_difference(e.reference, factor, aircraft.reference);
        if (!d.empty()) {
            const std::string want = fmt::format("the aircraft file {} has {}", aircraft.file,
                                                 reference_words(aircraft.reference));
            // Given in the configuration on purpose (a test rig, another normalisation): the
            // coefficients of the two sides are on different references, said once.
            if (e.reference_given)
                warnings.push_back(fmt::format(
                    "warning: {}: reference: {}{}; {}; the Euler coefficients are on the "
                    "configuration's reference, the tables' on the aircraft's",
                    e.config, d, e.half_model ? " for a half model" : "", want));
            else
                throw InputError(fmt::format(
                    "{}: no reference values for the mesh {} ({}; the solver's {}); {}; expected "
                    "the aircraft's (a `reference:` section in the configuration, or the "
                    "companion file `manta mesh` writes beside the mesh)",
                    e.config, e.mesh,
                    e.companion ? "its companion's model does not fit them"
                                : "no `reference:` section and no mesh companion file",
                    d, want));
        }
    }
    // A half model mirrors the flow in its plane y = 0: longitudinal motion only.
    if (e.half_model) {
        const struct {
            const std::vector<double>* v;
            double tol;
            const char* what;
            double scale;
            const char* unit;
        } lateral[5] = {{&tr.beta, lateral_angle_tol, "sideslip", deg, "deg"},
                        {&tr.rates[0], lateral_rate_tol, "roll rate p", deg, "deg/s"},
                        {&tr.rates[2], lateral_rate_tol, "yaw rate r", deg, "deg/s"},
                        {&tr.controls[1], deflection_tol, "aileron deflection", deg, "deg"},
                        {&tr.controls[2], deflection_tol, "rudder deflection", deg, "deg"}};
        for (const auto& l : lateral) {
            const ColumnPeak p = peak(tr.t, *l.v);
            if (std::abs(p.value) > l.tol)
                throw InputError(fmt::format(
                    "{}: a half model ({}), whose symmetry plane mirrors the flow; the "
                    "trajectory {} has {} {:.3g} {} at t = {:.4g} s; expected a full-model mesh "
                    "for a trajectory with sideslip, roll, yaw, aileron or rudder (`manta mesh "
                    "--model full`), or a longitudinal trajectory",
                    e.mesh, e.companion ? e.companion->file + ": model: half" : e.config, tr.source,
                    l.what, p.value * l.scale, l.unit, p.t));
        }
    }
    // Every control the trajectory moves needs a control surface of its mode.
    for (std::size_t k = 0; k < 3; ++k) {
        const ColumnPeak p = peak(tr.t, tr.controls[k]);
        if (std::abs(p.value) > deflection_tol && !has(e.control_modes, control_names[k])) {
            std::string modes;
            for (const std::string& m : e.control_modes) modes += (modes.empty() ? "" : ", ") + m;
            throw InputError(fmt::format(
                "{}: the control mode '{}' deflects (up to {:.3g} deg at t = {:.4g} s) and {}{} "
                "has no control surface of that mode (its control surfaces: {}); expected a "
                "control_surfaces entry with mode: {} for the mesh {}",
                tr.source, control_names[k], p.value * deg, p.t, e.config,
                e.companion ? " with the mesh companion " + e.companion->file : "",
                modes.empty() ? "none" : modes, control_names[k], e.mesh));
        }
    }
    // The flow's Mach number is the trajectory's entry Mach number.
    const double m0 = entry_mach(tr);
    if (e.mach && std::abs(*e.mach - m0) > 1e-6)
        throw InputError(fmt::format(
            "{}: flow.mach {:g}; the trajectory {} enters at Mach {:.6g}; expected no flow.mach "
            "(the replay takes the entry Mach number) or flow.mach {:.6g}",
            e.config, *e.mach, tr.source, m0, m0));
    for (const std::string& k : e.ignored_flow_keys)
        warnings.push_back(
            fmt::format("warning: {}: flow.{} is not used by the replay (the motion sets the flow "
                        "direction and rates)",
                        e.config, k));
    return warnings;
}

}  // namespace manta::replay
