"""The damped Mathieu equation as a one-hinge model, a check of Floquet stability:

    x'' + 2ζ x' + (δ + ε cos t) x = 0

A body of unit moment of inertia (kg m²) turns on a hinge (angle ``x``, rad) against a
parametric spring-damper, a generalized torque ``−(2ζ x' + (δ + ε cos t) x)`` (N m) from a
:class:`mbs.forces.UserForce`; no gravity. Time in s, so the forcing period is ``2π`` s. The
coefficients ``delta`` (1/s²), ``epsilon`` (1/s²) and ``zeta`` (1/s) are run-time parameters:
one generated library serves every point of a stability chart.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.forces import UserForce
from mbs.joints import Hinge
from mbs.tree import Model

PERIOD = 2 * np.pi
"""Period of the parametric excitation, s."""


def _parametric_spring(state, loads) -> None:
    x, rate, p = state.q("body.angle"), state.v("body.angle_rate"), state.p
    stiffness = p["delta"] + p["epsilon"] * ca.cos(state.t)
    loads.add_generalized("body.angle_rate", -(2 * p["zeta"] * rate + stiffness * x))


def mathieu(delta: float = 0.25, epsilon: float = 0.1, zeta: float = 0.0) -> Model:
    """The Mathieu oscillator with default coefficients ``delta``, ``epsilon``, ``zeta``; it
    starts at ``x = 0.01`` rad at rest."""
    m = Model("mathieu", gravity=(0.0, 0.0, 0.0))
    m.add_parameter("delta", delta, "1/s^2", "mean stiffness per unit inertia")
    m.add_parameter("epsilon", epsilon, "1/s^2", "amplitude of the stiffness variation per unit inertia")
    m.add_parameter("zeta", zeta, "1/s", "half the damping per unit inertia", low=0.0)
    m.add_body("body", "world", Hinge((0, 0, 1)), mass=1.0, inertia=np.eye(3))
    m.add_force(UserForce("parametric spring", _parametric_spring))
    m.set_initial(**{"body.angle": 0.01})
    return m
