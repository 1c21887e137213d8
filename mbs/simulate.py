"""Run a scene and write its results: ``results.csv``, ``run.json`` and plots.

``results.csv`` columns: ``time`` (s), every state by name (rad, rad/s, m, m/s, quaternion),
every model output by name, the energies ``kinetic_translational``, ``kinetic_rotational``,
``potential_gravity``, ``potential_spring``, ``total_energy`` (J), and the inputs of an input
table by parameter name (:mod:`mbs.inputs`; the value in force from that row on). The unit
of every column is in ``run.json`` (``"units"``; :mod:`mbs.results`). ``run.json`` records
the scene (with its aircraft file and aerodynamics switches: see :func:`run_record`),
parameters, ``--set`` values and input table, integrator, the step-error estimate and
figures, the initial state and where it came from (``"initial_state"``: a periodic trim,
:mod:`mbs.trims.start`, or the scene's own start) and the SHA-256 of ``results.csv``, so that
a results folder can be re-opened (e.g. by the viewer, :func:`scene_of_run`) without guessing.

:func:`prepare` sets a run up without running it (:class:`Run`: its step-error check and cost
estimate come before the work); :func:`simulate` prepares and runs.
"""
from __future__ import annotations

import io
import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mbs import scenes as _scenes
from mbs.backends.system import System, Trajectory
from mbs.inputs import InputTable
from mbs.results import read_results  # noqa: F401  (re-exported: the readers of results folders use it)

ENERGY_NAMES = ["kinetic_translational", "kinetic_rotational", "potential_gravity",
                "potential_spring", "total_energy"]


@dataclass
class Simulation:
    """A finished run of a scene: trajectory plus energies (n, 5) and outputs (n, n_out);
    ``param_rows`` (n, np): the parameters in force from each row on, when an input table
    changed them (``inputs``); ``settings``: the ``--set`` values (``speed`` included);
    ``units``: column -> unit; ``step_error``: the estimate made before the run, if any."""

    scene: _scenes.Scene
    system: System
    traj: Trajectory
    params: np.ndarray
    revs: float
    steps_per_rev: int
    energy: np.ndarray
    outputs: np.ndarray
    compensated: bool = True
    method: str = "rk4"
    param_rows: np.ndarray | None = None
    inputs: InputTable | None = None
    settings: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)
    step_error: object = None
    every: int = 1
    start: dict = field(default_factory=dict)

    @property
    def max_rel_energy_error(self) -> float:
        e = self.energy[:, -1]
        return float(np.abs(e / e[0] - 1).max())

    def title(self) -> str:
        """``forward-flight of the MBB Bo105 at 10 m/s``: scene, aircraft and initial speed."""
        from mbs.inputs import initial_speed

        craft = f" of the {self.scene.aircraft.name}" if self.scene.aircraft is not None else ""
        speed = initial_speed(self.system.info, self.traj.x[0])
        return f"{self.scene.name}{craft}" + ("" if speed is None else f" at {speed:.3g} m/s")

    def columns(self) -> dict[str, np.ndarray]:
        info = self.system.info
        cols = {"time": self.traj.t}
        cols.update({n: self.traj.x[:, i] for i, n in enumerate(info.state_names)})
        cols.update({n: self.outputs[:, i] for i, n in enumerate(info.output_names)})
        cols.update({n: self.energy[:, i] for i, n in enumerate(ENERGY_NAMES)})
        if self.inputs is not None:
            cols.update({n: self.param_rows[:, info.param_names.index(n)] for n in self.inputs.names})
        return cols

    def column_units(self) -> dict[str, str]:
        """The unit of every column of :meth:`columns` (empty when not known)."""
        known = {**self.units, **{n: "J" for n in ENERGY_NAMES}}
        return {n: known.get(n, "") for n in self.columns()}

    def summary(self) -> dict:
        steps = int(round(self.revs * self.steps_per_rev))
        out = {**run_record(self.scene), "revs": self.revs, "steps_per_rev": self.steps_per_rev,
               "steps": steps, "every": self.every, "dtype": str(self.system.dtype),
               "backend": self.system.backend, "method": self.method, "compensated_summation": self.compensated,
               "wall_s": self.traj.wall_s,
               "realtime_factor": (self.traj.t[-1] - self.traj.t[0]) / max(self.traj.wall_s, 1e-12),
               "nfev": self.traj.nfev, "result": self.traj.result.name, "message": self.traj.message,
               "parameters": dict(zip(self.system.info.param_names, self.params.tolist())),
               "set": dict(self.settings)}
        if self.inputs is not None:
            out["inputs"] = self.inputs.summary()
        out["initial_state"] = {**self.start, "state": dict(zip(self.system.info.state_names,
                                                                map(float, self.traj.x[0])))}
        if self.step_error is not None:
            out["step_error"] = self.step_error.summary()
        if self.scene.conservative:
            out["max_rel_energy_error"] = self.max_rel_energy_error
        if "main_rotor.speed" in self.system.info.output_names:  # the rotor speed is a state: what a pilot reads
            from mbs.drivetrain.report import pilot_figures

            failures = [v for n, v in out["parameters"].items() if n.endswith("_failure_time") and v <= self.traj.t[-1]]
            out["rotor_speed"] = pilot_figures(self.columns(), min(failures) if failures else None)
        out["units"] = self.column_units()
        return out


def run_record(scene: _scenes.Scene) -> dict:
    """What rebuilds ``scene`` (:func:`scene_of_run`): its name and, for a helicopter scene, its
    aircraft (name, file, SHA-256 of the file) and aerodynamics switches."""
    if scene.aircraft is None:
        return {"scene": scene.name}
    from mbs.models.helicopter import aero_switches
    from mbs.models.helicopter.air_options import environment_record

    craft = scene.aircraft
    out = {"scene": scene.name, "aircraft": {"name": craft.name, "file": str(craft.path.resolve()),
                                             "sha256": craft.digest}, "aero": aero_switches(scene)}
    air = environment_record(scene)
    return {**out, "environment": air} if air else out


def scene_of_run(meta: dict, where: str = "run.json", aircraft=None) -> _scenes.Scene:
    """The scene a ``run.json`` (``meta``, read from ``where``) records: ValueError naming what is
    missing, or an aircraft file that is gone or has changed since the run. ``aircraft``: the
    run's aircraft file found elsewhere (an :class:`mbs.aircraft.Aircraft`: a file that moved),
    which must be the one that ran (the same SHA-256)."""
    from mbs import aircraft as ac
    from mbs.models.helicopter import aero_switches, with_aero

    if "scene" not in meta:
        raise ValueError(f"no run.json with a scene name next to {where}: cannot tell which model to show")
    recorded = meta.get("aircraft")
    craft = None
    if aircraft is not None:
        if not recorded:
            raise ValueError(f"--aircraft {aircraft.path}: the run's scene {meta['scene']!r} has no aircraft file "
                             f"({where} records none); drop --aircraft")
        if aircraft.digest != recorded["sha256"]:
            raise ValueError(f"--aircraft {aircraft.path} is not the aircraft file the run was made with (its SHA-256 "
                             f"differs from the one {where} records for {recorded['file']}); give that file")
        craft = aircraft
    elif recorded:
        try:
            craft = ac.load(recorded["file"])
        except ac.AircraftError as exc:
            raise ValueError(f"{where}: the run's aircraft {recorded['name']!r} cannot be loaded: {exc}; if the file "
                             "moved, give its new place with --aircraft FILE") from None
        if craft.digest != recorded["sha256"]:
            raise ValueError(f"{where}: the aircraft file {recorded['file']} has changed since the run; the model "
                             "would not be the one that ran (restore the file, or run again)")
    scene = _scenes.get(meta["scene"], aircraft=craft)
    from mbs.models.helicopter.air_options import environment_of_record

    aero = meta.get("aero")
    if aero is not None and not (scene.aircraft is not None and sorted(aero) == sorted(aero_switches(scene))):
        scene = with_aero(scene, ",".join(aero) or "none")  # else the scene's own switches (or none to set)
    return environment_of_record(scene, meta.get("environment", {}))


ROW_SAMPLE = 200  # rows timed and measured for the cost estimate (at most a revolution)


@dataclass
class Run:
    """A run set up and not yet started (:func:`prepare`): ``steps`` steps of ``h`` s from ``x0``
    with parameters ``p`` (and the input table ``inputs``), rows every ``every`` steps;
    ``warnings``: what the set-up changed or could not honour, one line each; ``start``: where
    ``x0`` came from (``run.json``'s ``"initial_state"``: :mod:`mbs.trims.start`)."""

    scene: _scenes.Scene
    system: System
    p: np.ndarray
    x0: np.ndarray
    h: float
    steps: int
    steps_per_rev: int
    every: int = 1
    method: str = "rk4"
    compensated: bool = True
    inputs: InputTable | None = None
    settings: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    start: dict = field(default_factory=lambda: {"from": "scene", "what": "the scene's initial state"})

    @property
    def revs(self) -> float:
        return self.steps / self.steps_per_rev

    def window(self, h: float, n: int, every: int = 1, progress=None) -> tuple[Trajectory, np.ndarray | None]:
        """The first ``n`` steps of ``h`` s (the run's inputs held step by step); the trajectory and
        the parameters in force from each row on (None without an input table)."""
        if self.inputs is None:
            return self.system.run(self.x0, 0.0, h, n, every=every, p=self.p, method=self.method,
                                   progress=progress, compensated=self.compensated), None
        from mbs.inputs import run_held

        return run_held(self.system, self.x0, h, n, self.p, self.inputs, every, self.method, progress,
                        self.compensated)

    def check_step(self, tolerance: float | None = None):
        """The step-error estimate over the first revolution (:func:`mbs.step_error.estimate`)."""
        from mbs import step_error

        res = step_error.estimate(self.system, self.x0, self.p, self.h, self.steps_per_rev, self.steps,
                                  self.method, tolerance or step_error.DEFAULT_TOLERANCE,
                                  run=lambda h, n, every: self.window(h, n, every)[0], units=self.units)
        res.unit = self.units.get(res.state, "")
        return res

    def cost(self, step_s: float | None = None):
        """Time and size of the run (:class:`mbs.run_cost.RunCost`), measured: a step (``step_s``,
        else timed here over up to a revolution) and a sample of recorded rows."""
        from mbs.run_cost import RunCost

        n = max(1, min(self.steps, self.steps_per_rev, ROW_SAMPLE))
        start = time.perf_counter()
        traj, rows_p = self.window(self.h, n)
        step_s = step_s or (time.perf_counter() - start) / n
        sample = self._finish(traj, rows_p)  # also the warm-up of the bound functions
        evaluator = self.system if self.system.dtype == np.float64 else _float64_twin(self.scene, self.options)
        start = time.perf_counter()
        _histories(evaluator, traj, self.p if rows_p is None else rows_p)
        cols, text = sample.columns(), io.StringIO()
        np.savetxt(text, np.column_stack(list(cols.values())), delimiter=",", fmt="%.17g")
        row_s = (time.perf_counter() - start) / len(traj.t)
        rows = self.steps // self.every + 1 + (self.steps % self.every > 0)
        return RunCost(self.steps, rows, len(cols), step_s, row_s, len(text.getvalue()) / len(traj.t), self.every)

    def execute(self, progress=None, evaluate_progress=None) -> Simulation:
        """Run, then evaluate the energies and outputs at every recorded row (``evaluate_progress``
        reports that part, row by row)."""
        nfev = self.system.nfev
        traj, rows_p = self.window(self.h, self.steps, self.every, progress)
        traj.nfev -= nfev  # this run's evaluations (the checks before it ran on the same system)
        return self._finish(traj, rows_p, evaluate_progress)

    def _finish(self, traj: Trajectory, rows_p, progress=None) -> Simulation:
        evaluator = self.system if self.system.dtype == np.float64 else _float64_twin(self.scene, self.options)
        p = self.p if rows_p is None else rows_p
        energy, outputs = _histories(evaluator, traj, p, progress)
        return Simulation(self.scene, self.system, traj, self.p, self.revs, self.steps_per_rev, energy, outputs,
                          self.compensated, self.method, rows_p, self.inputs, dict(self.settings), dict(self.units),
                          every=self.every, start=dict(self.start))


def _histories(system: System, traj: Trajectory, p, progress=None) -> tuple[np.ndarray, np.ndarray]:
    """Energies (n, 5) and outputs (n, n_out) at the rows of ``traj``; ``p`` (np,) or per row (n, np)
    (checked parameters: the generated functions are called on bound buffers, unchecked)."""
    n = len(traj.t)
    rows = np.broadcast_to(np.asarray(p, dtype=float), (n, len(system.info.param_names)))
    energy, outputs = np.empty((n, len(ENERGY_NAMES))), np.empty((n, len(system.info.output_names)))
    bound = [(system.bind("energy"), energy), (system.bind("outputs"), outputs)]
    for i in range(n):
        for f, out in bound:
            f.inputs[0][:], f.inputs[1][...], f.inputs[2][:] = traj.x[i], traj.t[i], rows[i]
            f()
            out[i] = f.outputs[0]
        if progress and (i % 1000 == 999 or i == n - 1):
            progress(i + 1, n)
    return energy, outputs


def prepare(scene: str | _scenes.Scene, revs: float = 1.0, steps_per_rev: int | None = None,
            dtype: str = "float64", backend: str = "compiled", params: dict | None = None, every: int = 1,
            system: System | None = None, x0=None, options: dict | None = None, compensated: bool = True,
            method: str = "rk4", inputs: InputTable | None = None, speed: float | None = None) -> Run:
    """Set up a run of ``scene`` for ``revs`` main-rotor revolutions of ``method`` at
    ``steps_per_rev`` (see :func:`simulate`) without running it. ``params`` and ``speed`` (m/s,
    the initial forward speed of a free fuselage) are the ``--set`` values and ``inputs`` an
    input table: each is checked against the model (ValueError naming it) before anything is
    compiled."""
    from mbs import inputs as inp

    scene = _scenes.get(scene) if isinstance(scene, str) else scene
    if not (np.isfinite(revs) and revs > 0):
        raise ValueError(f"revs = {revs} must be positive")
    steps_per_rev = steps_per_rev or scene.steps_per_rev
    if steps_per_rev < 1:
        raise ValueError(f"steps_per_rev = {steps_per_rev} must be >= 1")
    settings = {**(params or {}), **({} if speed is None else {inp.SPEED: speed})}
    system, units = _system(scene, system, backend, dtype, options, settings, inputs)
    p = system.params(params or {})
    n = int(round(revs * steps_per_rev))
    if n < 1:
        raise ValueError(f"revs = {revs:g} is less than one step ({steps_per_rev} steps per revolution: give at "
                         f"least {1 / steps_per_rev:g})")
    x = system.x0() if x0 is None else system.check_state(x0)
    run = Run(scene, system, p, x, scene.revolution(system, p) / steps_per_rev, n, steps_per_rev, every, method,
              compensated, inputs, settings, units, dict(options or {}))
    if x0 is not None:
        run.start = {"from": "given", "what": "the initial state given to the run (x0)"}
    if speed is not None:
        run.x0 = inp.with_forward_speed(system.info, x, speed)
    run.warnings += _setup_warnings(run, revs, speed, x)
    return run


def _system(scene, system, backend, dtype, options, settings, inputs) -> tuple[System, dict]:
    """The run's system, built after the settings and inputs are checked on the symbolic model,
    and the units of its columns."""
    from mbs.results import column_units

    if system is not None:
        limits = {q["name"]: q for q in system.info.parameters}
        free = any(b["joint"] == "FreeJoint" for b in system.info.bodies)
        _check_inputs(scene.name, limits, free, settings, inputs)
        return system, {}
    from mbs.backends import build

    model = scene.model(**(options or {}))
    limits = {n: {"low": q.low, "high": q.high, "unit": q.unit} for n, q in model.parameters.items()}
    free = any(type(b.joint).__name__ == "FreeJoint" for b in model.bodies.values())
    _check_inputs(scene.name, limits, free, settings, inputs)
    return build(model, backend, dtype), column_units(model)


def _check_inputs(scene: str, limits: dict, free: bool, settings: dict, inputs) -> None:
    from mbs import inputs as inp

    inp.check_settings(settings, limits, scene, free)
    if inputs is not None:
        inp.check_table(inputs, limits, scene, settings)


def _setup_warnings(run: Run, revs: float, speed: float | None, x_default: np.ndarray) -> list[str]:
    """What the set-up changed or cannot honour: a ``revs`` that is no whole number of steps, a
    speed away from the scene's trim, input jumps between step starts, rows after the end."""
    from mbs import inputs as inp

    out = []
    if abs(run.steps - revs * run.steps_per_rev) > 1e-9 * run.steps:
        out.append(f"--revs {revs:g} is {revs * run.steps_per_rev:g} steps at {run.steps_per_rev} steps per "
                   f"revolution: running {run.steps} steps ({run.revs:g} revolutions)")
    own = inp.initial_speed(run.system.info, x_default)
    if speed is not None and own is not None and abs(speed - own) > 1e-9:
        controls = [q["name"] for q in run.system.info.parameters if q.get("control")]
        out.append(f"--set speed={speed:g}: the run starts at {speed:g} m/s with the attitude"
                   f"{' and controls' if controls else ''} of scene {run.scene.name!r} at {own:g} m/s, so it starts "
                   f"with a transient; without --start scene 'heli simulate' starts from the periodic trim at "
                   f"{speed:g} m/s")
    if run.inputs is not None:
        stop = run.steps * run.h
        out += [f"--inputs {run.inputs.path}: the jump at t = {t:.6g} s acts at the next step start, t = {a:.6g} s "
                f"(the step is {run.h:.6g} s); put jumps on multiples of the step"
                for t, a in inp.late_switches(run.inputs, run.h, stop)]
        late = run.inputs.time[run.inputs.time > stop * (1 + 1e-12)]
        if late.size:
            out.append(f"--inputs {run.inputs.path}: {late.size} row(s) after the end of the run (t = {stop:.6g} s) "
                       "are not used")
    return out


def simulate(scene: str | _scenes.Scene, revs: float = 1.0, steps_per_rev: int | None = None,
             dtype: str = "float64", backend: str = "compiled", params: dict | None = None,
             every: int = 1, progress=None, system: System | None = None, x0=None,
             options: dict | None = None, compensated: bool = True, method: str = "rk4",
             inputs: InputTable | None = None, speed: float | None = None) -> Simulation:
    """Run ``scene`` for ``revs`` main-rotor revolutions of ``method`` (a fixed-step method of
    the generated driver: ``rk4``, the paper's, ``rk8`` or ``euler``) at ``steps_per_rev``.

    ``compensated=False`` turns off the compensated summation of the step updates (plain
    floating-point arithmetic, as in the paper). ``inputs``: an input table
    (:class:`mbs.inputs.InputTable`) held step by step; ``speed``: the initial forward speed
    (m/s) of a free fuselage. No step-error check and no cost estimate here: ``heli simulate``
    makes them (:meth:`Run.check_step`, :meth:`Run.cost`).
    """
    return prepare(scene, revs, steps_per_rev, dtype, backend, params, every, system, x0, options, compensated,
                   method, inputs, speed).execute(progress)


def _float64_twin(scene, options) -> System:
    """Energies and outputs of single-precision runs are evaluated in float64."""
    return scene.system("vm", **(options or {}))


def write(sim: Simulation, out: Path, progress=None) -> dict[str, Path]:
    """Write ``results.csv`` (``progress(rows, n)`` as it goes), ``run.json`` and the plots into
    ``out``; returns the paths. The files are written under temporary names and renamed
    together at the end (:class:`mbs.atomic.Files`): Ctrl-C or an error leaves the folder as
    it was, and ``run.json`` records the SHA-256 of the ``results.csv`` it belongs to."""
    from mbs import atomic, plots
    from mbs.results import RESULTS_DIGEST, write_csv

    out = Path(out)
    names = {"results": "results.csv", "run": "run.json", "hinge_angles": "hinge_angles.png"}
    if sim.scene.conservative:
        names["energy_error"] = "energy_error.png"
    paths = {k: out / v for k, v in names.items()}
    with atomic.Files(stale=(out / "energy_error.png",)) as files:
        tmp = {k: files.temporary(p) for k, p in paths.items()}
        write_csv(sim.columns(), tmp["results"], progress)
        tmp["run"].write_text(json.dumps({**sim.summary(), RESULTS_DIGEST: atomic.sha256(tmp["results"])}, indent=1))
        plots.hinge_angles(sim, tmp["hinge_angles"])
        if "energy_error" in tmp:
            plots.energy_error([sim], tmp["energy_error"])
    return paths
