#!/usr/bin/env python3
"""The input file of the README's `fmpy simulate` example: a contact force and a pantograph position
for 3 s, every 10 ms (FMPy holds or interpolates them between rows).

Run:  python3 scripts/gen_fmu_input.py   (standard library only)
Output: examples/fmu/input.csv with the columns time, contact_force [N], position_from_start [m]
(from the case's start, 222 km/h as in the SYT measurement).
"""
import math
import pathlib

out = pathlib.Path(__file__).resolve().parent.parent / "examples" / "fmu" / "input.csv"
out.parent.mkdir(parents=True, exist_ok=True)
with open(out, "w") as f:
    f.write("time,contact_force,position_from_start\n")
    for k in range(301):
        t = k * 0.01
        force = 85.0 + 20.0 * math.sin(2 * math.pi * 1.3 * t) + 8.0 * math.sin(2 * math.pi * 5.1 * t)
        f.write(f"{t:.2f},{force:.4f},{222.0 / 3.6 * t:.4f}\n")
print(f"wrote {out}")
