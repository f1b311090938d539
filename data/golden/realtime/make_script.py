"""The scripted real-time input replayed through every front end (issue 18).

Writes script.csv: time_s, contact_force_n, position_from_start_m (from the case's start, as
`pcsim hil` reads it), one row per internal step of 1 ms, for the preset syt-7.0-9.8 with a
215 m window at 222 km/h. Rows 0-2999 are normal steps (the window moves at about 1.26 s and
again later); rows 3000-3004 are inputs the window must not take (a position outside the model,
a force of 1e300 N, a NaN force, a jump of 50 m in one step, a force of 1e6 N); rows
3005-3999 are normal again and continue from row 2999 as if the bad rows had not been given.

Usage: python3 make_script.py > script.csv
"""
import math
import sys

DT = 0.001
V = 222.0 / 3.6


def force(k):
    t = k * DT
    return 85.0 + 20.0 * math.sin(2 * math.pi * 1.3 * t) + 10.0 * math.sin(2 * math.pi * 7.0 * t)


out = sys.stdout
out.write("time_s,contact_force_n,position_from_start_m\n")
for k in range(4000):
    t = k * DT
    if k < 3000:
        f, x = force(k), V * t
    elif k == 3000:
        f, x = force(k), -1000.0
    elif k == 3001:
        f, x = 1e300, V * (k - 1) * DT
    elif k == 3002:
        f, x = float("nan"), V * (k - 2) * DT
    elif k == 3003:
        f, x = force(k), V * (k - 3) * DT + 50.0
    elif k == 3004:
        f, x = 1e6, V * (k - 4) * DT
    else:
        f, x = force(k - 5), V * (k - 5) * DT
    out.write(f"{t!r},{f!r},{x!r}\n")
