#!/usr/bin/env python3
"""The figures of docs/validation.md's generated tables, from the commands that give them.

Each generated table sits between two markers in docs/validation.md:

    <!-- generated: NAME (scripts/doc_tables.py) -->
    ...
    <!-- end: NAME -->

This script runs the table's commands with the given pcsim binary and writes the table between
its markers (``--write``), or, by default, checks that the text there is what the commands give
today and exits 1 with a diff where it is not (CI runs the check: a documented figure that no
longer reproduces fails the build).

    python3 scripts/doc_tables.py target/release/pcsim            # check
    python3 scripts/doc_tables.py target/release/pcsim --write    # regenerate

Standard library only; every run is seeded or deterministic, so the text is the same on any
machine (the byte goldens hold the numbers on both kernel paths).
"""

import csv
import difflib
import glob
import json
import math
import os
import re
import subprocess
import sys
import tempfile

DOC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "validation.md")
MINUS = "\u2212"


def num(x, digits=1):
    """A number as the docs write it: fixed digits, a true minus sign."""
    s = f"{x:.{digits}f}"
    if s.startswith("-") and float(s) == 0.0:
        s = s[1:]
    return s.replace("-", MINUS)


def short(x):
    """A range end: as few digits as it has (143, 20.2, -5)."""
    return f"{x:g}".replace("-", MINUS)


def cell(text):
    """A table cell's text with its padding (`| |` when empty)."""
    return f" {text} " if text else " "


def pcsim(binary, *args, codes=(0,)):
    """Run pcsim; an exit status outside `codes` stops the script with pcsim's own message."""
    out = subprocess.run([binary, *args], capture_output=True, text=True)
    if out.returncode not in codes:
        sys.exit(f"pcsim {' '.join(args)}: exit {out.returncode}\n{out.stderr}")
    return out.stdout


# ---------------------------------------------------------------------------------------------
# EN 50318:2002 (`pcsim validate`)

LABELS_2002 = {
    "mean": "mean [N]",
    "std": "σ [N]",
    "stat_max": "Fm + 3σ [N]",
    "stat_min": "Fm − 3σ [N]",
    "actual_max": "actual max [N]",
    "actual_min": "actual min [N]",
    "max_uplift_at_support_mm": "max uplift at support [mm]",
    "loss_of_contact_percent": "loss of contact [%]",
}


def table_en50318_2002(binary, _tmp):
    d = json.loads(pcsim(binary, "validate", "--json", "--quiet"))
    lines = ["| speed | quantity | value | range | result |", "|---|---|---|---|---|"]
    passed = total = 0
    for case in d["cases"]:
        first = True
        for r in case["rows"]:
            speed = f"{case['speed_kmh']:g} km/h" if first else ""
            first = False
            lo, hi = r["range"]
            rng = short(lo) if lo == hi else f"{short(lo)}–{short(hi)}"
            ok = r["pass"]
            passed += ok
            total += 1
            lines.append(f"|{cell(speed)}| {LABELS_2002[r['quantity']]} | {num(r['value'])} | {rng} | "
                         f"{'pass' if ok else 'FAIL'} |")
    lines.append("")
    lines.append(f"{passed} of {total} rows pass.")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# The seed's Table 1 (`pcsim validate seed-table1`)

LABELS_T1 = {
    "mean": "F_m [N]",
    "std": "σ [N]",
    "std_0_5hz": "σ 0–5 Hz [N]",
    "std_5_20hz": "σ 5–20 Hz [N]",
    "actual_max": "actual max [N]",
    "actual_min": "actual min [N]",
    "contact_point_range_mm": "contact-point range [mm]",
    "max_uplift_at_support_mm": "max uplift at support [mm]",
    "loss_of_contact_percent": "loss of contact [%]",
}


def distance(x, lo, hi):
    return max(lo - x, 0.0, x - hi)


def table_seed_table1(binary, _tmp):
    d = json.loads(pcsim(binary, "validate", "seed-table1", "--json", "--quiet"))
    out = []
    passed = total = 0
    for case in d["cases"]:
        out.append(f"**{case['speed_kmh']:g} km/h, {case['pantograph']} pantograph**")
        out.append("")
        out.append("| quantity | pcsim | paper | range | pcsim | paper | nearer the range |")
        out.append("|---|---|---|---|---|---|---|")
        for r in case["rows"]:
            lo, hi = r["range"]
            ours, theirs = r["value"], r["paper_value"]
            if r["pass"] and r["paper_pass"]:
                nearer = "both in range"
            else:
                a, b = distance(ours, lo, hi), distance(theirs, lo, hi)
                nearer = "paper" if b < a else ("pcsim" if a < b else "equally near")
            passed += r["pass"]
            total += 1
            out.append(f"| {LABELS_T1[r['quantity']]} | {num(ours)} | {num(theirs)} | "
                       f"{short(lo)}–{short(hi)} | {'pass' if r['pass'] else 'FAIL'} | "
                       f"{'pass' if r['paper_pass'] else 'FAIL'} | {nearer} |")
        out.append("")
    out.append(f"{passed} of {total} rows pass.")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# The real-time window against the full model (`pcsim realtime`)

def table_realtime_syt(binary, tmp):
    out = os.path.join(tmp, "rt")
    pcsim(binary, "realtime", "--preset", "syt-7.0-9.8", "--window", "60,107,119,120,215,240",
          "--quiet", "--out", out)
    with open(os.path.join(out, "realtime.csv")) as f:
        rows = list(csv.DictReader(f))
    lines = ["| window [m] | modes | moves | mean [N] | σ [N] | Δ mean | Δ σ | goal (mean < 1 %, σ < 3 %) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        dm, ds = float(r["mean_error_percent"]), float(r["std_error_percent"])
        goal = "pass" if abs(dm) < 1 and abs(ds) < 3 else "fail"
        sd = f"{ds:+.1f} %" if abs(ds) < 100 else f"{ds:+.0f} %"
        lines.append(f"| {r['window_m']} | {r['modes']} | {r['moves']} | {float(r['mean_n']):.2f} | "
                     f"{float(r['std_n']):.2f} | {dm:+.2f} % | {sd.replace('-', MINUS)} | {goal} |")
    r = rows[0]
    lines.append(f"| full model | | | {float(r['full_mean_n']):.2f} | {float(r['full_std_n']):.2f} | | | |")
    lines.append(f"| measured (paper §4.2) | | | {float(r['measured_mean_n']):.1f} | "
                 f"{float(r['measured_std_n']):.1f} | | | |")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# `pcsim run --verify` and `--sensitivity` on en50318-2002

STAT_LABELS = {
    "mean_n": "mean [N]",
    "std_n": "σ [N]",
    "std_0_5hz_n": "σ 0–5 Hz [N]",
    "std_5_20hz_n": "σ 5–20 Hz [N]",
    "stat_max_n": "Fm + 3σ [N]",
    "stat_min_n": "Fm − 3σ [N]",
    "actual_max_n": "actual max [N]",
    "actual_min_n": "actual min [N]",
    "max_uplift_at_support_mm": "max uplift at support [mm]",
    "loss_of_contact_percent": "loss of contact [%]",
    "max_lateral_offset_mm": "largest lateral offset [mm]",
    "min_head_margin_mm": "smallest head margin [mm]",
    "max_contact_wire_blowout_mm": "largest blow-out [mm]",
}


def table_verify_2002(binary, tmp):
    lines = ["| speed | statistic | value | refined | change | tolerance | converged | "
             "contact ×2 | change |", "|---|---|---|---|---|---|---|---|---|"]
    for speed in ("250", "300"):
        out = os.path.join(tmp, f"verify{speed}")
        pcsim(binary, "run", "--preset", "en50318-2002", "--speed", speed, "--verify",
              "--allow-contact-loss", "--quiet", "--out", out)
        with open(os.path.join(out, "summary.json")) as f:
            v = json.load(f)["verification"]
        first = True
        for s in v["pantographs"][0]["statistics"]:
            lines.append(
                f"|{cell(speed + ' km/h' if first else '')}| {STAT_LABELS[s['statistic']]} | "
                f"{num(s['value'], 2)} | {num(s['refined'], 2)} | "
                f"{s['change_percent']:+.2f} %".replace("-", MINUS)
                + f" | {s['tolerance_percent']:g} % | {'yes' if s['converged'] else 'NO'} | "
                f"{num(s['stiff_contact'], 2)} | "
                + f"{s['stiff_contact_change_percent']:+.1f} % |".replace("-", MINUS))
            first = False
    return "\n".join(lines)


def table_validate_verify_2002(binary, _tmp):
    d = json.loads(pcsim(binary, "validate", "--verify", "--json", "--quiet"))
    rows = [r for c in d["cases"] for r in c["rows"]]
    stand = sum(r["verification"]["established"] for r in rows)
    lines = [f"`pcsim validate --verify`: {stand} of {len(rows)} verdicts are established; "
             "not established:", ""]
    lines += [f"- {n}" for n in d["not_established"]] or ["- none"]
    return "\n".join(lines)


def table_sensitivity_2002(binary, tmp):
    out = os.path.join(tmp, "sens")
    pcsim(binary, "run", "--preset", "en50318-2002", "--sensitivity", "--quiet", "--out", out)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)["sensitivity"]
    lines = [f"{len(s['parameters'])} ranged values, {2 * len(s['parameters'])} runs one at a time "
             f"and {s['spec']['samples']} sampled (seed {s['spec']['seed']}); "
             f"{len(s['failed'])} runs not made, {len(s['events'])} with an error-level event.", "",
             "| statistic | value | band | moved most by (low → high end) | then |",
             "|---|---|---|---|---|"]
    for b in s["pantographs"][0]["statistics"]:
        m = b["movers"]

        def mover(k):
            if len(m) <= k or m[k]["moved"] == 0:
                return "—"
            if m[k]["swing"] is None:
                return f"`{m[k]['path']}` one end only, moved {m[k]['moved']:.2f}"
            return f"`{m[k]['path']}` {m[k]['swing']:+.2f}".replace("-", MINUS)
        lines.append(f"| {STAT_LABELS[b['statistic']]} | {num(b['value'], 2)} | "
                     f"{num(b['low'], 2)} – {num(b['high'], 2)} | {mover(0)} | {mover(1)} |")
    lines.append("")
    lines.append("| ranged value | case | range | why this range |")
    lines.append("|---|---|---|---|")
    for p in s["parameters"]:
        lines.append(f"| `{p['path']}` | {p['value']:g} | {short(p['low'])} – {short(p['high'])} | "
                     f"{p['range_source']} |")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# The seed's EVA figures (paper §4.1): each reading of Eqs. 20–21 against the whole set at once

# The paper's numbers (§4.1, as quoted in the text): (km/h, kN) -> (EVA m, converged energy J).
PAPER_EVA = {(150, 9.8): (185.2, 46.2), (222, 9.8): (215.3, 105.1), (250, 9.8): (257.8, 118.4),
             (222, 15.8): (186.4, 52.1)}
TOL_J = 0.01


def read_eva(directory):
    """Per case (km/h, kN): the window curves (d, centred snapshot/max/mean) and the density."""
    cases = {}
    with open(os.path.join(directory, "eva.csv")) as f:
        rows = list(csv.DictReader(f))
    index = {int(r["index"]): (int(float(r["speed_kmh"])), float(r["tension_kn"])) for r in rows}
    total = {int(r["index"]): float(r["total_energy_j"]) for r in rows}
    for path in sorted(glob.glob(os.path.join(directory, "cases", "case*_window.csv"))):
        i = int(re.search(r"case(\d+)_", os.path.basename(path)).group(1))
        with open(path) as f:
            w = list(csv.DictReader(f))
        with open(path.replace("_window.csv", "_distribution.csv")) as f:
            dist = list(csv.DictReader(f))
        cases[index[i]] = {
            "d": [float(r["window_m"]) for r in w],
            "centred": {v: [float(r[f"{v}_j"]) for r in w] for v in ("snapshot", "max", "mean")},
            "xi": [float(r["xi_m"]) for r in dist],
            "density": {v: [float(r[f"{v}_j_per_m"]) for r in dist]
                        for v in ("snapshot", "max", "mean")},
            "total_j": total[i],
        }
    return cases


def one_sided(xi, dens, d_grid, sign):
    """E(d) = ∫ over [0, d] ahead (sign +1) or behind (−1) of the pantograph (trapezoid, the
    density linear between grid points as the core integrates it)."""
    pts = sorted((sign * x, e) for x, e in zip(xi, dens) if sign * x >= 0)
    out, acc, k = [], 0.0, 0
    prev_x, prev_e = pts[0]
    for d in d_grid:
        while k + 1 < len(pts) and pts[k + 1][0] <= d:
            x1, e1 = pts[k + 1]
            acc += 0.5 * (prev_e + e1) * (x1 - prev_x)
            prev_x, prev_e, k = x1, e1, k + 1
        part = 0.0
        if k + 1 < len(pts) and d > prev_x:
            x1, e1 = pts[k + 1]
            ed = prev_e + (e1 - prev_e) * (d - prev_x) / (x1 - prev_x)
            part = 0.5 * (prev_e + ed) * (d - prev_x)
        out.append(acc + part)
    return out


def eva_step(d, e, tol):
    """The paper's criterion, as `analysis/eva.rs` `eva_by_step`: the first d whose next window
    adds less than the tolerance."""
    for i in range(len(e) - 1):
        if e[i + 1] - e[i] < tol:
            return d[i], e[i]
    return None, None


def reading(cases, view, window, step_m, scale):
    """The four EVAs and energies of one reading, with `scale` × the integral as the energy."""
    res = {}
    for key, c in cases.items():
        d = c["d"]
        if window == "centred":
            e = c["centred"][view]
        else:
            e = one_sided(c["xi"], c["density"][view], d, +1 if window == "ahead" else -1)
        k = max(1, int(round(step_m)))
        dd, ee = d[::k], [scale * x for x in e[::k]]
        res[key] = eva_step(dd, ee, TOL_J)
    return res


def fraction_reading(cases):
    """The fraction-of-total reading as a fit with its two constants (issue 53, item 6): the
    EVA is the shortest centred window holding a fraction f of the whole model's energy at the
    snapshot, f fitted to the paper's four lengths (the smallest largest miss, f on a 0.001
    grid), then one energy scale k fitted to its four energies (the geometric mean of the
    ratios). Returns (f, k, the four (length, scaled energy))."""
    def at(f):
        res = {}
        for key, c in cases.items():
            want = f * c["total_j"]
            i = next((i for i, e in enumerate(c["centred"]["snapshot"]) if e >= want), None)
            res[key] = (None, None) if i is None else (c["d"][i], c["centred"]["snapshot"][i])
        return res

    def length_miss(res):
        if any(res[k][0] is None for k in PAPER_EVA):
            return math.inf
        return max(abs(res[k][0] - l_p) / l_p for k, (l_p, _) in PAPER_EVA.items())
    f = min((j / 1000 for j in range(500, 1000)), key=lambda f: length_miss(at(f)))
    res = at(f)
    k = math.exp(sum(math.log(e_p / res[key][1]) for key, (_, e_p) in PAPER_EVA.items())
                 / len(PAPER_EVA))
    return f, k, {key: (l, None if e is None else k * e) for key, (l, e) in res.items()}


def score(res):
    """Largest relative miss over the paper's eight numbers (inf where no EVA was found)."""
    worst = 0.0
    for key, (l_p, e_p) in PAPER_EVA.items():
        l, e = res[key]
        if l is None:
            return math.inf
        worst = max(worst, abs(l - l_p) / l_p, abs(e - e_p) / e_p)
    return worst


def trends(res):
    """The paper's trends: the EVA rises with speed (9.8 kN), falls with tension (222 km/h), and
    is at least 160 m on every case run."""
    l = {k: v[0] for k, v in res.items()}
    if any(v is None for v in l.values()):
        return "no EVA"
    ok = []
    ok.append("speed ✓" if l[(150, 9.8)] < l[(222, 9.8)] < l[(250, 9.8)] else "speed ✗")
    ok.append("tension ✓" if l[(222, 9.8)] > l[(222, 15.8)] else "tension ✗")
    ok.append("≥ 160 m ✓" if min(l.values()) >= 160 else f"≥ 160 m ✗ ({min(l.values()):.0f})")
    return ", ".join(ok)


def table_eva_readings(binary, tmp):
    runs = {}
    for damping, flag in (("Rayleigh 0.02/0.02 (paper)", None), ("modal 0.01", "modal:0.01")):
        out = os.path.join(tmp, "eva-" + (flag or "paper").replace(":", ""))
        args = ["eva", "--preset", "syt-7.0-9.8", "--speed", "150,222,250", "--tension",
                "9.8,15.8", "--no-plot", "--quiet", "--out", out]
        if flag:
            args += ["--damping", flag]
        pcsim(binary, *args)
        runs[damping] = read_eva(out)
    # The one-sided windows integrate the written density: centred, the same integral must give
    # the core's window energies back, or the readings built on it are not to be trusted.
    c = runs["Rayleigh 0.02/0.02 (paper)"][(222, 9.8)]
    ahead = one_sided(c["xi"], c["density"]["snapshot"], [x / 2 for x in c["d"]], +1)
    behind = one_sided(c["xi"], c["density"]["snapshot"], [x / 2 for x in c["d"]], -1)
    for k in (50, 200, 800):
        mine, core = ahead[k] + behind[k], c["centred"]["snapshot"][k]
        assert abs(mine - core) <= 1e-3 * core + 1e-9, (k, mine, core)
    grid_dx = c["xi"][1] - c["xi"][0]
    scales = [("integral (J)", 1.0),
              (f"sum of grid values, no spacing (× 1/{grid_dx:g} m)", 1.0 / grid_dx),
              ("sum at a 0.1 m grid (× 10)", 10.0)]
    rows = []
    for damping, cases in runs.items():
        for view in ("snapshot", "max", "mean"):
            for window in ("centred", "ahead", "behind"):
                for step in (1.0, 10.0):
                    for sname, s in scales:
                        res = reading(cases, view, window, step, s)
                        rows.append((score(res), view, window, step, sname, damping, res))
                    # The scale as a free factor: the best of a log grid 1..1000 (an unknown
                    # grid spacing of the paper's sum, h = 1/k).
                    best = min(((score(reading(cases, view, window, step, 10 ** (j / 20))),
                                 10 ** (j / 20)) for j in range(0, 61)), key=lambda t: t[0])
                    res = reading(cases, view, window, step, best[1])
                    rows.append((best[0], view, window, step, f"free: × {best[1]:.3g} (best)",
                                 damping, res))
    literal = [r for r in rows if r[1] == "snapshot" and r[2] == "centred" and r[3] == 1.0
               and r[4] == "integral (J)" and r[5].startswith("Rayleigh")][0]
    fixed = sorted((r for r in rows if not r[4].startswith("free")), key=lambda r: r[0])
    free = sorted((r for r in rows if r[4].startswith("free")), key=lambda r: r[0])
    shown = [literal] + [r for r in fixed[:6] if r is not literal] + free[:4]

    def fmt_row(r):
        sc, view, window, step, sname, damping, res = r
        keys = [(150, 9.8), (222, 9.8), (250, 9.8), (222, 15.8)]
        lens = " / ".join("—" if res[k][0] is None else f"{res[k][0]:.0f}" for k in keys)
        ens = " / ".join("—" if res[k][1] is None else f"{res[k][1]:.1f}" for k in keys)
        miss = "—" if math.isinf(sc) else f"{100 * sc:.0f} %"
        return (f"| {view} | {window} | {step:g} | {sname} | {damping} | {lens} | {ens} | {miss} | "
                f"{trends(res)} |")
    lines = [f"{len(rows)} readings: 3 samplings (snapshot at mid-model, maximum over the passage, "
             "time average) × 3 windows (centred on the pantograph, ahead only, behind only) × "
             "Δd 1 or 10 m × 4 energy scales × 2 dampings; tolerance 0.01 J throughout.", "",
             "| sampling | window | Δd [m] | energy | damping | EVA 150 / 222 / 250 km/h, 9.8 kN; "
             "222 km/h, 15.8 kN [m] | converged energy, the same [J] | largest miss | trends |",
             "|---|---|---|---|---|---|---|---|---|",
             "| **paper** | | | | | 185 / 215 / 258 / 186 | 46.2 / 105.1 / 118.4 / 52.1 | | "
             "speed ✓, tension ✓, ≥ 160 m ✓ |"]
    lines += [fmt_row(r) for r in shown]
    # The fraction-of-total reading: two constants fitted, on the paper's damping.
    f, k, fres = fraction_reading(runs["Rayleigh 0.02/0.02 (paper)"])
    frow = (score(fres), "snapshot", "centred", 1.0,
            f"**a window holding f = {f:.3f} of the whole model's energy (fitted), × {k:.1f} "
            "(fitted)**", "Rayleigh 0.02/0.02 (paper)", fres)
    lines.append(fmt_row(frow))
    rows.append(frow)
    keys = [(150, 9.8), (222, 9.8), (250, 9.8), (222, 15.8)]
    misses = [100 * (fres[key][0] - PAPER_EVA[key][0]) / PAPER_EVA[key][0] for key in keys]
    within = [r for r in rows if r[0] <= 0.10]
    lines.append("")
    # The energies alone: their ratios, and the one factor that brings all four nearest.
    res = literal[6]
    e = {k: v[1] for k, v in res.items()}
    p = {k: v[1] for k, v in PAPER_EVA.items()}
    k_e = math.exp(sum(math.log(p[k] / e[k]) for k in p) / len(p))
    miss_e = max(abs(k_e * e[k] - p[k]) / p[k] for k in p)
    lines.append(
        f"In the literal reading the energies keep the paper's proportions: 250 against 150 km/h "
        f"{e[(250, 9.8)] / e[(150, 9.8)]:.2f} (paper {p[(250, 9.8)] / p[(150, 9.8)]:.2f}), 9.8 "
        f"against 15.8 kN {e[(222, 9.8)] / e[(222, 15.8)]:.2f} (paper "
        f"{p[(222, 9.8)] / p[(222, 15.8)]:.2f}); one factor, × {k_e:.1f}, brings all four within "
        f"{100 * miss_e:.0f} % of the paper's, but the lengths at which they converge do not follow: "
        f"with the energy so scaled, the step criterion stops at "
        + " / ".join(f"{v[0]:.0f}" if v[0] is not None else "—" for v in
                     reading(runs["Rayleigh 0.02/0.02 (paper)"], "snapshot", "centred", 1.0,
                             k_e).values())
        + " m (150 / 222 / 250 km/h at 9.8 kN, then 150 / 222 / 250 km/h at 15.8 kN).")
    lines.append("")
    lines.append(
        f"The fraction-of-total reading (the last row) is a fit with two constants, not a reading "
        f"of the text: the fraction f = {f:.3f} fitted to the four lengths, the scale × {k:.1f} to "
        "the four energies; even so its lengths miss the paper's by "
        + " / ".join(f"{m:+.0f} %" for m in misses) + " (the same order of cases).")
    lines.append("")
    if within:
        lines.append(f"{len(within)} reading(s) reproduce all eight numbers within 10 %.")
    else:
        best = min(rows, key=lambda r: r[0])
        lines.append(f"No reading reproduces the eight numbers within 10 %; the nearest misses one "
                     f"of them by {100 * best[0]:.0f} % ({best[1]}, {best[2]}, Δd {best[3]:g} m, "
                     f"{best[4]}, {best[5]}).")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Is the standard reachable without tuning? (item 3): the design search over the ranged guesses

# `pcsim validate --json`'s quantities as the design search's statistics.
DESIGN_STAT = {
    "mean": "mean_n", "std": "std_n", "std_0_5hz": "std_0_5hz_n", "std_5_20hz": "std_5_20hz_n",
    "stat_max": "stat_max_n", "stat_min": "stat_min_n", "actual_max": "actual_max_n",
    "actual_min": "actual_min_n", "contact_point_range_mm": "contact_point_range_mm",
    "max_uplift_at_support_mm": "max_uplift_at_support_mm",
    "loss_of_contact_percent": "loss_of_contact_percent",
}


def ranged_guesses(binary, preset):
    """The preset's ranged values whose source is a guess: (path, value, low, high)."""
    import tomllib
    d = tomllib.loads(pcsim(binary, "presets", "show", preset))
    out = []

    def walk(v, path):
        if isinstance(v, dict):
            if "value" in v and "range" in v:
                if str(v.get("source", "guess")).startswith("guess"):
                    if isinstance(v["value"], list):
                        out.extend((f"{path}[{i}]", x, r[0], r[1])
                                   for i, (x, r) in enumerate(zip(v["value"], v["range"])))
                    else:
                        out.append((path, v["value"], v["range"][0], v["range"][1]))
                return
            for k, x in v.items():
                walk(x, f"{path}.{k}" if path else k)
        elif isinstance(v, list):
            for i, x in enumerate(v):
                walk(x, f"{path}[{i}]")
    walk(d, "")
    return out


def judged(rng):
    """A range as `pcsim validate` judges it (`analysis/validation.rs` `compare`): the value
    rounded to 0.1, so ±0.05 at each end; a single non-zero value ±0.5."""
    lo, hi = rng
    if lo == hi and lo != 0:
        return lo - 0.5, hi + 0.5
    return lo - 0.05, hi + 0.05


def reach(binary, tmp, preset, validation, evaluations):
    """The design search over `preset`'s ranged guesses with every row of `validation` a
    constraint; the answer as a table."""
    rows = json.loads(pcsim(binary, "validate", validation, "--json", "--quiet"))["cases"]
    variables = ranged_guesses(binary, preset)
    speeds = sorted({c["speed_kmh"] for c in rows})
    spec = [f'[base]\npreset = "{preset}"\n']
    for path, _, lo, hi in variables:
        spec.append(f'[[variable]]\npath = "{path}"\nmin = {float(lo)!r}\nmax = {float(hi)!r}\n')
    for v in speeds:
        spec.append(f"[[speed]]\nkmh = {v!r}\n")
    spec.append('[[objective]]\nstatistic = "std_n"\npantograph = "worst"\n')
    for c in rows:
        pan = c.get("pantograph", "leading")
        for r in c["rows"]:
            lo, hi = judged(r["range"])
            spec.append(f'[[constraint]]\nstatistic = "{DESIGN_STAT[r["quantity"]]}"\n'
                        f'pantograph = "{pan}"\nspeeds_kmh = [{c["speed_kmh"]!r}]\n'
                        f"min = {float(lo)!r}\nmax = {float(hi)!r}\n")
    # The swarm, and every corner of the box (bounds from corner runs: the envelope of a response
    # monotone in each variable).
    corners = 2 ** len(variables)
    for name, budget in (("swarm", f"evaluations = {evaluations}\nseed = 1\n"),
                         ("corners", f'evaluations = {corners}\nmethod = "corners"\n')):
        path = os.path.join(tmp, f"reach-{preset}-{name}.toml")
        with open(path, "w") as f:
            f.write("\n".join(spec + [f"[budget]\n{budget}"]))
        # An infeasible search exits 1 with its answer written (the least violating design).
        pcsim(binary, "design", path, "--no-plot", "--quiet", "--out",
              os.path.join(tmp, f"reach-{preset}-{name}"), codes=(0, 1))
    with open(os.path.join(tmp, f"reach-{preset}-corners", "design.csv")) as f:
        ctable = list(csv.reader(f))
    chead = ctable[0]
    cevals = [r for r in ctable[1:]
              if r[chead.index("error")] == "" and r[chead.index("phase")] == "search"]
    assert len(cevals) == corners, f"{len(cevals)} of {corners} corners ran"
    out = os.path.join(tmp, f"reach-{preset}-swarm")
    with open(os.path.join(out, "design.json")) as f:
        d = json.load(f)
    answer = d["best"] if d["feasible"] else d["least_violating"]
    cols = d["columns"]
    with open(os.path.join(out, "design.csv")) as f:
        table = list(csv.reader(f))
    head = table[0]
    evals = [r for r in table[1:] if r[head.index("error")] == ""]
    lines = [f"`{preset}`, {len(variables)} ranged guesses, every row of `pcsim validate "
             f"{validation}` a constraint at its speed, {d['evaluations_asked']} evaluations "
             f"({d['method']}, seed {d['seed']}): "
             + ("**a design meets every row**" if d["feasible"] else
                f"**no design meets every row**; the least violating still misses "
                f"{len(answer['violated'])} of {sum(len(c['rows']) for c in rows)}") + ".", "",
             "| ranged guess | preset | range | " + ("the design" if d["feasible"] else
                                                    "the least violating design") + " | moves a statistic at the corners |",
             "|---|---|---|---|---|"]
    # A variable moves nothing when flipping it alone, at every corner, leaves every statistic
    # of every speed the same bytes.
    stat_cols = [i for i, h in enumerate(chead) if "@" in h]
    by_bits = {k: cevals[k] for k in range(corners)}
    for i, ((p, x, lo, hi), y) in enumerate(zip(variables, answer["x"])):
        moves = any(by_bits[k][j] != by_bits[k ^ (1 << i)][j]
                    for k in range(corners) for j in stat_cols)
        lines.append(f"| `{p}` | {x:g} | {short(lo)} – {short(hi)} | {y:.3g} | "
                     f"{'yes' if moves else 'no'} |")
    lines += ["", "| row | range | preset | " + ("the design" if d["feasible"] else
                                                  "least violating") + " | | nearest of any "
              f"evaluation ({len(evals)} + {corners} corners) | the corners' envelope |",
              "|---|---|---|---|---|---|---|"]
    reached = 0
    outside = 0
    premise = 0
    for c in rows:
        pan = c.get("pantograph", "leading")
        k = speeds.index(c["speed_kmh"])
        for r in c["rows"]:
            col = cols.index(f"{DESIGN_STAT[r['quantity']]}[{pan}]")
            y = answer["values"][k][col]
            lo, hi = r["range"]
            tag = f"{DESIGN_STAT[r['quantity']]}[{pan}]"
            ok = not any(v.startswith(tag) and v.endswith(f"@{c['speed_kmh']:g}")
                         for v in answer.get("violated", []))
            where = f"{c['speed_kmh']:g} km/h" + (f", {pan}" if "pantograph" in c else "")
            # The value nearest the (judged) range over every evaluation of the search.
            j = head.index(f"{tag}@{c['speed_kmh']:g}")
            jl, jh = judged(r["range"])
            cj = chead.index(f"{tag}@{c['speed_kmh']:g}")
            corner_values = [float(e[cj]) for e in cevals]
            near = min([float(e[j]) for e in evals] + corner_values,
                       key=lambda v: max(jl - v, 0.0, v - jh))
            inside = jl <= near <= jh
            reached += inside
            clo, chi = min(corner_values), max(corner_values)
            beyond = chi < jl or clo > jh
            outside += beyond
            # The premise checked: the swarm's designs, inside the box, inside the envelope.
            swarm_values = [float(e[j]) for e in evals]
            premise += all(clo - 0.05 <= v <= chi + 0.05 for v in swarm_values)
            lines.append(f"| {r['quantity']}, {where} | {short(lo)}–{short(hi)} | "
                         f"{num(r['value'])} | {num(y)} | {'met' if ok else 'MISSED'} | "
                         f"{num(near)}{'' if inside else ' (never met)'} | "
                         f"{num(clo)} – {num(chi)}{' (outside the range)' if beyond else ''} |")
    total = sum(len(c['rows']) for c in rows)
    lines += ["", f"{reached} of {total} rows are met by at least one evaluation; the others by "
              f"none. {outside} of {total} rows lie wholly outside the envelope of the "
              f"{corners} corners: for a statistic monotone in each variable over its range, "
              "no design in the box meets them. The premise, checked: on "
              f"{premise} of {total} rows every one of the swarm's {len(evals)} designs (inside "
              "the box) lies within the corners' envelope (± 0.05)."]
    return "\n".join(lines)


def table_reach_2002(binary, tmp):
    return reach(binary, tmp, "en50318-2002", "en50318-2002", 112)


def table_reach_table1(binary, tmp):
    return reach(binary, tmp, "stitched-2018-like", "seed-table1", 96)


def table_eva_grid(binary, tmp):
    """The EVA over the paper's grid of speeds and tensions (Fig. 7), on the snapshot and on the
    time average."""
    out = os.path.join(tmp, "eva-grid")
    pcsim(binary, "eva", "--preset", "syt-7.0-9.8", "--speed",
          "100,117,133,150,167,183,200,217,233,250", "--tension", "9.8,11.3,12.8,14.3,15.8,17.3,18.8",
          "--no-plot", "--quiet", "--out", out)
    with open(os.path.join(out, "eva.csv")) as f:
        rows = list(csv.DictReader(f))
    speeds = sorted({int(float(r["speed_kmh"])) for r in rows})
    tensions = sorted({float(r["tension_kn"]) for r in rows})
    at = {(int(float(r["speed_kmh"])), float(r["tension_kn"])): r for r in rows}
    lines = []
    for col, title in (("eva_step_m", "**EVA by the paper's criterion on the snapshot (Δd = 1 m, "
                                      "0.01 J), m**"),
                       ("eva_step_mean_m", "**EVA by the paper's criterion on the time average "
                                           "over the passage, m**")):
        lines += [title, "", "| km/h \\ kN | " + " | ".join(f"{t:g}" for t in tensions) + " |",
                  "|---|" + "---|" * len(tensions)]
        for v in speeds:
            lines.append(f"| {v} | " + " | ".join(f"{float(at[(v, t)][col]):.0f}" for t in tensions)
                         + " |")
        lines.append("")
    return "\n".join(lines).rstrip("\n")


def table_pantograph_fit(binary, tmp):
    """The documented example of `pcsim pantograph fit` (issue 43, item 3)."""
    import tomllib
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    out = os.path.join(tmp, "fit")
    pcsim(binary, "pantograph", "fit",
          os.path.join(root, "examples", "pantograph", "measured-apparent-mass.csv"),
          os.path.join(root, "examples", "pantograph", "start-25-percent-off.toml"),
          "--out", out)
    with open(os.path.join(out, "fit.json")) as f:
        r = json.load(f)
    p = tomllib.loads(pcsim(binary, "presets", "show", "benchmark-55m"))["pantographs"][0]
    truth = [x for k in ("masses_kg", "stiffness_n_per_m", "damping_ns_per_m")
             for x in p[k]["value"]]
    lines = [f"Residual {100 * r['residual_rms']:.2f} % RMS (from {100 * r['start_residual_rms']:.2f} % "
             f"at the start), {r['evaluations']} evaluations.", "",
             "| parameter | preset (the truth) | start | fitted | ± (1 σ) | within 2 σ |",
             "|---|---|---|---|---|---|"]
    for q, t in zip(r["parameters"], truth):
        ok = "at its bound" if q["at_bound"] else ("yes" if abs(q["value"] - t) <= 2 * q["std"] else "no")
        lines.append(f"| `{q['name']}` | {t:g} | {q['start']:g} | {q['value']:.4g} | {q['std']:.2g} | {ok} |")
    return "\n".join(lines)


def table_wear_default(binary, tmp):
    """`pcsim study wear` (issue 54): each train's sweep against 2sv/L, its wear per passage by
    term, NQ, the strip's life; the wire's years to its limit."""
    out = os.path.join(tmp, "wear")
    pcsim(binary, "study", "wear", "--no-plot", "--quiet", "--out", out)
    with open(os.path.join(out, "wear.json")) as f:
        w = json.load(f)
    lines = ["| train | km/h | A | median span's sweep [m/s] | 2sv/L (±0.3 m, 60 m) | below 330 mm/s [%] | "
             "wire per passage, mech/elec/arc [mm³] | NQ [%] | strip life [km] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for t in w["trains"]:
        sp = sorted(s["speed_m_s"] for s in t["sweep"]["spans"])
        p = t["pantographs"][0]
        terms = "/".join(f"{x:.2f}" for x in p["wire_terms_mm3"])
        lines.append(f"| {t['name']} | {t['speed_kmh']:g} | {t['current_a']:g} | {sp[len(sp) // 2]:.4f} | "
                     f"{2 * 0.3 * t['speed_kmh'] / 3.6 / 60:.4f} | {t['sweep']['share_below_limit_percent']:.0f} | "
                     f"{terms} | {p['nq_percent']:.3f} | {p['strip']['life_km']:.0f} |")
    wire = w["wire"]
    spans = ", ".join(f"{s['start_m']:.0f}–{s['end_m']:.0f} m" for s in wire["worst_spans"])
    lines += ["", f"The wire ({wire['section_mm2']:.0f} mm², renewed at {wire['limit_mm2']:.1f} mm² lost) "
              f"reaches its limit first at {wire['worst_position_m']:.1f} m after "
              f"{wire['years_to_limit']:.1f} years; the spans that wear first: {spans}."]
    return "\n".join(lines)


def run_stats(binary, tmp, preset, *args):
    """The leading pantograph's statistics of `pcsim run --preset PRESET ARGS`."""
    out = os.path.join(tmp, "run-" + preset + "-" + "-".join(args))
    pcsim(binary, "run", "--preset", preset, *args, "--quiet", "--out", out)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["pantographs"][0]["stats"]


def table_other_presets(binary, tmp):
    lines = ["| speed | Fm [N] | σ [N] | max / min [N] | uplift at support [mm] | loss [%] |",
             "|---|---|---|---|---|---|"]
    for v in ("275", "320"):
        s = run_stats(binary, tmp, "benchmark-55m", "--speed", v)
        lines.append(f"| {v} km/h | {num(s['mean_n'])} | {num(s['std_n'])} | "
                     f"{num(s['actual_max_n'])} / {num(s['actual_min_n'])} | "
                     f"{num(s['max_uplift_at_support_mm'])} | {num(s['loss_of_contact_percent'], 2)} |")
    return "\n".join(lines)


def table_syt(binary, tmp):
    s = run_stats(binary, tmp, "syt-7.0-9.8")
    return "\n".join([
        "| quantity (0–20 Hz, 222 km/h) | pcsim | measured (paper §4.2) | paper's model (converged window) |",
        "|---|---|---|---|",
        f"| mean [N] | {num(s['mean_n'])} (calibrated) | 85.1 | 85.8 |",
        f"| σ [N] | {num(s['std_n'])} | 18.2 | 18.9 |",
        f"| σ 0–5 / 5–20 Hz [N] | {num(s['std_0_5hz_n'])} / {num(s['std_5_20hz_n'])} | — | — |",
        f"| actual max / min [N] | {num(s['actual_max_n'])} / {num(s['actual_min_n'])} | — | — |",
    ])


TABLES = {
    "en50318-2002": table_en50318_2002,
    "seed-table1": table_seed_table1,
    "realtime-syt": table_realtime_syt,
    "syt": table_syt,
    "other-presets": table_other_presets,
    "verify-en50318-2002": table_verify_2002,
    "validate-verify-en50318-2002": table_validate_verify_2002,
    "sensitivity-en50318-2002": table_sensitivity_2002,
    "eva-grid": table_eva_grid,
    "eva-readings": table_eva_readings,
    "reach-en50318-2002": table_reach_2002,
    "reach-seed-table1": table_reach_table1,
    "pantograph-fit": table_pantograph_fit,
    "wear-default": table_wear_default,
}


def doc_files():
    """Every document that may hold a generated table: docs/*.md and the README."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    files = sorted(glob.glob(os.path.join(root, "docs", "*.md")))
    return files + [os.path.join(root, "README.md")]


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    write = "--write" in sys.argv
    if len(args) != 1:
        sys.exit(__doc__)
    binary = os.path.abspath(args[0])
    docs = {}
    for path in doc_files():
        with open(path, encoding="utf-8") as f:
            docs[path] = f.read()
    failed = []
    found = set()
    copies = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, make in TABLES.items():
            pat = re.compile(r"(<!-- generated: " + re.escape(name) +
                             r" \(scripts/doc_tables.py\) -->\n)(.*?)(\n<!-- end: " +
                             re.escape(name) + r" -->)", re.S)
            text = None
            for path, doc in docs.items():
                # Every copy of the table, in every document, from the last to the first (so
                # that a rewrite keeps the earlier copies' offsets).
                for m in reversed(list(pat.finditer(doc))):
                    found.add(name)
                    copies += 1
                    if text is None:
                        text = make(binary, tmp)
                    if m.group(2) == text:
                        continue
                    if write:
                        doc = doc[:m.start(2)] + text + doc[m.end(2):]
                    else:
                        diff = "\n".join(difflib.unified_diff(m.group(2).splitlines(),
                                                              text.splitlines(), "documented",
                                                              "today", lineterm=""))
                        failed.append(f"{name} in {os.path.relpath(path)}: the documented table "
                                      f"differs from what its command gives today:\n{diff}")
                docs[path] = doc
            if name not in found:
                failed.append(f"{name}: no markers in the docs")
    for path, doc in docs.items():
        unknown = set(re.findall(r"<!-- generated: (\S+) \(scripts/doc_tables.py\) -->", doc))
        failed += [f"{n} in {os.path.relpath(path)}: markers with no generator"
                   for n in sorted(unknown - set(TABLES))]
        if write:
            with open(path, "w", encoding="utf-8") as f:
                f.write(doc)
    for f in failed:
        print(f, file=sys.stderr)
    if failed and not write:
        sys.exit(1)
    print(f"{len(found)} generated tables ({copies} copies) "
          f"{'written' if write else 'match their commands'}")


if __name__ == "__main__":
    main()
