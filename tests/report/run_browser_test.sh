#!/usr/bin/env bash
# The reports in headless Chromium (issue 22, item 1): installs Debian's chromium when missing,
# writes the report.html of a run, an EVA sweep, a window sweep, a real-time study, a Monte Carlo
# study, a line's dropper run, a comparison with a measurement and a design search (every figure
# kind), and checks them in the browser
# (tests/report/check_reports.py: the DOM, no outside address, every figure rendered).
# Screenshots are kept in target/report-shots. Usage: run_browser_test.sh PCSIM_EXECUTABLE
set -euo pipefail
pcsim=$(readlink -f "$1")
root=$(cd "$(dirname "$0")/../.." && pwd)
if ! command -v chromium >/dev/null; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y -q chromium >/dev/null 2>&1 \
    || { apt-get update -q >/dev/null && apt-get install -y -q chromium >/dev/null; }
fi
work=$(mktemp -d /tmp/pcsim-report.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$pcsim" run --preset stitched-2018-like --report --quiet --out "$work/run" >/dev/null
# The assessment (issue 22, item 3) into the run's directory; it makes the report again.
"$pcsim" assess "$work/run" --system ac >/dev/null
"$pcsim" eva --preset syt-7.0-9.8 --speed 150,222 --tension 9.8 --report --quiet --out "$work/eva" >/dev/null
"$pcsim" window --preset syt-7.0-9.8 --speed 150,222 --tension 9.8 --max-window 260 --resolution 5 --report --quiet --out "$work/window" >/dev/null
"$pcsim" realtime --preset syt-7.0-9.8 --window 160,240 --quiet --out "$work/realtime" >/dev/null
"$pcsim" report "$work/realtime" >/dev/null
"$pcsim" run "$root/examples/cases/syt-irregular.toml" --seeds 4 --plot --quiet --out "$work/montecarlo" >/dev/null
"$pcsim" report "$work/montecarlo" >/dev/null
"$pcsim" run "$root/examples/cases/dropper-fatigue/en50318-2018-like-simple-sn-guess.toml" \
  --dropper-forces --report --quiet --out "$work/droppers" >/dev/null
# A "measurement": the run's own leading force, as a recording car's file gives it.
python3 - "$work/run/timeseries.csv" "$work/measured.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("position_m,force_n\n")
    for r in rows:
        f.write(f"{r['leading_position_m']},{r['leading_force_filtered_n']}\n")
PY
"$pcsim" compare "$work/run" "$work/measured.csv" --search 5m --quiet --out "$work/compare" >/dev/null
"$pcsim" report "$work/compare" >/dev/null
"$pcsim" design "$root/tests/design/swarm.toml" --quiet --out "$work/design" >/dev/null
"$pcsim" report "$work/design" >/dev/null
python3 "$root/tests/report/check_reports.py" "$(command -v chromium)" "$root/target/report-shots" \
  "$work/run" "$work/eva" "$work/window" "$work/realtime" "$work/montecarlo" "$work/droppers" \
  "$work/compare" "$work/design"
