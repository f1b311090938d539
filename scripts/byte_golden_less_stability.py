#!/usr/bin/env python3
"""Issue 20: checks that the preset runs are byte-identical to data/golden/preset_bytes.json
*before* it is regenerated, except for the new `stability` block of summary.json (stripped here).
Run from the repository root: python3 scripts/byte_golden_less_stability.py"""
import json, os, pathlib, subprocess, sys, tempfile
sys.path.insert(0, 'scripts')
from gen_byte_golden import RUNS, fnv1a64, summary_without_wall
gold = json.load(open('data/golden/preset_bytes.json'))
pcsim = 'target/release/pcsim'
ok = True
with tempfile.TemporaryDirectory() as d:
    for (preset, speed), g in zip(RUNS, gold):
        for path, env in [("portable", {"PCSIM_PORTABLE": "1"}), ("avx2", {})]:
            o = pathlib.Path(d) / f"{preset}-{speed}-{path}"
            args = [pcsim, "run", "--preset", preset, "--out", str(o), "--quiet"] + (["--speed", str(speed)] if speed else [])
            subprocess.run(args, check=True, stdout=subprocess.DEVNULL, env={**os.environ, **env})
            lines = (o / "summary.json").read_text().splitlines(keepends=True)
            i = next(k for k, l in enumerate(lines) if l.startswith('  "stability": {'))
            j = next(k for k in range(i, len(lines)) if lines[k].startswith('  }'))
            kept = lines[:i] + lines[j+1:]
            kept[i-1] = kept[i-1].rstrip('\n').rstrip(',') + '\n'
            h = fnv1a64(summary_without_wall(''.join(kept)))
            t = fnv1a64((o / "timeseries.csv").read_bytes())
            same = h == g[path]["summary_fnv1a64"] and t == g[path]["timeseries_fnv1a64"]
            ok &= same
            print(preset, speed, path, "summary less stability and timeseries identical" if same else "DIFFERENT")
print("ALL SAME" if ok else "SOME DIFFER")
