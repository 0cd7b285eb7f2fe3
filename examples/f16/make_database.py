#!/usr/bin/env python3
"""Write the Stevens & Lewis F-16 as MANTA files: the aero database (native YAML, `*.madb.yaml`)
and the aircraft file. The output is committed; nothing at build or test time runs this script.

Source data: the CSV tables in ../../../shared/reference/f16 (NASA NESC F16_aero.dml / F16_prop.dml
= Stevens, Lewis & Johnson, *Aircraft Control and Simulation*, 3rd ed. 2015, appendix, from NASA
TP-1538), see that folder's README.md. US customary units are converted to SI with the exact
definitions of the international foot and pound (1959), as manta/core/units.hpp.

Usage: python3 make_database.py [--reference DIR] [--out DIR]

The equations expressed (S&L form; angles in degrees where the tables use them):
  CX = CX0(a, de)                           + CXq q c/2V
  CY = -0.02 b + 0.021 da/20 + 0.086 dr/30  + (CYr r + CYp p) b/2V
  CZ = CZ0(a) (1 - beta_rad^2) - 0.19 de/25  + CZq q c/2V
  Cl = sign(b) CL0(a,|b|) + DLDA(a,b) da/20 + DLDR(a,b) dr/30 + (Clr r + Clp p) b/2V
  Cm = CM0(a, de)                           + Cmq q c/2V            (moment transfer: MANTA's EOM)
  Cn = sign(b) CN0(a,|b|) + DNDA(a,b) da/20 + DNDR(a,b) dr/30 + (Cnr r + Cnp p) b/2V
as MANTA tables that are summed at evaluation:
  static   (alpha, beta)          CX CY CZ Cl Cm Cn   at de = da = dr = 0
  elevator (alpha, elevator)      CX CZ Cm            CX0(a,de)-CX0(a,0), -0.19 de/25, CM0(a,de)-CM0(a,0)
  aileron  (alpha, beta, aileron) CY Cl Cn            S&L da = -MANTA aileron (sign conversion)
  rudder   (alpha, beta, rudder)  CY Cl Cn
  dynamic  (alpha)                CX_q CY_r CY_p CZ_q Cl_r Cl_p Cm_q Cn_r Cn_p
Every term but the beta^2 of CZ is multilinear in the table axes and so reproduced exactly by
MANTA's multilinear interpolation; the beta grid is dense (0.1 deg for |beta| <= 5 deg, 0.5 deg
beyond) so that the interpolation error of CZ0 (1 - beta^2) stays below |CZ0| (dbeta/2)^2:
7.6e-7 |CZ0| near zero sideslip, 1.9e-5 |CZ0| for 5 < |beta| <= 30 deg.
NESC's DAVE-ML uses beta in radians (180/pi) in the CZ term, S&L's code beta/57.3: the two differ
by 1.3e-5 relative in beta^2, i.e. below 1e-7 in CZ for |beta| < 5 deg; this file follows NESC.
"""

import argparse
import csv
import math
import os
import sys

FOOT = 0.3048                      # m, exact
POUND_MASS = 0.45359237            # kg, exact
G0 = 9.80665                       # m/s^2, exact
POUND_FORCE = POUND_MASS * G0      # N
SLUG = POUND_FORCE / FOOT          # kg
SLUG_FT2 = SLUG * FOOT * FOOT      # kg m^2

HERE = os.path.dirname(os.path.abspath(__file__))


def read_rows(path):
    """Non-comment CSV rows of a reference file."""
    with open(path, newline="") as f:
        return [row for row in csv.reader(f) if row and not row[0].startswith("#")]


def read_matrix(path):
    """Matrix CSV: header 'rowvar\\colvar,<col breakpoints>', rows '<row bp>,<values>'."""
    rows = read_rows(path)
    cols = [float(x) for x in rows[0][1:]]
    rbps, vals = [], []
    for r in rows[1:]:
        rbps.append(float(r[0]))
        vals.append([float(x) for x in r[1:]])
    return rbps, cols, vals


def read_columns(path):
    rows = read_rows(path)
    names = rows[0]
    data = [[float(x) for x in r] for r in rows[1:]]
    return {n: [r[i] for r in data] for i, n in enumerate(names)}


def interp1(xs, ys, x):
    """Piecewise-linear interpolation with linear extrapolation (S&L code)."""
    i = 0
    while i + 2 < len(xs) and x >= xs[i + 1]:
        i += 1
    w = (x - xs[i]) / (xs[i + 1] - xs[i])
    return ys[i] * (1.0 - w) + ys[i + 1] * w


def clean(x):
    """Round sums and differences of 3-decimal table data to the decimal they stand for."""
    return round(x, 12) + 0.0


def num(x):
    """Shortest text that reads back to the same double."""
    r = repr(float(x))
    if r in ("0.0", "-0.0"):
        return "0"
    if "e" in r:  # "8e-05" is a string to YAML 1.1 readers: give the mantissa a point
        m, e = r.split("e")
        return (m if "." in m else m + ".0") + "e" + e
    return r[:-2] if r.endswith(".0") else r


def seq(values):
    return "[" + ", ".join(num(v) for v in values) + "]"


class Reference:
    def __init__(self, ref_dir, cl0_file):
        a, de, self.cx = read_matrix(os.path.join(ref_dir, "cx_alpha_el.csv"))
        self.alpha, self.de = a, de
        _, _, self.cm = read_matrix(os.path.join(ref_dir, "cm_alpha_el.csv"))
        cz = read_columns(os.path.join(ref_dir, "cz0_alpha.csv"))
        assert cz["alpha_deg"] == a
        self.cz0 = cz["CZ0"]
        _, self.absbeta, self.cl0 = read_matrix(os.path.join(ref_dir, cl0_file))
        _, absb2, self.cn0 = read_matrix(os.path.join(ref_dir, "cn_alpha_absbeta.csv"))
        assert absb2 == self.absbeta
        _, self.beta_ctrl, self.dlda = read_matrix(os.path.join(ref_dir, "dlda_alpha_beta.csv"))
        _, _, self.dldr = read_matrix(os.path.join(ref_dir, "dldr_alpha_beta.csv"))
        _, _, self.dnda = read_matrix(os.path.join(ref_dir, "dnda_alpha_beta.csv"))
        _, _, self.dndr = read_matrix(os.path.join(ref_dir, "dndr_alpha_beta.csv"))
        damp = read_columns(os.path.join(ref_dir, "damping_alpha.csv"))
        assert damp["alpha_deg"] == a
        self.damp = damp
        self.thrust = {}
        for level in ("idle", "mil", "max"):
            alt, mach, t = read_matrix(os.path.join(ref_dir, f"thrust_{level}_alt_mach.csv"))
            self.thrust[level] = t
            self.alt_ft, self.mach = alt, mach

    def signed_absbeta(self, table, ia, beta_deg):
        """sign(beta) * T(alpha_i, |beta|) by linear interpolation in |beta|."""
        v = interp1(self.absbeta, table[ia], abs(beta_deg))
        return math.copysign(1.0, beta_deg) * v if beta_deg != 0.0 else 0.0


def beta_grid():
    """Sideslip breakpoints [deg]: every 0.1 deg to 5 deg, every 0.5 deg to 30 deg."""
    inner = [round(0.1 * k, 10) for k in range(0, 51)]
    outer = [round(5.0 + 0.5 * k, 10) for k in range(1, 51)]
    pos = inner + outer
    return [-b for b in reversed(pos[1:])] + pos


def database_text(ref, variant_note):
    alpha = ref.alpha
    betas = beta_grid()
    ia0 = ref.de.index(0.0)
    out = []
    w = out.append
    w("# Generated by examples/f16/make_database.py from shared/reference/f16 - do not edit by hand.")
    w("manta_aero_database: 1")
    w("info:")
    w("  name: F-16 (Stevens & Lewis)")
    w("  source: NASA TP-1538 via Stevens, Lewis & Johnson 2015 appendix / NASA NESC F16_aero.dml")
    w("  description: >-")
    w("    Subsonic F-16 of Stevens, Lewis & Johnson, Aircraft Control and Simulation, 3rd ed. 2015")
    w("    (data from NASA TP-1538, as corrected in NASA NESC F16_aero.dml, Garza & Morelli")
    w("    NASA TM-2003-212145). Body-axis forces, moments about 0.35 cbar. " + variant_note)
    w("    MANTA aileron = -(S&L aileron): positive rolls right wing down. Written by")
    w("    examples/f16/make_database.py; see docs/f16.md.")
    w("force_axes: body")
    w("extrapolation: linear")
    w("tables:")
    # static
    w("  - name: static")
    w("    kind: static")
    w("    axes:")
    w(f"      - {{name: alpha, values_deg: {seq(alpha)}}}")
    w(f"      - {{name: beta, values_deg: {seq(betas)}}}")
    w("    columns: [CX, CY, CZ, Cl, Cm, Cn]")
    w("    data:")
    for ia, a in enumerate(alpha):
        for b in betas:
            brad = math.radians(b)
            row = [ref.cx[ia][ia0],
                   clean(-0.02 * b),
                   ref.cz0[ia] * (1.0 - brad * brad),
                   ref.signed_absbeta(ref.cl0, ia, b),
                   ref.cm[ia][ia0],
                   ref.signed_absbeta(ref.cn0, ia, b)]
            w(f"      - {seq(clean(v) if i != 2 else v for i, v in enumerate(row))}")
    # elevator
    w("  - name: elevator")
    w("    kind: control")
    w("    axes:")
    w(f"      - {{name: alpha, values_deg: {seq(alpha)}}}")
    w(f"      - {{name: elevator, values_deg: {seq(ref.de)}}}")
    w("    columns: [CX, CZ, Cm]")
    w("    data:")
    for ia in range(len(alpha)):
        for ie, de in enumerate(ref.de):
            w(f"      - {seq([clean(ref.cx[ia][ie] - ref.cx[ia][ia0]), clean(-0.19 * de / 25.0), clean(ref.cm[ia][ie] - ref.cm[ia][ia0])])}")
    # aileron: MANTA aileron a (deg) is S&L da = -a.
    ail = [-21.5, 0.0, 21.5]
    w("  - name: aileron")
    w("    kind: control")
    w("    axes:")
    w(f"      - {{name: alpha, values_deg: {seq(alpha)}}}")
    w(f"      - {{name: beta, values_deg: {seq(ref.beta_ctrl)}}}")
    w(f"      - {{name: aileron, values_deg: {seq(ail)}}}")
    w("    columns: [CY, Cl, Cn]")
    w("    data:")
    for ia in range(len(alpha)):
        for ib in range(len(ref.beta_ctrl)):
            for a_manta in ail:
                da = -a_manta / 20.0
                w(f"      - {seq([clean(0.021 * da), clean(ref.dlda[ia][ib] * da), clean(ref.dnda[ia][ib] * da)])}")
    # rudder: same sign as S&L (trailing edge left positive).
    rdr = [-30.0, 0.0, 30.0]
    w("  - name: rudder")
    w("    kind: control")
    w("    axes:")
    w(f"      - {{name: alpha, values_deg: {seq(alpha)}}}")
    w(f"      - {{name: beta, values_deg: {seq(ref.beta_ctrl)}}}")
    w(f"      - {{name: rudder, values_deg: {seq(rdr)}}}")
    w("    columns: [CY, Cl, Cn]")
    w("    data:")
    for ia in range(len(alpha)):
        for ib in range(len(ref.beta_ctrl)):
            for r in rdr:
                dr = r / 30.0
                w(f"      - {seq([clean(0.086 * dr), clean(ref.dldr[ia][ib] * dr), clean(ref.dndr[ia][ib] * dr)])}")
    # dynamic
    names = [("CX_q", "CXq"), ("CY_r", "CYr"), ("CY_p", "CYp"), ("CZ_q", "CZq"), ("Cl_r", "Clr"),
             ("Cl_p", "Clp"), ("Cm_q", "Cmq"), ("Cn_r", "Cnr"), ("Cn_p", "Cnp")]
    w("  - name: dynamic")
    w("    kind: dynamic")
    w("    axes:")
    w(f"      - {{name: alpha, values_deg: {seq(alpha)}}}")
    w(f"    columns: [{', '.join(n for n, _ in names)}]")
    w("    data:")
    for ia in range(len(alpha)):
        w(f"      - {seq([ref.damp[src][ia] for _, src in names])}")
    return "\n".join(out) + "\n"


# S&L power mapping: P = 64.94 t (t <= 0.77), 217.38 t - 117.38 (t > 0.77); thrust is linear in P
# between idle (P = 0), military (P = 50) and maximum (P = 100). P = 50 is reached at
# t = 50/64.94 on the lower branch and at t = 167.38/217.38 on the upper one, so the S&L thrust is
# exactly the piecewise-linear table over these throttle breakpoints with values idle, mil, mil,
# max - except on 50/64.94 < t <= 0.77 (a band 5.9e-5 wide), where S&L's lower branch gives
# P slightly above 50 (up to 50.0038) and so thrust up to 7.6e-5 (T_max - T_mil) above mil.
THROTTLE_BREAKPOINTS = [0.0, 50.0 / 64.94, 167.38 / 217.38, 1.0]


def engine_block(ref):
    levels = ["idle", "mil", "mil", "max"]
    lines = []
    for i_alt in range(len(ref.alt_ft)):
        for i_m in range(len(ref.mach)):
            vals = [ref.thrust[lv][i_alt][i_m] * POUND_FORCE for lv in levels]
            lines.append(vals)
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--reference", default=os.path.join(HERE, "..", "..", "..", "shared", "reference", "f16"))
    ap.add_argument("--out", default=HERE)
    args = ap.parse_args()
    ref_dir = os.path.normpath(args.reference)
    if not os.path.isdir(ref_dir):
        sys.exit(f"make_database.py: reference folder {ref_dir} not found (--reference DIR)")

    main_ref = Reference(ref_dir, "cl_alpha_absbeta.csv")
    text = database_text(main_ref, "Rolling moment CL0 from cl_alpha_absbeta.csv (NESC).")
    with open(os.path.join(args.out, "f16.madb.yaml"), "w") as f:
        f.write(text)
    var_ref = Reference(ref_dir, "cl_alpha_absbeta_variant.csv")
    text = database_text(var_ref, "Rolling moment CL0 from cl_alpha_absbeta_variant.csv (the table"
                         " with which the 3rd-edition coordinated-turn trim, Table 3.6-3, was computed).")
    with open(os.path.join(args.out, "f16_cl0_variant.madb.yaml"), "w") as f:
        f.write(text)
    write_aircraft(main_ref, args.out)


def wing_planform():
    """Trapezoidal wing with S = 300 ft^2, b = 30 ft and a mean aerodynamic chord of exactly
    11.32 ft: with c_r = 2 S / (b (1 + t)), MAC = (2/3) c_r (1 + t + t^2) / (1 + t) solves for the
    taper t = 0.2275 (the F-16's is about 0.23); leading-edge sweep 40 deg. [ft]"""
    S, b, mac = 300.0, 30.0, 11.32
    k = 1.5 * mac * b / (2.0 * S)      # (1 + t + t^2) / (1 + t)^2 = k
    # (1 - k) t^2 + (1 - 2k) t + (1 - k) = 0, smaller root
    A, B, C = 1.0 - k, 1.0 - 2.0 * k, 1.0 - k
    t = (-B - math.sqrt(B * B - 4.0 * A * C)) / (2.0 * A)
    c_root = 2.0 * S / (b * (1.0 + t))
    return c_root, t * c_root


def write_aircraft(ref, out_dir):
    """The aircraft file (docs/aircraft-format.md), every number converted from the book's units."""
    ft = lambda v: v * FOOT
    geo = lambda v: round(v * FOOT, 10) + 0.0
    c_root, c_tip = wing_planform()
    x_root = 22.0                                    # ft aft of the nose: puts 0.35 cbar at 30.9 ft
    x_tip = x_root + 15.0 * math.tan(math.radians(40.0))
    mass = 20500.0 * POUND_FORCE / (32.17 * FOOT)    # W / g of S&L: 637.24 slug
    mass_nesc = 637.1595 * SLUG                      # NESC check cases: 20 500 lb / 32.174 ft/s^2
    inertia = dict(ixx=9496.0, iyy=55814.0, izz=63100.0, ixz=982.0)
    cases = [("nominal", 0.35, mass, "S&L nominal CG, Tables 3.6-2 and 3.6-3 (columns 1, 4 use 0.35 / 0.30)"),
             ("xcg_030", 0.30, mass, "S&L Table 3.6-3 columns 2 and 4 (forward CG)"),
             ("xcg_038", 0.38, mass, "S&L Table 3.6-3 column 3 (aft CG)"),
             ("nesc", 0.25, mass_nesc, "NASA NESC F-16 check cases: CG 0.25 cbar, m = 637.1595 slug (run with g = 32.174 ft/s^2)")]
    L = []
    w = L.append
    w("# F-16 of Stevens, Lewis & Johnson, Aircraft Control and Simulation, 3rd ed. (Wiley 2015),")
    w("# appendix (data from NASA TP-1538, Nguyen et al. 1979; corrections of NASA NESC F16_aero.dml).")
    w("# Generated by examples/f16/make_database.py - do not edit by hand; see docs/f16.md and README.md.")
    w("# Every US customary number of the book is converted exactly (1 ft = 0.3048 m, 1 lb = 0.45359237 kg,")
    w("# g0 = 9.80665 m/s^2); the comments give the book's values.")
    w("schema_version: 1")
    w("")
    w("name: F-16 (Stevens & Lewis)")
    w("description: >-")
    w("  Subsonic F-16 model of Stevens & Lewis (NASA TP-1538 wind-tunnel data, -10 <= alpha <= 45 deg,")
    w("  |beta| <= 30 deg, no Mach dependence), body-axis aero tables about 0.35 cbar, the S&L afterburning")
    w("  turbofan as a thrust table. Geometry is a minimal trapezoidal wing that reproduces S, b and cbar,")
    w("  needed by the file format only (nothing here computes aerodynamics from it).")
    w("")
    w("reference:")
    w(f"  area: {num(ft(ft(300.0)))}   # 300 ft^2")
    w(f"  span: {num(ft(30.0))}        # 30 ft")
    w(f"  chord: {num(ft(11.32))}     # 11.32 ft")
    w("  wing: wing")
    w("  moment_reference_mac_fraction: 0.35   # x_cgr of S&L: the tables' moments are about 0.35 cbar")
    w("")
    w("# Minimal plausible geometry (the format requires one): a trapezoidal wing of S = 300 ft^2,")
    w(f"# b = 30 ft and geometric MAC 11.32 ft (taper {c_tip / c_root:.4f}, root chord {c_root:.3f} ft, tip {c_tip:.3f} ft),")
    w("# 40 deg leading-edge sweep, root leading edge 22 ft aft of the nose. Length 49.25 ft, height 16.7 ft.")
    w("geometry:")
    w(f"  length: {num(ft(49.25))}")
    w(f"  height: {num(ft(16.7))}")
    w("  lifting_surfaces:")
    w("    - name: wing")
    w("      symmetric: true")
    w("      sections:")
    w(f"        - leading_edge: [{num(geo(x_root))}, 0.0, 0.0]")
    w(f"          chord: {num(geo(c_root))}")
    w("          airfoil: NACA 0004")
    w(f"        - leading_edge: [{num(geo(x_tip))}, {num(ft(15.0))}, 0.0]")
    w(f"          chord: {num(geo(c_tip))}")
    w("          airfoil: NACA 0004")
    w("")
    w("# Weight 20 500 lbf with g = 32.17 ft/s^2 (S&L); inertias 9496, 55 814, 63 100, Ixz 982 slug ft^2.")
    w("# CG as a fraction of cbar aft of the MAC leading edge (x_cg of S&L).")
    w("mass:")
    w("  default_case: nominal")
    w("  cases:")
    for name, xcg, m, note in cases:
        w(f"    - name: {name}            # {note}")
        w(f"      mass: {num(m)}")
        w(f"      cg_mac_fraction: {num(xcg)}")
        for k, v in inertia.items():
            w(f"      {k}: {num(v * SLUG_FT2)}")
    w("")
    w("# S&L engine as a table T(altitude, Mach, throttle). S&L map throttle t to power P = 64.94 t")
    w("# (t <= 0.77) or 217.38 t - 117.38 and interpolate thrust linearly in P between idle (P = 0),")
    w("# military (P = 50) and maximum (P = 100) tables; in t that is piecewise linear with breakpoints")
    w("# 0, 50/64.94, 167.38/217.38, 1 and values idle, mil, mil, max (exact except on the band")
    w("# 50/64.94 < t <= 0.77, 5.9e-5 wide, where S&L's thrust is up to 7.6e-5 (T_max - T_mil) above mil).")
    w("# Altitude 0 to 50 000 ft, Mach 0 to 1; linear extrapolation as the book's code. The power lag")
    w("# of S&L is not modelled (trims are unaffected: there P = P_c).")
    w("engine:")
    w("  type: table")
    w(f"  altitude: {seq(ft(h) for h in ref.alt_ft)}")
    w(f"  mach: {seq(ref.mach)}")
    w(f"  throttle: {seq(THROTTLE_BREAKPOINTS)}")
    w("  thrust:   # N; one row per (altitude, Mach), altitude-major; columns idle, mil, mil, max")
    for row in engine_block(ref):
        w(f"    - {seq(row)}")
    w("  angular_momentum: [" + num(160.0 * SLUG_FT2) + ", 0.0, 0.0]   # hx = 160 slug ft^2/s along body x")
    w("")
    w("# S&L limits: elevator +-25 deg, aileron +-21.5 deg, rudder +-30 deg (MANTA signs; the aileron")
    w("# limits are symmetric, so the sign conversion does not change them).")
    w("controls:")
    w("  elevator_deg: [-25.0, 25.0]")
    w("  aileron_deg: [-21.5, 21.5]")
    w("  rudder_deg: [-30.0, 30.0]")
    w("  throttle: [0.0, 1.0]")
    w("")
    w("environment:")
    w(f"  gravity: {num(32.17 * FOOT)}   # 32.17 ft/s^2 (S&L)")
    w("")
    w("# Range of the model's data: no Mach dependence (valid to about M 0.6), thrust tables to 50 000 ft.")
    w("envelope:")
    w("  max_mach: 0.6")
    w("  dive_mach: 0.6")
    w(f"  ceiling: {num(ft(50000.0))}")
    w("  alpha_deg: [-10.0, 45.0]")
    w("  beta_deg: [-30.0, 30.0]")
    w("")
    w("aero:")
    w("  database: f16.madb.yaml")
    w("  label: Stevens & Lewis F-16 tables (NASA TP-1538), body axes, 0.35 cbar")
    with open(os.path.join(out_dir, "aircraft.yaml"), "w") as f:
        f.write("\n".join(L) + "\n")


if __name__ == "__main__":
    main()
