"""Power as the engines see it.

The engines deliver the rotors' shaft power through the transmission and drive the
accessories (hydraulic pumps, generators, oil-cooler fan) besides:

    P_engine = (P_main + P_tail) / η + P_accessory

``P_main``, ``P_tail``: shaft power of the rotors (W), the drive torque of each rotor's shaft
(a joint reaction) times its speed; ``η``: transmission efficiency; ``P_accessory`` (W). The
aircraft data give ``η`` and ``P_accessory`` (section ``[engine]``, with sources).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Engine:
    """``efficiency``: the transmission's, in (0, 1]; ``accessory_power``: W, >= 0."""

    efficiency: float
    accessory_power: float

    def __post_init__(self):
        if not (np.isfinite(self.efficiency) and 0 < self.efficiency <= 1):
            raise ValueError(f"engine: transmission_efficiency = {self.efficiency} must be in (0, 1]")
        if not (np.isfinite(self.accessory_power) and self.accessory_power >= 0):
            raise ValueError(f"engine: accessory_power = {self.accessory_power} W must be finite and >= 0")

    @classmethod
    def of(cls, data) -> "Engine":
        """From the aircraft data ``data`` (its ``[engine]`` section)."""
        if "engine" not in data:
            raise ValueError("the aircraft data have no [engine] section (transmission_efficiency, accessory_power)")
        e = data["engine"]
        return cls(float(e["transmission_efficiency"]), float(e["accessory_power"]))

    def power(self, *shaft_powers):
        """Engine power (W) from the rotors' shaft powers (W; numbers, arrays or CasADi)."""
        return sum(shaft_powers) / self.efficiency + self.accessory_power
