/// @file report.cpp
/// `make_report`: read, build, render, write (figures first, the page last, each atomically);
/// the three-view drawing; PNG rendering with headless chromium.

#include "manta/report/report.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/report/html.hpp"

namespace manta::report {

namespace fs = std::filesystem;

namespace {

/// Run a program with arguments (no shell), stdout and stderr discarded; returns its exit status
/// or -1 if it could not be started.
int run_quietly(const std::vector<std::string>& args) {
    const pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        if (freopen("/dev/null", "w", stdout) == nullptr ||
            freopen("/dev/null", "w", stderr) == nullptr)
            _exit(127);
        execvp(argv[0], argv.data());
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Width and height of an SVG from its root element's attributes.
std::array<int, 2> svg_size(const std::string& svg) {
    auto attr = [&](const char* name) {
        const auto k = svg.find(std::string(" ") + name + "=\"");
        if (k == std::string::npos) return 800;
        return static_cast<int>(
            std::lround(std::atof(svg.c_str() + k + std::string(name).size() + 3)));
    };
    return {attr("width"), attr("height")};
}

}  // namespace

std::string three_view_svg(const AircraftInfo& a) {
    struct Box {
        double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
        void add(const std::array<double, 2>& p) {
            x0 = std::min(x0, p[0]);
            x1 = std::max(x1, p[0]);
            y0 = std::min(y0, p[1]);
            y1 = std::max(y1, p[1]);
        }
    };
    // Screen coordinates per view: side (x aft right, z up), top (x aft right, y right up: seen
    // from above with the nose to the left), front (seen from ahead: y right to the left, z up).
    auto side = [](const std::array<double, 2>& p) { return std::array<double, 2>{p[0], p[1]}; };
    auto top = [](const std::array<double, 2>& p) { return std::array<double, 2>{p[0], p[1]}; };
    auto front = [](const std::array<double, 2>& p) { return std::array<double, 2>{-p[0], p[1]}; };
    Box bs, bt, bf;
    for (const auto& o : a.side)
        for (const auto& p : o.points) bs.add(side(p));
    for (const auto& o : a.top)
        for (const auto& p : o.points) bt.add(top(p));
    for (const auto& o : a.front)
        for (const auto& p : o.points) bf.add(front(p));
    // Side and top views one above the other, the front view beside the top view; 720 px
    // wide in all (30 px between the views).
    const double scale =
        (720.0 - 30.0) / std::max(1e-3, std::max(bs.x1 - bs.x0, bt.x1 - bt.x0) + (bf.x1 - bf.x0));
    const double pad = 20, gap = 30;
    const double w_left = (bt.x1 - bt.x0) * scale, h_side = (bs.y1 - bs.y0) * scale;
    const double h_top = (bt.y1 - bt.y0) * scale, w_front = (bf.x1 - bf.x0) * scale;
    const double h_front = (bf.y1 - bf.y0) * scale;
    const double width = pad * 2 + w_left + gap + w_front;
    const double height = pad * 2 + 20 + h_side + gap + std::max(h_top, h_front) + 24;
    std::string s = fmt::format(
        R"(<svg xmlns="http://www.w3.org/2000/svg" width="{0:.0f}" height="{1:.0f}" viewBox="0 0 {0:.0f} {1:.0f}">)",
        width, height);
    s += "\n<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>\n";
    auto draw = [&](const std::vector<Outline>& outlines, auto map, const Box& b, double ox,
                    double oy, const char* label) {
        for (const auto& o : outlines) {
            std::string pts;
            for (const auto& p : o.points) {
                const auto q = map(p);
                pts += fmt::format("{:.1f},{:.1f} ", ox + (q[0] - b.x0) * scale,
                                   oy + (b.y1 - q[1]) * scale);
            }
            s += fmt::format(
                R"(<polygon points="{}" fill="#dfe7f2" fill-opacity="0.6" stroke="#1d3557" stroke-width="1"><title>{}</title></polygon>)",
                pts, escape_html(o.part));
            s += '\n';
        }
        s += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="12">{}</text>)", ox, oy - 6,
                         label);
        s += '\n';
    };
    const double y_side = pad + 20, y_low = y_side + h_side + gap;
    draw(a.side, side, bs, pad, y_side, "side");
    draw(a.top, top, bt, pad, y_low, "top (nose left)");
    draw(a.front, front, bf, pad + w_left + gap, y_low + (std::max(h_top, h_front) - h_front) / 2,
         "front");
    // Scale bar: 1 m.
    const double yb = height - 12;
    s += fmt::format(
        R"(<line x1="{0:.1f}" y1="{1:.1f}" x2="{2:.1f}" y2="{1:.1f}" stroke="#222" stroke-width="2"/><text x="{3:.1f}" y="{4:.1f}" font-size="12">1 m</text>)",
        pad, yb, pad + scale, pad + scale + 6, yb + 4);
    s += "\n</svg>\n";
    return s;
}

std::string find_chromium() {
    const char* path = std::getenv("PATH");
    if (!path) return {};
    const std::string p(path);
    for (const char* name : {"chromium", "chromium-browser", "google-chrome", "chrome"}) {
        std::size_t pos = 0;
        while (pos <= p.size()) {
            const auto k = p.find(':', pos);
            const std::string dir =
                p.substr(pos, k == std::string::npos ? std::string::npos : k - pos);
            const fs::path f = fs::path(dir.empty() ? "." : dir) / name;
            if (::access(f.c_str(), X_OK) == 0) return f.string();
            if (k == std::string::npos) break;
            pos = k + 1;
        }
    }
    return {};
}

nlohmann::json ReportResult::to_json() const {
    nlohmann::json j{{"layout", layout},         {"parts", parts},        {"missing", missing},
                     {"figures", n_figures},     {"files", files},        {"png_note", png_note},
                     {"html_bytes", html_bytes}, {"pictures", n_pictures}};
    if (!comparison.is_null()) j["comparison"] = comparison;
    return j;
}

ReportResult make_report(const ReportOptions& o) {
    if (o.html.empty()) throw InputError("--html: no output file given; expected a file name");
    RunData run = read_run(o.run_dir);
    if (o.compare_tables) {
        if (!run.tables || !run.tables->tables.count("static"))
            throw InputError(fmt::format(
                "--compare-tables: {} has no static table to compare with; expected a run "
                "directory with tables/ or a `manta tables --out` directory",
                o.run_dir.string()));
        TablesData other = read_compare_tables(*o.compare_tables);
        check_same_coefficients(*run.tables, other);
        if (!o.compare_label.empty()) {
            other.label = o.compare_label;
        } else if (other.label == run.tables->label) {
            // Two tables from the same source: the directory names tell them apart.
            const fs::path norm = fs::absolute(other.dir).lexically_normal();
            const std::string leaf =
                (norm.has_filename() ? norm : norm.parent_path()).filename().string();
            other.label += " (" + leaf + ")";
        }
        run.compare = std::move(other);
    }
    const ReportContent content = build_content(run);
    const std::string page = render_html(run, content);

    ReportResult r;
    r.layout = run.layout;
    if (run.aircraft) r.parts.push_back("aircraft");
    if (run.tables) r.parts.push_back("tables");
    if (run.compare) r.parts.push_back("compare-tables");
    for (const auto& m : run.manoeuvres) r.parts.push_back("manoeuvre:" + m.name);
    for (const auto& rp : run.replays) {
        r.parts.push_back("replay:" + rp.name);
        for (const auto& o : rp.others) r.parts.push_back("replay:" + rp.name + ":" + o.label);
    }
    if (run.run.is_object()) r.parts.push_back("provenance");
    r.missing = run.missing;
    if (content.comparison) r.comparison = content.comparison->to_json();
    auto add_missing = [&](const std::string& where, const std::vector<std::string>& files) {
        for (const auto& f : files) r.missing.push_back(where + "/" + f);
    };
    if (run.tables) add_missing("tables", run.tables->missing);
    if (run.compare) add_missing("compare-tables", run.compare->missing);
    for (const auto& m : run.manoeuvres) add_missing("manoeuvres/" + m.name, m.missing);
    for (const auto& rp : run.replays) {
        add_missing("replay/" + rp.name, rp.missing);
        for (const auto& o : rp.others) add_missing("replay-" + o.label + "/" + rp.name, o.missing);
    }
    r.n_pictures = content.pictures.size();
    // Plots in the page: one per menu, per flight path and per figure outside the menus.
    std::set<std::string> in_menu;
    for (const auto& g : content.groups) in_menu.insert(g.figure_ids.begin(), g.figure_ids.end());
    r.n_figures = content.groups.size() + content.paths.size();
    for (const auto& f : content.figures) r.n_figures += in_menu.count(f.id) == 0 ? 1 : 0;

    if (o.figures_dir) {
        const fs::path dir = *o.figures_dir;
        std::vector<fs::path> svgs;
        auto write = [&](const fs::path& file, const std::string& text) {
            core::write_file_atomic(file, text);
            r.files.push_back(file.string());
        };
        for (const auto& f : content.figures) {
            if (std::find(content.exported.begin(), content.exported.end(), f.id) ==
                content.exported.end())
                continue;
            write(dir / (f.id + ".svg"), to_svg(f));
            write(dir / (f.id + ".csv"), to_csv(f));
            svgs.push_back(dir / (f.id + ".svg"));
        }
        for (const auto& p : content.paths) {
            write(dir / (p.id + ".svg"), to_svg(p));
            write(dir / (p.id + ".csv"), to_csv(p));
            svgs.push_back(dir / (p.id + ".svg"));
        }
        for (const auto& p : content.pictures) {
            write(dir / (p.id + ".svg"), p.svg);
            svgs.push_back(dir / (p.id + ".svg"));
        }
        if (run.aircraft && !run.aircraft->top.empty()) {
            write(dir / "aircraft-three-view.svg", three_view_svg(*run.aircraft));
            svgs.push_back(dir / "aircraft-three-view.svg");
        }
        if (o.png) {
            const std::string browser = o.chromium.empty() ? find_chromium() : o.chromium;
            if (browser.empty()) {
                r.png_note = "no PNG: chromium not found (scripts/install-deps.sh installs it)";
            } else {
                for (const auto& svg : svgs) {
                    const auto size = svg_size(core::read_file(svg));
                    fs::path png = svg;
                    png.replace_extension(".png");
                    const fs::path tmp = png.string() + ".tmp.png";
                    const int rc = run_quietly(
                        {browser, "--headless", "--no-sandbox", "--disable-gpu",
                         "--hide-scrollbars", "--force-device-scale-factor=2",
                         fmt::format("--window-size={},{}", size[0], size[1]),
                         "--screenshot=" + tmp.string(), "file://" + fs::absolute(svg).string()});
                    std::error_code ec;
                    if (rc != 0 || !fs::exists(tmp)) {
                        fs::remove(tmp, ec);
                        r.png_note = fmt::format("no PNG for {}: {} exited with status {}",
                                                 svg.filename().string(), browser, rc);
                        break;
                    }
                    fs::rename(tmp, png, ec);
                    if (ec)
                        throw IoError(
                            fmt::format("{}: cannot write: {}", png.string(), ec.message()));
                    r.files.push_back(png.string());
                }
            }
        }
    }
    core::write_file_atomic(o.html, page);
    r.files.push_back(o.html.string());
    r.html_bytes = page.size();
    return r;
}

}  // namespace manta::report
