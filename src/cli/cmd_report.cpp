/// @file cmd_report.cpp
/// `manta report RUN_DIR --html FILE [--figures DIR] [--png] [--compare-tables DIR
/// [--compare-label TEXT]] [--json]`: the self-contained HTML report of a run directory
/// (docs/report.md).

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <memory>
#include <optional>
#include <string>

#include "checks.hpp"
#include "commands.hpp"
#include "manta/core/io.hpp"
#include "manta/report/report.hpp"

namespace manta::cli {

namespace {

/// The comparison's summary in a few lines (the numbers of --json, 4 significant digits).
void print_comparison(const nlohmann::json& c) {
    auto v = [](const nlohmann::json& x) {
        return x.is_number() ? fmt::format("{:.4g}", x.get<double>()) : std::string("-");
    };
    const std::string a = c["main"]["label"].get<std::string>();
    const std::string b = c["compare"]["label"].get<std::string>();
    fmt::print("  compared with {} ({}); {} / {} (ratio):\n", b,
               c["compare"]["dir"].get<std::string>(), a, b);
    for (const auto& e : c["summary"]) {
        std::string line = fmt::format("    M {}:", v(e["mach"]));
        for (const char* k : report::summary_names)
            line += fmt::format(" {} {} / {} ({})", k, v(e["main"][k]), v(e["compare"][k]),
                                v(e["ratio"][k]));
        fmt::print("{}\n", line);
    }
}

}  // namespace

void add_report(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "report",
        "Self-contained HTML report of a run directory (or of one tables, optimise or "
        "replay output directory)");
    auto o = std::make_shared<report::ReportOptions>();
    auto run_dir = std::make_shared<std::string>();
    auto html = std::make_shared<std::string>();
    auto figures = std::make_shared<std::string>();
    auto png = std::make_shared<bool>(false);
    auto json = std::make_shared<bool>(false);
    auto compare = std::make_shared<std::string>();
    cmd->add_option("RUN_DIR", *run_dir,
                    "Run directory (manta demo --out), or a tables, optimise "
                    "or replay output directory")
        ->required();
    cmd->add_option("--html", *html, "Write the report to this HTML file")
        ->required()
        ->check(output_path());
    cmd->add_option("--figures", *figures,
                    "Also write every figure as SVG and its curves as CSV into this folder")
        ->check(output_path());
    cmd->add_flag("--png", *png,
                  "With --figures: also render each SVG as PNG with headless chromium (a few "
                  "seconds per figure; skipped with a note when chromium is absent)");
    cmd->add_option("--chromium", o->chromium,
                    "Browser executable for the PNGs (default: chromium on PATH)");
    auto* compare_opt = cmd->add_option(
        "--compare-tables", *compare,
        "A second `manta tables --out` directory: its tables drawn beside RUN_DIR's "
        "on the same axes, with a summary of slopes, zero-incidence coefficients and "
        "control powers");
    cmd->add_option("--compare-label", o->compare_label,
                    "Name of the compared tables in the page (default: the source in its "
                    "summary.json, e.g. vlm or euler)")
        ->needs(compare_opt);
    cmd->add_flag("--json", *json, "Print one JSON object: parts shown, parts missing, files");
    cmd->callback([=, &action] {
        action = [=]() -> int {
            report::ReportOptions opt = *o;
            opt.run_dir = *run_dir;
            opt.html = *html;
            core::prepare_output_file(*html, "--html");
            std::optional<core::RunFolderLock> lock;
            if (!figures->empty()) {
                lock.emplace(*figures, "report", "--figures");
                opt.figures_dir = *figures;
            }
            opt.png = *png;
            if (!compare->empty()) opt.compare_tables = *compare;
            const report::ReportResult r = report::make_report(opt);
            if (*json) {
                print_json(r.to_json());
            } else {
                fmt::print("report of {} ({} layout): {} plots, {} bytes\n", *run_dir, r.layout,
                           r.n_figures, r.html_bytes);
                fmt::print("  shown: {}\n", fmt::join(r.parts, ", "));
                if (!r.missing.empty()) fmt::print("  absent: {}\n", fmt::join(r.missing, ", "));
                if (!r.comparison.is_null()) print_comparison(r.comparison);
                if (opt.figures_dir)
                    fmt::print("  figures: {} files in {}\n", r.files.size() - 1,
                               opt.figures_dir->string());
                if (!r.png_note.empty()) fmt::print("  {}\n", r.png_note);
                fmt::print("  wrote {}\n", *html);
            }
            return 0;
        };
    });
}

}  // namespace manta::cli
