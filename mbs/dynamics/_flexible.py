"""A flexible body and its sections (:mod:`mbs.flexible`) as one spatial quantity for the
composite path.

The composite path (:mod:`mbs.dynamics._composite`) needs, per flexible body, the spatial
inertia and wrench of the body with its sections and, for its modal rates, the sections'
momentum ``Γ = Σ_s I_s ψ_s``, the block ``Σ_s ψ_sᵀ I_s ψ_s`` and the force ``Σ_s ψ_sᵀ W_s``
(``ψ_s``: section ``s``'s twist per unit modal rate). Each is a sum over the sections of the
rigid-section formulas of :func:`mbs.dynamics._spatial.body_spatial`; here the sums are taken
in the body frame, where a section's place ``p_s``, turn ``R_s`` and modal Jacobians
(``Φ_s = ∂ṗ_s/∂v``, ``Ω_s = ∂ω_s/∂v``: forward-mode AD of its relative kinematics) depend on the
modal coordinates alone, and the totals are turned to the world once per body instead of once
per section. The sections' loads ``W_s`` carry their velocity products (``h - M H``, ``H`` by
AD of their absolute velocities), as every body's do.
"""
from __future__ import annotations

import casadi as ca

from mbs.dynamics._spatial import Spatial, skew, symmetric


def _cross_columns(p, m: ca.SX) -> ca.SX:
    """``p × m_k`` for every column ``m_k`` of ``m`` (3, k)."""
    return ca.mtimes(skew(p), m)


class Sums:
    """Running sums over the sections in the body frame (about its origin): mass, first
    moment, inertia about the origin, force and moment, modal momentum (6, n) (angular,
    linear), modal block (n, n) and modal force (n,)."""

    def __init__(self, n: int):
        self.mass, self.first, self.inertia = 0.0, ca.SX.zeros(3), ca.SX.zeros(3, 3)
        self.force, self.moment = ca.SX.zeros(3), ca.SX.zeros(3)
        self.momentum, self.block, self.modal_force = ca.SX.zeros(6, n), ca.SX.zeros(n, n), ca.SX.zeros(n)

    def add(self, body, rel, v, load_force, load_torque) -> None:
        """Section ``body`` at the relative motion ``rel`` (body frame), modal rates ``v``, its
        load: ``load_force`` (3,) in body-frame axes and ``load_torque`` (3,) in its own."""
        p, turn, m, j = rel.position, rel.rotation, body.mass, ca.DM(body.inertia)
        phi = ca.jtimes(rel.velocity, v, ca.SX.eye(v.numel()))
        omega = ca.jtimes(rel.omega, v, ca.SX.eye(v.numel()))
        j_omega = ca.mtimes([turn, j, omega])
        self.mass += m
        self.first += m * p
        self.inertia += ca.mtimes([turn, j, turn.T]) + m * (ca.dot(p, p) * ca.DM.eye(3) - ca.mtimes(p, p.T))
        self.force += load_force
        self.moment += ca.cross(p, load_force) + ca.mtimes(turn, load_torque)
        self.momentum += ca.vertcat(m * _cross_columns(p, phi) + j_omega, m * phi)
        self.block += m * ca.mtimes(phi.T, phi) + ca.mtimes([omega.T, j, omega])
        self.modal_force += ca.mtimes(phi.T, load_force) + ca.mtimes(omega.T, load_torque)


def flexible_spatials(lay, kin, spatial: dict, g: ca.SX, u: ca.SX, r0) -> dict[str, Spatial]:
    """Per flexible body of the layout ``lay`` its :func:`flexible_spatial`, from the
    kinematics ``kin``, every body's ``spatial``, the loads ``g`` (6 nb,) with the velocity
    products, the rates ``u`` and the reference point ``r0``."""
    index = {b.name: i for i, b in enumerate(lay.bodies)}
    out = {}
    for name, sections in lay.sections().items():
        turn_in = kin.motions[name].rotation.T
        sums = Sums(sections[0].joint.shares)
        for b in sections:
            load = g[kin.rows(index[b.name])]
            sums.add(b, kin.relative[b.name], u[lay.v_slices[b.name]], ca.mtimes(turn_in, load[:3]), load[3:])
        out[name] = flexible_spatial(spatial[name], kin.motions[name], sums, r0)
    return out


def flexible_spatial(frame: Spatial, motion, sums: Sums, r0) -> Spatial:
    """The flexible body with its sections about ``r0`` in world axes: the frame's own
    ``Spatial`` plus the section ``sums``, its frame at ``motion``; the modal extras placed in
    its last columns."""
    turn, o = motion.rotation, motion.position - r0
    mass, first = sums.mass, ca.mtimes(turn, sums.first)
    oo = ca.mtimes(o, o.T)
    rotational = (ca.mtimes([turn, sums.inertia, turn.T]) + mass * (ca.dot(o, o) * ca.DM.eye(3) - oo)
                  + 2 * ca.dot(o, first) * ca.DM.eye(3) - ca.mtimes(o, first.T) - ca.mtimes(first, o.T))
    coupling = skew(mass * o + first)
    inertia = ca.blockcat([[symmetric(rotational), coupling], [coupling.T, mass * ca.DM.eye(3)]])
    force = ca.mtimes(turn, sums.force)
    wrench = ca.vertcat(ca.cross(o, force) + ca.mtimes(turn, sums.moment), force)
    linear = ca.mtimes(turn, sums.momentum[3:, :])
    momentum = ca.vertcat(ca.mtimes(turn, sums.momentum[:3, :]) + _cross_columns(o, linear), linear)
    nk, n = frame.twist.shape[1], sums.block.shape[0]
    pad = ca.SX(nk - n, n)
    return Spatial(frame.twist, frame.inertia + inertia, frame.wrench + wrench, frame.to_body_state,
                   momentum=ca.horzcat(ca.SX(6, nk - n), momentum),
                   own_block=ca.blockcat([[ca.SX(nk - n, nk - n), pad], [pad.T, symmetric(sums.block)]]),
                   own_force=ca.vertcat(ca.SX(nk - n, 1), sums.modal_force))
