"""The elastic and structural-damping forces of a flexible body's modal coordinates."""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.forces import ForceElement


class ModalElasticity(ForceElement):
    """Generalized forces ``-∂U/∂q - D q'`` on the modal coordinates ``names`` of ``body``: the
    strain energy ``U = q·K·q / 2 + extra(q)`` (J; stiffness ``K`` (n, n) from the section data,
    N m for tip-normalised coordinates; ``extra`` a function of the coordinates' SX vector,
    e.g. :meth:`mbs.flexible.beam.ModalBlade.strain_energy`, its gradient by AD) and the
    damping ``D`` (n, n), N m s."""

    def __init__(self, body: str, names, stiffness: np.ndarray, damping: np.ndarray, extra=None):
        self.name, self.extra = f"elasticity {body}", extra
        self.coordinates = [f"{body}.{n}" for n in names]
        self.stiffness, self.damping = np.asarray(stiffness, float), np.asarray(damping, float)
        n = len(self.coordinates)
        for what, a in (("stiffness", self.stiffness), ("damping", self.damping)):
            if a.shape != (n, n) or not np.all(np.isfinite(a)):
                raise ValueError(f"{self.name}: {what} must be a finite ({n}, {n}) matrix, got shape {a.shape}")

    def _q(self, state) -> ca.SX:
        return ca.vertcat(*[state.q(n) for n in self.coordinates])

    def apply(self, state, loads) -> None:
        q, rates = self._q(state), ca.vertcat(*[state.v(n + "_rate") for n in self.coordinates])
        force = -ca.mtimes(ca.DM(self.stiffness), q) - ca.mtimes(ca.DM(self.damping), rates)
        if self.extra is not None:
            force -= ca.gradient(self.extra(q), q)
        for i, n in enumerate(self.coordinates):
            loads.add_generalized(n + "_rate", force[i])

    def potential(self, state):
        q = self._q(state)
        return 0.5 * ca.mtimes([q.T, ca.DM(self.stiffness), q]) + (self.extra(q) if self.extra is not None else 0)
