#!/usr/bin/env python3
"""SVG of the lift loops of the NACA 0012 slab pitching 1 deg about the quarter chord at M 0.2
(tests/euler/test_theodorsen_slow.cpp), last of three periods of 32 steps, against Theodorsen's
function with the slab's own steady lift slope (kappa = 1.1206, docs/validation.md).
Usage: loops_svg.py THEODORSEN_CSV OUT.svg (run in this folder)."""
import cmath, csv, math, sys

KAPPA, N = 1.1206, 32


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


table = {float(r["k"]): complex(float(r["F"]), float(r["G"])) for r in rows(sys.argv[1])}


def theory(k):  # CL per radian of pitch about a = -1/2
    a = -0.5
    return math.pi * (1j * k + a * k * k) + 2 * math.pi * KAPPA * table[k] * (1 + 1j * k * (0.5 - a))


W, H, M = 360, 300, 50
lim = 0.1
out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * W}" height="{H}" font-family="sans-serif" font-size="12">']
for panel, (k, name) in enumerate(((0.25, "manta_k025_coefficients.csv"), (0.5, "manta_k05_coefficients.csv"))):
    x0 = panel * W
    X = lambda a: x0 + M + (a + 1.1) / 2.2 * (W - 1.5 * M)
    Y = lambda c: H - M - (c + lim) / (2 * lim) * (H - 1.6 * M)
    out.append(f'<rect x="{X(-1.1):.1f}" y="{Y(lim):.1f}" width="{X(1.1) - X(-1.1):.1f}" height="{Y(-lim) - Y(lim):.1f}" fill="none" stroke="black"/>')
    for a in (-1, 0, 1):
        out.append(f'<text x="{X(a):.1f}" y="{Y(-lim) + 15:.1f}" text-anchor="middle">{a}</text>')
    for c in (-lim, 0, lim):
        out.append(f'<text x="{X(-1.1) - 4:.1f}" y="{Y(c) + 4:.1f}" text-anchor="end">{c:g}</text>')
    out.append(f'<text x="{X(0):.1f}" y="{H - 8}" text-anchor="middle">pitch angle [deg]</text>')
    out.append(f'<text x="{X(0):.1f}" y="{Y(lim) - 8:.1f}" text-anchor="middle">CL, k = {k}, last period</text>')
    rs = rows(name)[-(N + 1):]
    mean = sum(float(r["CL"]) for r in rs[1:]) / N
    t = theory(k) * math.radians(1.0)
    pts = " ".join(f"{X(math.sin(2 * math.pi * i / 64)):.1f},{Y(mean + abs(t) * math.sin(2 * math.pi * i / 64 + cmath.phase(t))):.1f}" for i in range(65))
    out.append(f'<polyline points="{pts}" fill="none" stroke="black" stroke-width="1.5"/>')
    pts = " ".join(f"{X(math.degrees(float(r['alpha']))):.1f},{Y(float(r['CL'])):.1f}" for r in rs)
    out.append(f'<polyline points="{pts}" fill="none" stroke="#c03020" stroke-width="1.5" stroke-dasharray="5,3"/>')
out.append(f'<text x="{M + 8}" y="{1.6 * M - 4}" fill="black">Theodorsen, kappa 1.1206 (solid)</text>')
out.append(f'<text x="{M + 8}" y="{1.6 * M + 12}" fill="#c03020">MANTA level 0, T/32 (dashed)</text>')
out.append("</svg>")
open(sys.argv[2], "w").write("\n".join(out) + "\n")
