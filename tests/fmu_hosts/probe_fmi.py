"""FMI 2.0 conformance cases that a strict host meets, against either FMU of the heli rotor
(the pythonfmu FMU or the native one): start values equal to their XML start, misuse of the
step's arguments, the instance name and the GUID, a communication step rounded to whole
nanoseconds, the fmi2Terminated status, FMU states (into an existing state, buffer size,
restored into an instance in another phase) and log categories.

``python -m fmu_hosts.probe_fmi CASE ARGS_JSON`` runs one case in this (fresh) process and prints
one JSON line, like :mod:`fmu_hosts.probe` (whose :class:`~fmu_hosts.probe.Probe` drives the instance).
"""
from __future__ import annotations

import ctypes
import json
import sys
from pathlib import Path

from fmu_hosts.probe import GOOD_STEP, Probe


def _ready(a: dict, strings: dict | None = None, reals: dict | None = None) -> Probe:
    p = Probe(a["fmu"])
    statuses = p.initialise(reals, strings)
    if max(statuses) > 1:
        raise RuntimeError(f"initialisation failed: {statuses} {p.messages[-3:]}")
    return p


def case_start_equal(a: dict) -> dict:
    """Scene ``scene`` with ``reals`` set to their XML start (the primary scene's defaults):
    the statuses, the messages of exitInitializationMode and ``names`` read after it."""
    p = Probe(a["fmu"])
    statuses = [p.setup(), p.enter(), p.set_strings([p.vr("scene")], [a["scene"]]), p.set(a["reals"])]
    first = len(p.messages)
    statuses.append(p.exit())
    return {"statuses": statuses, "exit_messages": p.messages[first:],
            "values": {n: p.get(n) for n in a["names"]}}


def case_step_misuse(a: dict) -> dict:
    """doStep with a negative, zero or NaN step size, a NaN or wrong current time: each
    status; then a good step."""
    p = _ready(a)
    bad = {"negative h": (0.0, -GOOD_STEP), "zero h": (0.0, 0.0), "NaN h": (0.0, float("nan")),
           "NaN t": (float("nan"), GOOD_STEP), "wrong t": (1.0, GOOD_STEP)}
    rec = {name: p.record("fmi2DoStep", p.step, t, h) for name, (t, h) in bad.items()}
    return {"bad": rec, "good": p.record("fmi2DoStep", p.step, 0.0, GOOD_STEP)}


def _instantiate(p: Probe, name: bytes, guid: bytes) -> tuple[bool, list]:
    """A raw fmi2Instantiate of the FMU that ``p`` loaded; (instance created, messages)."""
    from fmu.hosts import logger_callbacks

    messages: list = []
    callbacks = logger_callbacks(messages)
    uri = Path(p.unzipdir, "resources").as_uri().encode()
    c = p.slave._functions["fmi2Instantiate"](name, 1, guid, uri, ctypes.byref(callbacks), 0, 0)
    if c:
        p.slave._functions["fmi2FreeInstance"](c)
    return bool(c), messages


def case_instantiate(a: dict) -> dict:
    """fmi2Instantiate with an empty instance name, with another GUID, and with good ones."""
    p = Probe(a["fmu"])
    guid = p.md.guid.encode()
    out = {}
    for label, name, g in (("empty name", b"", guid), ("other GUID", b"x", b"{00000000-0000-0000-0000-000000000000}"),
                           ("good", b"good", guid)):
        created, messages = _instantiate(p, name, g)
        out[label] = {"created": created, "messages": messages}
    return out


def case_nanosecond_step(a: dict) -> dict:
    """``steps`` steps of the default communication step rounded up to whole nanoseconds
    (as a master counting nanoseconds takes it) with the default max_step, and the same with
    max_step set to that step (one sub-step for sure): the ``names`` after each."""
    runs = {}
    for label, reals in (("default max_step", {}), ("max_step = step", {"max_step": a["dt"]})):
        p = _ready(a, reals=reals)
        t, rows = 0.0, []
        for k in range(a["steps"]):
            status = p.step(t, a["dt"])
            t = (k + 1) * a["dt"]
            rows.append([status, *[p.get(n).hex() for n in a["names"]]])
        runs[label] = rows
    return runs


def _boolean_status(p: Probe) -> tuple[int, bool]:
    value = ctypes.c_int(7)
    status = p.raw("fmi2GetBooleanStatus", 3, ctypes.byref(value))  # 3: fmi2Terminated
    return status, bool(value.value)


def case_terminated_status(a: dict) -> dict:
    """fmi2GetBooleanStatus(fmi2Terminated) after a good step, after a discarded step (a NaN
    input) and after the FMU recovered."""
    p = _ready(a)
    out = {"good_step": p.step(0.0, GOOD_STEP), "after_good": _boolean_status(p)}
    p.set({"collective": float("nan")})
    out["discarded_step"] = p.step(GOOD_STEP, GOOD_STEP)
    out["after_discard"] = _boolean_status(p)
    p.set({"collective": a["collective"]})
    out["recovered_step"] = p.step(GOOD_STEP, GOOD_STEP)
    out["after_recovery"] = _boolean_status(p)
    return out


def _rss() -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    return 0


def case_state_into_same(a: dict) -> dict:
    """``calls`` fmi2GetFMUstate into the same state (after ``warmup`` calls): RSS growth
    (bytes), the worst status, and whether the state kept its address."""
    p = _ready(a)
    p.step(0.0, GOOD_STEP)
    state = ctypes.c_void_p()
    statuses = {p.raw("fmi2GetFMUstate", ctypes.byref(state))}
    first = state.value
    for _ in range(a["warmup"]):
        statuses.add(p.raw("fmi2GetFMUstate", ctypes.byref(state)))
    rss0 = _rss()
    for _ in range(a["calls"]):
        statuses.add(p.raw("fmi2GetFMUstate", ctypes.byref(state)))
    growth = _rss() - rss0
    same = state.value == first
    statuses.add(p.raw("fmi2FreeFMUstate", ctypes.byref(state)))
    return {"growth": growth, "worst": max(statuses), "same_address": same}


def case_small_buffer(a: dict) -> dict:
    """fmi2SerializeFMUstate into a buffer one byte smaller than the size asked for."""
    p = _ready(a)
    state, size = ctypes.c_void_p(), ctypes.c_size_t()
    p.raw("fmi2GetFMUstate", ctypes.byref(state))
    p.raw("fmi2SerializedFMUstateSize", state, ctypes.byref(size))
    buf = ctypes.create_string_buffer(size.value)
    rec = p.record("fmi2SerializeFMUstate", p.raw, "fmi2SerializeFMUstate", state, buf, size.value - 1)
    full = p.raw("fmi2SerializeFMUstate", state, buf, size.value)
    p.raw("fmi2FreeFMUstate", ctypes.byref(state))
    return {"small": rec, "full": full, "size": size.value}


def case_restore_phase(a: dict) -> dict:
    """A state saved while stepping, restored into instances that are instantiated, in
    initialisation mode, or terminated: the status of the restore and of the next steps, and
    the output ``name`` against the saving instance's."""
    src = _ready(a)
    src.step(0.0, GOOD_STEP)
    status, blob = src.save()
    src.step(GOOD_STEP, GOOD_STEP)
    expected = src.get(a["name"])
    out = {"save": status}
    for phase in ("instantiated", "initialization", "terminated"):
        p = Probe(a["fmu"], f"into-{phase}")
        if phase != "instantiated":
            p.setup(), p.enter()
        if phase == "terminated":
            p.exit(), p.raw("fmi2Terminate")
        rec = {"restore": p.load(blob), "step": p.step(GOOD_STEP, GOOD_STEP)}
        rec["equal"] = rec["step"] == 0 and p.get(a["name"]) == expected
        rec["messages"] = p.messages[-3:]
        out[phase] = rec
    return out


def case_log_categories(a: dict) -> dict:
    """fmi2SetDebugLogging with a known and with an unknown category."""
    from fmpy.fmi2 import fmi2String

    p = Probe(a["fmu"])

    def set_logging(name: str) -> int:
        return p.raw("fmi2SetDebugLogging", 1, 1, (fmi2String * 1)(name.encode()))

    return {"known": p.record("fmi2SetDebugLogging", set_logging, "logStatusError"),
            "unknown": p.record("fmi2SetDebugLogging", set_logging, "logNoSuchCategory")}


def case_feedthrough(a: dict) -> dict:
    """After one step, each input moved by ``delta`` (rad) in turn, without a step: the
    outputs whose value changed at once (direct feedthrough), per input."""
    p = _ready(a)
    p.step(0.0, GOOD_STEP)
    outputs = [v.name for v in p.md.modelVariables if v.causality == "output"]
    inputs = [v.name for v in p.md.modelVariables if v.causality == "input"]
    base = p.get_reals([p.vr(n) for n in outputs])[1]
    out = {}
    for name in inputs:
        value = p.get(name)
        p.set({name: value + a["delta"]})
        moved = p.get_reals([p.vr(n) for n in outputs])[1]
        p.set({name: value})
        out[name] = [n for n, b, m in zip(outputs, base, moved) if b != m]
    return out


CASES = {name[5:]: fn for name, fn in globals().items() if name.startswith("case_")}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    case, args = argv[0], json.loads(Path(argv[1]).read_text())
    print(json.dumps(CASES[case](args)))
    return 0


if __name__ == "__main__":
    from fmu.hosts import finish

    finish(main())
