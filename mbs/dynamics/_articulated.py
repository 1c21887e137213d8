"""The articulated path: Featherstone's articulated-body recursion over the quantities the
AD gives, O(n) operations for any tree.

All bodies are spatial quantities about one point in world components
(:mod:`mbs.dynamics._spatial`), so no transform sits between a body and its parent. The
velocity-product accelerations are already inside each body's wrench (``g = h - M H``):
what remains is the tree at rest under the wrenches ``W_i`` and joint forces ``Q`` with
joint motion subspaces ``S_k = ξ_k``, i.e. ``Mt u' = J_uᵀ g + Q`` of the composite path,
solved without forming ``Mt``. A joint with several rates is taken as one-rate joints in
series with massless links between them (its columns of ``J_u``, outboard first on the way
in): the same elimination as with its whole ``D = Sᵀ Iᴬ S``, without a matrix inverse.

* leaves to root, per rate with twist ``s``: ``U = Iᴬ s``, ``D = sᵀ U``,
  ``y = (Q_k + sᵀ Wᴬ) / D``; inboard goes ``Iᴬ - U Uᵀ / D`` and ``Wᴬ - U y``
  (``Iᴬ``, ``Wᴬ``: articulated inertia and wrench);
* root to leaves: ``u_k' = y - Uᵀ a / D``, ``a ← a + s u_k'`` (``a``: the spatial
  acceleration, zero at the world: gravity is a load).
"""
from __future__ import annotations

import casadi as ca

from mbs.dynamics._spatial import symmetric


class _Rate:
    """One rate's share of the recursion, from its twist ``s`` (6,), the articulated inertia
    (6, 6) and wrench (6,) outboard of it and its generalized force ``q``."""

    def __init__(self, s: ca.SX, inertia: ca.SX, wrench: ca.SX, q: ca.SX):
        u = ca.mtimes(inertia, s)
        inverse = 1 / ca.dot(s, u)
        self.s, self.k = s, u * inverse
        self.y = (q + ca.dot(s, wrench)) * inverse
        self.passed_inertia = symmetric(inertia - ca.mtimes(self.k, u.T))
        self.passed_wrench = wrench - u * self.y

    def accelerations(self, a: ca.SX | None) -> tuple[ca.SX, ca.SX]:
        """The rate's ``u'`` and the spatial acceleration (6,) outboard of it, from the one
        inboard (None at a root)."""
        if a is None:
            return self.y, self.s * self.y
        ud = self.y - ca.dot(self.k, a)
        return ud, a + self.s * ud


def _rates(twist: ca.SX, inertia: ca.SX, wrench: ca.SX, q: ca.SX) -> tuple[list[_Rate], ca.SX, ca.SX]:
    """A joint's rates, outboard first, and the inertia and wrench they pass inboard."""
    steps = []
    for c in reversed(range(twist.shape[1])):
        steps.append(_Rate(twist[:, c], inertia, wrench, q[c]))
        inertia, wrench = steps[-1].passed_inertia, steps[-1].passed_wrench
    return steps[::-1], inertia, wrench


def articulated(lay, spatial: dict, q: ca.SX) -> ca.SX:
    """``u'`` (nv,) from each body's :class:`Spatial` and the generalized forces ``q`` (nv,)."""
    inertia = {n: s.inertia for n, s in spatial.items()}
    wrench = {n: s.wrench for n, s in spatial.items()}
    joints = {}
    for b in reversed(lay.bodies):
        joints[b.name], ia, wa = _rates(spatial[b.name].twist, inertia[b.name], wrench[b.name],
                                        q[lay.v_slices[b.name]])
        if b.parent in inertia:
            inertia[b.parent] = symmetric(inertia[b.parent] + ia)
            wrench[b.parent] = wrench[b.parent] + wa
    acc, udot = {}, []
    for b in lay.bodies:
        a = acc.get(b.parent)
        for step in joints[b.name]:
            ud, a = step.accelerations(a)
            udot.append(ud)
        if a is not None:
            acc[b.name] = a
    return ca.vertcat(*udot, ca.SX(0, 1))
