#!/usr/bin/env python3
"""Plot -Cp(x/c) of MANTA's ONERA M6 solution beside SU2's at the span stations of Schmitt &
Charpin (AGARD AR-138, 1979) as one SVG (docs/validation.md). No plotting library needed.

Usage: plot-om6-cp.py MANTA_SURFACE_CSV SU2_SURFACE_CSV[.gz] OUT.svg [TITLE]
(MANTA's surface.csv from `manta cfd`; SU2's surface_flow.csv from ../shared/reference/onera_m6.)
"""
import csv, gzip, math, sys

SEMISPAN, ROOT_CHORD, TAPER, SWEEP = 1.1963, 0.8059, 0.562, math.radians(30.0)
STATIONS = [0.20, 0.44, 0.65, 0.80, 0.90, 0.95]


def read(path, cp_key):
    f = gzip.open(path, "rt") if path.endswith(".gz") else open(path)
    with f:
        return [(float(r["x"]), float(r["y"]), float(r["z"]), float(r[cp_key])) for r in csv.DictReader(f)]


def section(points, eta, tol=0.012):
    y0 = eta * SEMISPAN
    le = y0 * math.tan(SWEEP)
    c = ROOT_CHORD * (1 - (1 - TAPER) * y0 / SEMISPAN)
    pts = [((x - le) / c, z, cp) for x, y, z, cp in points if abs(y - y0) < tol * SEMISPAN]
    return [(xc, cp) for xc, z, cp in pts if -0.02 <= xc <= 1.02]


def main():
    ours, su2 = read(sys.argv[1], "Cp"), read(sys.argv[2], "Pressure_Coefficient")
    title = sys.argv[4] if len(sys.argv) > 4 else "ONERA M6, M 0.8395, alpha 3.06 deg"
    W, H, cols = 330, 240, 3
    rows = (len(STATIONS) + cols - 1) // cols
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{cols * W}" height="{rows * H + 40}" '
           'font-family="sans-serif" font-size="11">',
           f'<text x="10" y="18" font-size="14">{title}: -Cp against x/c; '
           '<tspan fill="#c0392b">MANTA</tspan> (dots), <tspan fill="#2c3e50">SU2 v8.1.0</tspan> (circles), same mesh</text>']
    for k, eta in enumerate(STATIONS):
        ox, oy = (k % cols) * W + 40, (k // cols) * H + 40
        pw, ph = W - 60, H - 50
        X = lambda v: ox + pw * (v + 0.02) / 1.04
        Y = lambda v: oy + ph * (1.5 - v) / 2.5  # -Cp from -1.0 to 1.5
        out.append(f'<rect x="{ox}" y="{oy}" width="{pw}" height="{ph}" fill="none" stroke="#999"/>')
        out.append(f'<text x="{ox + 5}" y="{oy + 14}">eta = {eta:.2f}</text>')
        for v in (-1.0, -0.5, 0.0, 0.5, 1.0, 1.5):
            out.append(f'<text x="{ox - 30}" y="{Y(v) + 4:.1f}">{v:+.1f}</text>')
            out.append(f'<line x1="{ox}" x2="{ox + pw}" y1="{Y(v):.1f}" y2="{Y(v):.1f}" stroke="#eee"/>')
        for v in (0.0, 0.5, 1.0):
            out.append(f'<text x="{X(v) - 8:.1f}" y="{oy + ph + 14}">{v:.1f}</text>')
        for pts, colour, shape in ((su2, "#2c3e50", "o"), (ours, "#c0392b", ".")):
            for xc, cp in section(pts, eta):
                if shape == "o":
                    out.append(f'<circle cx="{X(xc):.1f}" cy="{Y(-cp):.1f}" r="2.6" fill="none" stroke="{colour}"/>')
                else:
                    out.append(f'<circle cx="{X(xc):.1f}" cy="{Y(-cp):.1f}" r="1.5" fill="{colour}"/>')
    out.append("</svg>")
    with open(sys.argv[3], "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
