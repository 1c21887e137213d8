"""The aircraft's surroundings, as inputs of the aerodynamics.

* :mod:`mbs.environment.atmosphere`: the International Standard Atmosphere with a temperature
  offset (density, pressure, temperature, speed of sound, viscosity);
* :mod:`mbs.environment.air`: :class:`Air`, what a model's aerodynamic elements read of the air
  through the symbolic state (density, speed of sound, velocity: the air-velocity hook).
"""
from mbs.environment.air import Air, through_air

__all__ = ["Air", "through_air"]
