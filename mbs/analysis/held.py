"""The quasi-static rotor: its periodic response with the fuselage motion held, and the
period-mean loads on the held fuselage, with their derivatives by the implicit-function theorem.

The fuselage's body-axis velocities and rates ``b_v = (u, v, w, p, q, r)`` (m/s, rad/s) and
its attitude (roll ``φ``, pitch ``θ``, rad; heading 0) are held constant. The rotor states
(flap, lag, teeter, their rates, the inflows) follow the model's own equations with the
fuselage accelerations set to zero, i.e. the rotor rows of ``Mt u' = ht``:

    Mt_rr u_r' = ht_r

and the fuselage's period-mean acceleration is the period-mean load that holds it (aerodynamics,
gravity, hub loads including the rotor's inertial loads), divided by the aircraft's period-mean
inertia as one rigid body of its instantaneous configuration:

    f = ht_b − Mt_br u_r'     (6,): generalised load on the fuselage's body-axis velocities and rates
    ā = M̄⁻¹ f̄,   M̄ = mean(Mt_bb) (6, 6)     (u̇, v̇, ẇ m/s², ṗ, q̇, ṙ rad/s², body axes)

as Padfield's derivatives divide a mean force by the aircraft's mass and inertia. The mean of the
instantaneous ratio ``Mt_bb⁻¹ f`` differs from it where the inertia varies round the azimuth
in step with the loads: a two-bladed rotor's, both at 2/rev. On a UH-1H in hover that ratio
gave its roll damping L_p as +0.67 1/s where the same rotor as three blades of the same solidity
gives −0.35; divided as here the two-bladed rotor gives −0.32.

The rates enter the air velocities and the inertial (gyroscopic, Coriolis) loads of the
blades; the attitude stays frozen over the period, so it enters only through gravity.
``∫ f dt`` and ``∫ Mt_bb dt`` are integrated as quadrature states alongside (:data:`QUADRATURES`),
so the period means and their derivatives come out of the same tangent propagation as the
monodromy.

The periodic rotor response ``x_r(0)`` solves ``G = S x_r(τ) − x_r(0) = 0`` (``τ`` the shooting
interval, ``S`` the teeter reversal, :mod:`mbs.analysis.period`) by Newton with the AD
Jacobian. For ``y = (b_v, φ, θ, controls)``, with ``Φ = dx(τ)/d(x_r(0), y)`` from one
propagation, the implicit-function theorem gives

    dx_r(0)/dy = −(S Φ_rr − I)⁻¹ S Φ_ry,       dq̄/dy = (Φ_qr dx_r(0)/dy + Φ_qy) / τ

for the quadratures ``q = (f, Mt_bb)``, and ``dā/dy = M̄⁻¹ (df̄/dy − dM̄/dy ā)``.

No finite differences. Over the second half of the period the body accelerations repeat
(``S`` acts on the teeter only), so the mean over ``τ`` is the mean over the period.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from mbs.analysis.monodromy import TangentStepper, _evaluator, block_width, tangent_step
from mbs.analysis.newton import newton
from mbs.analysis.period import RotorPeriod
from mbs.analysis.shooting import TrimLayout, quaternion, residual_scales

HELD = ("u", "v", "w", "p", "q", "r", "roll", "pitch")
"""The held fuselage variables ``b``: body-axis velocities (m/s), rates (rad/s), attitude (rad)."""
ACCELERATIONS = ("du", "dv", "dw", "dp", "dq", "dr")
QUADRATURES = 6 + 36
"""Quadrature states after the model's: the holding load ``f`` (6,), then ``Mt_bb`` (6, 6) by columns."""


def _selection(n: int, rows: list[int]) -> ca.DM:
    """``P`` (n, len(rows)) with ``P e_k = e_rows[k]``."""
    out = ca.DM.zeros(n, len(rows))
    for k, i in enumerate(rows):
        out[i, k] = 1.0
    return out


def held_rhs(parts: ca.Function, lay: TrimLayout, nq: int) -> ca.Function:
    """``held(x, t, p) -> x'`` on the augmented state ``(x (nx,), ∫f dt (6,), ∫Mt_bb dt (36,))``:
    fuselage held, rotor rows of ``Mt u' = ht`` with ``u_b' = 0``, and the holding load ``f`` and
    the aircraft's inertia ``Mt_bb`` as the last rates."""
    nx, np_ = parts.size1_in(0), parts.size1_in(2)
    x, t, p = ca.MX.sym("x", nx + QUADRATURES), ca.MX.sym("t"), ca.MX.sym("p", np_)
    sd, mt, ht, zd = parts(x[:nx], t, p)
    nv = mt.size1()
    b = [i - nq for i in lay.body]
    r = [i for i in range(nv) if i not in b]
    ur = ca.solve(mt[r, r], ht[r], "ldl")
    load = ca.vertcat(ht[b] - ca.mtimes(mt[b, r], ur), ca.reshape(mt[b, b], 36, 1))
    keep = np.ones(nq)
    keep[lay.position + lay.quaternion] = 0.0
    xdot = ca.vertcat(sd * ca.DM(keep), ca.mtimes(_selection(nv, r), ur), zd, load)
    return ca.Function("held", [x, t, p], [xdot], ["x", "t", "p"], ["xdot"])


def held_project(project: ca.Function) -> ca.Function:
    """The model's projection on the first ``nx`` states; the quadratures pass through."""
    nx = project.size1_in(0)
    x = ca.MX.sym("x", nx + QUADRATURES)
    return ca.Function("held_project", [x], [ca.vertcat(project(x[:nx]), x[nx:])], ["x"], ["x_projected"])


class HeldStepper(TangentStepper):
    """Tangent step of the held-fuselage system (:func:`held_rhs`), generated and compiled once
    per model and method like :class:`mbs.analysis.monodromy.TangentStepper`, whose
    ``propagate`` it shares."""

    def __init__(self, model, method: str = "rk4", backend: str = "compiled"):
        from mbs.backends.info import info_of
        from mbs.dynamics import symbolic
        from mbs.integrators import FIXED_STEP

        tab, sym = FIXED_STEP[method], symbolic(model)
        self.lay = TrimLayout.of(info_of(sym, {}))
        if not self.lay.free:
            raise ValueError(f"model {model.name!r} has no free fuselage to hold")
        rhs = held_rhs(sym["parts"], self.lay, sym.layout.nq)
        self.method, self.stages = method, tab.stages
        self.nx, self.np = rhs.size1_in(0), rhs.size1_in(2)
        self.block = block_width(self.nx, tab.stages)
        step = tangent_step(rhs, held_project(sym["project"]), tab, self.block)
        fn = ca.Function(f"held_{step.name()}", step.mx_in(), step.call(step.mx_in()),
                         step.name_in(), step.name_out())
        self.backend, self._call = _evaluator(fn, sym, backend)


def start_function(lay: TrimLayout, nx: int, n_params: int) -> ca.Function:
    """``start(x_r, b, c, p_base) -> (x (nx + 6,), p, dx/dz, dp/dz)`` with ``z = (x_r, b, c)``:
    rotor states, held fuselage variables (:data:`HELD`), controls (rad)."""
    xr, b = ca.SX.sym("x_r", len(lay.rotor)), ca.SX.sym("b", len(HELD))
    c, pb = ca.SX.sym("c", len(lay.controls)), ca.SX.sym("p_base", n_params)
    x, p = [ca.SX(0)] * (nx + QUADRATURES), [pb[i] for i in range(n_params)]
    q = quaternion(b[6], b[7])
    for idx, values in ((lay.quaternion, q), (lay.body, b[:6]), (lay.rotor, xr)):
        for i, k in enumerate(idx):
            x[k] = values[i]
    for i, k in enumerate(lay.controls):
        p[k] = c[i]
    x, p, z = ca.vertcat(*x), ca.vertcat(*p), ca.vertcat(xr, b, c)
    return ca.Function("held_start", [xr, b, c, pb], [x, p, ca.jacobian(x, z), ca.jacobian(p, z)],
                       ["x_r", "b", "c", "p_base"], ["x", "p", "dx_dz", "dp_dz"])


@dataclass
class HeldSolution:
    """The periodic rotor response at held ``b`` (8,) and controls ``c``: rotor states at
    ``t = 0`` ``x_r`` (nr,), period-mean accelerations ``mean`` (6,), and when asked their
    total derivatives ``dmean`` (6, 8 + nc) and ``dx_r`` (nr, 8 + nc) along ``(b, c)``;
    Newton's final scaled residual and iterations; wall time (s)."""

    b: np.ndarray
    c: np.ndarray
    x_r: np.ndarray
    mean: np.ndarray
    residual: float
    iterations: int
    converged: bool
    dmean: np.ndarray | None = None
    dx_r: np.ndarray | None = None
    wall_s: float = 0.0


class HeldRotor:
    """Periodic response of the rotor with the fuselage held, for one model and step.

    stepper: :class:`HeldStepper`; period: the model's :class:`RotorPeriod`; steps_per_rev:
    fixed steps per main-rotor revolution; p_base (np,): the parameters other than controls;
    radius: reference length of the scaled residual (m).
    """

    def __init__(self, stepper: HeldStepper, period: RotorPeriod, steps_per_rev: int, p_base, radius: float):
        lay = self.lay = stepper.lay
        self.stepper, self.period, self.p_base = stepper, period, np.asarray(p_base, dtype=float)
        self.h, self.n = period.revolution / steps_per_rev, period.revs * steps_per_rev
        nx = stepper.nx - QUADRATURES
        self._start = start_function(lay, nx, len(self.p_base))
        self.sign, self.source = period.symmetry(nx)[lay.rotor], period.permutation(nx)[lay.rotor]
        self.scale = residual_scales([lay.state_names[k] for k in lay.rotor], period.omega, radius)
        self.nfwd = 0

    @property
    def nr(self) -> int:
        return len(self.lay.rotor)

    def propagate(self, x_r, b, c, all_directions: bool):
        """``(x(τ) (nx + 6,), dx(τ)/dz)`` along the rotor directions, and ``(b, c)`` when asked."""
        x0, p, dx0, dp = (np.asarray(a, dtype=float) for a in self._start(x_r, b, c, self.p_base))
        cols = slice(None) if all_directions else slice(0, self.nr)
        sens = self.stepper.propagate(x0.ravel(), p.ravel(), dx0[:, cols], dp[:, cols], 0.0, self.h, self.n)
        self.nfwd += sens.nfwd
        return sens.x, sens.dx

    def solve(self, b, c, x_r0, derivatives: bool = False, tol: float = 1e-12) -> HeldSolution:
        """The periodic rotor response at ``(b, c)`` from the guess ``x_r0`` (nr,)."""
        start, cache = time.perf_counter(), {}
        b, c = np.asarray(b, dtype=float), np.asarray(c, dtype=float)

        def evaluate(x_r):
            key = x_r.tobytes()
            if key not in cache:
                cache.clear()
                cache[key] = self.propagate(x_r, b, c, derivatives)
            return cache[key]

        residual = lambda x_r: (self.sign * evaluate(x_r)[0][self.source] - x_r) / self.scale  # noqa: E731
        jacobian = lambda x_r: self._periodicity(evaluate(x_r)[1])[:, :self.nr]  # noqa: E731
        res = newton(residual, jacobian, np.asarray(x_r0, dtype=float), tol, max_iterations=10)
        x_end, dx = evaluate(res.z)
        load, inertia = self._means(x_end[-QUADRATURES:])
        out = HeldSolution(b, c, res.z, np.linalg.solve(inertia, load), float(np.abs(res.r).max()),
                           len(res.history), res.converged)
        if derivatives:
            out.dx_r, out.dmean = self._implicit(dx, inertia, out.mean)
        out.wall_s = time.perf_counter() - start
        return out

    def _periodicity(self, dx: np.ndarray) -> np.ndarray:
        """Scaled ``dG/dz`` (nr, nz) of ``G = S x_r(τ) − x_r(0)``."""
        dg = self.sign[:, None] * dx[self.source]
        dg[:, :self.nr] -= np.eye(self.nr)
        return dg / self.scale[:, None]

    def _means(self, integrals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Period means of the holding load ``f̄`` (6,) and the inertia ``M̄`` (6, 6) from the
        quadratures' integrals over the period, or their derivatives along the last axis."""
        mean = integrals / self.period.duration
        return mean[:6], mean[6:].reshape((6, 6) + mean.shape[1:], order="F")

    def _implicit(self, dx: np.ndarray, inertia: np.ndarray, mean: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``dx_r(0)/dy`` (nr, ny) and ``dā/dy`` (6, ny) by the implicit-function theorem, with
        ``ā = M̄⁻¹ f̄``: ``dā = M̄⁻¹ (df̄ − dM̄ ā)``."""
        dg = self._periodicity(dx)
        dxr = -np.linalg.solve(dg[:, :self.nr], dg[:, self.nr:])
        dq = dx[-QUADRATURES:]
        dload, dinertia = self._means(dq[:, :self.nr] @ dxr + dq[:, self.nr:])
        return dxr, np.linalg.solve(inertia, dload - np.einsum("ijy,j->iy", dinertia, mean))
