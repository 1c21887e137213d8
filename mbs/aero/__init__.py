"""Aerodynamics as force elements: as simple as the paper's, no simpler than a user needs.

* :mod:`mbs.aero.sections`: :class:`Airfoil` (``c_L = a α``, ``c_D = c_d0 + c_d2 α²``, a smooth
  stall guard, flat-plate drag beyond it, reverse flow folded) and the force on one section.
* :mod:`mbs.aero.rotor`: :class:`RotorAero`, blade elements on every blade (quasi-steady strip
  theory) with the rotor's inflow states; thrust, shaft torque and power as signals.
  :class:`RotorModel` holds the per-scene switches:
* :mod:`mbs.aero.inflow`: uniform momentum inflow with the Pitt–Peters apparent mass, or
  Pitt–Peters three-state dynamic inflow with wake-skew gains;
* :mod:`mbs.aero.tiploss`: tip loss as an effective blade radius ``B R``;
* :mod:`mbs.aero.compressibility`: Prandtl–Glauert lift slope and drag divergence;
* :mod:`mbs.aero.wake`: the main rotor's wake at the airframe (downwash, swirl, immersion);
* :mod:`mbs.aero.airframe`: Padfield's Bo105 fuselage polynomials or published tables
  (:mod:`mbs.aero.airframe_tables`, splines of :mod:`mbs.aero.interpolation`), one-section tail
  surfaces in the free stream or the rotor's wake, the fuselage download and the hub drag.

Units: SI, angles in rad. Every element reads the air (density, speed of sound, wind, gusts,
turbulence) through the symbolic state: :mod:`mbs.environment.air`.
"""
from mbs.aero.airframe import Download, FuselageAero, FuselageTables, HubDrag, LiftingSurface
from mbs.aero.compressibility import Compressibility
from mbs.aero.inflow import momentum_inflow, pitt_peters_rates, uniform_rate, wake_skew
from mbs.aero.rotor import DiscLoads, Rotor, RotorAero, RotorModel
from mbs.aero.sections import EPS, Airfoil, section_force, soft_clip, turn
from mbs.aero.tiploss import effective_radius_factor, lift_factors
from mbs.aero.wake import Wake, WakeGeometry

__all__ = ["EPS", "Airfoil", "Compressibility", "DiscLoads", "Download", "FuselageAero", "FuselageTables", "HubDrag", "LiftingSurface",
           "Rotor", "RotorAero", "RotorModel", "Wake", "WakeGeometry", "effective_radius_factor", "lift_factors",
           "momentum_inflow", "pitt_peters_rates", "section_force", "soft_clip", "turn", "uniform_rate", "wake_skew"]
