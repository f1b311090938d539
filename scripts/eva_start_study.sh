#!/usr/bin/env bash
# Issue 20, item 8: the EVA lengths of `syt-7.0-9.8` (222 km/h, snapshot at eva.snapshot_at_m = 900 m)
# against the run's start position.
# The 99 % criterion is the shortest window around the pantograph holding 99 % of the catenary's
# vibration energy at the snapshot (Eq. 21 with the fraction criterion): it counts the energy the
# pantograph left behind since it started, so it grows with the distance run (the waves it
# launched travel on and decay slowly); the step criterion (Δd = 1 m, 0.01 J) looks at the
# energy near the pantograph and barely moves. Writes a Markdown table; docs/validation.md holds
# its output. Usage: scripts/eva_start_study.sh [path/to/pcsim]
set -euo pipefail
pcsim=${1:-target/release/pcsim}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| start_m (m) | analysis_m (m) | EVA step (m) | EVA 99 % (m) | EVA 99 % of the maximum (m) | EVA 99 % of the time average (m) |"
echo "|---|---|---|---|---|---|"
for s in 60 200 400 600 800; do
  "$pcsim" presets show syt-7.0-9.8 | python3 -c "
import re, sys
t = sys.stdin.read()
t = re.sub(r'(\nstart_m = \{ value = )[0-9.]+', r'\g<1>' + '$s.0', t)
a0 = max(300.0, $s + 60.0)
t = re.sub(r'(\nanalysis_m = \{ value = )\[[0-9., ]+\]', r'\g<1>[' + str(a0) + ', 1500.0]', t)
sys.stdout.write(t)" > "$tmp/c.toml"
  "$pcsim" --quiet eva "$tmp/c.toml" --out "$tmp/e" --no-plot >/dev/null 2>&1 || { echo "| $s | (refused: $("$pcsim" --quiet eva "$tmp/c.toml" --out "$tmp/e" --no-plot 2>&1 | head -1)) |"; continue; }
  python3 - "$tmp/e/eva.csv" "$s" <<'PY'
import csv, sys
r = next(csv.DictReader(open(sys.argv[1])))
f = lambda k: r.get(k) or "—"
print(f"| {sys.argv[2]} | [{max(300, int(sys.argv[2]) + 60)}, 1500] | {f('eva_step_m')} | {f('eva_fraction_m')} | {f('eva_fraction_max_m')} | {f('eva_fraction_mean_m')} |")
PY
done
