#!/usr/bin/env python3
"""Plot -Cp(x/c) on the Ranger 2000's wing at four span stations from `manta cfd` surface.csv files
as one SVG (docs/validation.md, "Ranger 2000 Euler": the shock on the upper wing at M 0.6, alpha
8 deg, the paper's Fig. 7). No plotting library needed. The critical pressure coefficient of the
first file's Mach number is drawn as a dashed line: above it (in -Cp) the flow is supersonic.

Usage: plot-ranger-cp.py OUT.svg LABEL=SURFACE_CSV [LABEL=SURFACE_CSV ...]
(the first file's summary.json beside it gives the Mach number and angle for the title.)

The wing planform is that of examples/ranger2000/aircraft.yaml: leading edge from (4.42, 0, 0) to
(4.6546, 5.23, 0.27409), chord 1.951 to 1.0126 m, linear in y.
"""
import csv, json, math, os, sys

SEMISPAN = 5.23
STATIONS = [0.25, 0.45, 0.65, 0.85]
COLOURS = ["#c0392b", "#2c3e50", "#27ae60", "#8e44ad"]
GAMMA = 1.4


def planform(y):
    f = y / SEMISPAN
    return 4.42 + 0.2346 * f, 1.951 + (1.0126 - 1.951) * f, 0.27409 * f  # x_le, chord, z_le


def read(path):
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["marker"] in ("wall", "aileron_right"):
                rows.append((float(r["x"]), float(r["y"]), float(r["z"]), float(r["Cp"]), float(r["Mach"])))
    return rows


def section(points, eta, tol=0.015):
    y0 = eta * SEMISPAN
    le, c, zle = planform(y0)
    out = []
    for x, y, z, cp, mach in points:
        if abs(y - y0) > tol * SEMISPAN:
            continue
        xc = (x - le) / c
        if -0.01 <= xc <= 1.01 and abs(z - zle) < 0.25 * c:
            out.append((xc, cp, mach, z - zle))
    return out


def cp_critical(mach):
    g = GAMMA
    return 2 / (g * mach * mach) * (((2 + (g - 1) * mach * mach) / (g + 1)) ** (g / (g - 1)) - 1)


def main():
    out_path, inputs = sys.argv[1], [a.split("=", 1) for a in sys.argv[2:]]
    if not inputs or any(len(a) != 2 for a in inputs):
        sys.exit("usage: plot-ranger-cp.py OUT.svg LABEL=SURFACE_CSV [LABEL=SURFACE_CSV ...]")
    data = [(label, read(path)) for label, path in inputs]
    summary = os.path.join(os.path.dirname(inputs[0][1]), "summary.json")
    mach = alpha = None
    if os.path.exists(summary):
        flow = json.load(open(summary))["flow"]
        mach, alpha = flow["mach"], flow["alpha_deg"]
    W, H, cols = 340, 250, 2
    rows = (len(STATIONS) + cols - 1) // cols
    title = f"Ranger 2000 wing, M {mach:g}, alpha {alpha:g} deg" if mach else "Ranger 2000 wing"
    legend = ", ".join(f'<tspan fill="{COLOURS[k]}">{label}</tspan>' for k, (label, _) in enumerate(data))
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{cols * W}" height="{rows * H + 44}" '
           'font-family="sans-serif" font-size="11">',
           f'<text x="10" y="18" font-size="14">{title}: -Cp against x/c (upper surface dots, lower open)</text>',
           f'<text x="10" y="34">{legend}; dashed: critical -Cp* at the free-stream Mach number</text>']
    lo, hi = -1.2, 3.6
    for k, eta in enumerate(STATIONS):
        ox, oy = (k % cols) * W + 44, (k // cols) * H + 50
        pw, ph = W - 64, H - 52
        X = lambda v: ox + pw * (v + 0.02) / 1.04
        Y = lambda v: oy + ph * (hi - v) / (hi - lo)
        svg.append(f'<rect x="{ox}" y="{oy}" width="{pw}" height="{ph}" fill="none" stroke="#999"/>')
        svg.append(f'<text x="{ox + 4}" y="{oy + 14}">eta = {eta:.2f} (y = {eta * SEMISPAN:.2f} m)</text>')
        for t in range(math.ceil(lo), math.floor(hi) + 1):
            svg.append(f'<line x1="{ox - 4}" x2="{ox}" y1="{Y(t):.1f}" y2="{Y(t):.1f}" stroke="#999"/>')
            svg.append(f'<text x="{ox - 8}" y="{Y(t) + 4:.1f}" text-anchor="end">{t}</text>')
        for t in (0, 0.5, 1):
            svg.append(f'<text x="{X(t):.1f}" y="{oy + ph + 14}" text-anchor="middle">{t:g}</text>')
        svg.append(f'<line x1="{ox}" x2="{ox + pw}" y1="{Y(0):.1f}" y2="{Y(0):.1f}" stroke="#ddd"/>')
        if mach:
            cs = -cp_critical(mach)
            svg.append(f'<line x1="{ox}" x2="{ox + pw}" y1="{Y(cs):.1f}" y2="{Y(cs):.1f}" '
                       'stroke="#777" stroke-dasharray="4,3"/>')
        for j, (label, pts) in enumerate(data):
            for xc, cp, m, dz in section(pts, eta):
                upper = dz > 0 or xc < 0.02
                fill = COLOURS[j] if upper else "none"
                v = max(lo, min(hi, -cp))
                svg.append(f'<circle cx="{X(xc):.1f}" cy="{Y(v):.1f}" r="1.6" fill="{fill}" '
                           f'stroke="{COLOURS[j]}" stroke-width="0.6"/>')
    svg.append("</svg>")
    tmp = out_path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(svg) + "\n")
    os.replace(tmp, out_path)
    for label, pts in data:
        peak = max((-cp, m) for x, y, z, cp, m in pts)
        print(f"{label}: wing nodes {len(pts)}, largest -Cp {peak[0]:.3f}, "
              f"largest surface Mach {max(m for *_, m in pts):.3f}")


if __name__ == "__main__":
    main()
