"""Newton's method with a backtracking line search, counting its work.

Generic: ``residual(z) -> r`` (scaled, so that one norm fits all components) and
``jacobian(z) -> J``; the step ``J dz = -r`` is accepted when the scaled residual's
2-norm falls by the Armijo factor, otherwise halved (down to ``min_step``).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np


@dataclass
class Iteration:
    """One Newton iteration: scaled residual (max norm) before the step, step length taken
    (1 = full Newton step), trial residual evaluations, wall time so far (s)."""

    residual: float
    step: float
    trials: int
    wall_s: float


@dataclass
class NewtonResult:
    """Solution ``z``, its scaled residual ``r``, the history, and why it stopped."""

    z: np.ndarray
    r: np.ndarray
    converged: bool
    reason: str
    history: list[Iteration] = field(default_factory=list)
    n_jacobian: int = 0
    n_residual: int = 0
    wall_s: float = 0.0

    @property
    def residuals(self) -> list[float]:
        """Max-norm scaled residual at every iterate, the final one included."""
        return [it.residual for it in self.history] + [float(np.abs(self.r).max())]


class Failure(RuntimeError):
    """A residual evaluation that cannot be made (diverged run, control outside its range)."""


def newton(residual: Callable, jacobian: Callable, z0: np.ndarray, tol: float = 1e-10,
           max_iterations: int = 20, min_step: float = 1.0 / 64, progress=None) -> NewtonResult:
    """Solve ``residual(z) = 0`` from ``z0``; stops at ``max |r| <= tol``."""
    res, start = NewtonResult(np.array(z0, dtype=float), np.array([np.inf]), False, ""), time.perf_counter()
    try:
        res.r, res.n_residual = residual(res.z), 1
    except Failure as exc:
        return _stop(res, f"the starting point cannot be evaluated: {exc}", start)
    while np.abs(res.r).max() > tol:
        if len(res.history) == max_iterations:
            return _stop(res, f"no convergence in {max_iterations} iterations (max |scaled residual| "
                              f"{np.abs(res.r).max():.2e} > {tol:g})", start)
        reason = _iterate(res, residual, jacobian, min_step, start)
        if progress:
            progress(len(res.history), max_iterations)
        if reason:
            return _stop(res, reason, start)
    res.converged = True
    return _stop(res, f"max |scaled residual| {np.abs(res.r).max():.2e} <= {tol:g}", start)


def _iterate(res: NewtonResult, residual, jacobian, min_step: float, start: float) -> str:
    """One damped Newton step in place; returns why it failed, or ''."""
    try:
        r, jac = res.r, jacobian(res.z)
    except Failure as exc:
        return f"the Jacobian cannot be evaluated: {exc}"
    res.n_jacobian += 1
    try:
        dz = np.linalg.solve(jac, -r)
    except np.linalg.LinAlgError:
        return "the Jacobian is singular: the unknowns do not determine the residual"
    step, trials, r_new, failure = _line_search(residual, res.z, dz, r, min_step)
    res.n_residual += trials
    res.history.append(Iteration(float(np.abs(r).max()), step, trials, time.perf_counter() - start))
    if r_new is None:
        why = f"; the smallest step could not be run: {failure}" if failure else ""
        return f"the line search found no decrease down to a step of {min_step:g}{why}"
    res.z, res.r = res.z + step * dz, r_new
    return ""


def _line_search(residual, z, dz, r, min_step: float) -> tuple[float, int, np.ndarray | None, str]:
    """Largest step ``2^-k`` with ``|r(z + step dz)| <= (1 - 1e-4 step) |r(z)|`` (2-norm); with
    none, why the last trial could not be evaluated ('' when it could)."""
    step, trials, norm = 1.0, 0, np.linalg.norm(r)
    while step >= min_step:
        trials += 1
        failure = ""
        try:
            r_new = residual(z + step * dz)
            if np.linalg.norm(r_new) <= (1 - 1e-4 * step) * norm:
                return step, trials, r_new, ""
        except Failure as exc:
            failure = str(exc)
        step /= 2
    return step, trials, None, failure


def _stop(res: NewtonResult, reason: str, start: float) -> NewtonResult:
    res.reason, res.wall_s = reason, time.perf_counter() - start
    return res
