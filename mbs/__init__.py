"""Rotor multibody simulation: open-loop trees of rigid bodies in minimal coordinates,
Jacobians by forward-mode automatic differentiation, generated code for speed.

Pipeline: :mod:`mbs.joints` (relative kinematics) -> :mod:`mbs.tree` (bodies, model)
-> :mod:`mbs.dynamics` (AD equations of motion) -> :mod:`mbs.integrators` -> evaluators
(:func:`build`: CasADi virtual machine or compiled C) -> :mod:`mbs.models` (scenes).
"""
from mbs.backends import BACKENDS, CompilerNotFound, Result, System, Trajectory, build
from mbs.forces import ForceElement, Loads, SpringDamper, State, UserForce
from mbs.joints import DrivenHinge, Fixed, FreeJoint, Hinge, Joint, Serial
from mbs.tree import Model

__all__ = [
    "Model", "Joint", "Fixed", "Hinge", "DrivenHinge", "FreeJoint", "Serial",
    "ForceElement", "SpringDamper", "UserForce", "State", "Loads",
    "build", "BACKENDS", "System", "Trajectory", "Result", "CompilerNotFound",
]
__version__ = "0.1.0"
