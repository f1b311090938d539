#!/usr/bin/env python3
"""One misuse probe of the pcsim FMU, through ctypes on the shared library (no FMPy guard rails).

Usage: probe.py LIBRARY PROBE. Exits 0 when every call returned its expected status. A crash of
the host shows as a negative return code in the driver (run_fmu_tests.py).
"""
import ctypes as C
import math
import os
import sys

OK, WARNING, DISCARD, ERROR, FATAL = 0, 1, 2, 3, 4
GUID = b"{6b1e4f0a-2c3d-4e5f-8a9b-0c1d2e3f4a5c}"
VR = dict(contact_force=1, position_from_start=2, wire_height=3, wire_velocity=4,
          pantograph_contact_force=5, window_length=6, step_size=7, sil=8, case=9)

lib = C.CDLL(sys.argv[1])
probe = sys.argv[2]
P = C.c_void_p
lib.fmi2Instantiate.restype = P
lib.fmi2Instantiate.argtypes = [C.c_char_p, C.c_int, C.c_char_p, C.c_char_p, P, C.c_int, C.c_int]
lib.fmi2FreeInstance.argtypes = [P]
lib.fmi2FreeInstance.restype = None
for name in ["fmi2EnterInitializationMode", "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset"]:
    getattr(lib, name).argtypes = [P]
lib.fmi2SetupExperiment.argtypes = [P, C.c_int, C.c_double, C.c_double, C.c_int, C.c_double]
lib.fmi2DoStep.argtypes = [P, C.c_double, C.c_double, C.c_int]
lib.fmi2GetReal.argtypes = [P, C.POINTER(C.c_uint), C.c_size_t, C.POINTER(C.c_double)]
lib.fmi2SetReal.argtypes = [P, C.POINTER(C.c_uint), C.c_size_t, C.POINTER(C.c_double)]
lib.fmi2SetBoolean.argtypes = [P, C.POINTER(C.c_uint), C.c_size_t, C.POINTER(C.c_int)]
lib.fmi2SetString.argtypes = [P, C.POINTER(C.c_uint), C.c_size_t, C.POINTER(C.c_char_p)]
lib.fmi2GetString.argtypes = [P, C.POINTER(C.c_uint), C.c_size_t, C.POINTER(C.c_char_p)]
lib.fmi2GetRealStatus.argtypes = [P, C.c_int, C.POINTER(C.c_double)]

failures = []

LOGGER = C.CFUNCTYPE(None, C.c_void_p, C.c_char_p, C.c_int, C.c_char_p, C.c_char_p, C.c_char_p)


class Callbacks(C.Structure):
    _fields_ = [("logger", LOGGER), ("allocate", C.c_void_p), ("free", C.c_void_p),
                ("step_finished", C.c_void_p), ("env", C.c_void_p)]


logged = []


@LOGGER
def log_message(env, name, status, category, fmt, msg):
    logged.append((status, (msg or b"").decode(errors="replace")))


CALLBACKS = Callbacks(log_message, None, None, None, None)


def expect(what, got, want):
    if got != want:
        failures.append(f"{what}: status {got}, expected {want}")


def new(name=b"probe", callbacks=None):
    c = lib.fmi2Instantiate(name, 1, GUID, None, C.cast(C.pointer(callbacks), P) if callbacks else None, 0, 0)
    if not c:
        failures.append("instantiate returned NULL")
    return c


def ready(c):
    expect("setup", lib.fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK)
    expect("enter init", lib.fmi2EnterInitializationMode(c), OK)
    expect("exit init", lib.fmi2ExitInitializationMode(c), OK)


def set_real(c, vr, v):
    return lib.fmi2SetReal(c, (C.c_uint * 1)(vr), 1, (C.c_double * 1)(v))


def get_real(c, vr):
    out = (C.c_double * 1)()
    s = lib.fmi2GetReal(c, (C.c_uint * 1)(vr), 1, out)
    return s, out[0]


def time_of(c):
    t = C.c_double()
    s = lib.fmi2GetRealStatus(c, 2, C.byref(t))
    return s, t.value


if probe == "double_free":
    c = new()
    lib.fmi2FreeInstance(c)
    lib.fmi2FreeInstance(c)  # a no-op
    expect("call after free", lib.fmi2EnterInitializationMode(c), ERROR)
elif probe == "use_after_free":
    c = new()
    ready(c)
    lib.fmi2FreeInstance(c)
    expect("step after free", lib.fmi2DoStep(c, 0.0, 0.001, 1), ERROR)
    expect("get after free", get_real(c, VR["wire_height"])[0], ERROR)
elif probe == "null":
    expect("step NULL", lib.fmi2DoStep(None, 0.0, 0.001, 1), ERROR)
    expect("get NULL", get_real(None, VR["wire_height"])[0], ERROR)
    lib.fmi2FreeInstance(None)
    c = new()
    expect("NULL value array", lib.fmi2GetReal(c, (C.c_uint * 1)(3), 1, None), ERROR)
    lib.fmi2FreeInstance(c)
elif probe == "foreign":
    buf = C.create_string_buffer(4096)
    expect("foreign pointer", lib.fmi2EnterInitializationMode(C.cast(buf, P)), ERROR)
    lib.fmi2FreeInstance(C.cast(buf, P))  # not ours: ignored, no crash
elif probe == "bad_instantiate":
    if lib.fmi2Instantiate(b"x", 1, b"{wrong}", None, None, 0, 0):
        failures.append("wrong GUID accepted")
    if lib.fmi2Instantiate(b"x", 0, GUID, None, None, 0, 0):
        failures.append("model-exchange type accepted")
    if lib.fmi2Instantiate(None, 1, GUID, None, None, 0, 0):
        failures.append("NULL name accepted")
elif probe == "set_output":
    c = new()
    expect("set output before init", set_real(c, VR["wire_height"], 1.0), ERROR)
    ready(c)
    expect("set output", set_real(c, VR["wire_velocity"], 1.0), ERROR)
    lib.fmi2FreeInstance(c)
elif probe == "param_after_init":
    c = new()
    expect("set parameter before init", set_real(c, VR["window_length"], 240.0), OK)
    ready(c)
    expect("set window after init", set_real(c, VR["window_length"], 120.0), ERROR)
    expect("set step after init", set_real(c, VR["step_size"], 0.002), ERROR)
    expect("set sil after init", lib.fmi2SetBoolean(c, (C.c_uint * 1)(VR["sil"]), 1, (C.c_int * 1)(1)), ERROR)
    expect("set case after init", lib.fmi2SetString(c, (C.c_uint * 1)(VR["case"]), 1, (C.c_char_p * 1)(b"en50318-2002")), ERROR)
    s, w = get_real(c, VR["window_length"])
    expect("window kept", (s, w), (OK, 240.0))
    lib.fmi2FreeInstance(c)
elif probe == "get_before_init":
    c = new()
    expect("get output before init", get_real(c, VR["wire_height"])[0], ERROR)
    expect("get parameter before init", get_real(c, VR["window_length"])[0], ERROR)
    lib.fmi2FreeInstance(c)
elif probe == "step_after_terminate":
    c = new()
    ready(c)
    expect("step", lib.fmi2DoStep(c, 0.0, 0.001, 1), OK)
    expect("terminate", lib.fmi2Terminate(c), OK)
    expect("step after terminate", lib.fmi2DoStep(c, 0.001, 0.001, 1), ERROR)
    expect("set input after terminate", set_real(c, VR["contact_force"], 1.0), ERROR)
    lib.fmi2FreeInstance(c)
elif probe == "nonfinite_input":
    c = new()
    ready(c)
    for v in [math.nan, math.inf, -math.inf]:
        expect(f"set contact_force={v}", set_real(c, VR["contact_force"], v), ERROR)
        expect(f"set position={v}", set_real(c, VR["position_from_start"], v), ERROR)
    expect("force unchanged", get_real(c, VR["contact_force"]), (OK, 0.0))
    lib.fmi2FreeInstance(c)
elif probe == "step_contract":
    c = new()
    ready(c)
    expect("wrong communication point", lib.fmi2DoStep(c, 0.5, 0.001, 1), ERROR)
    for h in [0.0, -0.001, math.nan, math.inf, 0.0015, 1000.0]:
        expect(f"step h={h}", lib.fmi2DoStep(c, 0.0, h, 1), ERROR)
    expect("valid step", lib.fmi2DoStep(c, 0.0, 0.002, 1), OK)
    expect("time", time_of(c), (OK, 0.002))
    expect("next point", lib.fmi2DoStep(c, 0.002, 0.001, 1), OK)
    lib.fmi2FreeInstance(c)
elif probe == "discard_rollback":
    c = new()
    ready(c)
    expect("set force", set_real(c, VR["contact_force"], 85.0), OK)
    expect("step", lib.fmi2DoStep(c, 0.0, 0.01, 1), OK)
    h0 = get_real(c, VR["wire_height"])
    expect("absurd force", set_real(c, VR["contact_force"], 1e9), OK)
    expect("absurd force refused", lib.fmi2DoStep(c, 0.01, 0.01, 1), DISCARD)
    expect("time rolled back", time_of(c), (OK, 0.01))
    expect("outputs rolled back", get_real(c, VR["wire_height"]), h0)
    expect("sane force", set_real(c, VR["contact_force"], 85.0), OK)
    expect("step again", lib.fmi2DoStep(c, 0.01, 0.01, 1), OK)
    s, h = get_real(c, VR["wire_height"])
    if not (s == OK and math.isfinite(h) and abs(h) < 0.5):
        failures.append(f"after the roll-back the height is {h}")
    lib.fmi2FreeInstance(c)
elif probe == "panic_is_fatal":
    os.environ["PCSIM_FMU_TEST_PANIC"] = "1"
    c = new()
    expect("panic inside", set_real(c, 0xFFFFFFF0, 1.0), FATAL)
    expect("unusable after fatal", lib.fmi2EnterInitializationMode(c), ERROR)
    lib.fmi2FreeInstance(c)
    c2 = new()
    ready(c2)
    expect("a new instance still works", lib.fmi2DoStep(c2, 0.0, 0.001, 1), OK)
    lib.fmi2FreeInstance(c2)
elif probe == "independent_instances":
    a, b, ref = new(b"a"), new(b"b"), new(b"ref")
    for c in (a, b, ref):
        ready(c)
    expect("force on a", set_real(a, VR["contact_force"], 400.0), OK)
    expect("force on b", set_real(b, VR["contact_force"], 85.0), OK)
    expect("force on ref", set_real(ref, VR["contact_force"], 85.0), OK)
    t = 0.0
    for _ in range(200):
        for c in (a, b, ref):
            expect("step", lib.fmi2DoStep(c, t, 0.001, 1), OK)
        t = round(t + 0.001, 9)
    hb, hr, ha = get_real(b, 3)[1], get_real(ref, 3)[1], get_real(a, 3)[1]
    if hb != hr:
        failures.append(f"instance b ({hb}) differs from an identical fresh instance ({hr})")
    if ha == hb:
        failures.append("instance a did not respond to its own input")
    s = (C.c_char_p * 1)()
    expect("get case", lib.fmi2GetString(b, (C.c_uint * 1)(VR["case"]), 1, s), OK)
    if s[0] != b"syt-7.0-9.8":
        failures.append(f"case string {s[0]!r}")
    for c in (a, b, ref):
        lib.fmi2FreeInstance(c)
elif probe == "position_outside":
    # The SYT case starts at 60 m on an 1800 m model: -100 m and 1910 m lie outside it.
    for pos in [-160.0, 1850.0]:
        c = new()
        ready(c)
        expect("step inside", lib.fmi2DoStep(c, 0.0, 0.001, 1), OK)
        expect("set position", set_real(c, VR["position_from_start"], pos), OK)
        expect(f"step at {pos + 60.0} m", lib.fmi2DoStep(c, 0.001, 0.001, 1), DISCARD)
        expect("time unchanged", time_of(c), (OK, 0.001))
        lib.fmi2FreeInstance(c)
elif probe == "position_glitch":
    # A one-sample glitch to 1700 m and back is refused and leaves no trace.
    a, ref = new(b"a"), new(b"ref")
    ready(a)
    ready(ref)
    v, t = 222.0 / 3.6, 0.0
    for k in range(300):
        x = v * t
        for c in (a, ref):
            expect("force", set_real(c, VR["contact_force"], 85.0 + 10.0 * math.sin(7.0 * t)), OK)
            expect("position", set_real(c, VR["position_from_start"], x), OK)
        if k == 100:
            expect("glitch set", set_real(a, VR["position_from_start"], 1700.0 - 60.0), OK)
            expect("glitch step refused", lib.fmi2DoStep(a, t, 0.001, 1), DISCARD)
            expect("back", set_real(a, VR["position_from_start"], x), OK)
        for c in (a, ref):
            expect("step", lib.fmi2DoStep(c, t, 0.001, 1), OK)
        t = round(t + 0.001, 9)
    ha, hr = get_real(a, VR["wire_height"])[1], get_real(ref, VR["wire_height"])[1]
    if ha != hr:
        failures.append(f"the refused glitch changed the response: {ha} vs {hr}")
    lib.fmi2FreeInstance(a)
    lib.fmi2FreeInstance(ref)
elif probe == "discard_logged":
    c = new(callbacks=CALLBACKS)
    ready(c)
    expect("set position", set_real(c, VR["position_from_start"], -500.0), OK)
    expect("step refused", lib.fmi2DoStep(c, 0.0, 0.001, 1), DISCARD)
    if not any(st == DISCARD and "outside" in m for st, m in logged):
        failures.append(f"the Discard was not logged with its reason: {logged}")
    expect("absurd force", set_real(c, VR["contact_force"], 1e9), OK)
    expect("position back", set_real(c, VR["position_from_start"], 0.0), OK)
    expect("absurd force refused", lib.fmi2DoStep(c, 0.0, 0.01, 1), DISCARD)
    if not any(st == DISCARD and "force_out_of_bound" in m for st, m in logged):
        failures.append(f"the refusal of the force was not logged with its reason: {logged}")
    lib.fmi2FreeInstance(c)
elif probe == "unknown_vr":
    c = new()
    ready(c)
    expect("unknown vr", get_real(c, 77)[0], ERROR)
    expect("bad case name", lib.fmi2SetString(c, (C.c_uint * 1)(VR["case"]), 1, (C.c_char_p * 1)(b"x")), ERROR)
    lib.fmi2FreeInstance(c)
elif probe == "realtime_golden":
    # Issue 18: the scripted input of data/golden/realtime gives the core session's statuses and,
    # bit for bit, its outputs. A non-finite input is refused when it is set (Error, with the
    # reason's code) and that row is not stepped; every other refusal is a logged Discard.
    import csv
    import re
    import struct
    g = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data", "golden", "realtime")
    script = list(csv.reader(open(os.path.join(g, "script.csv"))))[1:]
    want = list(csv.reader(open(os.path.join(g, "expected.csv"))))[1:]
    c = new(callbacks=CALLBACKS)
    ready(c)
    t, dt = 0.0, 0.001
    bits = lambda v: struct.pack("<d", v)
    for row, w in zip(script, want):
        del logged[:]
        sf = set_real(c, VR["contact_force"], float(row[1]))
        sp = set_real(c, VR["position_from_start"], float(row[2]))
        if sf != OK or sp != OK:
            codes = re.findall(r"\((\w+)\)", " ".join(m for _, m in logged))
            got = codes[0] if codes else f"set status {sf}/{sp}"
        else:
            st = lib.fmi2DoStep(c, t, dt, 1)
            if st == OK:
                t = round((t + dt) * 1e9) / 1e9
                got = "ok"
                (s1, h), (s2, v) = get_real(c, VR["wire_height"]), get_real(c, VR["wire_velocity"])
                if w[1] == "ok" and (bits(h) != bits(float(w[3])) or bits(v) != bits(float(w[4]))):
                    failures.append(f"row {w[0]}: height {h!r} velocity {v!r}, golden {w[3]} {w[4]}")
                    break
            else:
                codes = re.findall(r"\((\w+)\)", " ".join(m for _, m in logged))
                got = codes[0] if st == DISCARD and codes else f"step status {st}"
        if got != w[1]:
            failures.append(f"row {w[0]}: {got}, golden {w[1]}")
            break
    lib.fmi2FreeInstance(c)
    if not failures:
        print("FMI 2.0 on the real-time golden: 4000 rows, statuses and outputs identical")
else:
    print(f"unknown probe {probe}")
    sys.exit(2)

if failures:
    print(f"{probe}: " + "; ".join(failures))
    sys.exit(1)
print(f"{probe}: ok")
