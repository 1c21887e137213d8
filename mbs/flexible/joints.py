"""The two joint kinds of a flexible body.

* :class:`Modal`, the last part of the flexible body's own joint: it states the body's modal
  coordinates (its flexible states) and moves the body frame not at all; the frame is the
  body's floating frame of reference.
* :class:`Section`, the joint of each of its sections (the nodes carrying its mass, the
  points where aerodynamic loads act): it owns no coordinate but reads the last ``shares``
  coordinates of its parent, the modal ones, and states the section's motion relative to the
  body frame (:meth:`mbs.flexible.beam.ModalBlade.relative`). The tree places sections like
  any child body, so their velocities, the AD Jacobians in the modal rates (their own
  columns of ``J_u``) and the velocity products follow as for rigid bodies; the dynamics
  gives the shared rates their mass coupling (:mod:`mbs.dynamics._composite`).
"""
from __future__ import annotations

import casadi as ca

from mbs.joints import Joint, Relative


class Modal(Joint):
    """The modal coordinates of a flexible body (its ``beam``'s), e.g. ``flap``, ``flap2``,
    ``lag``, ``torsion``: tip deflection over the blade length (rad) and tip twist (rad)."""

    def __init__(self, beam):
        self.beam = beam
        self.nq = self.nv = beam.size
        self.q_names = beam.names
        self.v_names = tuple(n + "_rate" for n in beam.names)

    def relative(self, q, v, t, p) -> Relative:
        z = ca.SX.zeros(3)
        return Relative(z, ca.SX.eye(3), z, z)


class Section(Joint):
    """A section of a flexible body at span coordinate ``x`` (m from the root) of ``beam``."""

    nq = nv = 0

    def __init__(self, beam, x: float):
        self.beam, self.x = beam, float(x)
        self.shares = beam.size  # the parent's last coordinates: its modal ones

    def relative(self, q, v, t, p) -> Relative:
        return self.beam.relative(q, v, self.x)

    def qdot(self, q, v):
        return ca.SX(0, 1)

    def project(self, q):
        return ca.SX(0, 1)
