#!/usr/bin/env python3
"""SVG of the CL and Cm loops against the pitch angle over the last period (MANTA and SU2).
Usage: loops_svg.py SU2_HISTORY MANTA_COEFFICIENTS OUT.svg (Cm in SU2's CMz sign)."""
import csv, math, sys


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def loop(rs, name, sign):
    rs = rs[-26:]
    return [(1.01 * math.sin(106.69842 * float(r["t"])), sign * float(r[name])) for r in rs]


su2, manta = rows(sys.argv[1]), rows(sys.argv[2])
W, H, M = 360, 300, 50
out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * W}" height="{H}" font-family="sans-serif" font-size="12">']
for panel, (name, sign, lim) in enumerate((("CL", 1.0, 0.12), ("Cm", -1.0, 0.015))):
    x0 = panel * W
    X = lambda a: x0 + M + (a + 1.1) / 2.2 * (W - 1.5 * M)
    Y = lambda c: H - M - (c + lim) / (2 * lim) * (H - 1.6 * M)
    out.append(f'<rect x="{X(-1.1):.1f}" y="{Y(lim):.1f}" width="{X(1.1) - X(-1.1):.1f}" height="{Y(-lim) - Y(lim):.1f}" fill="none" stroke="black"/>')
    for a in (-1, 0, 1):
        out.append(f'<text x="{X(a):.1f}" y="{Y(-lim) + 15:.1f}" text-anchor="middle">{a}</text>')
    for c in (-lim, 0, lim):
        out.append(f'<text x="{X(-1.1) - 4:.1f}" y="{Y(c) + 4:.1f}" text-anchor="end">{c:g}</text>')
    out.append(f'<text x="{X(0):.1f}" y="{H - 8}" text-anchor="middle">pitch angle [deg]</text>')
    label = "CL" if name == "CL" else "CMz (SU2 sign, -Cm)"
    out.append(f'<text x="{X(0):.1f}" y="{Y(lim) - 8:.1f}" text-anchor="middle">{label}, last period</text>')
    for data, colour, dash in ((su2, "black", ""), (manta, "#c03020", ' stroke-dasharray="5,3"')):
        pts = " ".join(f"{X(a):.1f},{Y(c):.1f}" for a, c in loop(data, name, 1.0 if data is su2 else sign))
        out.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="1.5"{dash}/>')
out.append(f'<text x="{W - 60}" y="{H - 25}" fill="black">SU2 v8.1 (solid)</text>')
out.append(f'<text x="{W + 40}" y="{H - 25}" fill="#c03020">MANTA (dashed)</text>')
out.append("</svg>")
open(sys.argv[3], "w").write("\n".join(out) + "\n")
