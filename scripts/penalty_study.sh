#!/usr/bin/env bash
# Issue 20, item 8: σ of the leading pantograph against the contact penalty (Eq. 19), 25–200 kN/m.
# The standard's value, 50 kN/m, is EN 50318's reference contact stiffness (the paper's Eq. 19,
# ref [27]; docs/reference.md §3.1). Writes a Markdown table; docs/validation.md holds its output.
# Usage: scripts/penalty_study.sh [path/to/pcsim]
set -euo pipefail
pcsim=${1:-target/release/pcsim}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| contact penalty (kN/m) | en50318-2002 250 km/h σ (N) | en50318-2002 300 km/h σ (N) | stitched-2018-like 320 km/h σ (N) |"
echo "|---|---|---|---|"
for k in 25 50 100 150 200; do
  row="| $k"
  for pv in "en50318-2002 250" "en50318-2002 300" "stitched-2018-like 320"; do
    set -- $pv
    "$pcsim" presets show "$1" | python3 -c "
import re, sys
t = sys.stdin.read()
t = re.sub(r'(\[contact\]\nstiffness_n_per_m = \{ value = )[0-9.e+]+', r'\g<1>' + '$k' + '000.0', t)
sys.stdout.write(t)" > "$tmp/c.toml"
    "$pcsim" --quiet run "$tmp/c.toml" --speed "$2" --out "$tmp/r" >/dev/null 2>&1
    s=$(python3 -c "import json; print('%.2f' % json.load(open('$tmp/r/summary.json'))['pantographs'][0]['stats']['std_n'])")
    row="$row | $s"
  done
  echo "$row |"
done
