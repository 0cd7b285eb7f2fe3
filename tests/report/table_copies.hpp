#pragma once
/// @file table_copies.hpp
/// Synthetic second table sets for the comparison tests, made from the fixture's tables
/// (tests/data/report/run/tables) in a scratch folder: a copy with some columns scaled, and a
/// copy moved to other Mach and sideslip breakpoints.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "manta/report/text_csv.hpp"

namespace manta::report::test_data {

namespace fs = std::filesystem;

inline const fs::path fixture = fs::path(MANTA_SOURCE_DIR) / "tests/data/report/run";
inline const fs::path fixture_tables = fixture / "tables";

/// An empty scratch folder named after the test and the process.
inline fs::path scratch(const std::string& name) {
    const fs::path d = fs::temp_directory_path() /
                       ("manta_report_compare_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

inline std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

inline void write_csv(const fs::path& file, const std::vector<std::string>& columns,
                      const std::vector<std::vector<std::string>>& rows) {
    std::ofstream out(file);
    for (std::size_t j = 0; j < columns.size(); ++j) out << (j ? "," : "") << csv_field(columns[j]);
    out << '\n';
    for (const auto& r : rows) {
        for (std::size_t j = 0; j < r.size(); ++j) out << (j ? "," : "") << csv_field(r[j]);
        out << '\n';
    }
}

inline std::string text(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

/// A copy of the fixture's tables directory, its source named `source`, with every value in the
/// columns `scaled` (of tables.csv and samples.csv) multiplied by `factor`.
inline fs::path scaled_copy(const std::string& name, const std::vector<std::string>& scaled,
                            double factor, const std::string& source = "scaled") {
    const fs::path d = scratch(name);
    for (const char* f : {"tables.csv", "samples.csv"}) {
        TextCsv t = read_text_csv(fixture_tables / f);
        for (const auto& c : scaled) {
            const int j = t.find(c);
            if (j < 0) continue;
            const auto col = static_cast<std::size_t>(j);
            for (std::size_t i = 0; i < t.rows.size(); ++i)
                if (!t.rows[i][col].empty()) t.rows[i][col] = text(t.number(i, col) * factor);
        }
        write_csv(d / f, t.columns, t.rows);
    }
    fs::copy_file(fixture_tables / "dynamic.csv", d / "dynamic.csv");
    auto summary = read_json(fixture_tables / "summary.json");
    summary["source"]["name"] = source;
    std::ofstream(d / "summary.json") << summary.dump(2);
    return d;
}

/// The fixture's tables moved to Mach 0.1 and 0.6 and (static) sideslip -4 and 10 deg by the
/// bilinear extension of each (alpha, deflection) cell through its corners at Mach 0.2, 0.5 and
/// sideslip 0, 8 deg, alpha limited to [-2, 8] deg, no samples and no dynamic table:
/// multilinear interpolation at the fixture's Mach numbers and sideslips gives its values back.
inline fs::path moved_copy() {
    const fs::path d = scratch("moved");
    const TextCsv t = read_text_csv(fixture_tables / "tables.csv");
    const std::size_t ct = t.require("table"), ca = t.require("alpha_deg"), cm = t.require("mach"),
                      cb = t.require("beta_deg"), cd = t.require("delta_deg");
    // (table, alpha, delta) -> (mach, beta) -> row
    std::map<std::tuple<std::string, double, double>,
             std::map<std::pair<double, double>, std::size_t>>
        cells;
    for (std::size_t i = 0; i < t.rows.size(); ++i)
        cells[{t.rows[i][ct], t.number(i, ca), t.number(i, cd)}]
             [{t.number(i, cm), t.number(i, cb)}] = i;
    std::vector<std::vector<std::string>> rows;
    for (const auto& [key, corners] : cells) {
        const auto& [table, alpha, delta] = key;
        if (alpha < -2 || alpha > 8) continue;
        const bool lateral = table == "static";
        const std::vector<double> new_b =
            lateral ? std::vector<double>{-4, 10} : std::vector<double>{0};
        for (const double m : {0.1, 0.6})
            for (const double b : new_b) {
                const double tm = (m - 0.2) / 0.3, tb = lateral ? b / 8.0 : 0.0;
                std::vector<std::string> r = t.rows[corners.begin()->second];
                r[cm] = text(m);
                r[cb] = text(b);
                for (std::size_t j = 0; j < t.columns.size(); ++j) {
                    if (j == ct || j == ca || j == cm || j == cb || j == cd) continue;
                    auto v = [&](double mm, double bb) {
                        return t.number(corners.at({mm, bb}), j);
                    };
                    double x = (1 - tm) * v(0.2, 0.0) + tm * v(0.5, 0.0);
                    if (lateral)
                        x = (1 - tm) * (1 - tb) * v(0.2, 0.0) + tm * (1 - tb) * v(0.5, 0.0) +
                            (1 - tm) * tb * v(0.2, 8.0) + tm * tb * v(0.5, 8.0);
                    if (t.columns[j].rfind("sigma_", 0) == 0) x = std::abs(x);
                    r[j] = text(x);
                }
                rows.push_back(r);
            }
    }
    write_csv(d / "tables.csv", t.columns, rows);
    std::ofstream(d / "summary.json") << R"({"source": {"name": "moved"}})";
    return d;
}

}  // namespace manta::report::test_data
