"""A single-main-rotor helicopter as an open-loop tree, built from an aircraft file.

``build(cfg, aircraft)`` makes the model a :class:`Config` asks for (which bodies, rotors and
force elements) with the data of an :class:`mbs.aircraft.Aircraft`; the scenes of
:mod:`mbs.models.helicopter.scenes` are such configs. Frames and senses of rotation:
:mod:`mbs.models.helicopter.frames`; bodies and joints: :mod:`~mbs.models.helicopter.tree`;
aerodynamics: :mod:`~mbs.models.helicopter.aero`; the closed-form trim estimate:
:mod:`~mbs.models.helicopter.estimate`; the air: :mod:`~mbs.models.helicopter.environment`, and a
scene's air options: :mod:`~mbs.models.helicopter.air_options`; a scene's plot panels:
:mod:`~mbs.models.helicopter.panels`.
"""
from mbs.models.helicopter.aero import airfoil, main_rotor_wake, rotor_model
from mbs.models.helicopter.build import build, stored_trim
from mbs.models.helicopter.config import (AERO_SWITCHES, FULL, NONE, Config, aero_switches, applicable_switches,
                                          config_of, with_aero)
from mbs.models.helicopter.estimate import TrimEstimate, estimate_trim

__all__ = ["AERO_SWITCHES", "FULL", "NONE", "Config", "TrimEstimate", "aero_switches", "airfoil",
           "applicable_switches", "build", "config_of", "estimate_trim", "main_rotor_wake", "rotor_model",
           "stored_trim", "with_aero"]
