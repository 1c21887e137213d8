"""Drive the FMU from Python importers, and the equivalent direct run of the core.

- :func:`pitch_schedule`: the demonstration input table (a collective step and a cyclic
  doublet), piecewise constant with its switching times on the communication grid;
- :func:`run_fmpy`: ``fmpy.simulate_fmu`` with that table (checks that it reached the end);
- :class:`Instance`: fmpy's low-level ``FMU2Slave`` with a capturing logger (state
  save/restore, several instances, error statuses);
- :func:`run_libcosim`: the same run under OSP libcosim (``libcosimpy``), a second importer;
- :func:`run_core`: the same run directly through the core, with exactly the FMU's sub-steps.

Nothing here imports ``mbs`` at module level, so a process that only runs the FMU loads the
FMU's own copy of the core; :func:`finish` ends a host process that has written its result.
"""
from __future__ import annotations

import math
import os
import sys
from pathlib import Path

import numpy as np

STATUS = {0: "ok", 1: "warning", 2: "discard", 3: "error", 4: "fatal", 5: "pending"}


# -- inputs -----------------------------------------------------------------------------------

def pitch_schedule(defaults: dict, dt: float, steps_per_rev: int, collective_step: float = 0.02,
                   doublet: float = 0.01, revs=(2.0, 4.0, 5.0, 6.0)) -> np.ndarray:
    """Input table for fmpy: trim values, then ``collective`` + ``collective_step`` (rad) from
    ``revs[0]``, and a doublet of ±``doublet`` (rad) on the longitudinal cyclic (else the
    lateral) from ``revs[1]`` to ``revs[2]`` and ``revs[2]`` to ``revs[3]``.

    ``defaults``: input name -> trim value (rad). Switching times are ``k * dt`` with ``k`` an
    integer, i.e. exactly on fmpy's communication grid, so the inputs are piecewise constant
    over every communication step.
    """
    names = list(defaults)
    cyclic = "longitudinal_cyclic" if "longitudinal_cyclic" in names else names[min(1, len(names) - 1)]
    t1, t2, t3, t4 = (round(r * steps_per_rev) * dt for r in revs)
    rows, value = [], dict(defaults)
    rows.append((0.0, dict(value)))
    for t, name, delta in ((t1, "collective", collective_step), (t2, cyclic, doublet),
                           (t3, cyclic, -2 * doublet), (t4, cyclic, doublet)):
        if name in value:
            rows.append((t, dict(value)))
            value[name] += delta
            rows.append((t, dict(value)))
    table = np.zeros(len(rows), dtype=[("time", float)] + [(n, float) for n in names])
    for i, (t, v) in enumerate(rows):
        table[i] = (t, *[v[n] for n in names])
    return table


def inputs_at(table: np.ndarray, t: float) -> dict:
    """The held input values of a step starting at ``t`` (right-continuous at switches)."""
    i = int(np.searchsorted(table["time"], t * (1 + 1e-12) + 1e-15, side="right")) - 1
    return {n: float(table[n][max(i, 0)]) for n in table.dtype.names[1:]}


def grid(stop: float, dt: float, start: float = 0.0) -> list[float]:
    """Communication points as fmpy makes them: ``start + k dt``, the last one ``stop``."""
    n = int(round((stop - start) / dt))
    if not math.isclose(start + n * dt, stop):
        raise ValueError(f"stop - start = {stop - start} s is not a whole number of steps dt = {dt} s")
    return [start + k * dt for k in range(n)] + [stop]


# -- fmpy -------------------------------------------------------------------------------------

def run_fmpy(fmu: str | Path, stop: float, dt: float, table: np.ndarray | None = None,
             start_values: dict | None = None, outputs: list[str] | None = None,
             debug_logging: bool = False) -> np.ndarray:
    """``fmpy.simulate_fmu`` with the communication step ``dt`` (``output_interval``).

    Raises RuntimeError if the run stopped before ``stop`` (fmpy ends quietly on fmi2Discard).
    """
    from fmpy import simulate_fmu

    res = simulate_fmu(str(fmu), start_time=0.0, stop_time=stop, output_interval=dt, input=table,
                       start_values=start_values or {}, output=outputs, debug_logging=debug_logging)
    if not math.isclose(res["time"][-1], stop):
        raise RuntimeError(f"the FMU stopped at t = {res['time'][-1]} s before stop_time = {stop} s "
                           "(fmi2Discard: see the messages on stderr)")
    return res


def logger_callbacks(messages: list):
    """fmpy's FMI 2.0 callbacks with a logger that appends ``(status name, text)`` to
    ``messages``; keep the returned object alive as long as the instance."""
    from fmpy import calloc, free
    from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions,
                           fmi2CallbackLoggerTYPE)

    def log(env, instance, status, category, message):
        messages.append((STATUS.get(status, str(status)), message.decode(errors="replace")))

    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(log)
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    return cb


def open_slave(fmu: str | Path, name: str, unzipdir: str | None, logging_on: bool, messages: list):
    """Instantiate the FMU ``fmu`` (unzipped into ``unzipdir``, else a temporary folder) with
    fmpy's ``FMU2Slave``, logging into ``messages``; returns (model description, unzip folder,
    slave, callbacks)."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(str(fmu))
    unzipdir = unzipdir or extract(str(fmu))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=name)
    callbacks = logger_callbacks(messages)
    slave.instantiate(callbacks=callbacks, loggingOn=logging_on)
    return md, unzipdir, slave, callbacks


class Instance:
    """One FMU instance through fmpy's ``FMU2Slave``, with every log message captured in
    ``messages`` as ``(status name, text)``."""

    def __init__(self, fmu: str | Path, name: str = "instance", unzipdir: str | None = None,
                 logging_on: bool = True):
        self.messages: list[tuple[str, str]] = []
        self.md, self.unzipdir, self.slave, self._callbacks = open_slave(fmu, name, unzipdir, logging_on,
                                                                         self.messages)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.c = self.slave.component

    def initialise(self, start: float = 0.0, reals: dict | None = None, strings: dict | None = None) -> None:
        self.slave.setupExperiment(startTime=start)
        self.slave.enterInitializationMode()
        self.set(reals or {}, strings or {})
        self.slave.exitInitializationMode()

    def set(self, reals: dict, strings: dict | None = None) -> None:
        if reals:
            self.slave.setReal([self.vr[n] for n in reals], [float(v) for v in reals.values()])
        if strings:
            self.slave.setString([self.vr[n] for n in strings], list(strings.values()))

    def get(self, names: list[str]) -> list[float]:
        return list(self.slave.getReal([self.vr[n] for n in names]))

    def step(self, t: float, dt: float) -> int:
        """``fmi2DoStep``; returns the status (0 ok, 2 discard, 3 error, 4 fatal)."""
        from fmpy.fmi1 import FMICallException

        try:
            self.slave.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
            return 0
        except FMICallException as exc:
            return exc.status

    def save(self) -> bytes:
        """``fmi2GetFMUstate`` + ``fmi2SerializeFMUstate``."""
        state = self.slave.getFMUstate()
        blob = bytes(self.slave.serializeFMUstate(state))
        self.slave.freeFMUstate(state)
        return blob

    def restore(self, blob: bytes) -> None:
        """``fmi2DeSerializeFMUstate`` + ``fmi2SetFMUstate``."""
        state = self.slave.deSerializeFMUstate(blob)
        self.slave.setFMUstate(state)
        self.slave.freeFMUstate(state)

    def free(self) -> None:
        self.slave.terminate()
        self.slave.freeInstance()


def output_names(fmu: str | Path) -> list[str]:
    from fmpy import read_model_description

    return [v.name for v in read_model_description(str(fmu)).modelVariables if v.causality == "output"]


def run_instance(inst: Instance, times: list[float], table: np.ndarray, names: list[str],
                 first: int = 0) -> dict:
    """Step ``inst`` over ``times[first:]`` with the table's inputs; outputs after each step."""
    rows = []
    for k in range(first, len(times) - 1):
        inst.set(inputs_at(table, times[k]))
        status = inst.step(times[k], times[k + 1] - times[k])
        if status:
            raise RuntimeError(f"doStep at t = {times[k]} returned {STATUS[status]}: {inst.messages[-3:]}")
        rows.append(inst.get(names))
    return {"time": times[first + 1:], **{n: [r[i] for r in rows] for i, n in enumerate(names)}}


# -- libcosim ---------------------------------------------------------------------------------

def run_libcosim(fmu: str | Path, stop: float, dt: float, table: np.ndarray, names: list[str]) -> dict:
    """The run under OSP libcosim: integer-nanosecond time, inputs overridden before each
    step, outputs read after it. ``dt`` must be a whole number of nanoseconds."""
    from libcosimpy.CosimEnums import CosimVariableType  # noqa: F401
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    step_ns = round(dt * 1e9)
    if abs(step_ns - dt * 1e9) > 1e-6:
        raise ValueError(f"libcosim needs a whole number of nanoseconds per step, not {dt} s")
    log_output_level(CosimLogLevel.WARNING)
    ex = CosimExecution.from_step_size(step_size=step_ns)
    i = ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name="rotor"))
    vr = {v.name.decode(): v.reference for v in ex.slave_variables(i)}
    observer, override = CosimObserver.create_last_value(), CosimManipulator.create_override()
    ex.add_observer(observer)
    ex.add_manipulator(override)
    inputs = list(table.dtype.names[1:])
    n = int(round(stop / dt))
    rows, times = [], []
    for k in range(n):
        values = inputs_at(table, k * step_ns * 1e-9)
        override.slave_real_values(i, [vr[m] for m in inputs], [values[m] for m in inputs])
        if not ex.step():
            raise RuntimeError(f"libcosim step {k} failed")
        rows.append(observer.last_real_values(i, [vr[m] for m in names]))
        times.append((k + 1) * step_ns * 1e-9)
    return {"time": times, **{m: [r[j] for r in rows] for j, m in enumerate(names)}}


# -- the core, directly ---------------------------------------------------------------------

def run_core(scene: str, times: list[float], table: np.ndarray, max_step: float | None = None,
             params: dict | None = None, names: list[str] | None = None, method: str = "rk4",
             x0: list[float] | None = None, aircraft=None) -> dict:
    """The FMU's computation done directly with the core's public API: per communication
    step ``[t_k, t_k+1]``, ``system.run`` of ``n = ceil(dt / max_step)`` steps of ``method`` of
    ``dt / n`` with the inputs held, from ``x0`` (default the scene's initial state); outputs
    as the FMU defines them (hinge coordinates and rates, model outputs, fuselage position,
    Euler angles and velocities, total energy). ``aircraft``: as :func:`mbs.scenes.get`."""
    from mbs import scenes
    from mbs._rotation import quat_to_euler

    sc = scenes.get(scene, aircraft)
    system = sc.system("compiled")
    info = system.info
    base = system.params(params or {})
    h_max = max_step or sc.revolution(system, base) / sc.steps_per_rev
    x = system.x0() if x0 is None else np.array(x0, dtype=float)
    rows = []
    for k in range(len(times) - 1):
        p = system.params(base, **inputs_at(table, times[k]))
        dt = times[k + 1] - times[k]
        n = max(1, math.ceil(dt / h_max * (1 - 1e-6)))  # the FMUs' SUBSTEP_TOLERANCE
        x = system.run(x, times[k], dt / n, n, every=n, p=p, method=method).x[-1]
        rows.append(_core_outputs(system, info, x, times[k + 1], p, quat_to_euler))
    names = names or list(rows[0])
    return {"time": times[1:], **{n: [r[n] for r in rows] for n in names}}


def _core_outputs(system, info, x, t, p, quat_to_euler) -> dict:
    out = dict(zip(info.state_names, x.tolist()))
    out.update(zip(info.output_names, system.outputs(x, t, p).tolist()))
    out["total_energy"] = float(system.energy(x, t, p)[-1])
    for b in info.bodies:
        if b["joint"] == "FreeJoint":
            q = [info.state_names.index(n) for n in b["q_names"][3:7]]
            out.update(zip([f"{b['name']}.{a}" for a in ("roll", "pitch", "yaw")], quat_to_euler(x[q]).tolist()))
    return out


# -- tables and fresh-process hosts ----------------------------------------------------------

def table_rows(table: np.ndarray) -> list[dict]:
    return [{n: float(r[n]) for n in table.dtype.names} for r in table]


def call_status(fn, *args) -> int:
    from fmpy.fmi1 import FMICallException

    try:
        fn(*args)
        return 0
    except FMICallException as exc:
        return exc.status


def finish(code: int = 0) -> None:
    """End a host process once its result is written: flush, then leave without the
    interpreter's teardown. One host that had run the pythonfmu FMU aborted in that teardown
    during a full test run (glibc "corrupted double-linked list", after complete results), the
    symptom of pythonfmu 0.7.0's double release of its Python state at exit, which the FMU's
    front end now prevents (``fmu/pythonfmu/shim``; tests/test_fmu_exit.py runs C hosts through their
    exit); these hosts check what the FMU computed, not the interpreter's teardown."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
