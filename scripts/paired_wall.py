#!/usr/bin/env python3
"""Wall time of two whole commands, run in turn (A B A B ...), with the ratio A/B taken pair by
pair, so that the machine's drift during the measurement moves both sides of each ratio alike
(docs/performance.md quotes the medians).

Run:  python3 scripts/paired_wall.py [-n PAIRS] [--warmup W] [--pin CPU] --vs "B COMMAND" -- A COMMAND ...
Each command is split as a shell splits words and started without a shell, its output discarded;
with --pin, under `taskset -c CPU`. Prints min, median and max of A's and B's wall seconds and of
the ratios A/B. A command that fails stops the measurement with its exit status.
"""
import argparse
import shlex
import statistics
import subprocess
import sys
import time


def timed(cmd):
    t0 = time.monotonic()
    rc = subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                        stderr=subprocess.DEVNULL).returncode
    t = time.monotonic() - t0
    if rc != 0:
        sys.exit(f"paired_wall: {shlex.join(cmd)} exited with {rc}")
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=7, help="pairs timed (default 7)")
    ap.add_argument("--warmup", type=int, default=1, help="pairs run first, not timed (default 1)")
    ap.add_argument("--pin", help="a CPU list for taskset -c")
    ap.add_argument("--vs", required=True, help="command B, one string")
    ap.add_argument("a", nargs=argparse.REMAINDER, help="-- command A")
    args = ap.parse_args()
    a = args.a[1:] if args.a[:1] == ["--"] else args.a
    b = shlex.split(args.vs)
    if not a or args.n < 1:
        ap.error("command A and at least one pair are needed")
    if args.pin:
        a, b = ["taskset", "-c", args.pin] + a, ["taskset", "-c", args.pin] + b
    for _ in range(args.warmup):
        timed(a), timed(b)
    ta, tb = [], []
    for _ in range(args.n):
        ta.append(timed(a))
        tb.append(timed(b))
    ratios = [x / y for x, y in zip(ta, tb)]
    for name, v in [("A wall s", ta), ("B wall s", tb), ("A/B wall", ratios)]:
        print(f"{name:10} {min(v):9.4f} {statistics.median(v):9.4f} {max(v):9.4f}")


if __name__ == "__main__":
    main()
