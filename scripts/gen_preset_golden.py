#!/usr/bin/env python3
"""Golden results of five preset runs, made with the pcsim build *before* a refactor, so that the
refactor can prove it changed nothing (issue 9: every EN 50318 statistic and every column of
timeseries.csv byte-identical).

Run:  python3 scripts/gen_preset_golden.py target/release/pcsim
Output: data/golden/preset_runs.json: per run, the preset, the speed, the EN 50318 statistics of
each pantograph (exact, as summary.json prints them), the run statistics, and the FNV-1a 64-bit
hash and size of timeseries.csv. Compared by crates/pcsim-cli/tests/suite/preset_golden.rs.
"""
import json
import pathlib
import subprocess
import sys
import tempfile

RUNS = [("en50318-2002", 250), ("en50318-2002", 300), ("stitched-2018-like", 320),
        ("syt-7.0-9.8", 222), ("benchmark-55m", 275)]


def fnv1a64(data: bytes) -> str:
    h = 0xcbf29ce484222325
    for b in data:
        h ^= b
        h = (h * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def main():
    pcsim = sys.argv[1]
    out = []
    with tempfile.TemporaryDirectory() as d:
        for preset, speed in RUNS:
            o = pathlib.Path(d) / f"{preset}-{speed}"
            subprocess.run([pcsim, "run", "--preset", preset, "--speed", str(speed), "--out", str(o), "--quiet"],
                           check=True, stdout=subprocess.DEVNULL)
            summary = json.loads((o / "summary.json").read_text())
            ts = (o / "timeseries.csv").read_bytes()
            out.append({
                "preset": preset,
                "speed_kmh": speed,
                "pantographs": [{"name": p["name"], "stats": p["stats"]} for p in summary["pantographs"]],
                "run_statistics": summary.get("run_statistics"),
                "timeseries_fnv1a64": fnv1a64(ts),
                "timeseries_bytes": len(ts),
            })
    path = pathlib.Path(__file__).resolve().parent.parent / "data" / "golden" / "preset_runs.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
