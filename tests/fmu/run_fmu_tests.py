#!/usr/bin/env python3
"""FMU tests run by .ci/run: FMPy validation, simulate_fmu against pcsim's Rust run, misuse suite.

Usage: run_fmu_tests.py FMU PCSIM_EXECUTABLE
"""
import os
import subprocess
import sys
import tempfile
import zipfile

import numpy as np
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

fmu, pcsim = sys.argv[1], sys.argv[2]
here = os.path.dirname(os.path.abspath(__file__))
passed, failed = 0, 0


def check(name, ok, detail=""):
    global passed, failed
    if ok:
        passed += 1
        print(f"ok   {name} {detail}")
    else:
        failed += 1
        print(f"FAIL {name} {detail}")


# 1. fmpy validate
problems = validate_fmu(fmu)
check("fmpy validate", not problems, "; ".join(problems))

# 2. simulate_fmu with a time-varying contact force against `pcsim hil` (same held input).
dt, stop = 0.001, 4.0
t = np.round(np.arange(0.0, stop + dt / 2, dt), 9)
force = 85.0 + 20.0 * np.sin(2 * np.pi * 1.3 * t) + 10.0 * np.sin(2 * np.pi * 7.0 * t)
position = (222.0 / 3.6) * t
signals = np.zeros(len(t), dtype=[("time", np.float64), ("contact_force", np.float64), ("position_from_start", np.float64)])
signals["time"], signals["contact_force"], signals["position_from_start"] = t, force, position
res = simulate_fmu(fmu, start_time=0.0, stop_time=stop, step_size=dt, output_interval=dt, input=signals,
                   output=["wire_height", "wire_velocity", "pantograph_contact_force"])
with tempfile.TemporaryDirectory() as d:
    inp = os.path.join(d, "in.csv")
    out = os.path.join(d, "ref.csv")
    n = len(t) - 1  # FMPy steps from t[0] to t[-1]
    with open(inp, "w") as f:
        f.write("time_s,contact_force_n,position_from_start_m\n")
        for k in range(n):
            f.write(f"{float(t[k])!r},{float(force[k])!r},{float(position[k])!r}\n")
    subprocess.run([pcsim, "hil", "--preset", "syt-7.0-9.8", "--window", "215", "--input", inp, "--out", out], check=True,
                   stdout=subprocess.DEVNULL)
    ref = np.loadtxt(out, delimiter=",", skiprows=1, usecols=(0, 1, 2, 3))  # the 5th column is the status
# FMPy's first row is the initial state at t = 0; row k + 1 follows the k-th step.
fm_t, fm_h, fm_v = res["time"][1:], res["wire_height"][1:], res["wire_velocity"][1:]
m = min(len(fm_t), len(ref))
dt_err = np.max(np.abs(fm_t[:m] - ref[:m, 0]))
h_err = np.max(np.abs(fm_h[:m] - ref[:m, 1]))
v_err = np.max(np.abs(fm_v[:m] - ref[:m, 2]))
moving = np.ptp(ref[:m, 1])
check("simulate_fmu vs pcsim hil: same times", m == n and dt_err < 1e-9, f"({m} steps, time error {dt_err:.1e} s)")
check("simulate_fmu vs pcsim hil: wire height within 1e-9 m", h_err < 1e-9 and moving > 1e-3,
      f"(max error {h_err:.2e} m; the height moves over {moving * 1e3:.1f} mm)")
check("simulate_fmu vs pcsim hil: wire velocity within 1e-9 m/s", v_err < 1e-9, f"(max error {v_err:.2e} m/s)")
check("HIL echoes the input force", np.max(np.abs(res["pantograph_contact_force"][1:m + 1] - force[:m])) < 1e-9)

# 2b. The README's example: `fmpy simulate` with the shipped input file gives a moving wire.
readme_input = os.path.join(here, "..", "..", "examples", "fmu", "input.csv")
with tempfile.TemporaryDirectory() as d:
    out = os.path.join(d, "result.csv")
    fmpy_cli = os.path.join(os.path.dirname(sys.executable), "fmpy")
    r = subprocess.run([fmpy_cli, "simulate", fmu, "--input-file", readme_input, "--stop-time", "3",
                        "--output-interval", "0.001", "--output-file", out], capture_output=True, text=True)
    ok = r.returncode == 0 and os.path.exists(out)
    span = 0.0
    if ok:
        res = np.genfromtxt(out, delimiter=",", names=True)
        span = float(np.ptp(res["wire_height"]))
    check("README example: fmpy simulate with examples/fmu/input.csv moves the wire", ok and span > 0.01,
          f"(the height moves over {span * 1e3:.1f} mm) {r.stderr[-200:] if not ok else ''}")

# 3. SIL variant runs and computes its own contact force.
res_sil = simulate_fmu(fmu, stop_time=2.0, step_size=dt, output_interval=dt, start_values={"sil": True},
                       output=["pantograph_contact_force", "wire_height"])
fsil = res_sil["pantograph_contact_force"][500:]
check("SIL: contact force of pcsim's own pantograph", 60.0 < float(np.mean(fsil)) < 110.0 and float(np.std(fsil)) > 1.0,
      f"(mean {np.mean(fsil):.1f} N, σ {np.std(fsil):.1f} N over 1.5 s)")

# 3b. Lateral motion (issue 12): the 3D preset's contact point zig-zags over the stagger; the
# vertical default reports 0.
res_3d = simulate_fmu(fmu, stop_time=2.0, step_size=dt, output_interval=dt,
                      start_values={"sil": True, "case": "stitched-2018-like-3d"},
                      output=["contact_lateral", "wire_height"])
lat = res_3d["contact_lateral"][1:]
check("3D case: contact_lateral follows the ±0.3 m stagger",
      bool(np.all(np.isfinite(lat))) and float(np.max(np.abs(lat))) < 0.302 and float(np.ptp(lat)) > 0.2,
      f"(range {np.min(lat):.3f} to {np.max(lat):.3f} m over 2 s)")
res_v = simulate_fmu(fmu, stop_time=0.05, step_size=dt, output_interval=dt, output=["contact_lateral"])
check("vertical case: contact_lateral is 0", float(np.max(np.abs(res_v["contact_lateral"]))) == 0.0)

# 3b'. Two collector strips (issue 43): the preset's head of strips runs in the SIL window (its
# contact force the strips' sum, plausible, and not the one-head pantograph's).
res_2s = simulate_fmu(fmu, stop_time=2.0, step_size=dt, output_interval=dt,
                      start_values={"sil": True, "case": "benchmark-55m-two-strips"},
                      output=["pantograph_contact_force"])
res_1h = simulate_fmu(fmu, stop_time=2.0, step_size=dt, output_interval=dt,
                      start_values={"sil": True, "case": "benchmark-55m"},
                      output=["pantograph_contact_force"])
f2, f1 = res_2s["pantograph_contact_force"][500:], res_1h["pantograph_contact_force"][500:]
check("two strips (SIL): the head of strips' contact force",
      bool(np.all(np.isfinite(f2))) and 50.0 < float(np.mean(f2)) < 200.0 and float(np.std(f2)) > 1.0
      and not np.array_equal(f2, f1),
      f"(mean {np.mean(f2):.1f} N, σ {np.std(f2):.1f} N; one head: {np.mean(f1):.1f} N, {np.std(f1):.1f} N)")

# 3c. Irregularity (issue 13): a 10 mm sine on the contact wire from a CSV file moves the wire
# the pantograph sees by that much (HIL with a constant force, 3 s from the start).
with tempfile.TemporaryDirectory() as d:
    prof = os.path.join(d, "irregularity.csv")
    with open(prof, "w") as f:
        f.write("position_m,deviation_m\n")
        for i in range(0, 3601):
            x = 0.5 * i
            f.write(f"{x},{0.010 * np.sin(2 * np.pi * x / 20.0)}\n")
    sig = np.zeros(len(t), dtype=[("time", np.float64), ("contact_force", np.float64), ("position_from_start", np.float64)])
    sig["time"], sig["contact_force"], sig["position_from_start"] = t, 90.0, position
    plain = simulate_fmu(fmu, stop_time=3.0, step_size=dt, output_interval=dt, input=sig, output=["wire_height"])
    rough = simulate_fmu(fmu, stop_time=3.0, step_size=dt, output_interval=dt, input=sig, output=["wire_height"],
                         start_values={"irregularity_file": prof})
    diff = rough["wire_height"] - plain["wire_height"]
    check("irregularity_file: the wire height carries the 10 mm profile",
          0.0095 < float(np.max(np.abs(diff))) < 0.0105, f"(largest difference {np.max(np.abs(diff)) * 1e3:.2f} mm)")

# 3d. A case file (issue 41, item 5): `pcsim fmu build --case` bundles it (resources/case.toml,
# the `case` parameter's start value) and the FMU runs it as `pcsim hil CASE.toml` does; the
# preset's own text bundled gives the default FMU's heights exactly; a case file named by the
# `case` parameter (not bundled) runs the same; a case the window cannot run is refused at build.
with tempfile.TemporaryDirectory() as d:
    text = subprocess.run([pcsim, "presets", "show", "syt-7.0-9.8"], check=True, capture_output=True,
                          text=True).stdout
    stiff = text.replace('tension_n = { value = 9800.0', 'tension_n = { value = 15800.0')
    same_p, stiff_p = os.path.join(d, "same.toml"), os.path.join(d, "stiff.toml")
    open(same_p, "w").write(text)
    open(stiff_p, "w").write(stiff)
    built = {}
    for tag, path in [("same", same_p), ("stiff", stiff_p)]:
        out_dir = os.path.join(d, tag)
        subprocess.run([pcsim, "fmu", "build", "--out", out_dir, "--case", path, "--fmi-version", "2"], check=True,
                       stdout=subprocess.DEVNULL)
        built[tag] = os.path.join(out_dir, "pcsim_fmu.fmu")
    check("fmu build --case: fmpy validate", not validate_fmu(built["stiff"]), "; ".join(validate_fmu(built["stiff"])))
    with zipfile.ZipFile(built["stiff"]) as z:
        check("fmu build --case: resources/case.toml is the file", z.read("resources/case.toml").decode() == stiff)
    short = signals[signals["time"] <= 1.0]
    run = lambda f, **kw: simulate_fmu(f, stop_time=1.0, step_size=dt, output_interval=dt, input=short,
                                       output=["wire_height"], **kw)["wire_height"]
    base, same, stiff_h = run(fmu), run(built["same"]), run(built["stiff"])
    by_param = run(fmu, start_values={"case": stiff_p})
    check("fmu build --case: the preset's text gives the preset's heights exactly", np.array_equal(base, same))
    inp, out = os.path.join(d, "in.csv"), os.path.join(d, "ref.csv")
    with open(inp, "w") as f:
        f.write("time_s,contact_force_n,position_from_start_m\n")
        for k in range(len(short) - 1):
            f.write(f"{float(short['time'][k])!r},{float(short['contact_force'][k])!r},"
                    f"{float(short['position_from_start'][k])!r}\n")
    subprocess.run([pcsim, "hil", stiff_p, "--window", "215", "--input", inp, "--out", out], check=True,
                   stdout=subprocess.DEVNULL)
    ref = np.loadtxt(out, delimiter=",", skiprows=1, usecols=(1,))
    m = min(len(ref), len(stiff_h) - 1)
    err = float(np.max(np.abs(stiff_h[1:m + 1] - ref[:m])))
    moved = float(np.max(np.abs(stiff_h - base)))
    check("fmu build --case: the bundled case runs as `pcsim hil CASE.toml`", err < 1e-9 and moved > 1e-4,
          f"(max error {err:.1e} m; {moved * 1e3:.2f} mm from the preset's)")
    check("case parameter = a case file's path: the same heights as the bundled one", np.array_equal(by_param, stiff_h))
    windy = subprocess.run([pcsim, "presets", "show", "stitched-2018-like-3d-crosswind"], check=True,
                           capture_output=True, text=True).stdout
    windy_p = os.path.join(d, "windy.toml")
    open(windy_p, "w").write(windy)
    r = subprocess.run([pcsim, "fmu", "build", "--out", os.path.join(d, "windy"), "--case", windy_p],
                       capture_output=True, text=True)
    check("fmu build --case refuses a case the window cannot run, naming it",
          r.returncode == 2 and "--case" in r.stderr and "crosswind" in r.stderr
          and not os.path.exists(os.path.join(d, "windy")), r.stderr[-300:])

# 3e. The pantograph the window follows (issue 41, item 4): a case file whose [run] names
# window_pantograph = "trailing" (the 2018 line, two pantographs 200 m apart), bundled, runs as
# `pcsim hil --preset ... --pantograph trailing`, and not as the leading pantograph's window.
with tempfile.TemporaryDirectory() as d:
    text = subprocess.run([pcsim, "presets", "show", "en50318-2018-like-simple"], check=True,
                          capture_output=True, text=True).stdout
    trailing_p = os.path.join(d, "trailing.toml")
    open(trailing_p, "w").write(text.replace("[run]\n", '[run]\nwindow_pantograph = "trailing"\n', 1))
    out_dir = os.path.join(d, "trailing")
    subprocess.run([pcsim, "fmu", "build", "--out", out_dir, "--case", trailing_p, "--fmi-version", "2"],
                   check=True, stdout=subprocess.DEVNULL)
    short = signals[signals["time"] <= 1.0]
    h = simulate_fmu(os.path.join(out_dir, "pcsim_fmu.fmu"), stop_time=1.0, step_size=dt, output_interval=dt,
                     input=short, output=["wire_height"])["wire_height"]
    inp = os.path.join(d, "in.csv")
    with open(inp, "w") as f:
        f.write("time_s,contact_force_n,position_from_start_m\n")
        for k in range(len(short) - 1):
            f.write(f"{float(short['time'][k])!r},{float(short['contact_force'][k])!r},"
                    f"{float(short['position_from_start'][k])!r}\n")
    refs = {}
    for tag, extra in [("trailing", ["--pantograph", "trailing"]), ("leading", [])]:
        out = os.path.join(d, tag + ".csv")
        subprocess.run([pcsim, "hil", "--preset", "en50318-2018-like-simple", "--window", "215", "--input", inp,
                        "--out", out] + extra, check=True, stdout=subprocess.DEVNULL)
        refs[tag] = np.loadtxt(out, delimiter=",", skiprows=1, usecols=(1,))
    m = min(len(refs["trailing"]), len(h) - 1)
    err = float(np.max(np.abs(h[1:m + 1] - refs["trailing"][:m])))
    other = float(np.max(np.abs(h[1:m + 1] - refs["leading"][:m])))
    check("window_pantograph = \"trailing\" in the bundled case: the FMU runs as `pcsim hil --pantograph trailing`",
          err < 1e-9 and other > 1e-4, f"(max error {err:.1e} m; {other * 1e3:.2f} mm from the leading one's)")

# 4. Misuse suite: each probe in its own process, on the library inside the FMU.
with tempfile.TemporaryDirectory() as d:
    with zipfile.ZipFile(fmu) as z:
        z.extract("binaries/linux64/pcsim_fmu.so", d)
    so = os.path.join(d, "binaries", "linux64", "pcsim_fmu.so")
    probes = ["double_free", "use_after_free", "null", "foreign", "bad_instantiate", "set_output", "param_after_init",
              "get_before_init", "step_after_terminate", "nonfinite_input", "step_contract", "discard_rollback",
              "panic_is_fatal", "independent_instances", "unknown_vr", "position_outside", "position_glitch",
              "discard_logged", "realtime_golden"]
    for p in probes:
        r = subprocess.run([sys.executable, os.path.join(here, "probe.py"), so, p], capture_output=True, text=True)
        crashed = r.returncode < 0
        check(f"misuse probe {p}", r.returncode == 0,
              ("(host crashed: signal %d)" % -r.returncode) if crashed else r.stdout.strip().splitlines()[-1] if r.stdout.strip() else r.stderr[-300:])
    # The FMI 3.0 entry points of the same library.
    for p in ["wrong_state", "pointers", "panic_is_fatal", "states", "realtime_golden"]:
        r = subprocess.run([sys.executable, os.path.join(here, "probe3.py"), so, p], capture_output=True, text=True)
        crashed = r.returncode < 0
        check(f"FMI 3.0 misuse probe {p}", r.returncode == 0,
              ("(host crashed: signal %d)" % -r.returncode) if crashed else (r.stdout + r.stderr).strip()[-300:])

print(f"fmu: {passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
