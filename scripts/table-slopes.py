#!/usr/bin/env python3
"""Slopes of a MANTA tables.csv (docs/formats.md#tables-csv) per Mach number at zero sideslip.

    scripts/table-slopes.py OUT/tables.csv [--alpha-range -2 6] [--delta-range -5 5]

Prints, per Mach number of the static table at beta = 0: CL_alpha and Cm_alpha [1/rad]
(least-squares line over the alpha breakpoints in --alpha-range), CL, CD, Cm at alpha 0; and per
control table, CL_delta, Cm_delta (the elevator), Cl_delta, Cn_delta [1/rad] at alpha 0 (or the
breakpoint nearest it) by a least-squares line over the deflections in --delta-range.
"""
import argparse
import csv
import math
import sys


def line_slope(xs, ys):
    n = len(xs)
    if n < 2:
        return float("nan")
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("tables")
    ap.add_argument("--alpha-range", nargs=2, type=float, default=[-2.0, 6.0])
    ap.add_argument("--delta-range", nargs=2, type=float, default=[-5.0, 5.0])
    a = ap.parse_args()
    rows = []
    with open(a.tables) as f:
        for r in csv.DictReader(line for line in f if not line.startswith("#")):
            rows.append(r)
    if not rows:
        sys.exit(f"{a.tables}: no rows; expected a MANTA tables.csv")
    rad = math.pi / 180.0
    static = [r for r in rows if r["table"] == "static" and abs(float(r["beta_deg"])) < 1e-9]
    machs = sorted({float(r["mach"]) for r in static})
    print("static (beta 0): mach, CL_alpha, Cm_alpha [1/rad], CL0, CD0, Cm0")
    for m in machs:
        pts = sorted((float(r["alpha_deg"]), r) for r in static if abs(float(r["mach"]) - m) < 1e-12)
        sel = [(al, r) for al, r in pts if a.alpha_range[0] - 1e-9 <= al <= a.alpha_range[1] + 1e-9]
        xs = [al * rad for al, _ in sel]
        cla = line_slope(xs, [float(r["CL"]) for _, r in sel])
        cma = line_slope(xs, [float(r["Cm"]) for _, r in sel])
        zero = min(pts, key=lambda p: abs(p[0]))[1]
        print(f"  {m:.3g}  {cla:.4f}  {cma:.4f}  {float(zero['CL']):.4f}  {float(zero['CD']):.4f}  "
              f"{float(zero['Cm']):.4f}")
    for name in sorted({r["table"] for r in rows if r["table"] != "static"}):
        ctl = [r for r in rows if r["table"] == name]
        print(f"{name}: mach, alpha_deg, CL_d, Cm_d, Cl_d, Cn_d [1/rad]")
        for m in sorted({float(r["mach"]) for r in ctl}):
            at_m = [r for r in ctl if abs(float(r["mach"]) - m) < 1e-12]
            al0 = min({float(r["alpha_deg"]) for r in at_m}, key=abs)
            sel = sorted((float(r["delta_deg"]), r) for r in at_m
                         if abs(float(r["alpha_deg"]) - al0) < 1e-9
                         and a.delta_range[0] - 1e-9 <= float(r["delta_deg"]) <= a.delta_range[1] + 1e-9)
            xs = [d * rad for d, _ in sel]
            s = [line_slope(xs, [float(r[c]) for _, r in sel]) for c in ("CL", "Cm", "Cl", "Cn")]
            print(f"  {m:.3g}  {al0:g}  " + "  ".join(f"{v:.4f}" for v in s))


if __name__ == "__main__":
    main()
