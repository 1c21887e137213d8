"""The composite path: ``Mt = J_uᵀ M J_u`` and ``J_uᵀ g`` summed over subtrees, then
``Mt u' = ht`` by CasADi's sparse LDL.

``(J_uᵀ M J_u)_jk = Σ_i ξ_jᵀ I_i ξ_k = ξ_jᵀ Ic(b_k) ξ_k`` when ``b_j`` is ``b_k`` or one of
its ancestors (zero otherwise) and ``(J_uᵀ g)_k = ξ_kᵀ Wc(b_k)``, with ``Ic``, ``Wc`` the
spatial inertias and wrenches summed over the subtree of ``b_k`` (Featherstone's composite
rigid bodies): the same sums as the plain product, in O(n²) operations for a chain where
the product takes O(n³). The LDL costs O(n³) on a chain, little on a shallow tree.

A flexible body's modal rates move its sections (:mod:`mbs.flexible`), each with its own
twist ``ψ_s`` (its AD columns of ``J_u``), and nothing else. The body's :class:`Spatial` holds
its sections (:mod:`mbs.dynamics._flexible`: the subtree sums skip them) and their momentum
``Γ = Σ_s I_s ψ_s``: its columns take ``f = Ic ξ + Γ`` in place of ``Ic ξ``, its own block gains
``Γᵀ ξ + Σ_s ψ_sᵀ I_s ψ_s`` and its generalized force ``Σ_s ψ_sᵀ W_s``: the same sum
``Σ J_iᵀ M_i J_i`` over the sections.
"""
from __future__ import annotations

import casadi as ca
import numpy as np


def composite(lay, spatial: dict) -> tuple[ca.SX, ca.SX]:
    """``Mt`` (nv, nv, sparse) and ``J_uᵀ g`` (nv,) from each body's :class:`Spatial`."""
    inertia = {n: s.inertia for n, s in spatial.items()}
    wrench = {n: s.wrench for n, s in spatial.items()}
    for b in reversed(lay.bodies):
        if b.parent in inertia and not getattr(b.joint, "shares", 0):  # sections: inside their body's
            inertia[b.parent] = inertia[b.parent] + inertia[b.name]
            wrench[b.parent] = wrench[b.parent] + wrench[b.name]
    parent = {b.name: b.parent for b in lay.bodies}
    moving = [b.name for b in lay.moving()]
    blocks = {}
    for k in moving:
        sp = spatial[k]
        f, a = ca.mtimes(inertia[k], sp.twist), k
        f = f + sp.momentum if sp.momentum is not None else f
        while a in parent:  # b_k and its ancestors
            if a in moving:
                blocks[(a, k)] = ca.mtimes(spatial[a].twist.T, f)
            a = parent[a]
        if sp.momentum is not None:
            blocks[(k, k)] = blocks[(k, k)] + ca.mtimes(sp.momentum.T, sp.twist) + sp.own_block
    rows = [[blocks[(a, k)] if (a, k) in blocks else blocks[(k, a)].T if (k, a) in blocks
             else ca.SX(spatial[a].twist.shape[1], spatial[k].twist.shape[1]) for k in moving] for a in moving]
    jtg = ca.vertcat(*[ca.mtimes(spatial[k].twist.T, wrench[k])
                       + (spatial[k].own_force if spatial[k].own_force is not None else 0) for k in moving],
                     ca.SX(0, 1))
    return ca.sparsify(ca.blockcat(rows)) if moving else ca.SX(0, 0), jtg


def solve(parts: ca.Function, nx: int, np_: int) -> ca.Function:
    """``rhs(x, t, p) -> x'``: an MX wrapper of ``parts -> (s', Mt, ht, z')`` solving
    ``Mt u' = ht`` with CasADi's sparse LDL (code-generatable)."""
    x, t, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("p", np_)
    sd, mt, ht, zd = parts(x, t, p)
    return ca.Function("rhs", [x, t, p], [ca.vertcat(sd, ca.solve(mt, ht, "ldl"), zd)],
                       ["x", "t", "p"], ["xdot"])


def ldl_operations(pattern: ca.Sparsity) -> int:
    """Floating-point operations of the sparse LDLᵀ factorisation and solve of a matrix of
    ``pattern`` (fill-reducing order, as CasADi's LDL): per column ``j`` with ``c_j``
    entries below the diagonal in ``L``, ``c_j² + 2 c_j`` to factor and ``4 c_j + 1`` to solve."""
    if pattern.size1() == 0:
        return 0
    lt, _ = pattern.ldl(True)
    counts = np.diff(np.array(lt.T.colind()))  # entries per column of L
    return int(np.sum(counts**2 + 6 * counts + 1))
