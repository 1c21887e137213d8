"""Is the fixed step fine enough? A step-doubling estimate of its error before a run.

The first main-rotor revolution (or the whole run, when shorter) is run twice: with the run's
step ``h`` and with ``h/2``. For a method of order ``p`` the error of the ``h`` solution is
``|x_h - x_{h/2}| 2^p / (2^p - 1)`` (Richardson), at every step of the window. Each state's
largest error is compared with its scale: its range over the window, at least a thousandth
of its magnitude and a floor by its unit (:data:`FLOORS`: 1e-4 rad, 1e-3 rad/s, 1e-4 m,
1e-3 m/s; 1e-6 otherwise), so that a state that barely moves (the fuselage's rates in a
trimmed run, a few thousandths of a degree per second) is not judged by its own vibration. The worst state's
ratio, against the tolerance (default 1 %), decides; the step that would do follows from the
order, ``steps_per_rev (ratio / tolerance)^(1/p)``, with 10 % margin, rounded up to a
multiple of 10.

Cost: three revolutions' worth of steps (one at ``h``, two at ``h/2``), whatever the run's
length; the ``h`` window also times a step for the run's duration estimate.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

DEFAULT_TOLERANCE = 0.01
FLOORS = {"rad": 1e-4, "rad/s": 1e-3, "m": 1e-4, "m/s": 1e-3}
"""Smallest scale of a state's error by its unit (1 % of it: 6e-5 deg, 6e-4 deg/s, 1 µm, 10 µm/s)."""
FLOOR = 1e-6


def floors(names: list[str], units: dict[str, str]) -> np.ndarray:
    """The scale floor of each state ``names`` from its unit (``units``: name -> unit)."""
    return np.array([FLOORS.get(units.get(n, ""), FLOOR) for n in names])


def order_of(method: str) -> int:
    """The order of the fixed-step ``method`` (from its Butcher tableau in :mod:`mbs.integrators`)."""
    from mbs.integrators import TABLEAUX

    return TABLEAUX[method].order


@dataclass
class StepError:
    """The estimate: ``ratio`` of the worst state's error to its scale (None when it could not be
    estimated, ``note`` says why), that state's name, ``error`` and ``scale`` (its unit),
    ``tolerance``, ``suggested_steps_per_rev`` when the ratio exceeds it, the window (steps
    at the run's step), the cost ``wall_s`` and the measured time per step ``step_s`` (s)."""

    steps_per_rev: int
    method: str
    window_steps: int
    tolerance: float
    ratio: float | None
    state: str = ""
    error: float = 0.0
    scale: float = 0.0
    suggested_steps_per_rev: int | None = None
    unit: str = ""
    wall_s: float = 0.0
    step_s: float = 0.0
    note: str = ""

    @property
    def ok(self) -> bool:
        """False only when the estimate exceeds the tolerance."""
        return self.ratio is None or self.ratio <= self.tolerance

    def summary(self) -> dict:
        return {"estimated": self.ratio is not None, "ok": self.ok, "ratio": self.ratio, "state": self.state,
                "error": self.error, "scale": self.scale, "tolerance": self.tolerance,
                "suggested_steps_per_rev": self.suggested_steps_per_rev, "window_steps": self.window_steps,
                "method": self.method, "steps_per_rev": self.steps_per_rev, "wall_s": self.wall_s,
                "step_s": self.step_s, "unit": self.unit, "note": self.note}

    def message(self) -> str:
        """One line: what the estimate says (a warning when it exceeds the tolerance)."""
        if self.ratio is None:
            return f"step error not estimated: {self.note}"
        u = f" {self.unit}" if self.unit and self.unit != "1" else ""
        what = (f"estimated step error {100 * self.ratio:.3g} % of the range of {self.state} over the first "
                f"{self.window_steps} steps (error {self.error:.3g}{u}, range {self.scale:.3g}{u}; tolerance "
                f"{100 * self.tolerance:g} %)")
        if self.ok:
            return what
        return (f"{self.steps_per_rev} {self.method} steps per revolution are too coarse: {what}; "
                f"use --steps-per-rev {self.suggested_steps_per_rev} or more")


def estimate(system, x0, p, h: float, steps_per_rev: int, n_steps: int, method: str = "rk4",
             tolerance: float = DEFAULT_TOLERANCE, run=None, units: dict | None = None) -> StepError:
    """Step-doubling estimate for a run of ``n_steps`` steps of ``h`` s from ``x0`` with
    parameters ``p``: the window is one revolution, ``steps_per_rev`` steps, even for a shorter
    run (a window of a few steps sees too little motion to judge the step). ``run(h, n, every)``
    runs the window (default ``system.run``; a run with an input table passes its own) and
    returns a :class:`mbs.backends.system.Trajectory`; ``units``: state name -> unit (the
    scale floors, :func:`floors`)."""
    run = run or (lambda hh, n, every: system.run(x0, 0.0, hh, n, every=every, p=p, method=method))
    window = max(1, steps_per_rev)
    start = time.perf_counter()
    coarse = run(h, window, 1)
    step_s = (time.perf_counter() - start) / window
    fine = run(h / 2, 2 * window, 2) if coarse.ok else None
    base = StepError(steps_per_rev, method, window, tolerance, None, step_s=step_s)
    if not coarse.ok:
        base.note = f"the run fails within its first {window} steps ({coarse.message})"
    elif not fine.ok:
        base.note = f"the run at half the step fails ({fine.message})"
    else:
        names = system.info.state_names
        base = _compare(base, coarse.x, fine.x, names, order_of(method), floors(names, units or {}))
    base.wall_s = time.perf_counter() - start
    return base


def _compare(res: StepError, coarse: np.ndarray, fine: np.ndarray, names: list[str], order: int,
             floor: np.ndarray) -> StepError:
    error = np.abs(coarse - fine).max(axis=0) * 2**order / (2**order - 1)
    scale = np.maximum.reduce([np.ptp(fine, axis=0), 1e-3 * np.abs(fine).max(axis=0), floor])
    ratio = error / scale
    i = int(np.argmax(ratio))
    res.ratio, res.state, res.error, res.scale = float(ratio[i]), names[i], float(error[i]), float(scale[i])
    if not res.ok:
        needed = res.steps_per_rev * (res.ratio / res.tolerance) ** (1 / order) * 1.1
        res.suggested_steps_per_rev = int(math.ceil(needed / 10) * 10)
    return res
