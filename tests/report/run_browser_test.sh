#!/usr/bin/env bash
# The reports in headless Chromium (issue 22, item 1): installs Debian's chromium when missing,
# writes a run's, an EVA sweep's and a window sweep's report.html, and checks them in the browser
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
"$pcsim" window --preset syt-7.0-9.8 --speed 150,222 --tension 9.8 --report --quiet --out "$work/window" >/dev/null
python3 "$root/tests/report/check_reports.py" "$(command -v chromium)" "$root/target/report-shots" \
  "$work/run" "$work/eva" "$work/window"
