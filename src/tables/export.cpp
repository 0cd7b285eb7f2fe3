/// @file export.cpp
/// CSV, CEASIOM/SDSA and JSBSim exports of generated tables.

#include "manta/tables/export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/core/units.hpp"

namespace manta::tables {

namespace {

using core::format_exact;

/// Degrees for display: 10 significant digits (so 12 deg reads 12, not 11.999999999999998).
std::string deg(double rad) {
    const double d = rad * core::rad_to_deg;
    return fmt::format("{:.10g}", d == 0.0 ? 0.0 : d);
}

std::string plain(double v) {
    return fmt::format("{:.10g}", v == 0.0 ? 0.0 : v);
}

/// CSV field, quoted if it holds a comma, quote or line break.
std::string csv_text(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (const char c : s) {
        if (c == '"') q += '"';
        q += (c == '\n' || c == '\r') ? ' ' : c;
    }
    return q + "\"";
}

const aero::Table* find_table(const aero::AeroDatabase& db, aero::TableKind kind,
                              std::optional<aero::Axis> control = std::nullopt) {
    for (const auto& t : db.tables()) {
        if (t.kind != kind) continue;
        if (!control) return &t;
        for (const auto& a : t.axes)
            if (a.axis == *control) return &t;
    }
    return nullptr;
}

/// Flat indices of a table's grid -> per-axis indices (last fastest).
std::vector<std::size_t> unflatten(const aero::Table& t, std::size_t flat) {
    std::vector<std::size_t> idx(t.axes.size());
    for (std::size_t k = t.axes.size(); k-- > 0;) {
        const std::size_t n = t.axes[k].breakpoints.size();
        idx[k] = flat % n;
        flat /= n;
    }
    return idx;
}

/// The axis values of a table's entry `flat` (axes the table lacks are 0).
struct EntryPoint {
    double alpha = 0, mach = 0, beta = 0, elevator = 0, aileron = 0, rudder = 0;
    /// The deflection of whichever control axis the table has (0 if none).
    [[nodiscard]] double delta() const { return elevator + aileron + rudder; }
};

EntryPoint entry_point(const aero::Table& t, std::size_t flat) {
    const auto idx = unflatten(t, flat);
    EntryPoint p;
    for (std::size_t k = 0; k < t.axes.size(); ++k) {
        const double v = t.axes[k].breakpoints[idx[k]];
        switch (t.axes[k].axis) {
            case aero::Axis::alpha:
                p.alpha = v;
                break;
            case aero::Axis::mach:
                p.mach = v;
                break;
            case aero::Axis::beta:
                p.beta = v;
                break;
            case aero::Axis::elevator:
                p.elevator = v;
                break;
            case aero::Axis::aileron:
                p.aileron = v;
                break;
            case aero::Axis::rudder:
                p.rudder = v;
                break;
        }
    }
    return p;
}

/// Wind-axis forces and body moments of the database at q, in the order CL CD Cm CY Cl Cn.
std::array<double, 6> paper_order(const aero::AeroDatabase& db, const aero::AeroQuery<double>& q) {
    const aero::BodyCoefficients<double> b = db.evaluate(q, aero::Interpolation::multilinear);
    const auto w = aero::wind_from_body(b.CX, b.CY, b.CZ, q.alpha, q.beta);
    return {w.CL, w.CD, b.Cm, w.CY, b.Cl, b.Cn};
}

int column_index(const aero::Table& t, const std::string& name) {
    for (std::size_t i = 0; i < t.columns.size(); ++i)
        if (t.columns[i] == name) return static_cast<int>(i);
    return -1;
}

}  // namespace

std::string tables_csv(const std::vector<TableWithSigma>& tables) {
    std::string out =
        "# MANTA generated tables (docs/formats.md#tables-csv): static rows hold coefficients, "
        "control rows increments; sigma = Kriging standard deviation (0 at samples)\n"
        "table,alpha_deg,mach,beta_deg,delta_deg,CL,CD,CY,Cl,Cm,Cn,sigma_CL,sigma_CD,sigma_CY,"
        "sigma_Cl,sigma_Cm,sigma_Cn\n";
    for (const auto& ts : tables) {
        const aero::Table& t = ts.table;
        if (t.kind == aero::TableKind::dynamic) continue;
        const std::size_t nc = t.columns.size();
        for (std::size_t e = 0; e < t.n_points(); ++e) {
            const EntryPoint p = entry_point(t, e);
            out += fmt::format("{},{},{},{},{}", t.name, deg(p.alpha), plain(p.mach), deg(p.beta),
                               deg(p.delta()));
            for (const char* c : coefficient_names) {
                const int j = column_index(t, c);
                out += ',';
                out += j < 0 ? std::string("0")
                             : format_exact(t.values[e * nc + static_cast<std::size_t>(j)]);
            }
            for (const char* c : coefficient_names) {
                const int j = column_index(t, c);
                out += ',';
                out += j < 0 || ts.sigma.empty()
                           ? std::string("0")
                           : format_exact(ts.sigma[e * nc + static_cast<std::size_t>(j)]);
            }
            out += '\n';
        }
    }
    return out;
}

std::string dynamic_csv(const std::vector<TableWithSigma>& tables) {
    for (const auto& ts : tables) {
        const aero::Table& t = ts.table;
        if (t.kind != aero::TableKind::dynamic) continue;
        std::string out =
            "# MANTA dynamic derivatives (per non-dimensional rate p_hat = pb/2V, q_hat = qc/2V, "
            "r_hat = rb/2V; central differences)\nalpha_deg,mach";
        for (const auto& c : t.columns) {
            out += ',';
            out += c;
        }
        out += '\n';
        const std::size_t nc = t.columns.size();
        for (std::size_t e = 0; e < t.n_points(); ++e) {
            const EntryPoint p = entry_point(t, e);
            out += fmt::format("{},{}", deg(p.alpha), plain(p.mach));
            for (std::size_t j = 0; j < nc; ++j) {
                out += ',';
                out += format_exact(t.values[e * nc + j]);
            }
            out += '\n';
        }
        return out;
    }
    return {};
}

std::string samples_csv(const std::vector<Sample>& samples) {
    std::string out =
        "id,scenario,status,alpha_deg,beta_deg,mach,p_hat,q_hat,r_hat,elevator_deg,aileron_deg,"
        "rudder_deg,CL,CD,CY,Cl,Cm,Cn,CX,CY_body,CZ,CD_induced,CD_profile,wall_time_s,source,"
        "fingerprint,created_at,finished_at,error\n";
    for (const Sample& s : samples) {
        const auto& q = s.query;
        out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}", s.id, csv_text(s.scenario),
                           to_string(s.status), deg(q.alpha), deg(q.beta), plain(q.mach),
                           format_exact(q.p_hat), format_exact(q.q_hat), format_exact(q.r_hat),
                           deg(q.elevator), deg(q.aileron), deg(q.rudder));
        if (s.status == SampleStatus::done) {
            const auto& r = s.result;
            for (const double v : {r.wind.CL, r.wind.CD, r.wind.CY, r.body.Cl, r.body.Cm, r.body.Cn,
                                   r.body.CX, r.body.CY, r.body.CZ, r.CD_induced, r.CD_profile}) {
                out += ',';
                out += format_exact(v);
            }
        } else {
            out += ",,,,,,,,,,,";
        }
        out += fmt::format(
            ",{},{},{},{},{},{}\n",
            s.status == SampleStatus::pending ? "" : fmt::format("{:.6f}", s.wall_time_s),
            csv_text(s.source), csv_text(s.fingerprint), s.created_at, s.finished_at,
            csv_text(s.error));
    }
    return out;
}

std::string ceasiom_aero_table(const aero::AeroDatabase& db, double rate_step) {
    if (db.force_axes() != aero::ForceAxes::wind)
        throw InputError("CEASIOM export: the database has body-axis forces; expected wind axes");
    const aero::Table* st = find_table(db, aero::TableKind::static_table);
    std::vector<double> alpha{0.0}, mach{0.0}, beta{0.0};
    for (const auto& a : st->axes) {
        if (a.axis == aero::Axis::alpha)
            alpha = a.breakpoints;
        else if (a.axis == aero::Axis::mach)
            mach = a.breakpoints;
        else if (a.axis == aero::Axis::beta)
            beta = a.breakpoints;
        else
            throw InputError(fmt::format(
                "CEASIOM export: the static table has a '{}' axis; expected alpha, mach, beta",
                aero::to_string(a.axis)));
    }
    std::string out = fmt::format(
        "# CEASIOM/SDSA aerodata, aero table (Ghoreyshi et al. 2010, Table 5): {}\n"
        "# Angles in degrees; rates non-dimensional (p_hat = pb/2V, q_hat = qc/2V, r_hat = "
        "rb/2V);\n"
        "# CL CD CY wind axes, Cl Cm Cn body axes about the moment reference point.\n"
        "# Rows with a non-zero rate (beta = 0) give the coefficients at that rate.\n"
        "{:>10} {:>8} {:>10} {:>10} {:>10} {:>10} {:>16} {:>16} {:>16} {:>16} {:>16} {:>16}\n",
        db.info().name, "alpha", "Mach", "beta", "p_hat", "q_hat", "r_hat", "CL", "CD", "Cm", "CY",
        "Cl", "Cn");
    auto row = [&](const aero::AeroQuery<double>& q) {
        const auto c = paper_order(db, q);
        out += fmt::format("{:>10} {:>8} {:>10} {:>10} {:>10} {:>10}", deg(q.alpha), plain(q.mach),
                           deg(q.beta), plain(q.p_hat), plain(q.q_hat), plain(q.r_hat));
        for (const double v : c) out += fmt::format(" {:>16.9e}", v);
        out += '\n';
    };
    for (const double a : alpha)
        for (const double m : mach)
            for (const double b : beta) {
                aero::AeroQuery<double> q;
                q.alpha = a;
                q.mach = m;
                q.beta = b;
                row(q);
            }
    if (const aero::Table* dt = find_table(db, aero::TableKind::dynamic)) {
        std::vector<double> da{0.0}, dm{0.0};
        for (const auto& a : dt->axes) {
            if (a.axis == aero::Axis::alpha) da = a.breakpoints;
            if (a.axis == aero::Axis::mach) dm = a.breakpoints;
        }
        for (const double a : da)
            for (const double m : dm)
                for (int r = 0; r < 3; ++r) {
                    aero::AeroQuery<double> q;
                    q.alpha = a;
                    q.mach = m;
                    (r == 0 ? q.p_hat : r == 1 ? q.q_hat : q.r_hat) = rate_step;
                    row(q);
                }
    }
    return out;
}

std::string ceasiom_control_table(const aero::AeroDatabase& db) {
    std::string out = fmt::format(
        "# CEASIOM/SDSA aerodata, control table (Ghoreyshi et al. 2010, Table 5): {}\n"
        "# Increments dC added to the aero table; angles in degrees; beta = 0.\n"
        "{:>10} {:>8} {:>10} {:>10} {:>10} {:>16} {:>16} {:>16} {:>16} {:>16} {:>16}\n",
        db.info().name, "alpha", "Mach", "delta_e", "delta_r", "delta_a", "dCL", "dCD", "dCm",
        "dCY", "dCl", "dCn");
    const aero::Axis order[3] = {aero::Axis::elevator, aero::Axis::rudder, aero::Axis::aileron};
    for (const aero::Axis control : order) {
        const aero::Table* t = find_table(db, aero::TableKind::control, control);
        if (!t) continue;
        const std::size_t nc = t->columns.size();
        for (std::size_t e = 0; e < t->n_points(); ++e) {
            const EntryPoint p = entry_point(*t, e);
            out += fmt::format("{:>10} {:>8} {:>10} {:>10} {:>10}", deg(p.alpha), plain(p.mach),
                               deg(p.elevator), deg(p.rudder), deg(p.aileron));
            for (const char* c : {"CL", "CD", "Cm", "CY", "Cl", "Cn"}) {
                const int j = column_index(*t, c);
                out += fmt::format(" {:>16.9e}",
                                   j < 0 ? 0.0 : t->values[e * nc + static_cast<std::size_t>(j)]);
            }
            out += '\n';
        }
    }
    return out;
}

namespace {

std::string jsbsim_property(aero::Axis a) {
    switch (a) {
        case aero::Axis::alpha:
            return "aero/alpha-rad";
        case aero::Axis::beta:
            return "aero/beta-rad";
        case aero::Axis::mach:
            return "velocities/mach";
        case aero::Axis::elevator:
            return "fcs/elevator-pos-rad";
        case aero::Axis::aileron:
            return "fcs/left-aileron-pos-rad";
        case aero::Axis::rudder:
            return "fcs/rudder-pos-rad";
    }
    return "?";
}

/// <table> of one column over the varying axes of `t` (at most three).
std::string jsbsim_table(const aero::Table& t, std::size_t column, const std::string& indent) {
    std::vector<std::size_t> active;
    for (std::size_t k = 0; k < t.axes.size(); ++k)
        if (t.axes[k].breakpoints.size() > 1) active.push_back(k);
    if (active.size() > 3)
        throw InputError(fmt::format(
            "JSBSim export: table '{}' varies along {} axes; JSBSim tables have at most 3", t.name,
            active.size()));
    const std::size_t nc = t.columns.size();
    // Value at per-active-axis indices (inactive axes have one breakpoint: index 0).
    auto value = [&](const std::vector<std::size_t>& ai) {
        std::size_t flat = 0;
        for (std::size_t k = 0; k < t.axes.size(); ++k) {
            std::size_t i = 0;
            for (std::size_t a = 0; a < active.size(); ++a)
                if (active[a] == k) i = ai[a];
            flat = flat * t.axes[k].breakpoints.size() + i;
        }
        return format_exact(t.values[flat * nc + column]);
    };
    if (active.empty()) return indent + "<value>" + value({}) + "</value>\n";
    const std::string in2 = indent + "  ", in3 = indent + "    ";
    std::string out = indent + "<table>\n";
    const char* lookup[3] = {"row", "column", "table"};
    for (std::size_t a = 0; a < active.size(); ++a)
        out += fmt::format("{}<independentVar lookup=\"{}\">{}</independentVar>\n", in2, lookup[a],
                           jsbsim_property(t.axes[active[a]].axis));
    const auto& rows = t.axes[active[0]].breakpoints;
    auto block = [&](std::optional<std::size_t> layer) {
        std::string b;
        if (active.size() >= 2) {
            b += in3 + std::string(18, ' ');
            for (const double c : t.axes[active[1]].breakpoints)
                b += fmt::format(" {:>24}", format_exact(c));
            b += '\n';
        }
        for (std::size_t r = 0; r < rows.size(); ++r) {
            b += fmt::format("{}{:>18}", in3, format_exact(rows[r]));
            if (active.size() == 1) {
                b += fmt::format(" {:>24}", value({r}));
            } else {
                for (std::size_t c = 0; c < t.axes[active[1]].breakpoints.size(); ++c)
                    b += fmt::format(" {:>24}", layer ? value({r, c, *layer}) : value({r, c}));
            }
            b += '\n';
        }
        return b;
    };
    if (active.size() < 3) {
        out += in2 + "<tableData>\n" + block(std::nullopt) + in2 + "</tableData>\n";
    } else {
        const auto& layers = t.axes[active[2]].breakpoints;
        for (std::size_t l = 0; l < layers.size(); ++l)
            out += fmt::format("{}<tableData breakPoint=\"{}\">\n", in2, format_exact(layers[l])) +
                   block(l) + in2 + "</tableData>\n";
    }
    return out + indent + "</table>\n";
}

/// XML text escaping for descriptions.
std::string xml_escape(const std::string& s) {
    std::string o;
    for (const char c : s) {
        switch (c) {
            case '&':
                o += "&amp;";
                break;
            case '<':
                o += "&lt;";
                break;
            case '>':
                o += "&gt;";
                break;
            case '"':
                o += "&quot;";
                break;
            default:
                o += c;
        }
    }
    return o;
}

}  // namespace

std::string jsbsim_aerodynamics(const aero::AeroDatabase& db) {
    if (db.force_axes() != aero::ForceAxes::wind)
        throw InputError(
            "JSBSim export: the database has body-axis forces (CX CY CZ); expected wind axes "
            "(CL CD CY) for JSBSim's LIFT, DRAG and SIDE axes");
    struct AxisInfo {
        const char* coef;
        const char* axis;
        const char* length;  // reference length property ("" for forces)
        const char* word;
    };
    const AxisInfo axes[6] = {{"CL", "LIFT", "", "lift"},
                              {"CD", "DRAG", "", "drag"},
                              {"CY", "SIDE", "", "side"},
                              {"Cl", "ROLL", "metrics/bw-ft", "roll"},
                              {"Cm", "PITCH", "metrics/cbarw-ft", "pitch"},
                              {"Cn", "YAW", "metrics/bw-ft", "yaw"}};
    std::string out =
        "<?xml version=\"1.0\"?>\n"
        "<!-- JSBSim aerodynamics generated by MANTA (manta tables; "
        "docs/formats.md#jsbsim-export).\n"
        "     " +
        xml_escape(db.info().name) +
        "\n"
        "     Coefficients: CL CD CY wind axes, Cl Cm Cn body axes about the moment reference\n"
        "     point (set AERORP there); control signs of MANTA: elevator trailing edge down +,\n"
        "     left aileron trailing edge down +, rudder trailing edge left +. Tables are clamped\n"
        "     at their ends (JSBSim does not extrapolate). -->\n"
        "<aerodynamics>\n";
    for (const AxisInfo& ax : axes) {
        out += fmt::format("  <axis name=\"{}\">\n", ax.axis);
        for (const aero::Table& t : db.tables()) {
            for (std::size_t c = 0; c < t.columns.size(); ++c) {
                const std::string& col = t.columns[c];
                std::string rate;
                if (t.kind == aero::TableKind::dynamic) {
                    const auto us = col.find('_');
                    if (col.substr(0, us) != ax.coef) continue;
                    rate = col.substr(us + 1);
                } else if (col != ax.coef) {
                    continue;
                }
                const std::string fname =
                    rate.empty() ? fmt::format("aero/coefficient/manta/{}_{}", ax.coef, t.name)
                                 : fmt::format("aero/coefficient/manta/{}_{}", ax.coef, rate);
                std::string desc = rate.empty()
                                       ? fmt::format("{} from the {} table ({})", ax.word, t.name,
                                                     aero::to_string(t.kind))
                                       : fmt::format("{} due to {} ({} per non-dimensional rate)",
                                                     ax.word, rate, col);
                out += fmt::format(
                    "    <function name=\"{}\">\n      <description>{}</description>\n"
                    "      <product>\n        <property>aero/qbar-psf</property>\n"
                    "        <property>metrics/Sw-sqft</property>\n",
                    fname, xml_escape(desc));
                if (*ax.length) out += fmt::format("        <property>{}</property>\n", ax.length);
                if (!rate.empty()) {
                    const bool chord = rate == "q" || rate == "alphadot";
                    const char* body_rate = rate == "p"          ? "velocities/p-aero-rad_sec"
                                            : rate == "q"        ? "velocities/q-aero-rad_sec"
                                            : rate == "r"        ? "velocities/r-aero-rad_sec"
                                            : rate == "alphadot" ? "aero/alphadot-rad_sec"
                                                                 : "aero/betadot-rad_sec";
                    out += fmt::format(
                        "        <property>{}</property>\n        <property>{}</property>\n",
                        chord ? "aero/ci2vel" : "aero/bi2vel", body_rate);
                }
                out += jsbsim_table(t, c, "        ");
                out += "      </product>\n    </function>\n";
            }
        }
        out += "  </axis>\n";
    }
    return out + "</aerodynamics>\n";
}

}  // namespace manta::tables
