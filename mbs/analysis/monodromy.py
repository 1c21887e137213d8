"""Sensitivities of a fixed-step run: the monodromy matrix and the parameter Jacobian.

One step of an explicit method is ``x_{k+1} = step(x_k, t_k, h, p) = project(x_k + incr(x_k,
t_k, h, p))`` with ``incr`` from the method's tableau (:mod:`mbs.integrators`). Its forward-mode
derivative (CasADi ``forward``) carries a block of tangent directions alongside the state:

    X_{k+1} = d step/dx · X_k + d step/dp · P

Starting from ``X_0 = dx_0/dz``, ``P = dp/dz`` for any unknowns ``z``, ``N`` steps give
``X_N = dx_N/dz``; with identity seeds this is the monodromy ``M = dx_N/dx_0`` (nx, nx) and
``dx_N/dp`` (nx, np) when the ``N`` steps make one period. The derivative is that of the
discrete map the generated driver computes (exact to round-off), never a finite difference.

The tangent step ``tangent_<method>`` is generated once per model and method and compiled
into its own library (cached on disk like the model's), or run in CasADi's virtual machine.
The step loop runs in Python, one call per step and block of directions (a few µs of
overhead against the milliseconds of a block step), so that the number of steps and of
directions is chosen at run time.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

DIRECTIONS_PER_RHS_CALL = 32
"""Tangent directions per block times stages per step: 8 directions for RK4, 2 for rk8.
Larger blocks share more of the nominal evaluation but make the generated C grow (RK4 with 8
directions: 4 MB, compiled at ``-O1`` in about 25 s, once)."""


@dataclass
class Sensitivity:
    """Final state ``x`` (nx,) of ``steps`` steps and its derivative ``dx`` (nx, nd) along
    the seeds; work: right-hand sides of the nominal run and directional derivatives of the
    right-hand side (``nfwd``, one per stage, step and direction), wall time in s. When
    recorded, ``xs`` (m, nx) and ``dxs`` (m, nx, nd) at steps ``0, every, 2 every, ...`` before
    the last."""

    x: np.ndarray
    dx: np.ndarray
    steps: int
    nfev: int
    nfwd: int
    wall_s: float
    xs: np.ndarray | None = None
    dxs: np.ndarray | None = None


def tangent_step(rhs: ca.Function, project: ca.Function, tab, block: int) -> ca.Function:
    """``tangent_<m>(x, X, t, h, p, P) -> (x_next, X_next)``: one step of ``tab`` and its
    forward derivative along ``block`` directions; ``X`` (nx, block), ``P`` (np, block)."""
    from mbs.integrators import symbolic_step

    nx, np_ = rhs.size1_in(0), rhs.size1_in(2)
    step = symbolic_step(rhs, project, tab)
    x, t, h, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", np_)
    dx, dp = ca.MX.sym("X", nx, block), ca.MX.sym("P", np_, block)
    xn = step(x, t, h, p)
    zero = ca.MX.zeros(1, block)
    dxn = step.forward(block)(x, t, h, p, xn, dx, zero, zero, dp)
    return ca.Function(f"tangent_{tab.name}", [x, dx, t, h, p, dp], [xn, dxn],
                       ["x", "X", "t", "h", "p", "P"], ["x_next", "X_next"])


class TangentStepper:
    """Evaluator of one model's tangent step for one fixed-step method.

    model: :class:`mbs.Model`; method: a key of :data:`mbs.integrators.FIXED_STEP`;
    backend: ``"compiled"`` (generated C, cached; falls back to the virtual machine when no
    C compiler exists) or ``"vm"``.
    """

    def __init__(self, model, method: str = "rk4", backend: str = "compiled"):
        from mbs.dynamics import symbolic
        from mbs.integrators import FIXED_STEP

        if method not in FIXED_STEP:
            raise ValueError(f"unknown fixed-step method {method!r}; known: {sorted(FIXED_STEP)}")
        tab = FIXED_STEP[method]
        sym = symbolic(model)
        self.method, self.stages = method, tab.stages
        self.block = max(1, DIRECTIONS_PER_RHS_CALL // tab.stages)
        self.nx, self.np = sym["rhs"].size1_in(0), sym["rhs"].size1_in(2)
        fn = tangent_step(sym["rhs"], sym["project"], tab, self.block)
        self.backend, self._call = _evaluator(fn, sym, backend)

    def propagate(self, x0, p, dx0, dp, t0: float, h: float, n: int, every: int | None = None) -> Sensitivity:
        """``n`` steps of size ``h`` (s) from ``(x0, t0)`` with parameters ``p`` and their
        derivative along the seeds ``dx0`` (nx, nd), ``dp`` (np, nd); recorded every ``every``
        steps when given."""
        dx0, dp = np.atleast_2d(dx0), np.atleast_2d(dp)
        nd, start, blocks = dx0.shape[1], time.perf_counter(), []
        for j in range(0, nd, self.block):
            width = min(self.block, nd - j)
            xs, ds = self._block(x0, p, _pad(dx0[:, j:j + self.block], self.block),
                                 _pad(dp[:, j:j + self.block], self.block), t0, h, n, every or n)
            blocks.append((xs, ds[:, :, :width]))
        xs = blocks[0][0] if blocks else np.array([x0])
        ds = np.concatenate([b[1] for b in blocks], axis=2) if blocks else np.zeros((len(xs), self.nx, 0))
        work = n * self.stages
        sens = Sensitivity(xs[-1], ds[-1], n, work, work * len(blocks) * self.block, time.perf_counter() - start)
        if every:
            sens.xs, sens.dxs = xs[:-1], ds[:-1]
        return sens

    def _block(self, x0, p, dx, dp, t0, h, n, every) -> tuple[np.ndarray, np.ndarray]:
        """States (m + 1, nx) and tangents (m + 1, nx, block) at steps 0, every, ... and n."""
        x, d = np.asarray(x0, dtype=float), dx.ravel(order="F")
        dp, xs, ds = dp.ravel(order="F"), [], []
        for k in range(n):
            if k % every == 0:
                xs.append(x)
                ds.append(d)
            x, d = self._call(x, d, t0 + k * h, h, p, dp)
        xs.append(x)
        ds.append(d)
        return np.array(xs), np.array(ds).reshape(len(ds), self.nx, self.block, order="F")

    def monodromy(self, x0, p, t0: float, h: float, n: int) -> Sensitivity:
        """``dx`` = ``[dx_n/dx_0, dx_n/dp]`` (nx, nx + np): the monodromy and the parameter Jacobian."""
        seeds = np.eye(self.nx + self.np)
        return self.propagate(x0, p, seeds[:self.nx], seeds[self.nx:], t0, h, n)


def _pad(a: np.ndarray, width: int) -> np.ndarray:
    """``a`` with zero columns appended up to ``width``."""
    return np.hstack([a, np.zeros((a.shape[0], width - a.shape[1]))]) if a.shape[1] < width else a


def _evaluator(fn: ca.Function, sym, backend: str):
    """``(backend used, call(x, X, t, h, p, P) -> (x_next, X_next) as flat arrays)``."""
    if backend == "compiled":
        from mbs.backends.compiled import CompilerNotFound
        try:
            return "compiled", _compiled(fn, sym)
        except CompilerNotFound:
            backend = "vm"
    if backend != "vm":
        raise ValueError(f"unknown backend {backend!r}; choose 'compiled' or 'vm'")
    return "vm", _vm_caller(fn)


def _vm_caller(fn: ca.Function):
    """The caller of ``fn`` in the virtual machine, with the compiled caller's flat arrays."""
    shapes = [fn.size_in(i) for i in range(fn.n_in())]

    def call(*args):
        args = [np.reshape(a, s, order="F") for a, s in zip(args, shapes)]
        return [np.asarray(o, dtype=float).ravel(order="F") for o in fn(*args)]
    return call


def _compiled(fn: ca.Function, sym):
    """Generate and compile ``fn`` into its own cached library; returns its caller."""
    from mbs.backends.compiled import CompiledSystem, compile_source, generate
    from mbs.backends.info import info_of

    info = info_of(sym, {})
    # the library depends on the generated code only: scenes of one model that differ in their
    # initial state or default parameters (hover, forward flight) share it
    info.name, info.x0 = f"monodromy-{fn.name()}", [0.0] * len(info.x0)
    for q in info.parameters:
        q["default"] = 0.0
    folder = compile_source(generate({fn.name(): fn}, info, "float64"), info)
    return CompiledSystem(folder).function(fn.name())
