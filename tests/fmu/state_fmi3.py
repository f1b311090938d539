#!/usr/bin/env python3
"""FMI 3.0 and FMU-state checks run by .ci/run (FMPy):

- fmpy validate on the FMI 3.0 FMU; fmpy simulate of FMI 3.0 against FMI 2.0 to 1e-12;
- state round trip in both: step 1 s, save, step 1 s (A), restore, step 1 s (B): A == B bit for
  bit; serialise, free, a new instance, de-serialise, step: again equal; a state of another
  window is refused;
- 10 000 instantiate/initialise/free cycles in one process with bounded memory (RSS);
- 4 instances stepping in 4 threads give the same bytes as serial runs.

Usage: state_fmi3.py FMI2_FMU FMI3_FMU
"""
import os
import sys
import tempfile
import threading

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

# Absolute paths: FMPy changes the working directory while it loads a library, which races with
# a relative path opened in another thread.
fmu2, fmu3 = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
passed, failed = 0, 0


def check(name, ok, detail=""):
    global passed, failed
    passed, failed = (passed + 1, failed) if ok else (passed, failed + 1)
    print(f"{'ok  ' if ok else 'FAIL'} {name} {detail}")


problems = validate_fmu(fmu3)
check("fmpy validate (FMI 3.0)", not problems, "; ".join(problems))

dt, stop = 0.001, 3.0
t = np.round(np.arange(0.0, stop + dt / 2, dt), 9)
sig = np.zeros(len(t), dtype=[("time", np.float64), ("contact_force", np.float64), ("position_from_start", np.float64)])
sig["time"], sig["contact_force"], sig["position_from_start"] = (
    t, 85.0 + 20.0 * np.sin(2 * np.pi * 1.3 * t), 222.0 / 3.6 * t)
out = ["wire_height", "wire_velocity", "pantograph_contact_force"]
r2 = simulate_fmu(fmu2, stop_time=stop, step_size=dt, output_interval=dt, input=sig, output=out)
r3 = simulate_fmu(fmu3, stop_time=stop, step_size=dt, output_interval=dt, input=sig, output=out)
err = max(float(np.max(np.abs(r2[k] - r3[k]))) for k in out)
check("fmpy simulate: FMI 3.0 equals FMI 2.0 within 1e-12", len(r2) == len(r3) and err <= 1e-12
      and float(np.ptp(r3["wire_height"])) > 1e-3, f"(largest difference {err:.1e})")


_unpacked = {}


def unpacked(path):
    """The model description and the unzipped directory of an FMU, read once (main thread)."""
    if path not in _unpacked:
        _unpacked[path] = (read_model_description(path), extract(path))
    return _unpacked[path]


def slave(path, version, name="s", window=None):
    md, d = unpacked(path)
    cls = FMU2Slave if version == 2 else FMU3Slave
    s = cls(guid=md.guid, unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    s.instantiate()
    vr = {v.name: v.valueReference for v in md.modelVariables}
    if window is not None:
        (s.setReal if version == 2 else s.setFloat64)([vr["window_length"]], [window])
    if version == 2:
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
    else:
        s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    return s, vr


def steps(s, vr, version, k0, n, phase=0.0):
    setv = s.setReal if version == 2 else s.setFloat64
    getv = s.getReal if version == 2 else s.getFloat64
    hs = []
    for k in range(k0, k0 + n):
        tt = k * dt
        setv([vr["contact_force"], vr["position_from_start"]],
             [90.0 + 15.0 * np.sin(7.3 * tt + phase), 222.0 / 3.6 * (tt + dt)])
        s.doStep(tt, dt)
        hs.append(getv([vr["wire_height"], vr["wire_velocity"]]))
    return np.array(hs)


for version, path in ((2, fmu2), (3, fmu3)):
    s, vr = slave(path, version)
    steps(s, vr, version, 0, 1000)
    st = s.getFMUstate() if version == 2 else s.getFMUState()
    a = steps(s, vr, version, 1000, 1000)
    (s.setFMUstate if version == 2 else s.setFMUState)(st)
    b = steps(s, vr, version, 1000, 1000)
    check(f"FMI {version}.0 state: restore continues bit for bit", a.tobytes() == b.tobytes())
    blob = s.serializeFMUstate(st) if version == 2 else s.serializeFMUState(st)
    (s.freeFMUstate if version == 2 else s.freeFMUState)(st)
    s.terminate()
    s.freeInstance()
    s2, vr2 = slave(path, version, "s2")
    st2 = s2.deSerializeFMUstate(blob) if version == 2 else s2.deserializeFMUState(blob)
    (s2.setFMUstate if version == 2 else s2.setFMUState)(st2)
    c = steps(s2, vr2, version, 1000, 1000)
    check(f"FMI {version}.0 state: serialised, de-serialised in a new instance, bit for bit",
          a.tobytes() == c.tobytes(), f"({len(blob)} bytes)")
    s2.terminate()
    s2.freeInstance()
    s3, _ = slave(path, version, "s3", window=240.0)
    try:
        s3.deSerializeFMUstate(blob) if version == 2 else s3.deserializeFMUState(blob)
        refused = False
    except Exception:
        refused = True
    check(f"FMI {version}.0 state: a state of another window is refused", refused)
    s3.freeInstance()


def rss_kib():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4


md = read_model_description(fmu2)
d = extract(fmu2)
before = None
for i in range(10000):
    s = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier="pcsim_fmu", instanceName=f"i{i}")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    s.terminate()
    s.freeInstance()
    if i == 999:
        before = rss_kib()
after = rss_kib()
check("10 000 instantiate/initialise/free cycles: memory bounded", after < before + 16 * 1024,
      f"(RSS {before} kB after 1000, {after} kB after 10 000)")

serial = []
for i in range(4):
    s, vr = slave(fmu3, 3, f"serial{i}")
    serial.append(steps(s, vr, 3, 0, 2000, phase=float(i)).tobytes())
    s.freeInstance()
threaded = [None] * 4


def work(i):
    s, vr = slave(fmu3, 3, f"thread{i}")
    threaded[i] = steps(s, vr, 3, 0, 2000, phase=float(i)).tobytes()
    s.freeInstance()


ts = [threading.Thread(target=work, args=(i,)) for i in range(4)]
for th in ts:
    th.start()
for th in ts:
    th.join()
check("4 instances in 4 threads equal serial runs bit for bit", threaded == serial)

print(f"fmu (FMI 3.0, states, soak, threads): {passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
