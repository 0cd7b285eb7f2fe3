#!/usr/bin/env python3
"""Motion file of the pitching NACA 64A010 (AGARD CT5 as in SU2's test case,
/work/shared/reference/naca64a010_ct5/README.md): theta = 1.01 deg sin(106.69842 t) about the
reference point, three periods of 25 samples (dt = T/25). v0 = M c_inf with c_inf from
T = 288.15 K, gamma = 1.4, R = 287.058 J/(kg K) (SU2's air).
Usage: make_motion.py > ct5_rigid_motion.csv"""
import math

omega = 106.69842
amplitude = math.radians(1.01)
samples, periods = 25, 3
mach = 0.796
c_inf = math.sqrt(1.4 * 287.058 * 288.15)
T = 2 * math.pi / omega
print(f"# v0: {mach * c_inf!r}")
print(f"# mach: {mach}")
print("# AGARD CT5 pitching NACA 64A010: theta = 1.01 deg sin(106.69842 t), dt = T/25, 3 periods")
print("t,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder")
for i in range(samples * periods + 1):
    t = i * T / samples
    theta = amplitude * math.sin(2 * math.pi * (i % samples) / samples)
    print(f"{t!r},0,0,0,0,{theta!r},0,0,0,0")
