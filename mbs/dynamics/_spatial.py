"""Each body as a spatial quantity about one common point, in world components.

A unit rate ``u_k`` moves the whole subtree of its body rigidly, with one twist ``ξ_k``:
the body's own columns of ``J_u`` written as a world twist about the reference point
``r0`` (the first body's origin: any common point would do, one near the bodies keeps
float32 accurate when the aircraft is far from the world origin). Twists are ordered
(angular, linear at ``r0``); wrenches (moment about ``r0``, force).
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca


def skew(c) -> ca.SX:
    """``skew(c) @ w = c × w``."""
    return ca.vertcat(ca.horzcat(0, -c[2], c[1]), ca.horzcat(c[2], 0, -c[0]), ca.horzcat(-c[1], c[0], 0))


def symmetric(m: ca.SX) -> ca.SX:
    """``m`` known to be symmetric, its lower triangle taken from the upper one (the lower
    entries are then never computed, and round-off keeps the matrix exactly symmetric)."""
    return ca.triu(m) + ca.triu(m, False).T


@dataclass
class Spatial:
    """Body quantities about ``r0``, world components: ``twist`` (6, nk) of its own rates,
    ``inertia`` (6, 6), ``wrench`` (6,) of its load, and ``to_body_state`` (6, 6), the map
    from a twist to the body state (centre-of-mass velocity in world, angular velocity in
    body). A flexible body with its sections (:mod:`mbs.dynamics._flexible`) also has what its
    modal rates move besides the rigid twist: ``momentum`` (6, nk), ``own_block`` (nk, nk) and
    ``own_force`` (nk,)."""

    twist: ca.SX
    inertia: ca.SX
    wrench: ca.SX
    to_body_state: ca.SX
    momentum: ca.SX | None = None
    own_block: ca.SX | None = None
    own_force: ca.SX | None = None


def body_spatial(body, motion, own: ca.SX, load: ca.SX, r0) -> Spatial:
    """``body`` with its frame's ``motion``, its own columns ``own`` (6, nk) of ``J_u`` and its
    ``load`` (6,): force at the centre of mass (N, world), torque (N m, body)."""
    rot = motion.rotation
    c = motion.position + ca.mtimes(rot, ca.DM(body.com)) - r0
    cx = skew(c)
    w = ca.mtimes(rot, own[3:, :])
    twist = ca.vertcat(w, own[:3, :] + ca.mtimes(cx, w))
    cc = symmetric(ca.mtimes(c, c.T))
    rotational = symmetric(ca.mtimes([rot, ca.DM(body.inertia), rot.T])
                           + body.mass * ((cc[0, 0] + cc[1, 1] + cc[2, 2]) * ca.DM.eye(3) - cc))
    mcx = skew(body.mass * c)
    inertia = ca.blockcat([[rotational, mcx], [mcx.T, body.mass * ca.DM.eye(3)]])
    f, torque = load[:3], load[3:]
    wrench = ca.vertcat(ca.cross(c, f) + ca.mtimes(rot, torque), f)
    to_body = ca.blockcat([[-cx, ca.DM.eye(3)], [rot.T, ca.DM(3, 3)]])
    return Spatial(twist, inertia, wrench, to_body)
