#!/usr/bin/env python3
"""Time per fmi2DoStep at 1 kHz, driven from a Python loop the way a bench controller uses the FMU.

Usage: bench_fmu.py FMU [STEPS]. Prints the median and percentiles of the time of one
set-inputs + doStep + get-outputs cycle, and of doStep alone.
"""
import shutil
import sys
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

fmu = sys.argv[1]
steps = int(sys.argv[2]) if len(sys.argv) > 2 else 100_000
md = read_model_description(fmu)
vr = {v.name: v.valueReference for v in md.modelVariables}
d = extract(fmu)
slave = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bench")
slave.instantiate()
slave.setupExperiment(startTime=0.0)
slave.enterInitializationMode()
slave.exitInitializationMode()
dt, v = 0.001, 222.0 / 3.6
cycle = np.empty(steps)
dostep = np.empty(steps)
inputs = [vr["contact_force"], vr["position_from_start"]]
outputs = [vr["wire_height"], vr["wire_velocity"]]
for k in range(steps):
    t = k * dt
    t0 = time.perf_counter()
    slave.setReal(inputs, [85.0 + 15.0 * np.sin(7.3 * t), v * t])
    t1 = time.perf_counter()
    slave.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
    t2 = time.perf_counter()
    slave.getReal(outputs)
    t3 = time.perf_counter()
    cycle[k], dostep[k] = t3 - t0, t2 - t1
slave.terminate()
slave.freeInstance()
shutil.rmtree(d, ignore_errors=True)
for name, x in [("fmi2DoStep", dostep), ("set + doStep + get", cycle)]:
    q = np.percentile(x * 1e6, [50, 99, 99.99])
    print(f"{name:>20}: median {q[0]:.2f} µs, p99 {q[1]:.2f} µs, p99.99 {q[2]:.2f} µs, max {x.max() * 1e6:.1f} µs ({steps} steps at 1 kHz)")
