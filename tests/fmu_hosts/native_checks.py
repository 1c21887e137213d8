"""Misuse and bad-input cases of the native FMU, each in its own instance, through fmpy.

``python -m fmu_hosts.native_checks FMU CASE [CASE ...]`` prints one JSON object: per case the
statuses of the calls (0 ok, 1 warning, 2 discard, 3 error, 4 fatal), the messages the
logger received and whether a good call afterwards worked. Run it in a fresh process.
"""
from __future__ import annotations

import ctypes
import json
import math
import sys
import time

from fmu.hosts import Instance, call_status

REPEAT = 10


def _set_real(inst, name: str, value: float) -> int:
    """``fmi2SetReal`` of one value with its raw status (fmpy hides fmi2Warning)."""
    vr, v = (ctypes.c_uint * 1)(inst.vr[name]), (ctypes.c_double * 1)(value)
    return inst.slave.dll.fmi2SetReal(inst.slave.component, vr, ctypes.c_size_t(1), v)


def _setup(fmu: str, unzipdir: str, name: str, strings: dict | None = None, reals: dict | None = None):
    inst = Instance(fmu, name, unzipdir=unzipdir)
    inst.initialise(reals=reals, strings=strings)
    return inst


def _dt(inst) -> float:
    return float(inst.md.defaultExperiment.stepSize)


def case_unknown_vr(fmu, unzipdir) -> dict:
    """Unknown value references and a wrong type, ten times, then good calls."""
    inst = _setup(fmu, unzipdir, "unknown_vr")
    s = inst.slave
    statuses = [[call_status(s.getReal, [999]), call_status(s.setReal, [999], [1.0]), call_status(s.getString, [0]),
                 call_status(s.getInteger, [0])] for _ in range(REPEAT)]
    return {"statuses": statuses, "good_get": call_status(s.getReal, [inst.vr["blade1.flap"]]),
            "good_step": inst.step(0.0, _dt(inst)), "messages": inst.messages}


def case_step_before_init(fmu, unzipdir) -> dict:
    """doStep before exitInitializationMode, ten times, then the right order."""
    inst = Instance(fmu, "early", unzipdir=unzipdir)
    s, dt = inst.slave, _dt(inst)
    s.setupExperiment(startTime=0.0)
    early = [inst.step(0.0, dt)]
    s.enterInitializationMode()
    early += [inst.step(0.0, dt) for _ in range(REPEAT)]
    early.append(call_status(s.enterInitializationMode))
    s.exitInitializationMode()
    return {"statuses": early, "good_step": inst.step(0.0, dt), "messages": inst.messages}


def case_bad_parameter(fmu, unzipdir) -> dict:
    """exitInitializationMode with omega out of range (ten times), then a good omega."""
    inst = Instance(fmu, "bad_parameter", unzipdir=unzipdir)
    s = inst.slave
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    set_status = _set_real(inst, "omega", 1000.0)
    exits = [call_status(s.exitInitializationMode) for _ in range(REPEAT)]
    s.setReal([inst.vr["omega"]], [40.0])
    return {"set": set_status, "statuses": exits, "good_exit": call_status(s.exitInitializationMode),
            "good_step": inst.step(0.0, _dt(inst)), "messages": inst.messages}


def _deserialize(inst, blob: bytes) -> int:
    return call_status(inst.slave.deSerializeFMUstate, blob)


def case_corrupt_state(fmu, unzipdir) -> dict:
    """Damaged serialized states (flipped byte, truncated, foreign magic), ten rounds each."""
    inst = _setup(fmu, unzipdir, "corrupt")
    dt = _dt(inst)
    inst.step(0.0, dt)
    blob = inst.save()
    flipped = bytearray(blob)
    flipped[len(blob) // 2] ^= 0x5A
    foreign = b"NOTHELI!" + blob[8:]
    statuses = [[_deserialize(inst, bytes(flipped)), _deserialize(inst, blob[:-100]), _deserialize(inst, foreign)]
                for _ in range(REPEAT)]
    inst.step(dt, dt)
    after = inst.get(["blade1.flap"])
    inst.restore(blob)
    return {"statuses": statuses, "good_step": inst.step(dt, dt), "after_restore": inst.get(["blade1.flap"]),
            "continued": after, "size": len(blob), "messages": inst.messages}


def _real_starts(inst) -> dict:
    return {v.name: float(v.start) for v in inst.md.modelVariables
            if v.causality in ("input", "parameter") and v.type == "Real"}


def _in_initialisation(fmu, unzipdir, name: str, reals: dict, strings: dict):
    """An instance in initialization mode with ``reals`` and ``strings`` set; returns it and
    the status of the setting."""
    inst = Instance(fmu, name, unzipdir=unzipdir)
    inst.slave.setupExperiment(startTime=0.0)
    inst.slave.enterInitializationMode()
    return inst, call_status(inst.set, reals, strings)


def case_start_values(fmu, unzipdir) -> dict:
    """Scene ground-run with every XML start value applied and with none: the same values are in use
    either way, so both refuse forward flight's initial_forward_speed = 10 m/s (ground-run has no
    free fuselage) until it is set to 0; then both step alike."""
    applied, _ = _in_initialisation(fmu, unzipdir, "applied", {}, {})
    starts = _real_starts(applied)
    set_status = call_status(applied.set, starts, {"scene": "ground-run"})
    plain, _ = _in_initialisation(fmu, unzipdir, "plain", {}, {"scene": "ground-run"})
    outputs = [v.name for v in applied.md.modelVariables if v.causality == "output"]
    names = outputs + list(starts)
    before = [applied.get(names), plain.get(names)]
    exits = [call_status(applied.slave.exitInitializationMode), call_status(plain.slave.exitInitializationMode)]
    for inst in (applied, plain):
        inst.set({"initial_forward_speed": 0.0})
        exits.append(call_status(inst.slave.exitInitializationMode))
    dt = _dt(applied)
    steps = [applied.step(0.0, dt), plain.step(0.0, dt)]
    return {"set": set_status, "exits": exits, "steps": steps, "names": names, "starts": starts,
            "before": before, "after": [applied.get(outputs), plain.get(outputs)],
            "messages": applied.messages + plain.messages}


def case_huge_steps(fmu, unzipdir) -> dict:
    """Communication steps of 1e16 s and 1e4 s: refused at once, then a good step."""
    inst = _setup(fmu, unzipdir, "huge")
    out = {}
    for h in (1e16, 1e4):
        start = time.perf_counter()
        out[repr(h)] = [inst.step(0.0, h), time.perf_counter() - start]
    return {**out, "good_step": inst.step(0.0, _dt(inst)), "messages": inst.messages}


def case_max_step(fmu, unzipdir) -> dict:
    """max_step below its range, and small but allowed (many sub-steps), then back."""
    inst = _setup(fmu, unzipdir, "max_step")
    dt = _dt(inst)
    tiny = [_set_real(inst, "max_step", 1e-9), inst.step(0.0, dt)]
    small = [_set_real(inst, "max_step", 1e-6), inst.step(0.0, dt), inst.step(dt, 2000 * dt)]
    _set_real(inst, "max_step", dt / 3)
    return {"tiny": tiny, "small": small, "good_step": inst.step(dt, dt), "messages": inst.messages}


def case_diverging(fmu, unzipdir) -> dict:
    """Hover at the largest max_step, fastest rotor and full collective: within every range,
    yet the teeter angle leaves +-pi/2 after about 150 steps; also max_step beyond its range."""
    reals = {"max_step": 0.012, "omega": 53.3, "collective": 0.412}
    inst = _setup(fmu, unzipdir, "diverging", strings={"scene": "hover"}, reals=reals)
    t, status, k = 0.0, 0, 0
    for k in range(400):
        status = inst.step(t, 0.012)
        if status:
            break
        t += 0.012
    held = inst.get(["seesaw.teeter", "blade1.flap"])
    again = inst.step(t, 0.012)
    beyond = _setup(fmu, unzipdir, "beyond")
    set_beyond = _set_real(beyond, "max_step", 0.05)
    return {"status": status, "steps": k, "t": t, "held": held, "again": again, "set_beyond": set_beyond,
            "beyond": beyond.step(0.0, 0.5), "messages": inst.messages + beyond.messages}


def case_nan_input(fmu, unzipdir) -> dict:
    inst = _setup(fmu, unzipdir, "nan")
    dt = _dt(inst)
    first = inst.step(0.0, dt)
    statuses = [_set_real(inst, "collective", math.nan), inst.step(dt, dt), _set_real(inst, "collective", 0.9),
                inst.step(dt, dt)]
    _set_real(inst, "collective", 0.25)
    return {"first": first, "statuses": statuses, "good_step": inst.step(dt, dt), "messages": inst.messages}


def case_set_output(fmu, unzipdir) -> dict:
    inst = _setup(fmu, unzipdir, "output")
    s = inst.slave
    statuses = [call_status(s.setReal, [inst.vr["blade1.flap"]], [0.1]), call_status(s.setReal, [inst.vr["fuselage.qw"]], [1.0])]
    return {"statuses": statuses, "good_step": inst.step(0.0, _dt(inst)), "messages": inst.messages}


def _steps(inst, t: float, n: int) -> list[float]:
    dt = _dt(inst)
    for k in range(n):
        inst.step(t + k * dt, dt)
    return inst.get(["blade1.flap", "seesaw.teeter", "total_energy"])


def _status_queries(inst) -> list[int]:
    dll, c = inst.slave.dll, inst.slave.component
    status, real, boolean = ctypes.c_int(), ctypes.c_double(), ctypes.c_int()
    return [dll.fmi2GetStatus(c, 0, ctypes.byref(status)), dll.fmi2GetRealStatus(c, 2, ctypes.byref(real)),
            dll.fmi2GetBooleanStatus(c, 3, ctypes.byref(boolean))]


def case_life_cycle(fmu, unzipdir) -> dict:
    """Terminate (then stepping is an error), reset and run again, roll back with an FMU state."""
    inst = _setup(fmu, unzipdir, "life_cycle")
    dt = _dt(inst)
    state = inst.slave.getFMUstate()
    first = _steps(inst, 0.0, 20)
    queries = _status_queries(inst)
    inst.slave.setFMUstate(state)
    rolled_back = _steps(inst, 0.0, 20)
    inst.slave.freeFMUstate(state)
    inst.slave.terminate()
    after_terminate = [inst.step(20 * dt, dt), call_status(inst.slave.setReal, [inst.vr["collective"]], [0.3])]
    reset = call_status(inst.slave.reset)
    inst.initialise()
    return {"first": first, "rolled_back": rolled_back, "after_terminate": after_terminate, "reset": reset,
            "rerun": _steps(inst, 0.0, 20), "status_queries": queries, "messages": inst.messages}


def case_no_instance(fmu, unzipdir) -> dict:
    """Calls with a NULL instance and an instance without callbacks: errors, no crash."""
    inst = Instance(fmu, "lib", unzipdir=unzipdir)
    dll = inst.slave.dll
    state = ctypes.c_void_p()
    null_calls = [dll.fmi2GetFMUstate(None, ctypes.byref(state)), dll.fmi2DoStep(None, ctypes.c_double(0.0),
                                                                                 ctypes.c_double(1e-3), 1)]
    dll.fmi2Instantiate.restype = ctypes.c_void_p
    bare = dll.fmi2Instantiate(b"bare", 1, inst.md.guid.encode(), b"", None, 0, 0)
    vr = (ctypes.c_uint * 1)(999)
    value = (ctypes.c_double * 1)(0.0)
    bare_calls = [dll.fmi2GetReal(ctypes.c_void_p(bare), vr, ctypes.c_size_t(1), value),
                  dll.fmi2DoStep(ctypes.c_void_p(bare), ctypes.c_double(0.0), ctypes.c_double(1e-3), 1)]
    dll.fmi2FreeInstance(ctypes.c_void_p(bare))
    wrong_guid = dll.fmi2Instantiate(b"wrong", 1, b"{not-this-one}", b"", None, 0, 0)
    return {"null_calls": null_calls, "bare": bool(bare), "bare_calls": bare_calls, "wrong_guid": wrong_guid,
            "messages": inst.messages}


CASES = {name[5:]: fn for name, fn in globals().items() if name.startswith("case_")}


def main(argv: list[str] | None = None) -> int:
    from fmpy import extract

    argv = sys.argv[1:] if argv is None else argv
    fmu, names = argv[0], argv[1:] or list(CASES)
    unzipdir = extract(fmu)
    print(json.dumps({n: CASES[n](fmu, unzipdir) for n in names}))
    return 0


if __name__ == "__main__":
    from fmu.hosts import finish

    finish(main())
