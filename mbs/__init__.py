"""Rotor multibody simulation: open-loop trees of rigid bodies in minimal coordinates,
Jacobians by forward-mode automatic differentiation, generated code for speed.

Pipeline: :mod:`mbs.joints` (relative kinematics) -> :mod:`mbs.tree` (bodies, model)
-> :mod:`mbs.dynamics` (AD equations of motion) -> :mod:`mbs.integrators` -> evaluators
(:func:`build`: CasADi virtual machine or compiled C) -> :mod:`mbs.scenes` (what to model).

Names are imported lazily so that loading a compiled model (``mbs.backends.compiled``)
needs only numpy, not CasADi.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "Model": "mbs.tree", "Joint": "mbs.joints", "Fixed": "mbs.joints", "Hinge": "mbs.joints",
    "DrivenHinge": "mbs.joints", "FreeJoint": "mbs.joints", "Serial": "mbs.joints",
    "Slider": "mbs.joints",
    "ForceElement": "mbs.forces", "SpringDamper": "mbs.forces", "UserForce": "mbs.forces",
    "State": "mbs.forces", "Loads": "mbs.forces", "PointForce": "mbs.forces", "BodyTorque": "mbs.forces",
    "build": "mbs.backends", "BACKENDS": "mbs.backends", "System": "mbs.backends.system",
    "Trajectory": "mbs.backends.system", "Result": "mbs.backends.system",
    "CompilerNotFound": "mbs.backends.compiled",
}
__all__ = sorted(_EXPORTS)
__version__ = "0.1.0"


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'mbs' has no attribute {name!r}")
