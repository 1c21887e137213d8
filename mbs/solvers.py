"""One interface over every integrator: fixed-step methods in generated code and scipy's
``solve_ivp`` methods on the same compiled right-hand side.

``METHODS`` is the registry (name -> :class:`Method`):

* ``euler``, ``rk4``, ``rk8``: explicit, the model's generated C driver (one call per run);
  ``rk8`` takes the weights of Dormand and Prince's 8th-order solution (12 stages) with a
  fixed step;
* ``midpoint``: implicit midpoint rule, Newton with the AD Jacobian, generated into a
  separate library of the model (built on first use, cached on disk);
* ``RK45``, ``DOP853``, ``Radau``, ``BDF``, ``LSODA``: :func:`scipy.integrate.solve_ivp`
  calling the compiled right-hand side directly (no argument checks), with the AD Jacobian
  for the implicit ones (Radau, BDF, LSODA).

Contract of :func:`solve`:

1. It never raises for a failed run: the :class:`Solution` carries a :class:`Status` and a
   message (bad arguments still raise ``ValueError``).
2. ``nfev`` counts right-hand-side evaluations and ``njev`` Jacobian evaluations of this
   run only; ``wall_s`` is the wall time of the integration alone (s).
3. ``x`` has one row per recorded time ``t``; the first row is the initial state.
"""
from __future__ import annotations

import enum
import time
from dataclasses import dataclass, field

import numpy as np

from mbs.integrators import TABLEAUX, ButcherTableau


class Status(enum.Enum):
    """Outcome of a run, with the message a user sees."""

    success = "the run reached its end time"
    nonfinite = ("the state became non-finite: the step is probably beyond the method's "
                 "stability limit")
    newton = ("the implicit stage equation was not solved (Newton did not converge within "
              "its iterations) or the state became non-finite: reduce the step")
    solver = "the adaptive solver stopped before the end time"
    budget = "stopped: the run exceeded its wall-time budget"
    error = "the generated code reported an evaluation error"


@dataclass
class Solution:
    """Result of :func:`solve`: ``t`` (n,) s, ``x`` (n, nx) states, work counters."""

    method: str
    t: np.ndarray
    x: np.ndarray
    status: Status
    message: str
    nfev: int
    njev: int
    nsteps: int
    wall_s: float
    setting: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.status is Status.success


@dataclass(frozen=True)
class Method:
    """An integrator. kind: ``"fixed"`` (step ``h``) or ``"adaptive"`` (``rtol``, ``atol``)."""

    name: str
    kind: str
    description: str
    tableau: ButcherTableau | None = None
    uses_jacobian: bool = False


METHODS: dict[str, Method] = {m.name: m for m in (
    Method("euler", "fixed", "explicit Euler (order 1), generated C driver", TABLEAUX["euler"]),
    Method("rk4", "fixed", "classical Runge-Kutta (order 4, the paper's), generated C driver", TABLEAUX["rk4"]),
    Method("rk8", "fixed", "Dormand-Prince 8th-order weights with a fixed step (12 stages), generated C driver",
           TABLEAUX["rk8"]),
    Method("midpoint", "fixed", "implicit midpoint (order 2, A-stable, symmetric), Newton with the AD "
           "Jacobian, generated C driver", TABLEAUX["midpoint"], uses_jacobian=True),
    Method("RK45", "adaptive", "scipy Dormand-Prince 5(4)"),
    Method("DOP853", "adaptive", "scipy Dormand-Prince 8(5,3)"),
    Method("Radau", "adaptive", "scipy Radau IIA (order 5, implicit), AD Jacobian", uses_jacobian=True),
    Method("BDF", "adaptive", "scipy BDF (orders 1-5, implicit), AD Jacobian", uses_jacobian=True),
    Method("LSODA", "adaptive", "scipy LSODA (Adams/BDF switching), AD Jacobian", uses_jacobian=True),
)}
FIXED = tuple(n for n, m in METHODS.items() if m.kind == "fixed")
ADAPTIVE = tuple(n for n, m in METHODS.items() if m.kind == "adaptive")


class Problem:
    """A model ready for every method: its built :class:`mbs.System` (``system``) and, on
    first use, a second library with the AD Jacobian and the implicit midpoint step.

    model: :class:`mbs.Model`; backend: ``"compiled"`` or ``"vm"``; p: parameters (array
    or dict, defaults otherwise); midpoint_iterations: Newton iterations per midpoint step.
    """

    def __init__(self, model, backend: str = "compiled", p=None, midpoint_iterations: int = 4):
        from mbs.backends import build

        self.model, self.backend = model, backend
        self.system = build(model, backend)
        self.p = self.system.params(p)
        self.midpoint_iterations = midpoint_iterations
        self._implicit = None

    @property
    def info(self):
        return self.system.info

    @property
    def implicit(self):
        """The library with ``rhs_jac`` and the ``midpoint`` fixed-step driver."""
        if self._implicit is None:
            self._implicit = implicit_system(self.model, self.backend, self.midpoint_iterations)
        return self._implicit

    def rhs_function(self):
        """``f(t, x) -> x'`` calling the generated code directly (for scipy)."""
        p = self.p
        if self.backend == "compiled":
            rhs = self.system.bind("rhs")
            x_in, t_in, p_in = rhs.inputs
            p_in[:] = p

            def f(t, x):
                x_in[:], t_in[0] = x, t
                rhs()
                return rhs.outputs[0].copy()
            return f
        raw = self.system.functions["rhs"]
        return lambda t, x: np.asarray(raw(x, t, p)).ravel()

    def jacobian_function(self):
        """``J(t, x) -> d x'/dx`` (nx, nx) from forward-mode AD."""
        p, nx, lib = self.p, self.info.nx, self.implicit
        if self.backend == "compiled":
            raw = lib.function("rhs_jac")
            return lambda t, x: raw(x, t, p)[0].reshape(nx, nx, order="F")
        raw = lib.functions["rhs_jac"]
        return lambda t, x: np.asarray(raw(x, t, p))

    def jacobian(self, x, t: float = 0.0) -> np.ndarray:
        """Exact ``d x'/dx`` at ``(x, t)``, shape (nx, nx)."""
        return self.jacobian_function()(float(t), self.system.check_state(x))

    def energy(self, x, t: float = 0.0) -> float:
        """Total mechanical energy (J) at one state."""
        return float(self.system.energy(x, t, self.p)[-1])


def implicit_system(model, backend: str = "compiled", iterations: int = 4):
    """Build ``model``'s second library: ``rhs``, ``project``, ``rhs_jac`` and the
    ``mbs_run_midpoint`` driver (a :class:`mbs.System` whose only method is ``midpoint``)."""
    from mbs.backends import index
    from mbs.backends.compiled import CompiledSystem
    from mbs.backends.info import info_of
    from mbs.backends.vm import VMSystem
    from mbs.dynamics import symbolic
    from mbs.integrators import symbolic_midpoint_increment
    from mbs.linearize import rhs_jacobian

    sym = symbolic(model)
    jac = rhs_jacobian(sym["rhs"])
    functions = {"rhs": sym["rhs"], "project": sym["project"], "rhs_jac": jac,
                 "incr_midpoint": symbolic_midpoint_increment(sym["rhs"], jac, iterations)}
    if backend == "vm":
        vm = VMSystem(sym)
        vm.functions.update(functions)
        vm.info.methods = {"midpoint": iterations + 1}
        return vm
    info = info_of(sym, {"midpoint": iterations + 1})
    info.name = f"{info.name}-implicit{iterations}"
    # the Jacobian and the midpoint increment are keyed by the code that derives them from rhs:
    # serializing them costs more than generating their C
    derived = index.module_texts(("mbs/solvers.py", "mbs/linearize.py", "mbs/integrators/*.py"))
    return CompiledSystem(index.library(functions, info, extra=derived, derived=("rhs_jac", "incr_midpoint")))


def _fixed_steps(t0: float, t_end: float, h: float) -> int:
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"step size h = {h} s must be positive and finite")
    n = int(round((t_end - t0) / h))
    if n < 1 or abs(n * h - (t_end - t0)) > 1e-9 * max(abs(t_end - t0), h):
        raise ValueError(f"the span [{t0}, {t_end}] s is not a whole number of steps h = {h} s")
    return n


def _solve_fixed(problem: Problem, method: Method, x0, t0, t_end, h, every) -> Solution:
    n = _fixed_steps(t0, t_end, h)
    system = problem.implicit if method.name == "midpoint" else problem.system
    traj = system.run(x0, t0, h, n, every=every, p=problem.p, method=method.name, chunk=n)  # one C call
    done = int(round((traj.t[-1] - t0) / h)) if traj.ok else _steps_done(traj, t0, h)
    status = Status.success if traj.ok else (Status.error if traj.result.name == "evaluation_error"
                                             else Status.newton if method.name == "midpoint"
                                             else Status.nonfinite)
    msg = status.value if traj.ok else f"{status.value} ({traj.message.rsplit('(', 1)[-1].rstrip(')')})"
    calls = system.info.methods[method.name]
    njev = done * problem.midpoint_iterations if method.uses_jacobian else 0
    return Solution(method.name, traj.t, traj.x, status, msg, done * calls, njev, done, traj.wall_s,
                    {"h": h, "steps": n})


def _steps_done(traj, t0: float, h: float) -> int:
    """Steps completed before a failure (from the message "... step k)")."""
    try:
        return int(traj.message.rsplit("step", 1)[-1].strip(" )")) - 1
    except ValueError:
        return int(round((traj.t[-1] - t0) / h))


class _OverBudget(Exception):
    pass


def _budgeted(f, max_wall_s: float | None):
    if max_wall_s is None:
        return f
    deadline, count = time.perf_counter() + max_wall_s, [0]

    def g(t, x):
        count[0] += 1
        if count[0] % 64 == 0 and time.perf_counter() > deadline:
            raise _OverBudget
        return f(t, x)
    return g


def _solve_adaptive(problem: Problem, method: Method, x0, t0, t_end, rtol, atol, t_eval,
                    max_wall_s) -> Solution:
    from scipy.integrate import solve_ivp

    kwargs = {"method": method.name, "rtol": rtol, "atol": atol, "t_eval": t_eval}
    if method.uses_jacobian:
        kwargs["jac"] = problem.jacobian_function()
    f = _budgeted(problem.rhs_function(), max_wall_s)
    setting, start = {"rtol": rtol, "atol": atol}, time.perf_counter()
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(f, (t0, t_end), x0, **kwargs)
    except _OverBudget:
        return _failed(method, Status.budget, f"{Status.budget.value} ({max_wall_s} s)", x0, t0, start, setting)
    except FloatingPointError as exc:
        return _failed(method, Status.error, f"{Status.error.value}: {exc}", x0, t0, start, setting)
    wall = time.perf_counter() - start
    x = sol.y.T
    if sol.status < 0:
        status, msg = Status.solver, f"{Status.solver.value}: {sol.message}"
    elif not np.all(np.isfinite(x)):
        status, msg = Status.nonfinite, Status.nonfinite.value
    else:
        status, msg = Status.success, Status.success.value
    return Solution(method.name, sol.t, x, status, msg, int(sol.nfev), int(sol.njev), int(sol.t.size),
                    wall, setting | {"nlu": int(sol.nlu)})


def _failed(method, status, msg, x0, t0, start, setting) -> Solution:
    return Solution(method.name, np.array([t0]), np.asarray(x0)[None, :], status, msg, 0, 0, 0,
                    time.perf_counter() - start, setting)


def solve(problem: Problem, method: str, t_end: float, *, h: float | None = None,
          rtol: float | None = None, atol: float | None = None, x0=None, t0: float = 0.0,
          every: int = 1, t_eval=None, max_wall_s: float | None = None) -> Solution:
    """Integrate ``problem`` from ``t0`` to ``t_end`` (s) with ``method`` (a key of ``METHODS``).

    Fixed-step methods need ``h`` (s; the span must be a whole number of steps) and record
    every ``every`` steps. Adaptive methods need ``rtol`` (``atol`` defaults to ``rtol``)
    and record at ``t_eval`` (default: their own steps); ``max_wall_s`` stops a run that
    takes longer (status ``budget``).
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; known: {', '.join(METHODS)}")
    m = METHODS[method]
    x0 = problem.system.check_state(problem.system.x0() if x0 is None else x0)
    if m.kind == "fixed":
        if h is None:
            raise ValueError(f"method {method!r} is fixed-step: give the step h")
        return _solve_fixed(problem, m, x0, t0, t_end, h, every)
    if rtol is None or not rtol > 0:
        raise ValueError(f"method {method!r} is adaptive: give rtol > 0, got {rtol}")
    t_eval = None if t_eval is None else np.asarray(t_eval, dtype=float)
    return _solve_adaptive(problem, m, x0, t0, t_end, rtol, rtol if atol is None else atol, t_eval, max_wall_s)
