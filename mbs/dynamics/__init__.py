"""Equations of motion in minimal coordinates with forward-mode AD (the paper's method).

State ``x = (s, u, z)``: ``s`` (nq,) joint positions, ``u`` (nv,) joint rates, ``z`` (nz,)
extra first-order states of force elements (e.g. induced inflow; usually none). Body states
``V`` stack, per body, the centre-of-mass velocity (world components, m/s) and the angular
velocity (body components, rad/s), so that ``M = blockdiag(m I, J_c)``.

* ``H = dV/ds F + dV/dt`` from ONE forward directional derivative along ``(F, 1)`` (it
  carries the rates and accelerations of driven joints: they are functions of t);
* each body's own columns of ``J_u = dV/du`` (its joint's motion subspace) from one
  directional derivative per rate of its joint;
* the equations ``J_uᵀ M J_u u' = J_uᵀ (h - M H) + Q``, ``s' = F(s, u)`` are solved by one of
  two paths (:data:`PATHS`): ``composite`` forms ``Mt = J_uᵀ M J_u`` by subtree sums and
  factorises it (:mod:`._composite`), ``articulated`` runs the articulated-body recursion
  over the same quantities, O(n) for any tree (:mod:`._articulated`). The builder takes the
  one with fewer operations: shallow rotor trees the first, deep chains the second.

The joint reaction loads (:class:`Reactions`, what the parent passes to each body through its
joint) come from one backward Newton–Euler pass over the same quantities, with the body
accelerations ``J_u u' + H``; model outputs read them as ``state.reactions``.

Coordinates declared dependent (:meth:`mbs.tree.Model.add_dependent`: a geared rotor, a cyclic
pitch following the hub's azimuth) leave the state; the equations hold in the others
(:mod:`._dependent`).

No Jacobian is written by hand: each joint states only its relative kinematics.
"""
from __future__ import annotations

from mbs.dynamics._kinematics import Kinematics, body_states, kinematics, traverse
from mbs.dynamics._layout import Layout, state_layout
from mbs.dynamics._reactions import Reactions
from mbs.dynamics._symbolic import PATHS, Symbolic, symbolic

__all__ = ["Kinematics", "Layout", "PATHS", "Reactions", "Symbolic", "body_states", "kinematics", "state_layout",
           "symbolic", "traverse"]
