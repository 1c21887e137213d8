"""Time integrators. Runge-Kutta methods are data (Butcher tableaux); explicit ones become
generated code by :func:`symbolic_step` / :func:`symbolic_increment` in every built model,
the implicit midpoint rule (:mod:`mbs.integrators.midpoint`) by a separate generated
library, so that models which do not use it do not pay for its Jacobian.

``FIXED_STEP``: explicit methods compiled into every model (name -> tableau; ``stages`` is
the number of right-hand-side calls per step). ``TABLEAUX``: every fixed-step method.
"""
from __future__ import annotations

import casadi as ca

from mbs.integrators._tableau import ButcherTableau, rk_increment, rk_step
from mbs.integrators.euler import EULER
from mbs.integrators.midpoint import MIDPOINT, symbolic_midpoint_increment
from mbs.integrators.rk4 import RK4
from mbs.integrators.rk8 import RK8

FIXED_STEP: dict[str, ButcherTableau] = {t.name: t for t in (RK4, EULER, RK8)}
TABLEAUX: dict[str, ButcherTableau] = {t.name: t for t in (EULER, RK4, RK8, MIDPOINT)}


def symbolic_increment(rhs: ca.Function, tab: ButcherTableau) -> ca.Function:
    """``incr(x, t, h, p) -> dx``: the unrounded update of one step, ``x_next = project(x + dx)``.

    The fixed-step drivers add it with compensated (Kahan) summation, so that round-off does
    not accumulate over many steps (it matters in float32).
    """
    nx, np_ = rhs.size1_in(0), rhs.size1_in(2)
    x, t, h, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", np_)
    dx = rk_increment(rhs, x, t, h, p, tab)
    return ca.Function(f"incr_{tab.name}", [x, t, h, p], [dx], ["x", "t", "h", "p"], ["dx"])


def symbolic_step(rhs: ca.Function, project: ca.Function, tab: ButcherTableau) -> ca.Function:
    """``step(x, t, h, p) -> x_next``: one step of ``tab``, then projection onto the manifold."""
    nx, np_ = rhs.size1_in(0), rhs.size1_in(2)
    x, t, h, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", np_)
    xn = project(rk_step(rhs, x, t, h, p, tab))
    return ca.Function(f"step_{tab.name}", [x, t, h, p], [xn], ["x", "t", "h", "p"], ["x_next"])


__all__ = ["ButcherTableau", "FIXED_STEP", "TABLEAUX", "RK4", "RK8", "EULER", "MIDPOINT", "symbolic_step",
           "symbolic_increment", "symbolic_midpoint_increment", "rk_step"]
