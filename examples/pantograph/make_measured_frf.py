#!/usr/bin/env python3
"""Make examples/pantograph/measured-apparent-mass.csv: a SYNTHETIC "measured" frequency
response of a pantograph head, for the documented example of `pcsim pantograph fit` (no lab's
measured response of a pantograph with its published model is public).

It is pcsim's own apparent mass of the benchmark-55m preset's three-mass pantograph (reference
README §3.2 data) from 0.5 to 20 Hz at 60 points, with noise from a seeded generator (seed 43):
2 % of the magnitude and 0.02 rad of phase, one standard deviation. `pcsim pantograph fit`
started from a chain 25 % off should return the preset's values within the uncertainties it
reports (docs/validation.md, "Pantographs as built").

Run:  pcsim pantograph frf --preset benchmark-55m --from-hz 0.5 --to-hz 20 --points 60 --out out/frf
      python3 examples/pantograph/make_measured_frf.py out/frf/frf.csv > examples/pantograph/measured-apparent-mass.csv
"""
import csv
import math
import random
import sys

rng = random.Random(43)
print("frequency_hz,magnitude_kg,phase_deg")
for r in csv.DictReader(open(sys.argv[1])):
    m = float(r["magnitude_kg"]) * (1.0 + 0.02 * rng.gauss(0.0, 1.0))
    p = float(r["phase_deg"]) + math.degrees(0.02 * rng.gauss(0.0, 1.0))
    print(f"{float(r['frequency_hz']):.4f},{m:.5f},{p:.3f}")
