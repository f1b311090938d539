#!/usr/bin/env python3
"""Golden files for pcsim's rainflow counting (crates/pcsim-core/src/analysis/fatigue.rs).

The independent tool is the Python package `rainflow` (3.2.0, ASTM E1049-85 section 5.4.4,
https://pypi.org/project/rainflow/), not a runtime dependency of pcsim. Series:
  0  the package's own README signal (201 points of sines);
  1  a dropper-force-like record: preload, pantograph passages, a slack plateau at zero, noise;
  2  Gaussian values rounded to integers (ties, plateaus, equal reversals);
  3  a random walk of 2 000 steps;
  4  a short record (5 points).
The random series come from Python's `random` with fixed seeds, and are written out, so pcsim
reads the same numbers. Every number is written with `repr` (it reads back to the same double).

Run:  python3 -m venv /tmp/rf && /tmp/rf/bin/pip install rainflow==3.2.0
      /tmp/rf/bin/python scripts/gen_rainflow_golden.py
Output: data/golden/rainflow/series.csv (series,value), data/golden/rainflow/cycles.csv
        (series,range,mean,count,i_start,i_end: rainflow.extract_cycles, in its order)
"""
import math
import pathlib
import random

import rainflow

out = pathlib.Path(__file__).resolve().parent.parent / "data" / "golden" / "rainflow"
out.mkdir(parents=True, exist_ok=True)

series = []
t = [4.0 * i / 200 for i in range(201)]
series.append([0.2 + 0.5 * math.sin(x) + 0.2 * math.cos(10 * x) + 0.2 * math.sin(4 * x) for x in t])

rng = random.Random(20261202)
f = []
for i in range(3000):
    x = i / 1000.0
    v = 150.0 + 40.0 * math.exp(-((x - 1.0) / 0.05) ** 2) * math.sin(2 * math.pi * 12.0 * x)
    v += 25.0 * math.sin(2 * math.pi * 3.1 * x) * math.exp(-x) + rng.gauss(0.0, 2.0)
    f.append(max(v - 120.0 * math.exp(-((x - 2.0) / 0.1) ** 2), 0.0))
series.append(f)

rng = random.Random(7)
series.append([float(round(rng.gauss(0.0, 3.0))) for _ in range(400)])

rng = random.Random(11)
w, walk = 0.0, []
for _ in range(2000):
    w += rng.gauss(0.0, 1.0)
    walk.append(w)
series.append(walk)

series.append([1.0, -2.0, 3.0, -1.5, 0.5])

with open(out / "series.csv", "w") as fs:
    fs.write("series,value\n")
    for k, s in enumerate(series):
        for v in s:
            fs.write(f"{k},{v!r}\n")
with open(out / "cycles.csv", "w") as fc:
    fc.write("series,range,mean,count,i_start,i_end\n")
    for k, s in enumerate(series):
        for rng_, mean, count, i0, i1 in rainflow.extract_cycles(s):
            fc.write(f"{k},{rng_!r},{mean!r},{count!r},{i0},{i1}\n")
print("wrote", out / "series.csv", "and", out / "cycles.csv", "with rainflow", rainflow.__version__)
