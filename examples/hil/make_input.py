"""A working `pcsim hil` input for the preset syt-7.0-9.8 (issue 19, item 7).

Writes input.csv: the header `time_s,contact_force_n,position_from_start_m`, then one row per
internal step of 1 ms for 3 s: a pantograph at the preset's 222 km/h (position in m from the
case's start, as `pcsim hil` reads it) pressing with 85 N plus a 1.3 Hz and a 7 Hz component
(the shape of a measured contact force, not a measurement).

Usage: python3 make_input.py > input.csv
"""
import math
import sys

DT = 0.001
V = 222.0 / 3.6

out = sys.stdout
out.write("time_s,contact_force_n,position_from_start_m\n")
for k in range(3000):
    t = k * DT
    f = 85.0 + 20.0 * math.sin(2 * math.pi * 1.3 * t) + 10.0 * math.sin(2 * math.pi * 7.0 * t)
    out.write(f"{t:.3f},{f:.4f},{V * t:.4f}\n")
