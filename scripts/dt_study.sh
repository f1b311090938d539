#!/usr/bin/env bash
# The time step against the coupled stability limit (issue 20): for each preset and speed, the
# limit pcsim states (summary.json `stability`), σ of the leading pantograph at Δt = 0.25 ms and
# at the largest accepted Δt (rounded down to 1 µs), and whether 1.01 × that Δt is refused.
# Writes a Markdown table to stdout; docs/validation.md holds its output.
# Usage: scripts/dt_study.sh [path/to/pcsim]
set -euo pipefail
pcsim=${1:-target/release/pcsim}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
field() { python3 -c "import json,sys; print(eval(sys.argv[2], {}, {'s': json.load(open(sys.argv[1]))}))" "$1" "$2"; }
sigma() { "$pcsim" --quiet run --preset "$1" --speed "$2" --dt "$3" --out "$tmp/r" >/dev/null 2>&1
          field "$tmp/r/summary.json" "'%.2f' % s['pantographs'][0]['stats']['std_n']"; }
echo "| preset | km/h | ω (rad/s) | limit set by | accepted Δt (ms) | σ at 0.25 ms (N) | σ at accepted Δt (N) | difference | 1.01 × accepted Δt |"
echo "|---|---|---|---|---|---|---|---|---|"
for pv in "en50318-2002 250" "en50318-2002 300" "stitched-2018-like 275" "stitched-2018-like 320" "stitched-2018-like-3d 275" "benchmark-55m 250" "syt-7.0-9.8 222"; do
  set -- $pv
  "$pcsim" --quiet run --preset "$1" --speed "$2" --out "$tmp/d" >/dev/null 2>&1
  omega=$(field "$tmp/d/summary.json" "'%.0f' % s['stability']['omega_rad_s']")
  by=$(field "$tmp/d/summary.json" "s['stability']['limiting'].split(' (')[0]")
  dt=$(field "$tmp/d/summary.json" "'%.6f' % (int(s['stability']['dt_max_s'] * 1e6) * 1e-6)")
  above=$(field "$tmp/d/summary.json" "'%.8f' % (1.01 * s['stability']['dt_max_s'])")
  s0=$(sigma "$1" "$2" 0.00025); s1=$(sigma "$1" "$2" "$dt")
  if "$pcsim" --quiet run --preset "$1" --speed "$2" --dt "$above" --out "$tmp/y" >/dev/null 2>&1; then ref="accepted (wrong)"; else ref="refused"; fi
  d=$(python3 -c "print('%+.1f %%' % (100*($s1-$s0)/$s0))")
  echo "| $1 | $2 | $omega | $by | $(python3 -c "print('%.3f' % ($dt*1e3))") | $s0 | $s1 | $d | $ref |"
done
