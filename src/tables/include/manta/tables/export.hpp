#pragma once
/// @file export.hpp
/// Text exports of generated tables (formats: docs/formats.md):
///  - `tables.csv`: every entry of the static and control tables with its standard deviation;
///  - `dynamic.csv`: the dynamic derivatives over (alpha, M);
///  - `samples.csv`: every stored sample with its status, outputs, wall time and error;
///  - the CEASIOM/SDSA aerodata layout of Ghoreyshi et al. (2010), Table 5: an aero table of
///    alpha, M, beta, p_hat, q_hat, r_hat and CL CD Cm CY Cl Cn, and a control table of alpha, M,
///    delta_e, delta_r, delta_a and the six coefficient increments (angles in degrees);
///  - a JSBSim `<aerodynamics>` element (tables of at most three dimensions, JSBSim property
///    names, wind-axis forces LIFT DRAG SIDE, body-axis moments ROLL PITCH YAW).
/// Each function returns the text; the caller writes it (atomically).

#include <string>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/tables/generator.hpp"
#include "manta/tables/store.hpp"

namespace manta::tables {

/// CSV of the static and control tables: table, alpha_deg, mach, beta_deg, delta_deg, the six
/// coefficients (static: values; control: increments) and sigma_<coef> for each.
[[nodiscard]] std::string tables_csv(const std::vector<TableWithSigma>& tables);
/// CSV of the dynamic table: alpha_deg, mach and its columns ("" if `tables` has none).
[[nodiscard]] std::string dynamic_csv(const std::vector<TableWithSigma>& tables);
/// CSV of stored samples (angles in degrees; text fields quoted when needed).
[[nodiscard]] std::string samples_csv(const std::vector<Sample>& samples);

/// CEASIOM/SDSA aero table: a row per static entry (rates zero), then for every point of the
/// dynamic table (beta = 0) one row per rate with that rate at `rate_step` and the others zero.
/// Coefficients are the database's (wind-axis forces) at each state. Requires a static table over
/// (alpha, mach, beta) and a wind-axis database.
[[nodiscard]] std::string ceasiom_aero_table(const aero::AeroDatabase& db, double rate_step);
/// CEASIOM/SDSA control table: one block per control table, rows alpha, M, delta_e, delta_r,
/// delta_a (the other deflections zero) and the six increments.
[[nodiscard]] std::string ceasiom_control_table(const aero::AeroDatabase& db);

/// JSBSim aerodynamics XML of a wind-axis database: each table column becomes a <function> in
/// its axis (CL LIFT, CD DRAG, CY SIDE, Cl ROLL, Cm PITCH, Cn YAW), a <product> of aero/qbar-psf,
/// metrics/Sw-sqft, the reference length for moments (metrics/bw-ft or metrics/cbarw-ft), for a
/// dynamic column the rate factor (aero/bi2vel or aero/ci2vel times the body rate property) and
/// a <table> over the table's axes with more than one breakpoint (row, column, then <tableData
/// breakPoint=...> blocks). InputError for a body-axis database or a table with more than three
/// varying axes.
[[nodiscard]] std::string jsbsim_aerodynamics(const aero::AeroDatabase& db);

}  // namespace manta::tables
