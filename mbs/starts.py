"""Start states of a run: the scene's own, or the periodic trim at a speed.

``scene``: the model's initial state (a helicopter scene's: trimmed controls and attitude,
every blade released at zero flap and lag). ``periodic``: the periodic trim of
:func:`mbs.analysis.trim.trim` at the scene's own speed; ``periodic:V``: at ``V`` m/s (RK4 at
the run's steps per revolution, so that the run with the trim's controls held is periodic from
its first step): controls, attitude, velocities and every rotor state. The same function
gives ``heli simulate --start`` and the starts of ``heli fly``'s page, so that a flight flown
in the page replays in ``heli simulate`` from the same state, bit for bit on one machine.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

KINDS = ("scene", "periodic")


@dataclass
class Start:
    """A start: ``x0`` (nx,) state, ``controls`` (name -> rad) the trim's (empty for the scene's
    own start), ``speed`` the trim's speed (m/s; None for the scene's own start), ``text`` as
    written (``--start``), ``residual`` the trim's max-norm scaled periodicity residual."""

    text: str
    x0: np.ndarray
    controls: dict[str, float]
    speed: float | None = None
    residual: float | None = None

    def summary(self) -> dict:
        return {"start": self.text, "speed": self.speed, "controls": self.controls, "residual": self.residual}


def parse(text: str) -> tuple[str, float | None]:
    """``scene``, ``periodic`` or ``periodic:V`` (V in m/s) -> (kind, V or None); ValueError otherwise."""
    kind, _, speed = str(text).partition(":")
    if kind not in KINDS or (kind == "scene" and speed):
        raise ValueError(f"start {text!r} is not one of: scene, periodic, periodic:V (the periodic trim at V m/s)")
    if not speed:
        return kind, None
    try:
        value = float(speed)
    except ValueError:
        raise ValueError(f"start {text!r}: {speed!r} is not a speed in m/s") from None
    if not math.isfinite(value):
        raise ValueError(f"start {text!r}: the speed must be a finite number of m/s")
    return kind, value


def start(text: str, scene, system, steps_per_rev: int | None = None) -> Start:
    """The start ``text`` (:func:`parse`) of ``scene`` for ``system`` (its compiled model)."""
    kind, speed = parse(text)
    if kind == "scene":
        return Start(text, np.asarray(system.x0(), dtype=float), {})
    return periodic(scene, speed, steps_per_rev, system, text)


def periodic(scene, speed: float | None = None, steps_per_rev: int | None = None, system=None,
             text: str | None = None) -> Start:
    """The periodic trim of ``scene`` at ``speed`` (m/s; default the scene's own) as a start;
    ValueError naming the scene when it cannot be trimmed or the trim does not converge."""
    from mbs.analysis.trim import trim

    res = trim(scene, speed=speed, method="rk4", steps_per_rev=steps_per_rev or scene.steps_per_rev,
               system=system if system is not None and system.backend == "compiled" else None)
    if not res.converged:
        at = f" at {speed:g} m/s" if speed is not None else ""
        raise ValueError(f"the periodic trim of {scene.name!r}{at} did not converge ({res.reason}); start from "
                         "another speed or from the scene's own start")
    label = text or ("periodic" if speed is None else f"periodic:{speed:g}")
    return Start(label, np.asarray(res.x0, dtype=float), res.controls or _controls(scene, res.params),
                 float(res.speed), float(np.abs(res.residual).max()))


def _controls(scene, params) -> dict[str, float]:
    """The controls among the parameters ``params`` (a scene that is not trimmed for its controls:
    the periodic rotor response at the scene's own)."""
    model = scene.model()
    return {n: float(v) for (n, q), v in zip(model.parameters.items(), params) if q.control}
