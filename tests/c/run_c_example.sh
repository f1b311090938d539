#!/usr/bin/env bash
# Compile examples/c/hil_loop.c with the system C compiler against include/pcsim.h and the
# C library, run it on a 20 s input, and compare its output with `pcsim hil` on the same input:
# within 1e-12 (pcsim hil prints 13 significant digits). Usage: run_c_example.sh TARGET_DIR
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
target=$(readlink -f "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cc -std=c99 -Wall -Wextra -Werror "$root/examples/c/hil_loop.c" -I"$root/include" \
  -L"$target" -lpcsim_capi -o "$work/hil_loop"
python3 - "$work/in.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("time_s,contact_force_n,pantograph_position_m\n")
    for k in range(20000):
        t = k * 0.001
        force = 85.0 + 20.0 * math.sin(2 * math.pi * 1.3 * t) + 10.0 * math.sin(2 * math.pi * 7.0 * t)
        f.write(f"{t!r},{force!r},{222.0 / 3.6 * t!r}\n")
PY
LD_LIBRARY_PATH="$target" "$work/hil_loop" syt-7.0-9.8 215 "$work/in.csv" > "$work/c.csv"
"$target/pcsim" hil --preset syt-7.0-9.8 --window 215 --input "$work/in.csv" --out "$work/ref.csv" >/dev/null
python3 - "$work/c.csv" "$work/ref.csv" <<'PY'
import csv, sys
a = list(csv.reader(open(sys.argv[1])))[1:]
b = list(csv.reader(open(sys.argv[2])))[1:]
assert len(a) == len(b) and len(a) > 1000, (len(a), len(b))
worst = max(abs(float(x[i]) - float(y[i])) for x, y in zip(a, b) for i in (0, 1, 2))
moving = max(float(x[1]) for x in a) - min(float(x[1]) for x in a)
assert worst < 1e-12 and moving > 1e-3, (worst, moving)
print(f"C example: {len(a)} steps, largest difference from pcsim hil {worst:.1e} (the wire moves over {moving * 1e3:.1f} mm)")
PY
