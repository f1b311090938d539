#!/usr/bin/env python3
"""Worst relative deviation of the five preset runs from data/golden/preset_runs.json.

Usage: python3 scripts/preset_deviation.py target/release/pcsim [--portable]
(run from the repository root; writes to the system temporary directory)."""
import json, os, subprocess, sys, tempfile
g=json.load(open('data/golden/preset_runs.json'))
binp=sys.argv[1]; extra=sys.argv[2:]
for r in g:
    out=os.path.join(tempfile.gettempdir(), f"pcsim-dev-{r['preset']}-{r['speed_kmh']}")
    subprocess.run([binp]+extra+['run','--preset',r['preset'],'--speed',str(r['speed_kmh']),'--quiet','--out',out],check=True,capture_output=True)
    s=json.load(open(out+'/summary.json'))
    worst=0;wk=None
    for a,b in zip(r['pantographs'],s['pantographs']):
        for k,v in a['stats'].items():
            d=abs(b['stats'][k]-v)/max(abs(v),1e-9)
            if d>worst: worst=d;wk=k
    print(f"{r['preset']:20s} {r['speed_kmh']:4} worst rel dev {worst:.2e} ({wk})")
