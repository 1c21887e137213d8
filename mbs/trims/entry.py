"""A trim as stored data, and the check that a stored trim still holds for a model."""
from __future__ import annotations

import numpy as np

from mbs.trims.store import identity

TOLERANCE = 1e-8
"""Largest max-norm scaled periodicity residual of a stored trim that is used (per rotor radius
and revolution; the trims converge to 1e-10 or below)."""


TURNING = ("main_hub.azimuth", "transmission.angle")
"""States that advance by 2π per revolution on a periodic solution (a drive train's azimuths)."""


def scene_identity(scene, parameters: dict, speed: float, climb_rate: float, method: str,
                   steps_per_rev: int) -> dict:
    """:func:`mbs.trims.store.identity` of the scene ``scene`` (a :class:`mbs.scenes.Scene`)."""
    return identity(scene.aircraft, scene.name, _switches(scene), parameters, speed, climb_rate, method,
                    steps_per_rev)


def _switches(scene) -> list[str]:
    if scene.aircraft is None:
        return []
    from mbs.models.helicopter import aero_switches

    return aero_switches(scene)


def entry_of(result, scene, parameters: dict | None = None) -> dict:
    """The stored form of the converged trim ``result`` (:class:`mbs.analysis.trim.Trim`) of
    ``scene`` at the run-time ``parameters`` (name -> value, the controls excluded)."""
    ident = scene_identity(scene, parameters or {}, result.speed, result.climb_rate, result.method,
                           result.steps_per_rev)
    craft = scene.aircraft
    about = {"aircraft": craft.name, "aircraft_file": str(craft.path.resolve())} if craft is not None else {}
    return {"scene": ident["scene"], **about, **ident, "shooting_revs": result.period.revs,
            "controls": {k: float(v) for k, v in result.controls.items()}, "roll": float(result.roll),
            "pitch": float(result.pitch), "max_abs_residual": float(np.abs(result.residual).max()),
            "state": {k: float(v) for k, v in result.state.items()}}


def residual(entry: dict, system, scene) -> float:
    """Max-norm scaled periodicity residual of the stored ``entry`` for ``system`` (the scene's
    model, its parameters those of the entry): ``S x(τ) - x(0)`` over every state but the
    position, after the trim's shooting interval ``τ`` with its controls held; ``inf`` when the
    model's states or controls are not those of the entry or the run fails. A tail rotor whose
    gear ratio does not repeat soon is checked over the period it was trimmed over, that of the
    nearest ratio that repeats (:func:`mbs.analysis.period.periodic_scene`)."""
    from mbs.analysis.period import periodic_scene, scene_period
    from mbs.analysis.shooting import residual_scales
    from mbs.analysis.trim import reference_radius

    info = system.info
    try:
        x0 = np.array([entry["state"][n] for n in info.state_names])
        p = system.params(entry["controls"])
    except (KeyError, ValueError):
        return float("inf")
    period = scene_period(periodic_scene(scene), system, p)
    n = period.revs * entry["steps_per_rev"]
    traj = system.run(x0, 0.0, period.duration / n, n, every=n, p=p, method=entry["method"])
    if not traj.ok:
        return float("inf")
    keep = [i for i, name in enumerate(info.state_names) if name not in ("fuselage.x", "fuselage.y", "fuselage.z")
            and name not in TURNING]
    source = period.permutation(info.nx)[keep]
    r = period.symmetry(info.nx)[keep] * traj.x[-1][source] - x0[keep]
    radius = reference_radius(scene)
    return float(np.max(np.abs(r) / residual_scales([info.state_names[i] for i in keep], period.omega, radius)))
