/// @file surface.cpp
/// Surface snapshots of an Euler replay in the report (docs/report.md, "Surface Cp"): the file
/// read (docs/formats.md#surface-snapshot), the snapshots picked for the flagged intervals, and
/// plan views coloured by Cp as SVG, the triangles of each colour band merged into polygons.

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "manta/core/error.hpp"
#include "manta/core/io.hpp"
#include "manta/report/html.hpp"
#include "manta/report/report.hpp"

namespace manta::report {

namespace fs = std::filesystem;

namespace {

/// The fields of a comma-separated line.
std::vector<std::string_view> fields(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t a = 0;
    while (true) {
        const std::size_t b = line.find(',', a);
        out.push_back(line.substr(a, b == std::string_view::npos ? std::string_view::npos : b - a));
        if (b == std::string_view::npos) break;
        a = b + 1;
    }
    return out;
}

template <class T>
bool parse(std::string_view s, T& v) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.remove_suffix(1);
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if constexpr (std::is_floating_point_v<T>)
        return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(v);
    else
        return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

}  // namespace

namespace {

/// A snapshot file being read: lines with their numbers, errors naming both.
struct Reader {
    std::string text, name;
    std::size_t pos = 0;
    int line_no = 0;
    std::string_view line;
    explicit Reader(const fs::path& file) : text(core::read_file(file)), name(file.string()) {}
    bool next() {
        if (pos >= text.size()) return false;
        const std::size_t e = text.find('\n', pos);
        line = std::string_view(text).substr(pos,
                                             e == std::string::npos ? std::string::npos : e - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos = e == std::string::npos ? text.size() : e + 1;
        ++line_no;
        return true;
    }
    [[nodiscard]] InputError fail(const std::string& what) const {
        return InputError(fmt::format(
            "{}:{}: {}; expected a surface snapshot file (docs/formats.md#surface-snapshot)", name,
            line_no, what));
    }
    /// The format line, then the `# key: value` lines into `meta`; stops at the first other line.
    void header(const char* format, std::map<std::string, std::string>& meta) {
        if (!next() || line != format) throw fail(fmt::format("no '{}' line", format));
        while (next() && line.starts_with("#")) {
            const std::size_t c = line.find(':');
            if (c == std::string_view::npos) continue;
            std::string_view k = line.substr(1, c - 1), v = line.substr(c + 1);
            while (!k.empty() && k.front() == ' ') k.remove_prefix(1);
            while (!v.empty() && v.front() == ' ') v.remove_prefix(1);
            meta[std::string(k)] = std::string(v);
        }
    }
    template <class T>
    T meta_number(const std::map<std::string, std::string>& meta, const char* key) {
        const auto it = meta.find(key);
        T v{};
        if (it == meta.end()) throw fail(fmt::format("no '# {}:' line", key));
        if (!parse(it->second, v))
            throw fail(fmt::format("'# {}: {}' is not a number", key, it->second));
        return v;
    }
};

}  // namespace

SurfaceWall read_surface_wall(const fs::path& file) {
    Reader rd(file);
    SurfaceWall w;
    w.file = file;
    rd.header("# MANTA surface wall 1", w.meta);
    const auto n_nodes = rd.meta_number<std::size_t>(w.meta, "nodes");
    const auto n_tri = rd.meta_number<std::size_t>(w.meta, "triangles");
    if (!w.meta.count("markers")) throw rd.fail("no '# markers:' line");
    for (const auto& m : fields(w.meta["markers"])) w.markers.emplace_back(m);
    if (rd.line != "x,y,z") throw rd.fail(fmt::format("header '{}'; expected x,y,z", rd.line));
    w.x.reserve(n_nodes);
    for (std::size_t i = 0; i < n_nodes; ++i) {
        if (!rd.next()) throw rd.fail(fmt::format("{} nodes of {}", i, n_nodes));
        const auto f = fields(rd.line);
        std::array<double, 3> v{};
        if (f.size() != 3 || !parse(f[0], v[0]) || !parse(f[1], v[1]) || !parse(f[2], v[2]))
            throw rd.fail(fmt::format("node row '{}' is not three numbers x,y,z", rd.line));
        w.x.push_back(v);
    }
    if (!rd.next() || rd.line != "a,b,c,marker")
        throw rd.fail(fmt::format("'{}' after the {} nodes; expected the header a,b,c,marker",
                                  rd.line, n_nodes));
    w.triangles.reserve(n_tri);
    for (std::size_t i = 0; i < n_tri; ++i) {
        if (!rd.next()) throw rd.fail(fmt::format("{} triangles of {}", i, n_tri));
        const auto f = fields(rd.line);
        std::array<std::int32_t, 4> v{};
        bool ok = f.size() == 4;
        for (std::size_t k = 0; ok && k < 4; ++k) ok = parse(f[k], v[k]) && v[k] >= 0;
        ok = ok && static_cast<std::size_t>(std::max({v[0], v[1], v[2]})) < n_nodes &&
             static_cast<std::size_t>(v[3]) < std::max<std::size_t>(w.markers.size(), 1);
        if (!ok)
            throw rd.fail(
                fmt::format("triangle row '{}'; expected node indices below {} and a marker index",
                            rd.line, n_nodes));
        w.triangles.push_back(v);
    }
    return w;
}

SurfaceSnapshot read_surface_snapshot(const fs::path& file,
                                      std::shared_ptr<const SurfaceWall> wall) {
    Reader rd(file);
    SurfaceSnapshot s;
    s.file = file;
    rd.header("# MANTA surface snapshot 1", s.meta);
    s.t = rd.meta_number<double>(s.meta, "t");
    s.step = rd.meta_number<int>(s.meta, "step");
    const auto n = rd.meta_number<std::size_t>(s.meta, "nodes");
    if (wall && n != wall->x.size())
        throw rd.fail(
            fmt::format("{} nodes; its wall {} has {}", n, wall->file.string(), wall->x.size()));
    if (rd.line != "Cp") throw rd.fail(fmt::format("header '{}'; expected Cp", rd.line));
    s.cp.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        double v = 0.0;
        if (!rd.next()) throw rd.fail(fmt::format("{} values of {}", i, n));
        if (!parse(rd.line, v)) throw rd.fail(fmt::format("Cp '{}' is not a number", rd.line));
        s.cp.push_back(v);
    }
    s.wall = std::move(wall);
    return s;
}

std::vector<SnapshotPick> pick_snapshots(const ReplayData& r, std::size_t max_flagged) {
    std::vector<SnapshotPick> picks;
    const auto& idx = r.snapshot_index;
    if (idx.empty()) return picks;
    auto nearest = [&](double t) {
        std::size_t best = 0;
        for (std::size_t i = 1; i < idx.size(); ++i)
            if (std::abs(std::get<1>(idx[i]) - t) < std::abs(std::get<1>(idx[best]) - t)) best = i;
        return best;
    };
    std::vector<std::array<double, 2>> intervals;
    const nlohmann::json& j = r.summary;
    if (j.is_object() && j.contains("flags") && j["flags"].is_array()) {
        for (std::size_t f = 0; f < j["flags"].size(); ++f) {
            const auto& fl = j["flags"][f];
            if (!fl.is_object()) continue;
            const double t0 = fl.value("t_start", 0.0), t1 = fl.value("t_end", t0);
            intervals.push_back({t0, t1});
            // The time of the largest |difference| / tolerance of the flagged coefficients.
            double t_max = 0.5 * (t0 + t1), worst = -1.0;
            std::string worst_name;
            if (r.comparison && fl.contains("coefficients") && fl["coefficients"].is_array()) {
                const auto& t = r.comparison->at("t");
                for (const auto& c : fl["coefficients"]) {
                    if (!c.is_string()) continue;
                    const std::string n = c.get<std::string>();
                    const std::string col = n + "_diff";
                    if (!r.comparison->has(col)) continue;
                    double tol = 1.0;
                    if (j.contains("tolerances") && j["tolerances"].is_object() &&
                        j["tolerances"].contains(n) && j["tolerances"][n].is_number())
                        tol = j["tolerances"][n].get<double>();
                    const auto& d = r.comparison->at(col);
                    for (std::size_t i = 0; i < t.size(); ++i)
                        if (t[i] >= t0 - 1e-9 && t[i] <= t1 + 1e-9 &&
                            std::abs(d[i]) / tol > worst) {
                            worst = std::abs(d[i]) / tol;
                            t_max = t[i];
                            worst_name = fmt::format("{} {:+.3g}", n, d[i]);
                        }
                }
            }
            const std::size_t k = nearest(t_max);
            const bool seen = std::any_of(picks.begin(), picks.end(),
                                          [&](const SnapshotPick& p) { return p.snapshot == k; });
            if (seen || picks.size() >= max_flagged) continue;
            picks.push_back(
                {k, static_cast<int>(f), t_max,
                 fmt::format(
                     "flagged interval {} ({:g}-{:g} s): largest difference at t = {:g} s{}", f + 1,
                     t0, t1, t_max, worst_name.empty() ? "" : " (" + worst_name + ")")});
        }
    }
    // The reference: outside every flagged interval, farthest from them.
    std::size_t ref = idx.size() / 2;
    if (!intervals.empty()) {
        double best = -1.0;
        for (std::size_t i = 0; i < idx.size(); ++i) {
            const double t = std::get<1>(idx[i]);
            double d = std::numeric_limits<double>::infinity();
            for (const auto& iv : intervals)
                d = std::min(d, t < iv[0] ? iv[0] - t : t > iv[1] ? t - iv[1] : -1.0);
            if (d > best) {
                best = d;
                ref = i;
            }
        }
        if (best < 0.0) return picks;  // every snapshot is flagged: no reference
    }
    if (std::none_of(picks.begin(), picks.end(),
                     [&](const SnapshotPick& p) { return p.snapshot == ref; }))
        picks.push_back({ref, -1, std::get<1>(idx[ref]),
                         intervals.empty() ? std::string("reference (no flagged interval)")
                                           : std::string("reference: outside every flagged "
                                                         "interval, the farthest from them")});
    std::sort(picks.begin(), picks.end(), [&](const SnapshotPick& a, const SnapshotPick& b) {
        return std::get<1>(idx[a.snapshot]) < std::get<1>(idx[b.snapshot]);
    });
    return picks;
}

namespace {

/// Cool-to-warm colour of u in [0, 1] (blue, light grey, red).
std::string cp_colour(double u) {
    static const std::array<std::array<double, 3>, 3> c{
        {{59, 76, 192}, {221, 221, 221}, {180, 4, 38}}};
    u = std::clamp(u, 0.0, 1.0);
    const std::size_t k = u < 0.5 ? 0 : 1;
    const double w = u < 0.5 ? u / 0.5 : (u - 0.5) / 0.5;
    int rgb[3];
    for (std::size_t i = 0; i < 3; ++i)
        rgb[i] = static_cast<int>(std::lround(c[k][i] + w * (c[k + 1][i] - c[k][i])));
    return fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]);
}

/// The outline loops of a set of consistently oriented triangles: the directed edges not
/// cancelled by a neighbour's reversed edge, chained into closed loops.
std::vector<std::vector<std::int32_t>> loops(const std::vector<std::array<std::int32_t, 3>>& tris) {
    auto key = [](std::int32_t a, std::int32_t b) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
               static_cast<std::uint32_t>(b);
    };
    std::unordered_set<std::uint64_t> edges;
    edges.reserve(tris.size() * 3);
    for (const auto& t : tris)
        for (int e = 0; e < 3; ++e) {
            const std::int32_t a = t[static_cast<std::size_t>(e)],
                               b = t[static_cast<std::size_t>((e + 1) % 3)];
            if (!edges.erase(key(b, a))) edges.insert(key(a, b));
        }
    std::unordered_multimap<std::int32_t, std::int32_t> from;
    from.reserve(edges.size());
    for (const std::uint64_t e : edges)
        from.emplace(static_cast<std::int32_t>(e >> 32),
                     static_cast<std::int32_t>(e & 0xffffffffULL));
    std::vector<std::vector<std::int32_t>> out;
    while (!from.empty()) {
        auto it = from.begin();
        const std::int32_t start = it->first;
        std::vector<std::int32_t> loop{start};
        std::int32_t cur = it->second;
        from.erase(it);
        while (cur != start) {
            loop.push_back(cur);
            auto nx = from.find(cur);
            if (nx == from.end()) break;  // open chain (a non-manifold wall): drawn as it is
            cur = nx->second;
            from.erase(nx);
        }
        out.push_back(std::move(loop));
    }
    return out;
}

/// Perpendicular distance of p from the segment a-b.
double segment_distance(const std::array<double, 2>& p, const std::array<double, 2>& a,
                        const std::array<double, 2>& b) {
    const double dx = b[0] - a[0], dy = b[1] - a[1];
    const double l2 = dx * dx + dy * dy;
    double u = l2 > 0.0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0.0;
    u = std::clamp(u, 0.0, 1.0);
    return std::hypot(p[0] - a[0] - u * dx, p[1] - a[1] - u * dy);
}

/// A closed polyline simplified by Douglas-Peucker within `eps` (split at its first point and
/// the point farthest from it), rounded to whole units, repeated points dropped.
std::vector<std::array<long, 2>> simplified(const std::vector<std::array<double, 2>>& p,
                                            double eps) {
    const std::size_t n = p.size();
    std::vector<std::array<long, 2>> out;
    if (n < 3) return out;
    std::vector<char> keep(n + 1, 0);
    std::size_t far = 0;
    double best = -1.0;
    for (std::size_t i = 1; i < n; ++i) {
        const double d = std::hypot(p[i][0] - p[0][0], p[i][1] - p[0][1]);
        if (d > best) {
            best = d;
            far = i;
        }
    }
    keep[0] = keep[far] = keep[n] = 1;
    auto at = [&](std::size_t i) -> const std::array<double, 2>& { return p[i % n]; };
    std::vector<std::array<std::size_t, 2>> stack{{0, far}, {far, n}};
    while (!stack.empty()) {
        const auto [i0, i1] = stack.back();
        stack.pop_back();
        double dmax = -1.0;
        std::size_t imax = i0;
        for (std::size_t i = i0 + 1; i < i1; ++i) {
            const double d = segment_distance(at(i), at(i0), at(i1));
            if (d > dmax) {
                dmax = d;
                imax = i;
            }
        }
        if (dmax > eps) {
            keep[imax] = 1;
            stack.push_back({i0, imax});
            stack.push_back({imax, i1});
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (!keep[i]) continue;
        const std::array<long, 2> q{std::lround(p[i][0]), std::lround(p[i][1])};
        if (out.empty() || q != out.back()) out.push_back(q);
    }
    if (out.size() > 1 && out.front() == out.back()) out.pop_back();
    return out;
}

}  // namespace

CpRange cp_range(const std::vector<const SurfaceSnapshot*>& snapshots) {
    std::vector<double> all;
    for (const auto* s : snapshots) all.insert(all.end(), s->cp.begin(), s->cp.end());
    CpRange r;
    if (all.empty()) return r;
    std::sort(all.begin(), all.end());
    auto at = [&](double q) {
        return all[static_cast<std::size_t>(q * static_cast<double>(all.size() - 1))];
    };
    r.lo = at(0.01);
    r.hi = at(0.99);
    if (!(r.hi > r.lo)) {
        r.lo = all.front() - 0.5;
        r.hi = all.back() + 0.5;
    }
    return r;
}

std::string cp_picture_svg(const SurfaceSnapshot& s, const CpRange& range, const std::string& title,
                           int levels) {
    if (!s.wall) return {};
    const double simplify = 1.0;  // half pixels
    levels = std::max(2, levels);
    // Plan views at one scale: from above (nose up, +y to the right) and from below (nose up,
    // +y to the left). Geometry axes: x aft, y right, z up.
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    const SurfaceWall& wall = *s.wall;
    for (const auto& p : wall.x) {
        xmin = std::min(xmin, p[0]);
        xmax = std::max(xmax, p[0]);
        ymin = std::min(ymin, p[1]);
        ymax = std::max(ymax, p[1]);
    }
    const double view_w = 330.0, view_h_max = 360.0;  // px
    const double sx = std::max(ymax - ymin, 1e-9), sy = std::max(xmax - xmin, 1e-9);
    const double scale = std::min(view_w / sx, view_h_max / sy);
    const double w = sx * scale, h = sy * scale;
    const double top = 34.0, gap = 24.0, bar_w = 14.0;
    const double total_w = 2 * w + gap + 90.0, total_h = top + h + 30.0;
    // Coordinates in half pixels, whole numbers (u = 2 px).
    auto U = [](double px) { return static_cast<long>(std::lround(2.0 * px)); };
    std::string svg = fmt::format(
        R"(<svg xmlns="http://www.w3.org/2000/svg" class="cp-picture" width="{:.0f}" height="{:.0f}" viewBox="0 0 {} {}" font-family="sans-serif" font-size="22">)",
        total_w, total_h, U(total_w), U(total_h));
    svg += '\n';
    svg += fmt::format(R"(<text x="{}" y="{}" font-size="26">{}</text>)", U(4), U(18),
                       escape_html(title));
    svg += '\n';
    const double dlevel = (range.hi - range.lo) / levels;
    auto level_of = [&](double cp) {
        const int k = static_cast<int>(std::floor((cp - range.lo) / dlevel));
        return std::clamp(k, 0, levels - 1);
    };
    for (int view = 0; view < 2; ++view) {
        const double ox = view == 0 ? 0.0 : w + gap;
        auto px = [&](std::size_t i) {
            const double y = wall.x[i][1];
            return ox + (view == 0 ? (y - ymin) : (ymax - y)) * scale;
        };
        auto py = [&](std::size_t i) { return top + (wall.x[i][0] - xmin) * scale; };
        // The triangles facing the viewer (normal into the flow, up for the top view), by band.
        std::vector<std::vector<std::array<std::int32_t, 3>>> band(
            static_cast<std::size_t>(levels));
        for (const auto& t : wall.triangles) {
            const auto& a = wall.x[static_cast<std::size_t>(t[0])];
            const auto& b = wall.x[static_cast<std::size_t>(t[1])];
            const auto& c = wall.x[static_cast<std::size_t>(t[2])];
            const double nz =
                (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);  // z of normal
            if (view == 0 ? nz <= 0.0 : nz >= 0.0) continue;
            const double cp =
                (s.cp[static_cast<std::size_t>(t[0])] + s.cp[static_cast<std::size_t>(t[1])] +
                 s.cp[static_cast<std::size_t>(t[2])]) /
                3.0;
            band[static_cast<std::size_t>(level_of(cp))].push_back({t[0], t[1], t[2]});
        }
        // A band's path: the outline loops of its triangles in half pixels, simplified
        // (Douglas-Peucker within `simplify` half pixels), relative moves.
        auto path_of = [&](const std::vector<std::array<std::int32_t, 3>>& tris) {
            std::string d;
            for (const auto& loop : loops(tris)) {
                std::vector<std::array<double, 2>> pts;
                pts.reserve(loop.size());
                for (const std::int32_t n : loop)
                    pts.push_back({2.0 * px(static_cast<std::size_t>(n)),
                                   2.0 * py(static_cast<std::size_t>(n))});
                const std::vector<std::array<long, 2>> q = simplified(pts, simplify);
                if (q.size() < 3) continue;
                d += fmt::format("M{} {}l", q[0][0], q[0][1]);
                for (std::size_t i = 1; i < q.size(); ++i)
                    d += fmt::format("{} {} ", q[i][0] - q[i - 1][0], q[i][1] - q[i - 1][1]);
                d.back() = 'z';
            }
            return d;
        };
        svg += fmt::format(R"(<text x="{}" y="{}">{}</text>)", U(ox + 2), U(top - 4),
                           view == 0 ? "from above" : "from below");
        svg += '\n';
        // Each band's region is drawn as the union of it and every band above (the higher
        // bands painted over it), so that simplified edges leave no gap between bands.
        std::vector<std::array<std::int32_t, 3>> upper;
        std::vector<std::string> paths(static_cast<std::size_t>(levels));
        for (int k = levels; k-- > 0;) {
            const auto& tris = band[static_cast<std::size_t>(k)];
            if (tris.empty()) continue;
            upper.insert(upper.end(), tris.begin(), tris.end());
            paths[static_cast<std::size_t>(k)] = path_of(upper);
        }
        std::string outline;
        for (int k = 0; k < levels; ++k) {
            const std::string& d = paths[static_cast<std::size_t>(k)];
            if (d.empty()) continue;
            if (outline.empty()) outline = d;  // the lowest band's union: every visible triangle
            svg += fmt::format(R"(<path fill="{}" d="{}"/>)", cp_colour((k + 0.5) / levels), d);
            svg += '\n';
        }
        if (!outline.empty())
            svg += fmt::format(
                R"(<path fill="none" stroke="#333" stroke-width="1" stroke-linejoin="round" d="{}"/>)",
                outline);
        svg += '\n';
    }
    // The colour bar: one box per band, Cp from low (bottom) to high (top).
    const double bx = 2 * w + gap + 10.0, by0 = top, bh = h;
    for (int k = 0; k < levels; ++k) {
        const double y1 = by0 + bh * (1.0 - static_cast<double>(k) / levels);
        const double y0 = by0 + bh * (1.0 - static_cast<double>(k + 1) / levels);
        svg += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="{}"/>)", U(bx),
                           U(y0), U(bar_w), U(y1) - U(y0), cp_colour((k + 0.5) / levels));
    }
    svg += '\n';
    for (int k = 0; k <= 4; ++k) {
        const double v = range.lo + (range.hi - range.lo) * k / 4.0;
        svg += fmt::format(R"(<text x="{}" y="{}">{:.2f}</text>)", U(bx + bar_w + 4),
                           U(by0 + bh * (1.0 - k / 4.0) + 4), v);
    }
    svg += fmt::format(R"(<text x="{}" y="{}">Cp</text>)", U(bx), U(top - 4));
    svg += fmt::format(R"(<text x="{}" y="{}" font-size="20">{:.3g} m nose to tail, {:.3g} m )"
                       R"(wide; bands of Cp {:.3g}, ends clipped</text>)",
                       U(2), U(top + h + 20), sy, sx, dlevel);
    svg += "\n</svg>\n";
    return svg;
}

}  // namespace manta::report
