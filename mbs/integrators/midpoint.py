"""Implicit midpoint rule: ``x_{n+1} = x_n + h k`` with ``k = f(x_n + h/2 k, t_n + h/2)``.

The one-stage Gauss method (order 2). It is A-stable with ``R(z) = (1 + z/2)/(1 - z/2)``,
so ``|R| = 1`` on the whole imaginary axis: undamped linear modes keep their energy for any
step. It is symmetric, conserves every quadratic invariant of the flow exactly (a free
joint's quaternion norm, the energy of a linear undamped system) and is symplectic for
Hamiltonian systems in canonical coordinates. It is not L-stable: very stiff decaying
components alternate in sign (``R(-inf) = -1``) instead of vanishing.

The stage equation is solved by full Newton iterations with the right-hand side's Jacobian
from forward-mode AD (see :func:`mbs.linearize.rhs_jacobian`), a fixed number of them so
that the step is one generated function; a step whose final residual exceeds
``rtol (1 + |k|)`` returns NaN, which the fixed-step driver reports as a failed run.
"""
from __future__ import annotations

import casadi as ca

from mbs.integrators._tableau import ButcherTableau

MIDPOINT = ButcherTableau(name="midpoint", a=((0.5,),), b=(1.0,), c=(0.5,), order=2)


def symbolic_midpoint_increment(rhs: ca.Function, jac: ca.Function, iterations: int = 4,
                                rtol: float = 1e-9) -> ca.Function:
    """``incr_midpoint(x, t, h, p) -> dx`` (NaN where Newton did not converge).

    rhs: ``(x, t, p) -> x'``; jac: ``(x, t, p) -> dx'/dx`` (nx, nx). One step costs
    ``iterations + 1`` right-hand sides and ``iterations`` Jacobians.
    """
    if iterations < 1:
        raise ValueError(f"iterations = {iterations} must be >= 1")
    nx, np_ = rhs.size1_in(0), rhs.size1_in(2)
    x, t, h, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", np_)
    tm, k = t + h / 2, ca.MX.zeros(nx)
    for _ in range(iterations):
        xm = x + h / 2 * k
        residual = k - rhs(xm, tm, p)
        k = k - ca.solve(ca.MX.eye(nx) - h / 2 * jac(xm, tm, p), residual, "qr")
    residual = k - rhs(x + h / 2 * k, tm, p)
    converged = ca.norm_inf(residual) <= rtol * (1 + ca.norm_inf(k))
    dx = ca.if_else(converged, h * k, ca.DM.nan(nx))
    return ca.Function("incr_midpoint", [x, t, h, p], [dx], ["x", "t", "h", "p"], ["dx"])
