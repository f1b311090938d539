#!/usr/bin/env python3
"""The FMI 3.0 misuse suite of the pcsim FMU, through ctypes on the shared library (no FMPy guard
rails): calls in the wrong state give Error, a panic gives Fatal and the host survives, NULL,
foreign and freed pointers give Error, a wrong token or event mode gives no instance, states are
checked. Each probe runs in its own process (a crash shows as a negative return code).

Usage: probe3.py LIBRARY PROBE"""
import ctypes as C
import os
import sys

OK, WARNING, DISCARD, ERROR, FATAL = 0, 1, 2, 3, 4
TOKEN = b"{6b1e4f0a-2c3d-4e5f-8a9b-0c1d2e3f4a5c}"
VR_FORCE, VR_POS, VR_HEIGHT, VR_WINDOW = 1, 2, 3, 6
TEST_PANIC_VR = 0xFFFFFFF0

lib = C.CDLL(sys.argv[1])
probe = sys.argv[2]
P = C.c_void_p
B = C.c_bool
LOG = C.CFUNCTYPE(None, C.c_void_p, C.c_int, C.c_char_p, C.c_char_p)
lib.fmi3InstantiateCoSimulation.restype = P
lib.fmi3InstantiateCoSimulation.argtypes = [C.c_char_p, C.c_char_p, C.c_char_p, B, B, B, B, P, C.c_size_t, P, LOG, P]
lib.fmi3FreeInstance.argtypes = [P]
lib.fmi3FreeInstance.restype = None
for n in ["fmi3ExitInitializationMode", "fmi3Terminate", "fmi3Reset", "fmi3EnterEventMode", "fmi3EnterStepMode",
          "fmi3EnterConfigurationMode", "fmi3EvaluateDiscreteStates"]:
    getattr(lib, n).argtypes = [P]
lib.fmi3EnterInitializationMode.argtypes = [P, B, C.c_double, C.c_double, B, C.c_double]
lib.fmi3DoStep.argtypes = [P, C.c_double, C.c_double, B, C.POINTER(B), C.POINTER(B), C.POINTER(B), C.POINTER(C.c_double)]
lib.fmi3SetFloat64.argtypes = [P, C.POINTER(C.c_uint32), C.c_size_t, C.POINTER(C.c_double), C.c_size_t]
lib.fmi3GetFloat64.argtypes = [P, C.POINTER(C.c_uint32), C.c_size_t, C.POINTER(C.c_double), C.c_size_t]
lib.fmi3GetInt32.argtypes = [P, C.POINTER(C.c_uint32), C.c_size_t, C.POINTER(C.c_int32), C.c_size_t]
lib.fmi3GetFMUState.argtypes = [P, C.POINTER(P)]
lib.fmi3SetFMUState.argtypes = [P, P]
lib.fmi3FreeFMUState.argtypes = [P, C.POINTER(P)]
lib.fmi3DeserializeFMUState.argtypes = [P, C.POINTER(C.c_uint8), C.c_size_t, C.POINTER(P)]

logged = []


@LOG
def log_message(env, status, category, message):
    logged.append((status, (message or b"").decode(errors="replace")))


failures = []


def expect(what, got, want):
    if got != want:
        failures.append(f"{what}: status {got}, expected {want}")


def new(token=TOKEN, event_mode=False):
    return lib.fmi3InstantiateCoSimulation(b"probe3", token, None, False, False, event_mode, False, None, 0, None,
                                           log_message, None)


def init(c):
    expect("enter init", lib.fmi3EnterInitializationMode(c, False, 0.0, 0.0, False, 0.0), OK)
    expect("exit init", lib.fmi3ExitInitializationMode(c), OK)


def set_f64(c, vr, v):
    return lib.fmi3SetFloat64(c, (C.c_uint32 * 1)(vr), 1, (C.c_double * 1)(v), 1)


def step(c, t, h=0.001):
    a, b, e, last = B(), B(), B(), C.c_double()
    return lib.fmi3DoStep(c, t, h, True, C.byref(a), C.byref(b), C.byref(e), C.byref(last))


if probe == "wrong_state":
    c = new()
    expect("DoStep before init", step(c, 0.0), ERROR)
    expect("ExitInitializationMode before Enter", lib.fmi3ExitInitializationMode(c), ERROR)
    s = P()
    expect("GetFMUState before init", lib.fmi3GetFMUState(c, C.byref(s)), ERROR)
    expect("EnterStepMode before init", lib.fmi3EnterStepMode(c), ERROR)
    expect("EnterEventMode (no event mode)", lib.fmi3EnterEventMode(c), ERROR)
    expect("EnterConfigurationMode", lib.fmi3EnterConfigurationMode(c), ERROR)
    expect("EvaluateDiscreteStates", lib.fmi3EvaluateDiscreteStates(c), ERROR)
    init(c)
    expect("set a parameter after init", set_f64(c, VR_WINDOW, 100.0), ERROR)
    expect("set an output", set_f64(c, VR_HEIGHT, 1.0), ERROR)
    expect("GetInt32 (no such type)", lib.fmi3GetInt32(c, (C.c_uint32 * 1)(1), 1, (C.c_int32 * 1)(), 1), ERROR)
    expect("DoStep at the wrong time", step(c, 5.0), ERROR)
    expect("DoStep by a fraction of the internal step", step(c, 0.0, 0.0005), ERROR)
    expect("Terminate", lib.fmi3Terminate(c), OK)
    expect("DoStep after Terminate", step(c, 0.0), ERROR)
    lib.fmi3FreeInstance(c)
elif probe == "pointers":
    expect("NULL instance", lib.fmi3Terminate(None), ERROR)
    foreign = C.c_uint64(7)
    expect("foreign instance", lib.fmi3Terminate(C.cast(C.pointer(foreign), P)), ERROR)
    c = new()
    lib.fmi3FreeInstance(c)
    lib.fmi3FreeInstance(c)  # a repeated free is a no-op
    expect("freed instance", lib.fmi3Terminate(c), ERROR)
    if new(token=b"{wrong}"):
        failures.append("a wrong instantiation token gave an instance")
    if new(event_mode=True):
        failures.append("eventModeUsed gave an instance (the FMU has no event mode)")
elif probe == "panic_is_fatal":
    os.environ["PCSIM_FMU_TEST_PANIC"] = "1"
    c = new()
    expect("the panicking set", set_f64(c, TEST_PANIC_VR, 1.0), FATAL)
    expect("any call after Fatal", lib.fmi3Terminate(c), ERROR)
    if not any(s == FATAL for s, _ in logged):
        failures.append("the panic was not logged as Fatal")
    lib.fmi3FreeInstance(c)
elif probe == "states":
    c = new()
    init(c)
    s = P()
    expect("GetFMUState", lib.fmi3GetFMUState(c, C.byref(s)), OK)
    other = new()
    init(other)
    expect("a state of another instance", lib.fmi3SetFMUState(other, s), ERROR)
    junk = (C.c_uint8 * 64)()
    t = P()
    expect("a junk serialised state", lib.fmi3DeserializeFMUState(c, junk, 64, C.byref(t)), ERROR)
    expect("FreeFMUState", lib.fmi3FreeFMUState(c, C.byref(s)), OK)
    if s.value:
        failures.append("FreeFMUState did not set the pointer to NULL")
    s2 = C.c_void_p(12345)
    expect("free a foreign state", lib.fmi3FreeFMUState(c, C.byref(s2)), ERROR)
    lib.fmi3FreeInstance(other)
    lib.fmi3FreeInstance(c)
elif probe == "realtime_golden":
    # Issue 18: the scripted input of data/golden/realtime through the FMI 3.0 entry points gives
    # the core session's statuses and, bit for bit, its outputs (as probe.py for FMI 2.0).
    import csv
    import re
    import struct
    g = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data", "golden", "realtime")
    script = list(csv.reader(open(os.path.join(g, "script.csv"))))[1:]
    want = list(csv.reader(open(os.path.join(g, "expected.csv"))))[1:]
    c = new()
    init(c)
    t, dt = 0.0, 0.001
    bits = lambda v: struct.pack("<d", v)
    out = (C.c_double * 2)()
    for row, w in zip(script, want):
        del logged[:]
        sf, sp = set_f64(c, VR_FORCE, float(row[1])), set_f64(c, VR_POS, float(row[2]))
        if sf != OK or sp != OK:
            codes = re.findall(r"\((\w+)\)", " ".join(m for _, m in logged))
            got = codes[0] if codes else f"set status {sf}/{sp}"
        else:
            st = step(c, t, dt)
            if st == OK:
                t = round((t + dt) * 1e9) / 1e9
                got = "ok"
                lib.fmi3GetFloat64(c, (C.c_uint32 * 2)(VR_HEIGHT, 4), 2, out, 2)
                if w[1] == "ok" and (bits(out[0]) != bits(float(w[3])) or bits(out[1]) != bits(float(w[4]))):
                    failures.append(f"row {w[0]}: height {out[0]!r} velocity {out[1]!r}, golden {w[3]} {w[4]}")
                    break
            else:
                codes = re.findall(r"\((\w+)\)", " ".join(m for _, m in logged))
                got = codes[0] if st == DISCARD and codes else f"step status {st}"
        if got != w[1]:
            failures.append(f"row {w[0]}: {got}, golden {w[1]}")
            break
    lib.fmi3FreeInstance(c)
    if not failures:
        print("FMI 3.0 on the real-time golden: 4000 rows, statuses and outputs identical")
else:
    sys.exit(f"unknown probe {probe}")

if failures:
    print("; ".join(failures))
    sys.exit(1)
print(f"{probe}: ok")
