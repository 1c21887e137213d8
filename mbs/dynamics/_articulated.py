"""The articulated path: Featherstone's articulated-body recursion over the quantities the
AD gives, O(n) operations for any tree.

All bodies are spatial quantities about one point in world components
(:mod:`mbs.dynamics._spatial`), so no transform sits between a body and its parent. The
velocity-product accelerations are already inside each body's wrench (``g = h - M H``):
what remains is the tree at rest under the wrenches ``W_i`` and joint forces ``Q`` with
joint motion subspaces ``S_k = ξ_k``, i.e. ``Mt u' = J_uᵀ g + Q`` of the composite path,
solved without forming ``Mt``:

* leaves to root: ``U = Iᴬ S``, ``D = Sᵀ U``, ``y = D⁻¹ (Q_k + Sᵀ Wᴬ)``; the parent
  receives ``Iᴬ - U D⁻¹ Uᵀ`` and ``Wᴬ - U y`` (``Iᴬ``, ``Wᴬ``: articulated inertia and wrench);
* root to leaves: ``u_k' = y - (U D⁻¹)ᵀ a_parent``, ``a = a_parent + S u_k'``.
"""
from __future__ import annotations

import casadi as ca

from mbs.dynamics._spatial import symmetric


class _Inverse:
    """``D⁻¹`` of a small symmetric positive definite matrix (a joint's ``Sᵀ Iᴬ S``): the
    reciprocal for one rate, an unrolled LDLᵀ otherwise."""

    def __init__(self, d: ca.SX):
        n = d.shape[0]
        self.n, self.low, self.diag = n, [[None] * n for _ in range(n)], [None] * n
        for j in range(n):
            self.diag[j] = d[j, j] - sum((self.low[j][k] ** 2 * self.diag[k] for k in range(j)), ca.SX(0))
            for i in range(j + 1, n):
                s = d[i, j] - sum((self.low[i][k] * self.low[j][k] * self.diag[k] for k in range(j)), ca.SX(0))
                self.low[i][j] = s / self.diag[j]
        self.reciprocal = [1 / v for v in self.diag]

    def times(self, b: ca.SX) -> ca.SX:
        """``D⁻¹ b`` for ``b`` (n, m)."""
        y = [b[i, :] for i in range(self.n)]
        for i in range(self.n):
            for k in range(i):
                y[i] = y[i] - self.low[i][k] * y[k]
        y = [v * r for v, r in zip(y, self.reciprocal)]
        for i in reversed(range(self.n)):
            for k in range(i + 1, self.n):
                y[i] = y[i] - self.low[k][i] * y[k]
        return ca.vertcat(*y)


class _Joint:
    """One joint's share of the recursion: its motion subspace ``S`` (6, nk), ``K = U D⁻¹``
    (6, nk) and ``y`` (nk,); what it passes to its parent's articulated body."""

    def __init__(self, s: ca.SX, inertia: ca.SX, wrench: ca.SX, q: ca.SX):
        u = ca.mtimes(inertia, s)
        inverse = _Inverse(ca.mtimes(s.T, u))
        self.s, self.k = s, inverse.times(u.T).T
        self.y = inverse.times(q + ca.mtimes(s.T, wrench))
        self.passed_inertia = symmetric(inertia - ca.mtimes(self.k, u.T))
        self.passed_wrench = wrench - ca.mtimes(u, self.y)

    def accelerations(self, a_parent: ca.SX | None) -> tuple[ca.SX, ca.SX]:
        """The joint's ``u'`` (nk,) and its body's spatial acceleration (6,), from the
        parent's (None at a root: the world does not accelerate, gravity is a load)."""
        if a_parent is None:
            return self.y, ca.mtimes(self.s, self.y)
        ud = self.y - ca.mtimes(self.k.T, a_parent)
        return ud, a_parent + ca.mtimes(self.s, ud)


def articulated(lay, spatial: dict, q: ca.SX) -> ca.SX:
    """``u'`` (nv,) from each body's :class:`Spatial` and the generalized forces ``q`` (nv,)."""
    inertia = {n: s.inertia for n, s in spatial.items()}
    wrench = {n: s.wrench for n, s in spatial.items()}
    joints = {}
    for b in reversed(lay.bodies):
        ia, wa = inertia[b.name], wrench[b.name]
        if b.joint.nv:
            joints[b.name] = j = _Joint(spatial[b.name].twist, ia, wa, q[lay.v_slices[b.name]])
            ia, wa = j.passed_inertia, j.passed_wrench
        if b.parent in inertia:
            inertia[b.parent] = symmetric(inertia[b.parent] + ia)
            wrench[b.parent] = wrench[b.parent] + wa
    acc, udot = {}, []
    for b in lay.bodies:
        a = acc.get(b.parent)
        if b.name in joints:
            ud, a = joints[b.name].accelerations(a)
            udot.append(ud)
        if a is not None:
            acc[b.name] = a
    return ca.vertcat(*udot, ca.SX(0, 1))
