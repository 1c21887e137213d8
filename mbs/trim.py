"""Trim of a helicopter scene: the entry point of ``heli trim``.

The method, periodic shooting with Newton's method on the exact AD Jacobian of the fixed-step
map, is in :mod:`mbs.analysis.trim` (equations in :mod:`mbs.analysis.shooting`, period in
:mod:`mbs.analysis.period`, Jacobian in :mod:`mbs.analysis.monodromy`).
"""
from __future__ import annotations

from mbs.analysis.trim import TORQUE_NOTE, Trim, estimate, trim, trimmable, write_trim

CONTROLS = ("collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective")

__all__ = ["CONTROLS", "TORQUE_NOTE", "Trim", "estimate", "trim", "trimmable", "write_trim"]
