"""A planar four-bar linkage as a local loop: the coupler on a joint assembly from the ground.

Ground pivots A (the crank's, at the origin) and D at ``(ground, 0, 0)`` m; crank AB, coupler
BC, rocker DC, all in the x-y plane turning about z. The coupler is the one body: the joint
from the ground is the crank's hinge (the coordinate, ``coupler.crank``), the crank's length and
the coupler's hinge at B, whose angle the rocker's link of length ``rocker`` from D closes
(:class:`mbs.loops.LinkLoop`); the crank and the rocker are massless links inside the joint.
The open branch (C on the far side of the line BD from A... the branch of the assembly at crank
angle ``crank0``) is kept. Outputs: the rocker angle ψ (rad, from the ground's x axis at D),
the loop's closure margin and link-length error.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.joints import Fixed, Hinge
from mbs.loops import Assembly, LinkLoop, LoopJoint, Newton, add_loop_outputs
from mbs.tree import Model


def open_branch(crank: float, coupler: float, rocker: float, ground: float, phi: float) -> tuple[float, float]:
    """Coupler angle θ3 and rocker angle θ4 (rad, absolute) of the open branch at crank angle
    ``phi``, by intersecting two circles (for the assembly; the tests use Freudenstein's form)."""
    b = np.array([crank * np.cos(phi), crank * np.sin(phi)])
    dx = np.array([ground, 0.0]) - b
    dist = np.hypot(*dx)
    along = (coupler**2 - rocker**2 + dist**2) / (2 * dist)
    height = np.sqrt(coupler**2 - along**2)
    c = b + along * dx / dist + height * np.array([-dx[1], dx[0]]) / dist
    return float(np.arctan2(*(c - b)[::-1])), float(np.arctan2(c[1], c[0] - ground))


def fourbar(crank: float = 1.0, coupler: float = 3.0, rocker: float = 2.5, ground: float = 3.0,
            mass: float = 2.0, gravity: float = 9.81, crank0: float = np.pi / 2, crank_rate: float = 4.0,
            solver: str = "closed-form", name: str = "fourbar") -> Model:
    """The four-bar of link lengths ``crank``, ``coupler``, ``rocker``, ``ground`` (m) with a
    uniform slender coupler of ``mass`` (kg) under ``gravity`` (m/s², along -y), starting at
    crank angle ``crank0`` (rad) and rate ``crank_rate`` (rad/s). ``solver``: "closed-form" or
    "newton" (the same closure by Newton steps from the assembly's coupler angle plus the
    crank's turn). One degree of freedom, conservative."""
    if solver not in ("closed-form", "newton"):
        raise ValueError(f"solver {solver!r}: choose closed-form or newton")
    theta3, _ = open_branch(crank, coupler, rocker, ground, crank0)
    link = LinkLoop("fourbar", "coupler", (coupler, 0.0, 0.0), rocker, lambda t, p: ca.DM([ground, 0.0, 0.0]),
                    Assembly(theta3 - crank0, (ground, 0.0, 0.0), {"crank": crank0}))
    loop = link if solver == "closed-form" else Newton(link, guess=_coupler_guess(theta3 - crank0, crank0), iterations=8)
    joint = LoopJoint(Hinge((0, 0, 1), name="crank"), Fixed(at=(crank, 0.0, 0.0)), Hinge((0, 0, 1), name="coupler"),
                      loop=loop)
    m = Model(name, gravity=(0.0, -gravity, 0.0))
    m.add_body("coupler", "world", joint, mass=mass, com=(coupler / 2, 0.0, 0.0),
               inertia=mass * coupler**2 / 12 * np.diag([1e-3, 1.0, 1.0]),
               shape={"kind": "box", "size": [coupler, 0.05, 0.05], "offset": [coupler / 2, 0, 0]})
    m.set_initial(**{"coupler.crank": crank0, "coupler.crank_rate": crank_rate})
    m.add_output("rocker.angle", lambda s: _rocker_angle(s, coupler, ground), "rad",
                 "rocker angle ψ from the ground's x axis at D")
    add_loop_outputs(m)
    return m


def _coupler_guess(gamma0: float, phi0: float):
    """A crude predictor: the coupler keeps its absolute angle (the relative angle turns back with the crank)."""
    return lambda joint, q, t, p: gamma0 - (q[0] - phi0)


def _rocker_angle(state, coupler: float, ground: float) -> ca.SX:
    c = state.point_position("coupler", ca.DM([coupler, 0.0, 0.0]))
    return ca.atan2(c[1], c[0] - ground)
