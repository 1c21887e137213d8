"""The tree traversal (the paper's) and what forward-mode AD takes from it.

Body states ``V`` stack, per body, the centre-of-mass velocity (world components, m/s) and
the angular velocity (body components, rad/s), so that the body mass matrix is
``M = blockdiag(m I, J_c)``. From ``V`` the AD gives each body's own columns of
``J_u = dV/du`` (its joint's motion subspace) and, along ``(F, 1)``, ``H = dV/ds F + dV/dt``
(the velocity-product accelerations, with the rates and accelerations of driven joints).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca

from mbs.joints import Params, Relative, compose


def _placement(body) -> Relative:
    z = ca.SX.zeros(3)
    return Relative(ca.DM(body.at), ca.DM(body.frame), z, z)


def traverse(lay, s, u, t, p: Params, relatives: dict | None = None) -> dict[str, Relative]:
    """Absolute motion of every body frame, root to leaves (the paper's traversal); each joint's
    relative motion also into ``relatives`` when given."""
    z = ca.SX.zeros(3)
    world = Relative(z, ca.SX.eye(3), z, z)
    motions: dict[str, Relative] = {}
    for b in lay.bodies:
        parent = motions.get(b.parent, world)
        rel = b.joint.relative(s[lay.q_slices[b.name]], u[lay.v_slices[b.name]], t, p)
        motions[b.name] = compose(compose(parent, _placement(b)), rel)
        if relatives is not None:
            relatives[b.name] = rel
    return motions


def body_states(lay, motions) -> ca.SX:
    """``V``: per body (centre-of-mass velocity in world, angular velocity in body), (6 nb,)."""
    parts = []
    for b in lay.bodies:
        m = motions[b.name]
        parts += [m.velocity + ca.mtimes(m.rotation, ca.cross(m.omega, ca.DM(b.com))), m.omega]
    return ca.vertcat(*parts)


def poses(lay, motions) -> ca.SX:
    """Per body its origin (3, m, world) and rotation body -> world (9, row major), (12 nb,)."""
    return ca.vertcat(*[ca.vertcat(motions[b.name].position, ca.reshape(motions[b.name].rotation.T, 9, 1))
                        for b in lay.bodies])


def position_rates(lay, s, u) -> ca.SX:
    """``s' = F(s, u)``, (nq,)."""
    return ca.vertcat(*[b.joint.qdot(s[lay.q_slices[b.name]], u[lay.v_slices[b.name]]) for b in lay.bodies],
                      ca.SX(0, 1))


@dataclass
class Kinematics:
    """The tree's motion at a symbolic state: body-frame ``motions``, ``V`` (6 nb,), ``H``
    (6 nb,), ``own`` per moving body its columns of ``J_u`` (6, nk) (a section of a flexible
    body: those of its body's modal rates), ``sdot`` (nq,) and each joint's ``relative`` motion."""

    motions: dict[str, Relative]
    V: ca.SX
    H: ca.SX
    own: dict[str, ca.SX]
    sdot: ca.SX
    relative: dict[str, Relative] = field(default_factory=dict)

    def rows(self, i: int) -> slice:
        """The rows of body ``i`` (layout order) in ``V`` and ``H``."""
        return slice(6 * i, 6 * i + 6)


def _rates(lay, b) -> int:
    """The rates moving body ``b`` relative to its parent: its joint's, or a flexible body's
    modal rates for one of its sections."""
    v = lay.v_slices[b.name]
    return v.stop - v.start


def kinematics(lay, s, u, t, p: Params) -> Kinematics:
    """Traverse the tree and differentiate: one direction along ``(F, 1)`` for ``H`` and, per
    moving body, one per rate of its own joint for its columns of ``J_u``."""
    relative: dict[str, Relative] = {}
    motions = traverse(lay, s, u, t, p, relative)
    V, sdot = body_states(lay, motions), position_rates(lay, s, u)
    H = ca.jtimes(V, ca.vertcat(s, t), ca.vertcat(sdot, 1))
    own = {b.name: ca.jtimes(V[6 * i:6 * i + 6], u[lay.v_slices[b.name]], ca.SX.eye(_rates(lay, b)))
           for i, b in enumerate(lay.bodies) if _rates(lay, b)}
    return Kinematics(motions, V, H, own, sdot, relative)
