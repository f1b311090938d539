#!/usr/bin/env python3
"""Follow the README's "Using it" block as a new user would: every `pcsim` command in order, in a
fresh scratch folder (the repository's examples/ and data/ beside it), each timed; a command that
exits non-zero stops the walk with its output. Prints each command's wall time (the figures the
README quotes for a 2-core machine).

Run:  python3 scripts/readme_walk.py target/release/pcsim [--from N]
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def commands():
    with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
        readme = f.read()
    block = readme.split("## Using it", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    for line in block.splitlines():
        cmd = re.sub(r"\s+#.*$", "", line).strip()
        if cmd.startswith("pcsim ") and "…" not in cmd:
            yield cmd


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 1:
        sys.exit(__doc__)
    binary = os.path.abspath(args[0])
    start = int(sys.argv[sys.argv.index("--from") + 1]) if "--from" in sys.argv else 0
    work = tempfile.mkdtemp(prefix="pcsim-readme-")
    for d in ("examples", "data"):
        os.symlink(os.path.join(ROOT, d), os.path.join(work, d))
    rows = []
    for k, cmd in enumerate(commands()):
        if k < start:
            continue
        shell = re.sub(r"(^|&& )pcsim ", lambda m: m.group(1) + binary + " ", cmd)
        t0 = time.monotonic()
        p = subprocess.run(shell, shell=True, cwd=work, capture_output=True, text=True,
                           env={**os.environ, "PCSIM_PROGRESS": "none"})
        wall = time.monotonic() - t0
        rows.append((k, wall, cmd))
        print(f"{k:3d} {wall:8.1f} s  {cmd}", flush=True)
        if p.returncode != 0:
            print(p.stdout[-3000:], p.stderr[-3000:], sep="\n", file=sys.stderr)
            sys.exit(f"command {k} exited with {p.returncode}: {cmd}")
    shutil.rmtree(work, ignore_errors=True)
    print(f"{len(rows)} commands, {sum(r[1] for r in rows):.0f} s in all")


if __name__ == "__main__":
    main()
