"""Cases of the FMI 2.0 and 3.0 standards that a strict host checks, run on this project's FMUs in
the scripted C host (:mod:`fmu_hosts.script_host`): stopTime, start values written or not, the state
machines, status queries, FMU states and their serialized form. Each case returns what the host
answered (statuses, values, messages) for the tests to assert; none asserts itself.

A :class:`Target` is one FMU as a host drives it: the unzipped FMU's facts, the interface
(``cs`` co-simulation or ``me`` model exchange), the compiled host and its environment (a host
linked to libpython for the pythonfmu FMU).
"""
from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

from fmu_hosts import script_host as sh

OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
GUID_BYTE = 18
"""A byte of the GUID in a serialized state's header: both FMUs write an 8-byte tag and two 4-byte
fields, then the GUID (``fmu/pythonfmu/shim/fmi2_shim.c``, ``fmu/native/heli_core.c``)."""


@dataclass
class Target:
    facts: dict
    kind: str
    host: Path
    env: dict | None = None

    @property
    def v3(self) -> bool:
        return self.facts["version"] == 3

    @property
    def me(self) -> bool:
        return self.kind == "me"

    def vr(self, name: str) -> int:
        return self.facts["vr"][name]

    def run(self, lines: list[str]) -> list[dict]:
        return sh.run(self.host, lines, env=self.env)


def target(fmu: str | Path, kind: str, folder: Path, host: Path, env: dict | None = None) -> Target:
    """The FMU ``fmu`` unzipped into ``folder`` (a fresh one), driven through ``kind`` by ``host``."""
    if folder.exists():
        shutil.rmtree(folder)
    return Target(sh.fmu_facts(fmu, folder), kind, host, env)


def begin(t: Target, values: dict | None = None, start: float = 0.0, stop: float | None = None, slot: int = 0,
          lib: int = 0, name: str = "host") -> list[str]:
    """Instantiate, set up (``stop``: stopTimeDefined), write ``values`` in Initialization Mode and
    initialise; model exchange then goes from Event Mode into Continuous-Time Mode."""
    lines = sh.instantiate(t.facts, t.kind, name, slot, lib)
    lines += [f"setup 0 0 {start!r} {0 if stop is None else 1} {0.0 if stop is None else stop!r}", "enter",
              *sh.write_values(t.facts, values or {}), "exit"]
    return lines + (["newdiscrete", "ctmode"] if t.me else [])


def scalar_outputs(t: Target) -> list[int]:
    """Value references of the FMU's scalar outputs (FMI 3.0 arrays are left out)."""
    return [t.vr(n) for n in t.facts["outputs"] if t.facts["sizes"].get(n, 1) == 1]


def advance(t: Target, steps: int, dt: float, reads: list[int], start: float = 0.0) -> str:
    """The command of ``steps`` steps of ``dt`` s (model exchange: explicit Euler), reading ``reads``."""
    vrs = " ".join(map(str, reads))
    if t.me:
        return f"euler {steps} {start!r} {dt!r} {t.facts['n_states']} {vrs}"
    return f"steps {steps} {start!r} {dt!r} {vrs}"


# -- stopTime -----------------------------------------------------------------------------------

def stop_time(t: Target, dt: float, steps: int = 10) -> dict:
    """stopTime before startTime (refused at setup, FMI 3.0 at EnterInitializationMode); then with
    stopTime 2e-10 (relative) short of ``steps`` steps of ``dt``: the steps up to it (the last ends
    past it by rounding only), one step past it, and the last successful time; model exchange: a
    time at stopTime and one past it."""
    stop = steps * dt * (1 - 2e-10)
    early = t.run(sh.instantiate(t.facts, t.kind) + ["setup 0 0 1.0 1 0.5", "enter"])
    lines = begin(t, stop=stop)
    if t.me:
        lines += [f"settime {stop!r}", f"settime {stop * (1 + 1e-6) + 1e-6!r}"]
    else:
        lines += [f"step {k * dt!r} {dt!r}" for k in range(steps)]
        lines += [f"step {steps * dt!r} {dt!r}"] + ([] if t.v3 else ["realstatus 2"])
    res = t.run(lines)
    return {"early": early[-2:], "stop": stop, "run": res[len(begin(t, stop=stop)):]}


# -- start values -------------------------------------------------------------------------------

def start_value_runs(t: Target, values: dict, steps: int, dt: float) -> tuple[list[dict], list[dict]]:
    """The same run of ``steps`` steps with ``values`` written, once without any other start value
    and once after every XML start value of the FMU's inputs and parameters: the host's results of
    each (initialisation and the steps)."""
    reads = scalar_outputs(t)
    none = t.run(begin(t, values) + [advance(t, steps, dt, reads)])
    every = t.run(begin(t, {**t.facts["starts"], **values}) + [advance(t, steps, dt, reads)])
    return none, every


def comparable(results: list[dict]) -> list[tuple]:
    """What must agree between two runs: each exit, step and read's status, values and messages."""
    keep = ("exit", "steps", "euler", "newdiscrete", "ctmode")
    return [(r["status"], r["values"], [m[2] for m in r["log"]]) for r in results if r["cmd"].split()[0] in keep]


# -- status queries, strings -------------------------------------------------------------------------

def status_queries(t: Target, dt: float) -> list[dict]:
    """fmi2GetRealStatus(fmi2LastSuccessfulTime) after initialisation, after a step, after refused
    steps (NaN, infinite, negative step size); both status queries with a NULL value pointer."""
    lines = begin(t) + ["realstatus 2", f"step 0.0 {dt!r}", "realstatus 2", f"step {dt!r} nan", "realstatus 2",
                        f"step {dt!r} inf", "realstatus 2", f"step {dt!r} -0.99", "realstatus 2",
                        "realstatus 2 null", "boolstatus 3 null", "boolstatus 3"]
    return t.run(lines)[len(begin(t)):]


def strings_not_utf8(t: Target, dt: float) -> list[dict]:
    """fmi2SetString of ``scene`` with bytes that are not UTF-8 (a stray byte, an overlong NUL, a
    surrogate), then a good value and a step: the instance must stay usable."""
    vr = t.vr("scene")
    lines = sh.instantiate(t.facts, t.kind) + ["setup 0 0 0.0 0 0.0", "enter",
                                                *[f"sets {vr} x:{h}" for h in ("ff41", "c080", "eda080")],
                                                f"sets {vr} s:hover", f"gets {vr}", "exit", f"step 0.0 {dt!r}"]
    return t.run(lines)[2:]


# -- FMU states -----------------------------------------------------------------------------------------

def blob_cases(t: Target, dt: float, folder: Path) -> dict:
    """A serialized state after one step, then deserialized as it is, truncated by a byte,
    extended by a byte, with a flipped bit in the middle of its data and in its header's GUID;
    each deserialization's result."""
    saved = folder / "state.bin"
    lines = begin(t) + [f"step 0.0 {dt!r}", "getstate 0", "serialize 0 0", f"blob 0 save {saved}"]
    cases = {"intact": [], "truncated": ["blob 0 cut 1"], "extended": ["blob 0 grow 1"],
             "bit in the data": ["blob 0 flip -1 0x04"], "bit in the GUID": ["blob 0 flip -2 0x01"]}
    out = {}
    head = t.run(lines)
    size = int(head[-1]["values"][0])
    for name, change in cases.items():
        change = [c.replace("-1", str(size * 2 // 3)).replace("-2", str(GUID_BYTE)) for c in change]
        res = t.run(begin(t) + [f"blob 0 load {saved}", *change, "deserialize 0 1", "setstate 1",
                                f"step {dt!r} {dt!r}"])
        out[name] = res[len(begin(t)) + 1 + len(change):]
    return out


def foreign_states(t: Target, dt: float, copy: Path) -> list[dict]:
    """FMU states offered to an instance that did not save them: one of another instance of the
    same library, one of another copy of the FMU (another library, as another build would be);
    then the instance's own state, which must work."""
    other = sh.copy_facts(t.facts, copy)
    lines = begin(t, slot=0, lib=0, name="first") + [f"step 0.0 {dt!r}", "getstate 0"]
    lines += begin(t, slot=1, lib=0, name="second") + [f"step 0.0 {dt!r}", "getstate 1"]
    lines += begin(Target(other, t.kind, t.host), slot=2, lib=1, name="copy") + [f"step 0.0 {dt!r}", "getstate 2"]
    lines += ["use 0", "setstate 1", "setstate 2", "serialize 1 0", "setstate 0", advance(t, 1, dt, [], start=dt)]
    return t.run(lines)[-6:]


def serialize_into_null(t: Target, dt: float) -> dict:
    """fmiXSerializeFMUState into a NULL buffer of the right size, then into a real one."""
    res = t.run(begin(t) + [f"step 0.0 {dt!r}", "getstate 0", "serialize 0 0 null", "serialize 0 0"])
    return {"null": res[-2], "buffer": res[-1]}


# -- the state machines ----------------------------------------------------------------------------

def me_state_machine(t: Target) -> dict:
    """Model exchange, each call in a mode the standard does not allow it in and then where it is:
    derivatives in Instantiated; CompletedIntegratorStep and SetContinuousStates in Event Mode;
    NewDiscreteStates (FMI 3.0 UpdateDiscreteStates) in Continuous-Time Mode; EnterStepMode."""
    n = t.facts["n_states"]
    script = [("derivatives in Instantiated", f"getdx {n}"), ("setup", "setup 0 0 0.0 0 0.0"), ("enter", "enter"),
              ("exit", "exit"), ("completed in Event Mode", "completed"), ("states in Event Mode", f"setx {n}"),
              ("discrete states in Event Mode", "newdiscrete"), ("continuous-time mode", "ctmode"),
              ("discrete states in Continuous-Time Mode", "newdiscrete"), ("completed", "completed"),
              ("derivatives", f"getdx {n}"), ("event mode", "eventmode"), ("enter step mode", "enterstep")]
    if not t.v3:
        script = script[:-1]
    res = t.run(sh.instantiate(t.facts, "me") + [line for _, line in script])[2:]
    return {name: r for (name, _), r in zip(script, res)}


def cs_state_machine(t: Target, dt: float) -> dict:
    """FMI 3.0 co-simulation without Event Mode: EnterStepMode in Instantiated, Initialization Mode
    and Step Mode, UpdateDiscreteStates in Step Mode, then a step."""
    script = [("enter step mode in Instantiated", "enterstep"), ("setup", "setup 0 0 0.0 0 0.0"), ("enter", "enter"),
              ("enter step mode in Initialization Mode", "enterstep"), ("exit", "exit"),
              ("enter step mode in Step Mode", "enterstep"), ("update discrete states in Step Mode", "newdiscrete"),
              ("step", f"step 0.0 {dt!r}")]
    res = t.run(sh.instantiate(t.facts, "cs") + [line for _, line in script])[2:]
    return {name: r for (name, _), r in zip(script, res)}


def fmi3_messages(t: Target) -> dict:
    """FMI 3.0 calls the FMU refuses, whose messages must name FMI 3.0 variables and value references:
    setting the array output ``blade.root.force_x``, reading ``scene`` as Float64, a continuous
    state that is not finite (model exchange: ``blade.flap[2]``)."""
    lines = begin(t) + [f"setr {t.vr('blade.root.force_x')} = 0.1 0.1 0.1 0.1", f"getr {t.vr('scene')}"]
    if t.me:
        x = [0.0] * t.facts["n_states"]
        x[state_index(t, "blade.flap", 2)] = float("nan")
        lines += [f"setx {len(x)} " + " ".join(map(repr, x))]
    res = t.run(lines)[len(begin(t)):]
    return {"set output": res[0], "wrong type": res[1], **({"state": res[2]} if t.me else {})}


def state_index(t: Target, state: str, element: int = 1) -> int:
    """The position of a continuous state (FMI 3.0: an array's element, counted from 1) in the
    FMU's vector of continuous states."""
    k = 0
    for name in t.facts["states"]:
        if name == state:
            return k + element - 1
        k += t.facts["sizes"].get(name, 1)
    raise KeyError(state)


# -- the controller ---------------------------------------------------------------------------------------

def heading_steps(t: Target, headings: list[float], dt: float, repeats: int = 5, timeout: float = 60.0) -> dict:
    """The controller stepped with each heading in turn (``repeats`` times each, the trim heading
    between): per heading the statuses, the wall time of each step (s), the outputs after the
    last and the messages."""
    yaw, trim = t.vr("fuselage.yaw"), float(t.facts["starts"]["fuselage.yaw"])
    outputs = " ".join(str(t.vr(n)) for n in t.facts["outputs"])
    lines, k = begin(t), 0
    for psi in headings:
        for _ in range(repeats):
            lines += [f"setr {yaw} = {psi!r}", f"step {k * dt!r} {dt!r}", f"getr {outputs}", f"setr {yaw} = {trim!r}"]
            k += 1
            lines += [f"step {k * dt!r} {dt!r}"]
            k += 1
    res = sh.run(t.host, lines, env=t.env, timeout=timeout)[len(begin(t)):]
    out = {}
    for i, psi in enumerate(headings):
        rows = [res[(i * repeats + j) * 5: (i * repeats + j + 1) * 5] for j in range(repeats)]
        out[psi] = {"statuses": [r[1]["status"] for r in rows], "seconds": [r[1]["seconds"] for r in rows],
                    "outputs": rows[-1][2]["values"], "log": [m for r in rows for m in r[1]["log"]]}
    return out
