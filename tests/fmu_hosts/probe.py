"""Bad-case host runs against any FMI 2.0 co-simulation FMU of the heli rotor (the Python
FMU, or a native one given its path): the host must survive every case, each call must
answer a non-fatal status with a message naming the call or the variable, and a good call
afterwards must work again.

:class:`Probe` drives one instance through the FMU's C functions directly (fmpy loads the
library; statuses are returned, never raised) with a logger that records every message
(loggingOn is false: errors must reach the logger anyway). Each case in ``CASES`` returns
a JSON-able dict of call records ``{"call", "status", "messages", ...}``.

``python -m fmu_hosts.probe CASE ARGS_JSON`` runs one case in this (fresh) process and prints one
JSON line; the tests run every case in its own interpreter, so a crash shows as the exit
code of that process. Arguments: ``fmu`` (path to the ``.fmu``), ``dt`` (s), ``repeat``.
Only variable names and the XML model description are used, so the same cases run against
any FMU with this model's variables.
"""
from __future__ import annotations

import ctypes
import json
import math
import sys
import time
from pathlib import Path

from fmu.hosts import STATUS, open_slave

UNKNOWN_VR = 987654  # a value reference that no variable of the FMU has
GOOD_STEP = 1.0e-3  # s: a communication step every scene takes


class Probe:
    """One instance of an FMU through its raw FMI 2.0 functions (logging off unless asked);
    ``messages`` holds every logged ``(status name, text)``, :meth:`record` the ones logged
    during one call."""

    def __init__(self, fmu: str, name: str = "probe", unzipdir: str | None = None, logging_on: bool = False):
        self.messages: list[tuple[str, str]] = []
        self.md, self.unzipdir, self.slave, self._callbacks = open_slave(fmu, name, unzipdir, logging_on,
                                                                         self.messages)
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.c = self.slave.component

    def raw(self, fname: str, *args) -> int:
        """Call the FMI function ``fname`` (e.g. ``"fmi2DoStep"``); returns its status."""
        return int(self.slave._functions[fname](self.c, *args))

    def record(self, call: str, fn, *args, **extra) -> dict:
        """Run ``fn(*args)`` (returning a status, or (status, value)) and record the call."""
        first = len(self.messages)
        out = fn(*args)
        status, value = out if isinstance(out, tuple) else (out, None)
        rec = {"call": call, "status": status, "messages": self.messages[first:], **extra}
        return rec if value is None else {**rec, "value": value}

    def vr(self, name: str) -> int:
        return self.vars[name].valueReference

    # -- the FMI calls ----------------------------------------------------------------------
    def setup(self, start: float = 0.0) -> int:
        return self.raw("fmi2SetupExperiment", 0, ctypes.c_double(0.0), ctypes.c_double(start), 0,
                        ctypes.c_double(0.0))

    def enter(self) -> int:
        return self.raw("fmi2EnterInitializationMode")

    def exit(self) -> int:
        return self.raw("fmi2ExitInitializationMode")

    def step(self, t: float, dt: float) -> int:
        return self.raw("fmi2DoStep", ctypes.c_double(t), ctypes.c_double(dt), 1)

    def get_reals(self, vrs: list[int]) -> tuple[int, list[float]]:
        from fmpy.fmi2 import fmi2Real, fmi2ValueReference

        values = (fmi2Real * len(vrs))()
        status = self.raw("fmi2GetReal", (fmi2ValueReference * len(vrs))(*vrs), len(vrs), values)
        return status, list(values)

    def set_reals(self, vrs: list[int], values: list[float]) -> int:
        from fmpy.fmi2 import fmi2Real, fmi2ValueReference

        return self.raw("fmi2SetReal", (fmi2ValueReference * len(vrs))(*vrs), len(vrs),
                        (fmi2Real * len(vrs))(*values))

    def set_strings(self, vrs: list[int], values: list[str]) -> int:
        from fmpy.fmi2 import fmi2String, fmi2ValueReference

        return self.raw("fmi2SetString", (fmi2ValueReference * len(vrs))(*vrs), len(vrs),
                        (fmi2String * len(vrs))(*[v.encode() for v in values]))

    def get(self, name: str) -> float:
        """One Real by name (asserting an OK status)."""
        status, values = self.get_reals([self.vr(name)])
        if status:
            raise RuntimeError(f"getReal({name!r}) answered {STATUS[status]}: {self.messages[-3:]}")
        return values[0]

    def set(self, reals: dict) -> int:
        return self.set_reals([self.vr(n) for n in reals], [float(v) for v in reals.values()]) if reals else 0

    def initialise(self, reals: dict | None = None, strings: dict | None = None) -> list[int]:
        """setupExperiment, enterInitializationMode, the values, exitInitializationMode."""
        statuses = [self.setup(), self.enter()]
        if strings:
            statuses.append(self.set_strings([self.vr(n) for n in strings], list(strings.values())))
        return [*statuses, self.set(reals or {}), self.exit()]

    def save(self) -> tuple[int, bytes]:
        """fmi2GetFMUstate, fmi2SerializedFMUstateSize, fmi2SerializeFMUstate, fmi2FreeFMUstate."""
        state, size = ctypes.c_void_p(), ctypes.c_size_t()
        statuses = [self.raw("fmi2GetFMUstate", ctypes.byref(state))]
        statuses.append(self.raw("fmi2SerializedFMUstateSize", state, ctypes.byref(size)))
        buf = ctypes.create_string_buffer(size.value)
        statuses.append(self.raw("fmi2SerializeFMUstate", state, buf, size.value))
        statuses.append(self.raw("fmi2FreeFMUstate", ctypes.byref(state)))
        return max(statuses), buf.raw[:size.value]

    def load(self, blob: bytes) -> int:
        """fmi2DeSerializeFMUstate, then (if it worked) fmi2SetFMUstate and fmi2FreeFMUstate;
        the worst status."""
        state = ctypes.c_void_p()
        status = self.raw("fmi2DeSerializeFMUstate", ctypes.create_string_buffer(blob, len(blob)), len(blob),
                          ctypes.byref(state))
        if status > 1 or not state.value:
            return max(status, 3)
        statuses = [status, self.raw("fmi2SetFMUstate", state), self.raw("fmi2FreeFMUstate", ctypes.byref(state))]
        return max(statuses)

    def free(self) -> None:
        self.slave.terminate()
        self.slave.freeInstance()


def real_starts(md) -> dict:
    """XML start values of the Real inputs and parameters, as written (text)."""
    return {v.name: v.start for v in md.modelVariables
            if v.type == "Real" and v.causality in ("input", "parameter") and v.start is not None}


def _initialised(a: dict, reals: dict | None = None) -> Probe:
    p = Probe(a["fmu"])
    statuses = p.initialise(reals)
    if any(statuses):
        raise RuntimeError(f"initialisation failed: {statuses} {p.messages[-3:]}")
    return p


def _recovers(p: Probe, t: float = 0.0, dt: float = GOOD_STEP) -> dict:
    """A good step and a good getReal after the bad calls."""
    rec = p.record("fmi2DoStep", p.step, t, dt)
    status, values = p.get_reals([p.vr("blade1.flap"), p.vr("total_energy")])
    return {**rec, "get_status": status, "finite": all(math.isfinite(v) for v in values)}


# -- the cases ------------------------------------------------------------------------------

def case_unknown_vr(a: dict) -> dict:
    """getReal and setReal of a value reference no variable has, ``repeat`` times each."""
    p = _initialised(a)
    gets = [p.record("fmi2GetReal", p.get_reals, [UNKNOWN_VR]) for _ in range(a["repeat"])]
    mixed = p.record("fmi2GetReal", p.get_reals, [p.vr("blade1.flap"), UNKNOWN_VR])
    sets = [p.record("fmi2SetReal", p.set_reals, [UNKNOWN_VR], [1.0]) for _ in range(a["repeat"])]
    return {"get": gets, "mixed": mixed, "set": sets, "after": _recovers(p)}


def case_bad_parameter(a: dict) -> dict:
    """``name`` = ``value`` set in initialisation mode: setReal and ``repeat`` calls of
    exitInitializationMode fail; then ``good`` is set and initialisation and a step work."""
    p = Probe(a["fmu"])
    p.setup()
    p.enter()
    rec = {"set": p.record("fmi2SetReal", p.set, {a["name"]: a["value"]})}
    rec["exit"] = [p.record("fmi2ExitInitializationMode", p.exit) for _ in range(a["repeat"])]
    rec["fix"] = p.record("fmi2SetReal", p.set, {a["name"]: a["good"]})
    rec["exit_fixed"] = p.record("fmi2ExitInitializationMode", p.exit)
    return {**rec, "after": _recovers(p)}


def case_bad_tunable(a: dict) -> dict:
    """``name`` = ``value`` set while stepping: setReal fails, ``repeat`` steps are refused,
    then ``good`` is set and a step works."""
    p = _initialised(a)
    t = 0.0
    rec = {"set": p.record("fmi2SetReal", p.set, {a["name"]: a["value"]})}
    rec["steps"] = [p.record("fmi2DoStep", p.step, t, GOOD_STEP) for _ in range(a["repeat"])]
    rec["fix"] = p.record("fmi2SetReal", p.set, {a["name"]: a["good"]})
    return {**rec, "after": _recovers(p, t)}


def case_step_before_init(a: dict) -> dict:
    """doStep ``repeat`` times right after instantiate, then initialise and step."""
    p = Probe(a["fmu"])
    steps = [p.record("fmi2DoStep", p.step, 0.0, GOOD_STEP) for _ in range(a["repeat"])]
    init = p.initialise()
    return {"steps": steps, "init": init, "after": _recovers(p)}


def case_corrupt_state(a: dict) -> dict:
    """Deserialise and set corrupt states ``repeat`` times each (garbage, a truncated
    state, JSON that is no state); then restore a good state and step."""
    p = _initialised(a)
    status, good = p.save()
    blobs = {"garbage": b"\x00\xff not a state \x13" * 3, "truncated": good[: len(good) // 2],
             "foreign": json.dumps({"format": "something-else", "x": [1, 2]}).encode()}
    rec = {name: [p.record("fmi2DeSerializeFMUstate+fmi2SetFMUstate", p.load, blob) for _ in range(a["repeat"])]
           for name, blob in blobs.items()}
    rec["good"] = p.record("fmi2DeSerializeFMUstate+fmi2SetFMUstate", p.load, good)
    return {**rec, "save_status": status, "after": _recovers(p)}


def case_all_starts(a: dict) -> dict:
    """Scene ``scene`` with every XML start value applied (as a master that applies them
    all does), then initialise (again with the values ``fix`` if that failed), get outputs,
    step."""
    p = Probe(a["fmu"])
    starts = real_starts(p.md)
    p.setup()
    p.enter()
    rec = {"set_scene": p.record("fmi2SetString", p.set_strings, [p.vr("scene")], [a["scene"]]),
           "set_starts": p.record("fmi2SetReal", p.set, {n: float(s) for n, s in starts.items()}),
           "exit": p.record("fmi2ExitInitializationMode", p.exit)}
    if rec["exit"]["status"] > 1 and a.get("fix"):
        rec["fixed"] = [p.set(a["fix"]), p.exit()]
    names = [n for n in a["names"] if n in p.vars]
    rec["get"] = p.record("fmi2GetReal", p.get_reals, [p.vr(n) for n in names], names=names)
    return {**rec, "after": _recovers(p)}


def case_huge_steps(a: dict) -> dict:
    """doStep with ``sizes`` (s), ``repeat`` times each, timed; then a good step."""
    p = _initialised(a)
    rec = {}
    for h in a["sizes"]:
        start = time.perf_counter()
        rec[repr(h)] = [p.record("fmi2DoStep", p.step, 0.0, h) for _ in range(a["repeat"])]
        rec[repr(h) + "_seconds"] = time.perf_counter() - start
    return {**rec, "after": _recovers(p)}


def case_diverging(a: dict) -> dict:
    """``reals`` at initialisation, then steps of ``dt`` until one is refused (at most
    ``max_steps``); the state must stay where it was, and a good max_step recovers."""
    p = _initialised(a, a.get("reals"))
    t, rec = 0.0, None
    for _ in range(a["max_steps"]):
        rec = p.record("fmi2DoStep", p.step, t, a["dt"])
        if rec["status"]:
            break
        t += a["dt"]
    rec["t"] = t
    rec["time_after"] = p.get_reals([p.vr("blade1.flap")])
    p.set({"max_step": a["good_max_step"]})
    return {"refused": rec, "after": _recovers(p, t, a["dt"])}


def case_set_output(a: dict) -> dict:
    """setReal of the output ``name``, ``repeat`` times; the output keeps its value."""
    p = _initialised(a)
    before = p.get(a["name"])
    sets = [p.record("fmi2SetReal", p.set, {a["name"]: before + 1.0}) for _ in range(a["repeat"])]
    return {"set": sets, "unchanged": p.get(a["name"]) == before, "after": _recovers(p)}


def case_start_roundtrip(a: dict) -> dict:
    """Set every Real input and parameter to its XML start text, read it back (hex): set when
    instantiated (read in Initialization Mode: the standards allow no reading before), in
    Initialization Mode, and after it."""
    p = Probe(a["fmu"])
    starts = real_starts(p.md)
    out = {}
    for when, before, after in (("instantiated", None, lambda: (p.setup(), p.enter())), ("initialization", None, None),
                                ("stepping", p.exit, None)):
        if before:
            before()
        set_status = p.set({n: float(s) for n, s in starts.items()})
        if after:
            after()
        status, values = p.get_reals([p.vr(n) for n in starts])
        out[when] = {"set_status": set_status, "get_status": status,
                     "values": {n: float(v).hex() for n, v in zip(starts, values)}}
    return {"starts": {n: float(s).hex() for n, s in starts.items()}, "text": starts, **out}


def case_broken_resources(a: dict) -> dict:
    """``resources/<damage>`` overwritten with garbage in an extracted copy: instantiate
    must still give an instance whose every call answers an error, and freeing it works;
    a second FMU instance from an intact copy then runs."""
    from fmpy import extract

    broken = Path(extract(a["fmu"]))
    target = broken / "resources" / a["damage"]
    if not target.is_file():
        return {"skipped": f"no {target.relative_to(broken)} in this FMU"}
    target.write_text("{ damaged")
    p = Probe(a["fmu"], "broken", unzipdir=str(broken))
    rec = {"setup": p.record("fmi2SetupExperiment", p.setup),
           "get": [p.record("fmi2GetReal", p.get_reals, [0]) for _ in range(a["repeat"])],
           "step": p.record("fmi2DoStep", p.step, 0.0, GOOD_STEP)}
    p.slave.freeInstance()
    return {**rec, "after": _recovers(_initialised(a))}


def case_reset(a: dict) -> dict:
    """A bad value, fmi2Reset, then a fresh initialisation and a step ``repeat`` times."""
    p = _initialised(a)
    out = []
    for _ in range(a["repeat"]):
        p.set({"collective": math.nan})
        statuses = [p.raw("fmi2Reset"), *p.initialise()]
        out.append({"statuses": statuses, "step": p.step(0.0, GOOD_STEP)})
    return {"cycles": out, "sys_path": len(sys.path), "after": _recovers(p, GOOD_STEP)}


def case_memory(a: dict) -> dict:
    """``cycles`` instantiate/free cycles in this process: resident memory growth (bytes)
    after ``warmup`` cycles, and the length of ``sys.path``."""
    import psutil

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md, unzipdir = read_model_description(a["fmu"]), extract(a["fmu"])

    def cycle(k: int) -> None:
        s = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=f"cycle{k}")
        s.instantiate(loggingOn=False)
        s.freeInstance()

    for k in range(a["warmup"]):
        cycle(k)
    rss0, path0 = psutil.Process().memory_info().rss, len(sys.path)
    for k in range(a["cycles"]):
        cycle(k)
    rss1 = psutil.Process().memory_info().rss
    return {"growth": rss1 - rss0, "per_cycle": (rss1 - rss0) / a["cycles"], "sys_path": [path0, len(sys.path)]}


CASES = {name[5:]: fn for name, fn in globals().items() if name.startswith("case_")}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    case, args = argv[0], json.loads(Path(argv[1]).read_text())
    print(json.dumps(CASES[case]({"repeat": 10, **args})))
    return 0


if __name__ == "__main__":
    from fmu.hosts import finish

    finish(main())
