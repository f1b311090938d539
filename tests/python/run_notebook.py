#!/usr/bin/env python3
"""Execute a notebook with nbclient (run by .ci/run): any failing cell fails the run.

Usage: run_notebook.py NOTEBOOK"""
import sys

import nbformat
from nbclient import NotebookClient

nb = nbformat.read(sys.argv[1], as_version=4)
NotebookClient(nb, timeout=600, kernel_name="python3").execute()
outs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
text = "".join(o.get("text", "") for o in outs if o.get("output_type") == "stream")
if "checks pass" not in text:
    sys.exit("the notebook's checks did not run to the end")
# The figures show (issue 19: a `matplotlib.use("Agg")` had left the notebook without any).
figures = sum(1 for o in outs if "image/png" in o.get("data", {}))
if figures == 0:
    sys.exit("the notebook shows no figure")
print(f"notebook {sys.argv[1]}: {len(nb.cells)} cells executed, checks pass")
