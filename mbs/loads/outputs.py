"""Joint reaction loads as named model outputs.

The loads come from :class:`mbs.dynamics.Reactions` (one backward Newton–Euler pass over the
tree, nothing written by hand). An output is evaluated when a result is recorded, never
inside an integrator step, so declaring loads does not slow the step.
"""
from __future__ import annotations

import casadi as ca

from mbs.joints import DrivenHinge, Hinge
from mbs.tree import WORLD, Model, leaf_joints

COMPONENTS = ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")
"""The six outputs of one joint load, in this order: forces (N), moments (N m)."""

SIDES = {"child": "that the parent passes to", "parent": "that the parent receives from"}


def _check(model: Model, body: str, frame: str | None, on: str) -> None:
    if body not in model.bodies:
        raise ValueError(f"joint loads of unknown body {body!r}; bodies: {', '.join(model.bodies)}")
    if frame not in (None, WORLD) and frame not in model.bodies:
        raise ValueError(f"joint loads of {body!r}: unknown frame {frame!r}; give a body name or 'world'")
    if on not in SIDES:
        raise ValueError(f"joint loads of {body!r}: on = {on!r}; choose 'child' or 'parent'")


def add_joint_loads(model: Model, body: str, name: str | None = None, frame: str | None = None,
                    on: str = "child", what: str | None = None, signs=(1, 1, 1, 1, 1, 1)) -> list[str]:
    """Declare the six outputs ``<name>.force_x`` … ``<name>.moment_z`` (N, N m) of the load
    transmitted by the joint of ``body`` (default name ``<body>.joint``).

    on: "child", the load the parent passes to ``body``; "parent", the load ``body`` and its
    subtree pass back to the parent (the opposite). Moments about the joint (the origin of
    ``body``'s frame); components in the axes of ``body`` (default), of the body ``frame`` or
    of the world (``frame="world"``). what: the description's subject. signs: a factor per
    component (e.g. to read a clockwise rotor's blade axes as a counter-clockwise one's).
    Returns the names.
    """
    _check(model, body, frame, on)
    name = name or f"{body}.joint"
    sign = 1.0 if on == "child" else -1.0
    axes = f"{frame or body} axes" if frame != WORLD else "world axes"
    subject = what or f"load {SIDES[on]} {body} through its joint"
    names = []
    for k, comp in enumerate(COMPONENTS):
        unit, kind = ("N", "force") if k < 3 else ("N m", "moment about the joint")
        model.add_output(f"{name}.{comp}", lambda s, k=k: sign * signs[k] * _load(s, body, frame)[k], unit,
                         f"{subject}: {kind} along {axes} {comp[-1]}")
        names.append(f"{name}.{comp}")
    return names


def _load(state, body: str, frame: str | None) -> ca.SX:
    return ca.vertcat(*state.reactions.at(body, frame))


def add_hinge_torque(model: Model, body: str, hinge: str, name: str, description: str, sign: float = 1.0) -> str:
    """Declare the output ``name`` (N m): the moment the parent passes to ``body`` about the
    axis of ``hinge`` in its joint (a driven hinge's drive torque, a free hinge's spring and
    damper torque), times ``sign`` (-1: about the opposite direction)."""
    _check(model, body, None, "child")
    hinges = [j.name for j in leaf_joints(model.bodies[body].joint) if isinstance(j, (Hinge, DrivenHinge))]
    if hinge not in hinges:
        raise ValueError(f"body {body!r}: its joint has no hinge called {hinge!r}; "
                         f"its hinges: {', '.join(hinges) or 'none'}")
    model.add_output(name, lambda s: sign * s.reactions.about_axis(body, hinge), "N m", description)
    return name
