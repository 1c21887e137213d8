"""Naming the loop that could not close, when a run stopped on a non-finite state.

A local loop's dependent coordinates are NaN where the loop cannot close (:mod:`mbs.loops`), so
such a run stops with the generated code's non-finite status. This module finds which loop and
when: it redoes the failed step from the last state recorded before it, one step at a time,
and evaluates the closure margins (the outputs ``<loop>.closure_margin``) at the failed step's
stage states and times; the first negative or non-finite margin names the loop. Run-time only
(numpy and the model's generated functions).
"""
from __future__ import annotations

import numpy as np

SUFFIX = ".closure_margin"


def margins(info) -> list[tuple[int, str]]:
    """(output index, loop name) of every closure margin among the model's outputs."""
    return [(i, n[:-len(SUFFIX)]) for i, n in enumerate(info.output_names) if n.endswith(SUFFIX)]


def _stages(system, method: str, x: np.ndarray, t: float, h: float, p) -> list[tuple[np.ndarray, float]]:
    """(state, time) at which ``method``'s step from ``(x, t)`` evaluates the right-hand side
    (the step's start and end only for an implicit method)."""
    try:
        from mbs.integrators import TABLEAUX
        tab = TABLEAUX[method]
    except (ImportError, KeyError):
        return [(x, t), (x, t + h)]
    a = np.array(tab.a, dtype=float)
    if np.any(np.triu(a)):
        return [(x, t), (x, t + 0.5 * h), (x, t + h)]
    out, slopes = [], []
    for i, c in enumerate(tab.c):
        xi = x + h * sum((a[i, j] * k for j, k in enumerate(slopes)), np.zeros_like(x))
        out.append((xi, t + c * h))
        if not np.all(np.isfinite(xi)):
            break
        slopes.append(system._eval("rhs", xi, t + c * h, p)[0])
    return out


def explain(system, method: str, x: np.ndarray, t: float, h: float, steps: int, p) -> str | None:
    """Why the run from the recorded state ``x`` at ``t`` (s) failed within ``steps`` steps of
    ``h`` (s): "loop <name> cannot close at t = ... s (closure margin ...)", or None when every
    loop closes there (or the model has none)."""
    loops = margins(system.info)
    if not loops:
        return None
    with np.errstate(all="ignore"):
        for _ in range(max(int(steps), 1)):
            rows, status, done = system._run(method, x, t, h, 0, 1, 1, p, np.zeros_like(x), False)
            if status or not done:
                break
            x, t = rows[-1], t + h
        for xs, ts in _stages(system, method, x, t, h, p):
            if not np.all(np.isfinite(xs)):
                return None
            y = system._eval("outputs", xs, ts, p)[0]
            for i, name in loops:
                if not y[i] >= 0:
                    return (f"loop {name} cannot close at t = {ts:.6g} s, closure margin {y[i]:.3g}: its link "
                            "cannot reach its anchor or its Newton solve did not converge")
    return None


def reworded(system, traj, method: str, t0: float, h: float, k: int, p) -> str:
    """The message of a run that stopped on a non-finite state after ``k`` steps: the loop that
    could not close, if one did not, in place of the generic reason (the time and step of the
    failed step stay last, in parentheses)."""
    why = explain(system, method, traj.x[-1], traj.t[-1], h, k - int(round((traj.t[-1] - t0) / h)), p)
    if not why:
        return traj.message
    _, _, where = traj.message.rpartition(" (at t")
    return f"the state became non-finite: {why} (at t{where}"
