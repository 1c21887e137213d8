"""Periodic start states of the FMU's scenes: the trimmed periodic solution, as data.

A scene's own initial state releases every blade at zero flap and lag; in the Bo105 scenes
the lag then rings at its low damping for many revolutions. The FMU can start instead from
the scene's periodic trim (``initial_state = "periodic"``): controls, attitude, fuselage
velocities and every rotor state from :func:`mbs.analysis.trim.trim` (RK4 at the scene's
steps per revolution, the FMU's default step), so that a run with the trim inputs held is
periodic from its first step.

The trims of the packaged Bo105 are computed once and stored with their provenance in
``periodic_starts.json`` (``python -m fmu.periodic`` rewrites it); another aircraft's are
trimmed when its FMU is built. The FMU build checks each stored start against
the model it compiles by running it over the shooting interval of the trim (two
revolutions, teeter reversed) and uses it when the scaled periodicity residual is below
:data:`TOLERANCE`; otherwise it trims that scene again at build time (slower: the tangent
step is compiled) and says so. The test suite checks that the stored starts still hold.
"""
from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from fmu import DEFAULT_SCENES

HERE = Path(__file__).resolve().parent
DATA = HERE / "periodic_starts.json"
TOLERANCE = 1e-8
"""Largest max-norm scaled periodicity residual of a stored start (per rotor radius and
revolution; the trims converge to 1e-10 or below)."""


def compute(scene) -> dict:
    """The periodic trim of ``scene`` (a name or a :class:`mbs.scenes.Scene`) at its own speed as
    a stored entry: controls (rad), every state by name (SI units, rad), the trim's figures and
    its provenance. A scene whose rotor speed is a state is trimmed at the rotor's nominal speed
    with the governor's reference (engines) or the drive torque as the extra control
    (:mod:`mbs.analysis.rotor_speed_trim`)."""
    from mbs.analysis.trim import trim

    if free_rotor(scene):
        return _compute_rotor_speed(scene)
    res = trim(scene, method="rk4")
    if not res.converged:
        raise RuntimeError(f"the periodic trim of {getattr(scene, 'name', scene)!r} did not converge: {res.reason}")
    return {"speed": res.speed, "climb_rate": res.climb_rate, "method": res.method,
            "steps_per_rev": res.steps_per_rev, "shooting_revs": res.period.revs, "controls": res.controls,
            "roll": res.roll, "pitch": res.pitch, "state": res.state,
            "max_abs_residual": float(np.abs(res.residual).max()), "iterations": res.iterations,
            "provenance": provenance()}


def free_rotor(scene) -> bool:
    """Whether ``scene`` (a name or a :class:`mbs.scenes.Scene`) turns its rotors on a drive train."""
    from mbs import scenes

    sc = scenes.get(scene) if isinstance(scene, str) else scene
    return bool(sc.options.get("drive_train", getattr(getattr(sc.builder, "config", None), "drive_train", None)))


def _compute_rotor_speed(scene) -> dict:
    from mbs import scenes
    from mbs.analysis.rotor_speed_trim import rotor_speed_trim
    from mbs.analysis.trim import evaluators

    sc = scenes.get(scene) if isinstance(scene, str) else scene
    system, stepper = evaluators(sc)
    extra = "governor_speed" if "governor_speed" in system.info.param_names else "drive_torque"
    i = system.info.state_names.index
    speed = round(float(np.linalg.norm(system.x0()[[i("fuselage.u"), i("fuselage.v"), i("fuselage.w")]])), 6)
    res = rotor_speed_trim(sc, speed, extra=extra, system=system, stepper=stepper)
    if not res.converged:
        raise RuntimeError(f"the periodic trim of {sc.name!r} did not converge: {res.reason}")
    controls = [q["name"] for q in system.info.parameters if q.get("control") and not q["name"].endswith("_throttle")]
    return {"speed": speed, "climb_rate": 0.0, "method": "rk4", "steps_per_rev": sc.steps_per_rev,
            "shooting_revs": scene_revs(sc, system), "controls": {**{c: res.unknowns[c] for c in controls},
                                                                   extra: res.unknowns[extra]},
            "roll": res.unknowns["roll"], "pitch": res.unknowns["pitch"],
            "state": dict(zip(system.info.state_names, map(float, res.x0))), "max_abs_residual": res.residual,
            "iterations": res.iterations, "provenance": provenance()}


def scene_revs(sc, system) -> int:
    from mbs.analysis.period import scene_period

    return scene_period(sc, system).revs


def provenance() -> dict:
    """Where an entry comes from: the command, the date, the versions and the source commit."""
    try:
        commit = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=HERE, capture_output=True,
                                text=True, timeout=10).stdout.strip() or None
    except OSError:
        commit = None
    return {"generated_by": "python -m fmu.periodic (mbs.analysis.trim.trim)",
            "date": datetime.date.today().isoformat(), "commit": commit,
            "rotor_mbs": _version("rotor-mbs"), "casadi": _version("casadi")}


def _version(dist: str) -> str | None:
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return None


def residual(entry: dict, system, scene) -> float:
    """Max-norm scaled periodicity residual of the stored ``entry`` for ``system`` (the scene's
    model): :func:`mbs.trims.entry.residual`, the check of every stored trim."""
    from mbs.trims.entry import residual as periodicity

    return periodicity(entry, system, scene)


def stored() -> dict:
    """The stored entries by scene (empty when the file is absent)."""
    return json.loads(DATA.read_text())["scenes"] if DATA.exists() else {}


def start(scene, system, log=None) -> dict | None:
    """The periodic start of ``scene`` (a :class:`mbs.scenes.Scene`) for ``system``: the
    stored entry when it holds for this model, else a fresh trim; None when the scene cannot
    be trimmed."""
    from mbs.analysis.trim import trimmable

    if not trimmable(scene) and not (free_rotor(scene) and _flies(scene)):
        return None
    bo105 = scene.aircraft is None or (scene.aircraft.packaged and scene.aircraft.key == "bo105")
    entry = stored().get(scene.name) if bo105 else None
    r = residual(entry, system, scene) if entry else float("inf")
    if r <= TOLERANCE:
        return {**entry, "check_residual": r}
    if log and bo105:
        log(f"the stored periodic start of {scene.name!r} does not hold for this model (residual {r:.3g} > "
            f"{TOLERANCE:g}); trimming it now (python -m fmu.periodic stores it)")
    elif log:
        log(f"trimming the periodic start of {scene.name!r} of the {scene.aircraft.name} (the stored starts are "
            "the Bo105's)")
    entry = compute(scene)
    return {**entry, "check_residual": residual(entry, system, scene)}


def _flies(scene) -> bool:
    cfg = getattr(scene.builder, "config", None)
    return scene.options.get("fuselage", getattr(cfg, "fuselage", None)) == "free"


def write(scene_names) -> Path:
    """Trim every scene of ``scene_names`` and store the entries in :data:`DATA`."""
    entries = {**stored(), **{name: compute(name) for name in scene_names}}
    DATA.write_text(json.dumps({"about": __doc__.split("\n\n")[0], "scenes": entries}, indent=1) + "\n")
    return DATA


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="trim the FMU's scenes and store their periodic start states")
    ap.add_argument("--scenes", default=",".join(DEFAULT_SCENES), help="comma-separated scenes to trim")
    args = ap.parse_args(argv)
    print(f"wrote {write(args.scenes.split(','))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
