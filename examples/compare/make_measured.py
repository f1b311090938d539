#!/usr/bin/env python3
"""Make examples/compare/measured.csv: a SYNTHETIC "measured" contact-force record for the README's
`pcsim compare` line (no recording car's data is public with its catenary's design data).

It is pcsim's own run of the benchmark-55m preset at 320 km/h (the leading pantograph's raw
contact force), resampled every 0.25 m by linear interpolation, its positions shifted by -7.5 m
(as a recording car's odometer would be off), with white noise of 5 N RMS from a seeded generator
(seed 55). `pcsim compare` should find the shift (+7.5 m) and a correlation close to 1.

Run:  pcsim run --preset benchmark-55m --out out/b55
      python3 examples/compare/make_measured.py out/b55/timeseries.csv > examples/compare/measured.csv
"""
import csv
import random
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
x = [float(r["leading_position_m"]) for r in rows]
f = [float(r["leading_force_n"]) for r in rows]
rng = random.Random(55)
shift, dx = -7.5, 0.25
print("position_m,force_n")
p, k = x[0] + 1.0, 0
while p < x[-1] - 1.0:
    while x[k + 1] < p:
        k += 1
    t = (p - x[k]) / (x[k + 1] - x[k])
    force = f[k] * (1 - t) + f[k + 1] * t + rng.gauss(0.0, 5.0)
    print(f"{p + shift:.2f},{force:.3f}")
    p += dx
