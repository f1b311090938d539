#!/usr/bin/env bash
# The rows of `pcsim eva`, `pcsim window` and `pcsim validate --json` for a small grid, made with
# the build *before* a refactor (issue 18), on the portable kernels (the same bytes on every
# machine). Compared by crates/pcsim-cli/tests/suite/byte_golden.rs, and by the Python tests (the
# core's typed rows through `pcsim.eva`, `pcsim.window`, `pcsim.validate`).
# Made again in issue 23 when the implicit corrections' triangular solves took their row sums in
# the four-lane dot kernel: validate.json's values moved by at most 2e-14 relative, the EVA and
# window rows kept their bytes.
# Made again in issue 23 when a mirror offset's points (S − d) read their partner's transform
# (output P − 1 − s, negated) instead of one of their own: validate.json's values moved by at most
# 9.7e-13 relative (en50318-2002 at 300 km/h, the statistical minimum, −13.14 N: 1.3e-11 N), the
# EVA and window rows kept their bytes.
# Made again in issue 23 when the moving rows' sines took each block's seeds (modes past 256) as
# the first block's turned by one direct sin_cos: validate.json's values moved by at most 1.2e-12
# relative (en50318-2002 at 300 km/h, the statistical minimum, −13.14 N: 1.5e-11 N), the EVA and
# window rows kept their bytes.
# Issue 39 made the window's default search the fine one (every window at the resolution from the
# longest down to the first failure); the golden was made with the lattice search, now
# `--coarse-only`, which its command here names: the same rows.
# Usage: scripts/gen_study_golden.sh target/release/pcsim
set -euo pipefail
pcsim=$(readlink -f "$1")
root=$(cd "$(dirname "$0")/.." && pwd)
dest="$root/data/golden/studies"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$dest"
export PCSIM_PORTABLE=1
cd "$work"
"$pcsim" eva --preset syt-7.0-9.8 --speed 150,222 --tension 9.8 --out eva --no-plot --quiet >/dev/null
"$pcsim" window --preset syt-7.0-9.8 --speed 150 --tension 9.8 --max-window 240 --coarse 40 --resolution 10 --coarse-only --out win --no-plot --quiet >/dev/null
"$pcsim" validate --json > validate.json
cp eva/eva.csv "$dest/eva.csv"
cp win/window.csv "$dest/window.csv"
cp win/fit.csv "$dest/fit.csv"
cp validate.json "$dest/validate.json"
echo "wrote $dest"
