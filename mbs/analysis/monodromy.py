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
The cached library is found through a key computed without generating C: the SHA-256 of the
serialized right-hand side and projection (``Function.serialize``), the tableau, the block
width, the CasADi version, the compiler and the source of the modules that shape the
generated code. The cache's index (:mod:`mbs.backends.index`) maps the key to the library's
folder; only without a valid entry is the C generated (and compiled, unless a library of that
source is cached).
The step loop runs in Python, one call per step and block of directions (a few µs of
overhead against the tenths of a millisecond of a block step), so that the number of steps
and of directions is chosen at run time. Blocks are independent: compiled blocks run in
parallel threads (the generated code runs without Python's lock), one evaluator per thread.
"""
from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import numpy as np

DIRECTIONS_PER_RHS_CALL = 32
"""Tangent directions per block times stages per step: 8 directions for RK4, 2 for rk8.
Larger blocks share more of the nominal evaluation but make the generated C grow (RK4 with 8
directions: 4 MB, compiled at ``-O1`` in about 25 s, once)."""

STATE_DIRECTIONS_PER_BLOCK = 384
"""Bound on states × directions of one block (:func:`block_width`). The generated code grows
with both, and gcc's time with the size of one function faster than linearly: the 193-state
elastic rotor's RK4 tangent with 8 directions is 17.9 MB of C, 200 s to compile and 0.42 ms
per direction and step; with 1 direction 3.5 MB, 16 s and 0.31 ms (its code fits the caches
better). The Bo105 scenes (22–47 states) keep 8."""


def block_width(nx: int, stages: int) -> int:
    """Tangent directions per block for ``nx`` states and a method of ``stages`` stages:
    :data:`DIRECTIONS_PER_RHS_CALL` // stages, fewer when ``nx`` × directions would pass
    :data:`STATE_DIRECTIONS_PER_BLOCK`; at least 1."""
    return max(1, min(DIRECTIONS_PER_RHS_CALL // stages, STATE_DIRECTIONS_PER_BLOCK // nx))


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

    def __init__(self, model, method: str = "rk4", backend: str = "compiled", sym=None,
                 workers: int | None = None):
        """sym: the model's :func:`mbs.dynamics.symbolic` when already built; workers: threads
        for the blocks of directions (compiled backend; default the usable cores, at most 4)."""
        from mbs.integrators import FIXED_STEP

        if method not in FIXED_STEP:
            raise ValueError(f"unknown fixed-step method {method!r}; known: {sorted(FIXED_STEP)}")
        tab = FIXED_STEP[method]
        if sym is None:
            from mbs.dynamics import symbolic

            sym = symbolic(model)
        self.method, self.stages = method, tab.stages
        self.nx, self.np = sym["rhs"].size1_in(0), sym["rhs"].size1_in(2)
        self.block = block_width(self.nx, tab.stages)
        self.backend, self._calls = _evaluators(sym, tab, self.block, backend, workers or _cores())

    def propagate(self, x0, p, dx0, dp, t0: float, h: float, n: int, every: int | None = None) -> Sensitivity:
        """``n`` steps of size ``h`` (s) from ``(x0, t0)`` with parameters ``p`` and their
        derivative along the seeds ``dx0`` (nx, nd), ``dp`` (np, nd); recorded every ``every``
        steps when given."""
        dx0, dp = np.atleast_2d(dx0), np.atleast_2d(dp)
        start = time.perf_counter()
        blocks = self._blocks(x0, p, dx0, dp, t0, h, n, every or n)
        xs = blocks[0][0] if blocks else np.array([x0])
        ds = np.concatenate([b[1] for b in blocks], axis=2) if blocks else np.zeros((len(xs), self.nx, 0))
        work = n * self.stages
        sens = Sensitivity(xs[-1], ds[-1], n, work, work * len(blocks) * self.block, time.perf_counter() - start)
        if every:
            sens.xs, sens.dxs = xs[:-1], ds[:-1]
        return sens

    def _blocks(self, x0, p, dx0, dp, t0, h, n, every) -> list[tuple[np.ndarray, np.ndarray]]:
        """:meth:`_block` for each block of ``block`` seed columns, the tangents cut to the
        block's true width; with several evaluators, evaluator ``w`` runs blocks ``w, w + W, ...``
        in its own thread."""
        starts, calls = list(range(0, dx0.shape[1], self.block)), self._callers()
        workers = max(1, min(len(calls), len(starts)))

        def one(call, j: int) -> tuple[np.ndarray, np.ndarray]:
            xs, ds = self._block(call, x0, p, _pad(dx0[:, j:j + self.block], self.block),
                                 _pad(dp[:, j:j + self.block], self.block), t0, h, n, every)
            return xs, ds[:, :, :min(self.block, dx0.shape[1] - j)]

        def share(w: int) -> list[tuple[np.ndarray, np.ndarray]]:
            return [one(calls[w], j) for j in starts[w::workers]]
        if workers == 1:
            return share(0)
        with ThreadPoolExecutor(workers) as pool:
            shares = list(pool.map(share, range(workers)))
        return [shares[k % workers][k // workers] for k in range(len(starts))]

    def _callers(self) -> list:
        """The evaluators, one per thread (a subclass may set a single ``_call``)."""
        return getattr(self, "_calls", None) or [self._call]

    def _block(self, call, x0, p, dx, dp, t0, h, n, every) -> tuple[np.ndarray, np.ndarray]:
        """States (m + 1, nx) and tangents (m + 1, nx, block) at steps 0, every, ... and n,
        evaluated by ``call`` (one thread's evaluator)."""
        x, d = np.asarray(x0, dtype=float), dx.ravel(order="F")
        dp, xs, ds = dp.ravel(order="F"), [], []
        for k in range(n):
            if k % every == 0:
                xs.append(x)
                ds.append(d)
            x, d = call(x, d, t0 + k * h, h, p, dp)
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


def _cores() -> int:
    """Usable CPU cores, at most 4 (a Jacobian has 4 blocks of RK4 directions)."""
    try:
        return max(1, min(4, len(os.sched_getaffinity(0))))
    except AttributeError:  # not on Linux
        return max(1, min(4, os.cpu_count() or 1))


def _evaluators(sym, tab, block: int, backend: str, workers: int) -> tuple[str, list]:
    """``(backend used, [call(x, X, t, h, p, P) -> (x_next, X_next) as flat arrays, ...])``:
    ``workers`` independent compiled callers, or one in the virtual machine."""
    if backend == "compiled":
        from mbs.backends.compiled import CompilerNotFound
        try:
            return "compiled", _compiled_keyed(sym, tab, block, workers)
        except CompilerNotFound:
            backend = "vm"
    if backend != "vm":
        raise ValueError(f"unknown backend {backend!r}; choose 'compiled' or 'vm'")
    return "vm", [_vm_caller(tangent_step(sym["rhs"], sym["project"], tab, block))]


def _evaluator(fn: ca.Function, sym, backend: str):
    """``(backend used, call(x, X, t, h, p, P) -> (x_next, X_next) as flat arrays)`` for a
    tangent function ``fn`` built by the caller (its library found by its generated source)."""
    if backend == "compiled":
        from mbs.backends.compiled import CompilerNotFound
        try:
            return "compiled", _compiled(fn, sym)
        except CompilerNotFound:
            backend = "vm"
    if backend != "vm":
        raise ValueError(f"unknown backend {backend!r}; choose 'compiled' or 'vm'")
    return "vm", _vm_caller(fn)


def _compiled(fn: ca.Function, sym):
    """Generate and compile ``fn`` into its own cached library; returns its caller."""
    from mbs.backends.compiled import CompiledSystem

    return CompiledSystem(_build(fn, sym, f"monodromy-{fn.name()}")).function(fn.name())


def _vm_caller(fn: ca.Function):
    """The caller of ``fn`` in the virtual machine, with the compiled caller's flat arrays."""
    shapes = [fn.size_in(i) for i in range(fn.n_in())]

    def call(*args):
        args = [np.reshape(a, s, order="F") for a, s in zip(args, shapes)]
        return [np.asarray(o, dtype=float).ravel(order="F") for o in fn(*args)]
    return call


GENERATING_MODULES = ("mbs/analysis/monodromy.py", "mbs/integrators/*.py")
"""Sources besides the backends' (:data:`mbs.backends.index.GENERATING_MODULES`) whose change can
change the generated tangent library (they enter its key)."""


def library_key(sym, tab, block: int) -> str:
    """Hex key of the tangent library of ``sym`` (:func:`mbs.dynamics.symbolic`) for the
    tableau ``tab`` and ``block`` directions, from the serialized right-hand side and
    projection and everything else the generated C depends on; no code is generated."""
    from mbs.backends import index

    info = _library_info(sym, f"monodromy-tangent_{tab.name}")
    return index.key({"rhs": sym["rhs"], "project": sym["project"]}, info, "float64",
                     (repr(tab), str(block), *index.module_texts(GENERATING_MODULES)))


def _compiled_keyed(sym, tab, block: int, workers: int) -> list:
    """``workers`` callers of the compiled tangent step (each with its own buffers), from the
    library that the index maps :func:`library_key` to; generated (and compiled unless a
    library of the same source is cached) only when the index has no valid entry."""
    from mbs.backends import index
    from mbs.backends.compiled import CompiledSystem

    name, key = f"tangent_{tab.name}", library_key(sym, tab, block)
    folder = index.lookup(key)
    if folder is None:
        folder = _build(tangent_step(sym["rhs"], sym["project"], tab, block), sym, f"monodromy-{name}")
        index.record(key, folder)
    return [CompiledSystem(folder).function(name) for _ in range(workers)]


def _library_info(sym, name: str):
    """The description of a tangent library of ``sym``: the library depends on the generated code
    only, so scenes of one model that differ in their initial state or default parameters (hover,
    forward flight) share it."""
    from mbs.backends.info import info_of

    info = info_of(sym, {})
    info.name, info.x0 = name, [0.0] * len(info.x0)
    for q in info.parameters:
        q["default"] = 0.0
    return info


def _build(fn: ca.Function, sym, prefix: str) -> Path:
    """Generate ``fn`` and compile it into ``<cache>/<prefix>-<source hash>``; returns the folder."""
    from mbs.backends.compiled import compile_source, generate

    info = _library_info(sym, prefix)
    return compile_source(generate({fn.name(): fn}, info, "float64"), info)
