"""The run-time interface shared by the two evaluators (virtual machine and compiled C).

Contract of every evaluator (subclasses implement ``_eval`` and ``_run``):

1. ``x`` is the state ``(s, u)`` of shape ``(nx,)``; ``t`` in s; ``p`` the parameters in
   the order of ``info.parameters`` (defaults when omitted).
2. Inputs are checked: a wrong shape or a non-finite entry raises ``ValueError`` naming
   the coordinate or parameter and its value.
3. Inputs are never modified; outputs are fresh arrays.
4. ``nfev`` counts right-hand-side evaluations, including those inside generated steps.
5. A run that produces a non-finite state stops and reports ``Result.nonfinite`` with the
   time of the failed step; it never returns NaN silently.
"""
from __future__ import annotations

import enum
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from mbs.backends import closure
from mbs.backends.info import ModelInfo


class Result(enum.Enum):
    """Outcome of a run, with the message a user sees."""

    successful = "the run reached its end time"
    nonfinite = ("the state became non-finite: the step is probably beyond the method's "
                 "stability limit (reduce the step) or the model diverged")
    evaluation_error = "the generated code reported an evaluation error"


@dataclass
class Trajectory:
    """Recorded run: ``t`` (n,) s, ``x`` (n, nx) states; ``x[0]`` is the initial state."""

    t: np.ndarray
    x: np.ndarray
    result: Result
    message: str
    nfev: int
    wall_s: float
    info: ModelInfo

    @property
    def ok(self) -> bool:
        return self.result is Result.successful

    def column(self, name: str) -> np.ndarray:
        """The recorded history of one state by name, e.g. ``"blade1.flap"``."""
        return self.x[:, self.info.state_names.index(name)]


class Bound:
    """One of the model's functions bound to fixed buffers, for inner loops (scipy's
    right-hand side, Newton iterations): write the arguments into ``inputs`` (arrays in the
    function's input order, e.g. ``x``, ``t``, ``p`` for ``rhs``), call with no argument,
    read ``outputs`` (updated in place, not copied). Nothing is checked or converted per
    call; a failed evaluation raises FloatingPointError.

    >>> rhs = system.bind("rhs")                                # doctest: +SKIP
    >>> rhs.inputs[0][:] = x; rhs.inputs[2][:] = system.params()  # doctest: +SKIP
    >>> rhs(); xdot = rhs.outputs[0]                            # doctest: +SKIP
    """

    def __init__(self, name: str, inputs: list[np.ndarray], outputs: list[np.ndarray], call: Callable[[], int]):
        self.name, self.inputs, self.outputs, self._call = name, inputs, outputs, call

    def __call__(self) -> None:
        if self._call():
            raise FloatingPointError(f"generated function {self.name} reported an error")


class System:
    """Numerical model; see the module docstring for the contract."""

    backend = "base"

    def __init__(self, info: ModelInfo, dtype: str = "float64"):
        self.info = info
        self.dtype = np.dtype(dtype)
        self.nfev = 0

    # -- to be provided by the evaluator ----------------------------------------------
    def _eval(self, name: str, *args) -> list[np.ndarray]:
        raise NotImplementedError

    def _run(self, method, x0, t0, h, k0, n, every, p, comp, compensated=True) -> tuple[np.ndarray, int, int]:
        """Run ``n`` steps from step index ``k0``; rows at every ``every`` steps and the
        last; ``comp`` (nx,) is the summation compensation, updated in place; returns
        (rows, status (0 ok, 1 non-finite, 2 error), steps done)."""
        raise NotImplementedError

    # -- checks ---------------------------------------------------------------------------
    def check_state(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape != (self.info.nx,):
            raise ValueError(f"state must have shape ({self.info.nx},), got {x.shape}")
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            i = bad[0]
            raise ValueError(f"state x[{i}] ({self.info.state_names[i]!r}) is {x[i]}, not finite")
        return x

    def params(self, p=None, **named: float) -> np.ndarray:
        """Parameter vector: defaults, then ``p`` (array or dict), then keyword overrides."""
        out = np.array([q["default"] for q in self.info.parameters], dtype=float)
        names = self.info.param_names
        if isinstance(p, dict):
            named = {**p, **named}
        elif p is not None:
            out = np.asarray(p, dtype=float).copy()
            if out.shape != (len(names),):
                raise ValueError(f"parameters must have shape ({len(names)},), got {out.shape}")
        for k, v in named.items():
            if k not in names:
                raise ValueError(f"unknown parameter {k!r}; known: {names}")
            out[names.index(k)] = v
        for q, v in zip(self.info.parameters, out):
            if not np.isfinite(v):
                raise ValueError(f"parameter {q['name']!r} is {v}, not finite")
            if not q.get("low", -np.inf) <= v <= q.get("high", np.inf):
                raise ValueError(f"parameter {q['name']!r} = {v} {q['unit']} is outside its range "
                                 f"[{q['low']}, {q['high']}]")
        return out

    @staticmethod
    def _check_time(t: float, h: float | None = None) -> None:
        if not np.isfinite(t):
            raise ValueError(f"time t = {t} is not finite")
        if h is not None and not (np.isfinite(h) and h > 0):
            raise ValueError(f"step size h = {h} s must be positive and finite")

    # -- public API ---------------------------------------------------------------------
    def x0(self, **values: float) -> np.ndarray:
        """Default initial state with coordinates overridden by name."""
        x = np.array(self.info.x0, dtype=float)
        for k, v in values.items():
            if k not in self.info.state_names:
                raise ValueError(f"unknown coordinate {k!r}")
            x[self.info.state_names.index(k)] = v
        return x

    def project(self, x) -> np.ndarray:
        """``x`` with every quaternion normalised (the integrators do this after each step)."""
        return self._eval("project", self.check_state(x))[0]

    def bind(self, name: str) -> Bound:
        """The function ``name`` (e.g. ``"rhs"``, ``"step_rk4"``) on fixed buffers: the
        cheapest repeated call from Python (:class:`Bound`)."""
        raise NotImplementedError

    def rhs(self, x, t: float = 0.0, p=None) -> np.ndarray:
        """``x' = f(x, t, p)``, shape (nx,)."""
        x, p = self.check_state(x), self.params(p)
        self._check_time(t)
        self.nfev += 1
        return self._eval("rhs", x, t, p)[0]

    def energy(self, x, t: float = 0.0, p=None) -> np.ndarray:
        """(translational kinetic, rotational kinetic, gravity, spring, total) in J."""
        return self._eval("energy", self.check_state(x), t, self.params(p))[0]

    def outputs(self, x, t: float = 0.0, p=None) -> np.ndarray:
        """The model's named outputs (``info.output_names``) at ``(x, t)``."""
        return self._eval("outputs", self.check_state(x), t, self.params(p))[0]

    def history(self, name: str, traj: "Trajectory", p=None) -> np.ndarray:
        """``energy``/``outputs``/``poses`` evaluated at every recorded row of ``traj``."""
        p = self.params(p)
        return np.array([getattr(self, name)(x, t, p) for x, t in zip(traj.x, traj.t)])

    def poses(self, x, t: float = 0.0, p=None) -> tuple[np.ndarray, np.ndarray]:
        """Body-frame origins (nb, 3) in m and rotations body->world (nb, 3, 3), world frame."""
        a = self._eval("poses", self.check_state(x), t, self.params(p))[0].reshape(-1, 12)
        return a[:, :3].copy(), a[:, 3:].reshape(-1, 3, 3)

    def kinematics(self, x, t: float = 0.0, p=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Body states ``V`` (6 nb,), ``J_u = dV/du`` (6 nb, nv) and ``H = dV/ds F + dV/dt`` (6 nb,)."""
        v, ju, hh = self._eval("kin", self.check_state(x), t, self.params(p))
        return v, ju.reshape(self.info.nv, -1).T, hh

    def step(self, x, t: float, h: float, n: int = 1, p=None, method: str = "rk4") -> np.ndarray:
        """``n`` fixed steps of size ``h`` from ``(x, t)``; returns the final state."""
        traj = self.run(x, t, h, n, every=n, p=p, method=method)
        if not traj.ok:
            raise FloatingPointError(f"{traj.message}")
        return traj.x[-1]

    def run(self, x0, t0: float, h: float, n_steps: int, every: int = 1, p=None,
            method: str = "rk4", progress: Callable[[int, int], None] | None = None,
            chunk: int | None = None, compensated: bool = True) -> Trajectory:
        """Integrate ``n_steps`` fixed steps of ``method``, recording every ``every`` steps.

        Each step adds its update with compensated (Kahan) summation, carried across the
        chunks of one call (a new call starts from zero compensation: the result depends on
        ``x0`` alone); ``compensated=False`` gives plain summation. ``progress(done, total)``
        is called after each chunk of steps.
        """
        if method not in self.info.methods:
            raise ValueError(f"unknown fixed-step method {method!r}; known: {sorted(self.info.methods)}")
        x0, p = self.check_state(x0), self.params(p)
        self._check_time(t0, h)
        if n_steps < 0 or every < 1:
            raise ValueError(f"n_steps = {n_steps} must be >= 0 and every = {every} >= 1")
        chunk = chunk or max(every, (max(n_steps, 1) // 50) // every * every or every)
        rows, x, k, status, start = [x0[None, :]], x0, 0, 0, time.perf_counter()
        comp = np.zeros(self.info.nx)
        while k < n_steps and status == 0:
            n = min(chunk, n_steps - k)
            out, status, done = self._run(method, x, t0, h, k, n, every, p, comp, compensated)
            self.nfev += done * self.info.methods[method]
            rows.append(out[: done // every] if status else out)
            k += done
            x = rows[-1][-1] if len(rows[-1]) else x
            if progress:
                progress(k, n_steps)
        traj = self._trajectory(rows, t0, h, k, n_steps, every, status, start)
        if status == 1:  # a local loop that cannot close turns the state non-finite: name it
            traj.message = closure.reworded(self, traj, method, t0, h, k, p)
        return traj

    def _trajectory(self, rows, t0, h, k, n_steps, every, status, start) -> Trajectory:
        x = np.concatenate(rows).astype(float)
        steps = np.r_[0, np.minimum(np.arange(1, len(x)) * every, k)]
        res = [Result.successful, Result.nonfinite, Result.evaluation_error][status]
        msg = res.value if not status else f"{res.value} (at t = {t0 + k * h:.6g} s, step {k + 1})"
        return Trajectory(t0 + steps * h, x, res, msg, self.nfev, time.perf_counter() - start, self.info)
