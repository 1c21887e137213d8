"""Closure equations without a closed form: :class:`Newton`, a fixed number of Newton steps in
the generated code.

The steps start from a predictor (``guess``: the loop's assembly value unless given) and use the
Jacobian ``∂g/∂q_d`` of the closure equations by AD. They are unrolled into the generated code,
so the solution is a pure function of the state, the time and the parameters (what the
monodromy, the FMU's saved states and the trim need; no solution is carried between calls).

Derivatives: the forward-mode AD of the last iterate is the implicit-function theorem's. The
Newton map ``N(θ) = θ - g_θ⁻¹ g`` has ``∂N/∂θ = 0`` at a root, so once an iterate has converged
the tangent of the next one is ``-g_θ⁻¹ (g_q q' + g_t)`` whatever the tangents before, and the
second-order tangent of the one after is the theorem's second derivative. Two steps beyond
convergence therefore give exact rates and accelerations (the tests compare them with a closed
form to 1e-12).

Failure: after the steps the residual is checked; above ``tolerance`` the coordinates are NaN
(the run stops, and the loop and the time are named, :mod:`mbs.backends.closure`). Convergence
is not guaranteed in general: it needs the predictor inside Newton's basin; the margin output
(``1 - |g|/tolerance``) shows how the last step fared.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import casadi as ca
import numpy as np

from mbs.loops.loop import Loop, closed


@dataclass
class Newton(Loop):
    """The closure equations of ``loop`` solved by ``iterations`` Newton steps from
    ``guess(joint, q, t, p) -> (n,)`` (default: the loop's assembly values); the solution is
    refused (NaN) where the residual after them exceeds ``tolerance`` (the residual's unit)."""

    loop: Loop
    guess: Callable | None = None
    iterations: int = 6
    tolerance: float = 1e-6

    def __post_init__(self):
        self.name, self.dependent = self.loop.name, tuple(self.loop.dependent)
        if not (isinstance(self.iterations, int) and 1 <= self.iterations <= 50):
            raise ValueError(f"loop {self.name!r}: Newton iterations = {self.iterations!r}; give 1 to 50")
        if not (np.isfinite(self.tolerance) and self.tolerance > 0):
            raise ValueError(f"loop {self.name!r}: tolerance {self.tolerance} must be positive")

    def bind(self, joint) -> None:
        self.loop.bind(joint)

    def residual(self, joint, q_all, t, p) -> ca.SX:
        return self.loop.residual(joint, q_all, t, p)

    def _start(self, joint, q, t, p) -> ca.SX:
        if self.guess is not None:
            return ca.vertcat(self.guess(joint, q, t, p))
        assembly = getattr(self.loop, "assembly", None)
        return ca.SX(ca.DM([assembly.angle] if assembly is not None else np.zeros(len(self.dependent))))

    def iterate(self, joint, q, t, p) -> tuple[ca.SX, ca.SX]:
        """The last iterate (n,) and its residual (n,)."""
        x = ca.SX.sym("dependent", len(self.dependent))
        g = ca.vertcat(self.loop.residual(joint, joint.merge(q, x), t, p))
        jac = ca.jacobian(g, x)
        theta = self._start(joint, q, t, p)
        for _ in range(self.iterations):
            gk, jk = ca.substitute([g, jac], [x], [theta])
            theta = theta - (gk / jk if g.numel() == 1 else ca.solve(jk, gk))
        return theta, ca.substitute(g, x, theta)

    def margin(self, joint, q, t, p) -> ca.SX:
        return 1 - ca.norm_inf(self.iterate(joint, q, t, p)[1]) / self.tolerance

    def solve(self, joint, q, t, p) -> ca.SX:
        theta, g = self.iterate(joint, q, t, p)
        return closed(theta, 1 - ca.norm_inf(g) / self.tolerance)
