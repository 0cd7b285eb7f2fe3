#!/usr/bin/env python3
"""First harmonics over the last period (25 steps) of CL and Cm from SU2's rigid CT5 history and a
`manta cfd --motion` coefficients.csv (MANTA's Cm turned to SU2's CMz sign).
Usage: harmonics.py SU2_HISTORY MANTA_COEFFICIENTS"""
import csv, math, sys

OMEGA = 106.69842


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def harmonic(t, c):
    """Trapezoidal Fourier projection over the last 25 intervals: c ~ c0 + a sin + b cos."""
    t, c = t[-26:], c[-26:]
    period = t[-1] - t[0]
    a = b = 0.0
    for k in range(25):
        for j in (k, k + 1):
            w = 0.5 * (t[k + 1] - t[k])
            a += w * c[j] * math.sin(OMEGA * t[j])
            b += w * c[j] * math.cos(OMEGA * t[j])
    a, b = 2 * a / period, 2 * b / period
    return math.hypot(a, b), math.degrees(math.atan2(b, a))


su2, manta = rows(sys.argv[1]), rows(sys.argv[2])
for name, sign in (("CL", 1.0), ("Cm", -1.0)):
    A1, p1 = harmonic([float(r["t"]) for r in su2], [float(r[name]) for r in su2])
    A2, p2 = harmonic([float(r["t"]) for r in manta], [sign * float(r[name]) for r in manta])
    print(f"{name}: SU2 {A1:.4f} at {p1:+.1f} deg, MANTA {A2:.4f} at {p2:+.1f} deg: "
          f"amplitude {100 * (A2 / A1 - 1):+.1f} %, phase {p2 - p1:+.1f} deg")
inner = [int(r["inner_iterations"]) for r in manta[1:]]
print(f"inner iterations per step: mean {sum(inner) / len(inner):.1f}, max {max(inner)}")
