"""A torsion spring and damper between two coordinates: a shaft from a gearbox to a rotor."""
from __future__ import annotations

import numpy as np

from mbs.forces import ForceElement


class TorsionShaft(ForceElement):
    """Spring ``stiffness`` (N m/rad) and damper ``damping`` (N m s/rad) on the twist
    ``θ_out − ratio θ_in`` of a shaft from the coordinate ``driving`` (``θ_in``, rad) to
    ``driven`` (``θ_out``); equal and opposite torques, ``ratio`` times on the driving side."""

    def __init__(self, name: str, driving: str, driven: str, stiffness: float, damping: float = 0.0,
                 ratio: float = 1.0):
        for what, v in (("stiffness", stiffness), ("damping", damping), ("ratio", ratio)):
            if not np.isfinite(v):
                raise ValueError(f"{name}: {what} {v} is not finite")
        self.name, self.driving, self.driven = name, driving, driven
        self.stiffness, self.damping, self.ratio = float(stiffness), float(damping), float(ratio)

    def twist(self, state):
        return state.q(self.driven) - self.ratio * state.q(self.driving)

    def apply(self, state, loads):
        rate = state.v(self.driven + "_rate") - self.ratio * state.v(self.driving + "_rate")
        torque = -self.stiffness * self.twist(state) - self.damping * rate
        loads.add_generalized(self.driven + "_rate", torque)
        loads.add_generalized(self.driving + "_rate", -self.ratio * torque)

    def potential(self, state):
        return 0.5 * self.stiffness * self.twist(state) ** 2
