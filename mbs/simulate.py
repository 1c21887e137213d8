"""Run a scene and write its results: ``results.csv``, ``run.json`` and plots.

``results.csv`` columns: ``time`` (s), every state by name (rad, rad/s, m, m/s, quaternion),
every model output by name, and the energies ``kinetic_translational``,
``kinetic_rotational``, ``potential_gravity``, ``potential_spring``, ``total_energy`` (J).
``run.json`` records the scene (with its aircraft file and aerodynamics switches: see
:func:`run_record`), parameters, integrator and figures, so that a results folder can be
re-opened (e.g. by the viewer, :func:`scene_of_run`) without guessing.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mbs import scenes as _scenes
from mbs.backends.system import System, Trajectory

ENERGY_NAMES = ["kinetic_translational", "kinetic_rotational", "potential_gravity",
                "potential_spring", "total_energy"]


@dataclass
class Simulation:
    """A finished run of a scene: trajectory plus energies (n, 5) and outputs (n, n_out)."""

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

    @property
    def max_rel_energy_error(self) -> float:
        e = self.energy[:, -1]
        return float(np.abs(e / e[0] - 1).max())

    def columns(self) -> dict[str, np.ndarray]:
        info = self.system.info
        cols = {"time": self.traj.t}
        cols.update({n: self.traj.x[:, i] for i, n in enumerate(info.state_names)})
        cols.update({n: self.outputs[:, i] for i, n in enumerate(info.output_names)})
        cols.update({n: self.energy[:, i] for i, n in enumerate(ENERGY_NAMES)})
        return cols

    def summary(self) -> dict:
        out = {**run_record(self.scene), "revs": self.revs, "steps_per_rev": self.steps_per_rev,
               "steps": int(round(self.revs * self.steps_per_rev)), "dtype": str(self.system.dtype),
               "backend": self.system.backend, "method": self.method, "compensated_summation": self.compensated,
               "wall_s": self.traj.wall_s,
               "realtime_factor": (self.traj.t[-1] - self.traj.t[0]) / max(self.traj.wall_s, 1e-12),
               "nfev": self.traj.nfev, "result": self.traj.result.name, "message": self.traj.message,
               "parameters": dict(zip(self.system.info.param_names, self.params.tolist()))}
        if self.scene.conservative:
            out["max_rel_energy_error"] = self.max_rel_energy_error
        return out


def run_record(scene: _scenes.Scene) -> dict:
    """What rebuilds ``scene`` (:func:`scene_of_run`): its name and, for a helicopter scene, its
    aircraft (name, file, SHA-256 of the file) and aerodynamics switches."""
    if scene.aircraft is None:
        return {"scene": scene.name}
    from mbs.models.helicopter import aero_switches

    craft = scene.aircraft
    return {"scene": scene.name, "aircraft": {"name": craft.name, "file": str(craft.path.resolve()),
                                              "sha256": craft.digest}, "aero": aero_switches(scene)}


def scene_of_run(meta: dict, where: str = "run.json") -> _scenes.Scene:
    """The scene a ``run.json`` (``meta``, read from ``where``) records: ValueError naming what is
    missing, or an aircraft file that is gone or has changed since the run."""
    from mbs import aircraft
    from mbs.models.helicopter import with_aero

    if "scene" not in meta:
        raise ValueError(f"no run.json with a scene name next to {where}: cannot tell which model to show")
    recorded = meta.get("aircraft")
    craft = None
    if recorded:
        try:
            craft = aircraft.load(recorded["file"])
        except aircraft.AircraftError as exc:
            raise ValueError(f"{where}: the run's aircraft {recorded['name']!r} cannot be loaded: {exc}") from None
        if craft.digest != recorded["sha256"]:
            raise ValueError(f"{where}: the aircraft file {recorded['file']} has changed since the run; the model "
                             "would not be the one that ran (restore the file, or run again)")
    scene = _scenes.get(meta["scene"], aircraft=craft)
    aero = meta.get("aero")
    return with_aero(scene, ",".join(aero) or "none") if aero is not None else scene


def simulate(scene: str | _scenes.Scene, revs: float = 1.0, steps_per_rev: int | None = None,
             dtype: str = "float64", backend: str = "compiled", params: dict | None = None,
             every: int = 1, progress=None, system: System | None = None, x0=None,
             options: dict | None = None, compensated: bool = True, method: str = "rk4") -> Simulation:
    """Run ``scene`` for ``revs`` main-rotor revolutions of ``method`` (a fixed-step method of
    the generated driver: ``rk4``, the paper's, ``rk8`` or ``euler``) at ``steps_per_rev``.

    ``compensated=False`` turns off the compensated summation of the step updates (plain
    floating-point arithmetic, as in the paper).
    """
    scene = _scenes.get(scene) if isinstance(scene, str) else scene
    if not (np.isfinite(revs) and revs > 0):
        raise ValueError(f"revs = {revs} must be positive")
    steps_per_rev = steps_per_rev or scene.steps_per_rev
    if steps_per_rev < 1:
        raise ValueError(f"steps_per_rev = {steps_per_rev} must be >= 1")
    system = system or scene.system(backend, dtype, **(options or {}))
    p = system.params(params or {})
    h = scene.revolution(system, p) / steps_per_rev
    n = int(round(revs * steps_per_rev))
    traj = system.run(system.x0() if x0 is None else x0, 0.0, h, n, every=every, p=p, progress=progress,
                      compensated=compensated, method=method)
    evaluator = system if system.dtype == np.float64 else _float64_twin(scene, options)
    return Simulation(scene, system, traj, p, revs, steps_per_rev, evaluator.history("energy", traj, p),
                      evaluator.history("outputs", traj, p), compensated, method)


def _float64_twin(scene, options) -> System:
    """Energies and outputs of single-precision runs are evaluated in float64."""
    return scene.system("vm", **(options or {}))


def write(sim: Simulation, out: Path) -> dict[str, Path]:
    """Write ``results.csv``, ``run.json`` and the plots into ``out``; returns the paths."""
    from mbs import plots

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cols = sim.columns()
    paths = {"results": out / "results.csv", "run": out / "run.json"}
    np.savetxt(paths["results"], np.column_stack(list(cols.values())), delimiter=",",
               header=",".join(cols), comments="", fmt="%.17g")
    paths["run"].write_text(json.dumps(sim.summary(), indent=1))
    paths["hinge_angles"] = plots.hinge_angles(sim, out / "hinge_angles.png")
    if sim.scene.conservative:
        paths["energy_error"] = plots.energy_error([sim], out / "energy_error.png")
    return paths


def read_results(folder_or_csv: Path) -> tuple[dict[str, np.ndarray], dict]:
    """Columns of a ``results.csv`` and the ``run.json`` beside it (empty if absent)."""
    path = Path(folder_or_csv)
    csv = path / "results.csv" if path.is_dir() else path
    if not csv.exists():
        raise FileNotFoundError(f"no results file at {csv}")
    names = csv.read_text().split("\n", 1)[0].split(",")
    data = np.loadtxt(csv, delimiter=",", skiprows=1, ndmin=2)
    meta_path = csv.parent / "run.json"
    meta = json.loads(meta_path.read_text()) if meta_path.exists() else {}
    return {n: data[:, i] for i, n in enumerate(names)}, meta
