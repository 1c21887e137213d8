"""Joint reaction loads: one backward Newton–Euler pass over the tree.

In minimal coordinates the loads a joint carries are not states. With the accelerations
``u'`` of the forward dynamics, each body's state acceleration is ``V' = J_u u' + H`` (the
AD quantities of the equations of motion), and the load the body lacks is ``M V' - h``
(``h``: its applied loads with gravity and the gyroscopic term). Summed over the subtree of a
body, where the loads its inner joints pass cancel in pairs, this is the load its parent
passes through the body's joint:

    F_b = Σ_{j in subtree(b)} T_jᵀ (M_j V'_j - h_j)

(``T_j``: body ``j``'s map from a world twist about the reference point to its body state,
so ``T_jᵀ`` turns its load into a wrench about that point; :mod:`mbs.dynamics._spatial`).
In the spatial form this is ``Σ I_j a_j - W_j`` with ``a_j = Σ_{k ≤ j} ξ_k u'_k``, the
quantities the articulated recursion already has. A joint's spring, damper or drive acts
across the joint (a generalized force ``Q``), so ``F_b`` includes the part it carries: along
a rate ``k`` of the joint ``ξ_kᵀ F_b = Q_k``, the constraint carries the rest. A driven
hinge has no rate: its drive torque is ``F_b``'s moment about its axis.

Forces in N, moments in N m about the joint (the child body frame's origin, or a hinge of
the joint for :meth:`Reactions.about_axis`).
"""
from __future__ import annotations

import casadi as ca

from mbs.joints import DrivenHinge, Hinge, Params, Relative, Serial, compose


def _leaves(joint, q, v):
    """The elementary joints of ``joint`` in series order with their coordinates and rates."""
    if not isinstance(joint, Serial):
        yield joint, q, v
        return
    i = k = 0
    for part in joint.parts:
        yield from _leaves(part, q[i:i + part.nq], v[k:k + part.nv])
        i, k = i + part.nq, k + part.nv


class Reactions:
    """The joint reactions of a tree at a symbolic state (built once, on first use).

    lay: the :class:`mbs.dynamics.Layout`; spatial: each body's
    :class:`mbs.dynamics._spatial.Spatial` about ``r0`` (3,) m; udot: the accelerations
    ``u'`` (nv,); motions: each body frame's absolute motion; ``s``, ``u``, ``t``, ``p``: the
    state, time and parameters (for the frames inside a joint).
    """

    def __init__(self, lay, spatial: dict, udot: ca.SX, motions: dict[str, Relative], r0, s, u, t, p: Params):
        self.lay, self.spatial, self.udot, self.motions, self.r0 = lay, spatial, udot, motions, r0
        self._s, self._u, self._t, self._p = s, u, t, p
        self._bodies = {b.name: b for b in lay.bodies}
        self._sums: dict[str, ca.SX] | None = None

    def wrenches(self) -> dict[str, ca.SX]:
        """Per body the load from its parent: moment about ``r0`` and force, world (6,)."""
        if self._sums is None:
            acc, own = {}, {}
            for b in self.lay.bodies:
                sp = self.spatial[b.name]
                a = acc.get(b.parent, ca.SX.zeros(6))
                moved = sp.twist.shape[1]  # by its joint's rates (a flexible body's section: the body's modal ones)
                acc[b.name] = a + ca.mtimes(sp.twist, self.udot[self.lay.v_slices[b.name]]) if moved else a
                own[b.name] = ca.mtimes(sp.inertia, acc[b.name]) - sp.wrench
            for b in reversed(self.lay.bodies):
                if b.parent in own:
                    own[b.parent] = own[b.parent] + own[b.name]
            self._sums = own
        return self._sums

    def _check(self, body: str) -> None:
        if body not in self._bodies:
            raise KeyError(f"unknown body {body!r}; known: {', '.join(self._bodies)}")

    def world(self, body: str, point=None) -> tuple[ca.SX, ca.SX]:
        """Force (3,) and moment (3,) that the parent passes to ``body`` through its joint,
        world components; the moment about ``point`` (3,) m, world (default the joint)."""
        self._check(body)
        w = self.wrenches()[body]
        point = self.motions[body].position if point is None else point
        return w[3:], w[:3] - ca.cross(point - self.r0, w[3:])

    def at(self, body: str, frame: str | None = None) -> tuple[ca.SX, ca.SX]:
        """:meth:`world` about the joint in the axes of ``body`` (default), of the body
        ``frame`` or of the world (``frame="world"``)."""
        force, moment = self.world(body)
        if frame == "world":
            return force, moment
        self._check(frame or body)
        turn = self.motions[frame or body].rotation.T
        return ca.mtimes(turn, force), ca.mtimes(turn, moment)

    def hinge_frame(self, body: str, hinge: str) -> tuple[Relative, Hinge | DrivenHinge]:
        """The hinge called ``hinge`` inside the joint of ``body`` and the absolute motion of
        its frame before its own turn (origin on the axis; the axis has the same components
        before and after the turn)."""
        self._check(body)
        b = self._bodies[body]
        q, v = self._s[self.lay.q_slices[body]], self._u[self.lay.v_slices[body]]
        if hasattr(b.joint, "full"):  # a loop joint (mbs.loops): its dependent coordinates too
            q, v = b.joint.full(q, v, self._t, self._p)
        z = ca.SX.zeros(3)
        parent = self.motions.get(b.parent, Relative(z, ca.SX.eye(3), z, z))
        frame = compose(parent, Relative(ca.DM(b.at), ca.DM(b.frame), z, z))
        for leaf, ql, vl in _leaves(b.joint, q, v):
            if isinstance(leaf, (Hinge, DrivenHinge)) and leaf.name == hinge:
                return frame, leaf
            frame = compose(frame, leaf.relative(ql, vl, self._t, self._p))
        names = [j.name for j, _, _ in _leaves(b.joint, q, v) if isinstance(j, (Hinge, DrivenHinge))]
        raise KeyError(f"body {body!r}: its joint has no hinge called {hinge!r}; "
                       f"its hinges: {', '.join(names) or 'none'}")

    def about_axis(self, body: str, hinge: str) -> ca.SX:
        """Moment (N m) that the parent passes to ``body`` about the axis of its joint's
        ``hinge``: a driven hinge's drive torque, a free hinge's spring and damper torque."""
        frame, leaf = self.hinge_frame(body, hinge)
        _, moment = self.world(body, frame.position)
        return ca.dot(moment, ca.mtimes(frame.rotation, ca.DM(leaf.axis)))
