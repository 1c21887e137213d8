"""The model: rigid bodies on an open-loop tree, joints, parameters and force elements.

Frames: every body frame sits at the body's joint (its origin moves with the joint);
the centre of mass ``com`` and the inertia tensor about it are given in that frame.
The world frame is fixed; ``gravity`` (m/s^2) is given in world components. The Bo105
models use x forward/north, y right/east, z down.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Iterator

import numpy as np

from mbs.joints import Hinge, Joint, OneAxis, Serial  # noqa: F401 (Hinge: doctest)

WORLD = "world"


@dataclass
class Body:
    """A rigid body and the joint that attaches it to ``parent``.

    mass: kg. com: (3,) centre of mass in the body frame, m. inertia: (3, 3) about the
    centre of mass in body-frame axes, kg m^2. at: (3,) joint origin in the parent frame, m.
    frame: (3, 3) joint-frame axes in parent-frame components. ``shape`` is free-form
    geometry data for viewers (e.g. ``{"kind": "box", "size": [...]}``).
    """

    name: str
    parent: str
    joint: Joint
    mass: float
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.eye(3))
    at: np.ndarray = field(default_factory=lambda: np.zeros(3))
    frame: np.ndarray = field(default_factory=lambda: np.eye(3))
    shape: dict = field(default_factory=dict)


@dataclass
class Parameter:
    """A run-time input of the generated code (changing it needs no recompilation).

    ``control`` marks inputs a pilot or controller changes during a run (pitch angles);
    the others are set before a run. Values outside ``[low, high]`` are rejected.
    """

    name: str
    default: float
    unit: str = ""
    description: str = ""
    control: bool = False
    low: float = -float("inf")
    high: float = float("inf")


@dataclass
class ExtraState:
    """A first-order state that is not a joint coordinate (e.g. an induced-inflow velocity).

    Its rate is set by a force element with :meth:`mbs.forces.Loads.set_rate`.
    """

    name: str
    initial: float = 0.0
    unit: str = ""
    description: str = ""


@dataclass
class Output:
    """A named output: ``fn(state) -> SX`` scalar, evaluated by the generated code."""

    name: str
    fn: Callable
    unit: str = ""
    description: str = ""


def _vector(name: str, what: str, value, shape) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape != shape:
        raise ValueError(f"body {name!r}: {what} must have shape {shape}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"body {name!r}: {what} {a.tolist()} is not finite")
    return a


def check_inertia(name: str, inertia, physical: bool = True) -> np.ndarray:
    """Validate a 3x3 inertia tensor: symmetric, positive definite and, when ``physical``, the
    triangle inequality (which any real distribution of mass satisfies)."""
    j = _vector(name, "inertia", inertia, (3, 3))
    scale = max(np.abs(j).max(), 1e-300)
    if np.abs(j - j.T).max() > 1e-9 * scale:
        raise ValueError(f"body {name!r}: inertia tensor {j.tolist()} is not symmetric")
    ev = np.linalg.eigvalsh(j)
    if ev[0] <= 0:
        raise ValueError(f"body {name!r}: inertia tensor is not positive definite "
                         f"(principal moments {ev.tolist()} kg m^2)")
    if physical and ev[0] + ev[1] < ev[2] * (1 - 1e-9):
        raise ValueError(f"body {name!r}: principal moments {ev.tolist()} kg m^2 violate the "
                         "triangle inequality I1 + I2 >= I3")
    return j


def check_rotation(name: str, frame) -> np.ndarray:
    r = _vector(name, "frame", frame, (3, 3))
    if np.abs(r @ r.T - np.eye(3)).max() > 1e-9 or np.linalg.det(r) < 0:
        raise ValueError(f"body {name!r}: frame {r.tolist()} is not a proper rotation matrix")
    return r


def leaf_joints(joint: Joint) -> Iterator[Joint]:
    """The elementary joints inside ``joint`` (itself unless it is a :class:`Serial`)."""
    if isinstance(joint, Serial):
        for part in joint.parts:
            yield from leaf_joints(part)
    else:
        yield joint


class Model:
    """Builder for an open-loop multibody tree.

    >>> m = Model("pendulum", gravity=(0, 0, 9.81))
    >>> m.add_body("rod", parent="world", joint=Hinge(axis=(0, 1, 0)), mass=1.0,
    ...            com=(0, 0, 1.0), inertia=np.diag([1e-3, 1e-3, 1e-4]))
    """

    def __init__(self, name: str, gravity=(0.0, 0.0, 9.80665)):
        self.name = name
        self.gravity = _vector(name, "gravity", gravity, (3,))
        self.bodies: dict[str, Body] = {}
        self.parameters: dict[str, Parameter] = {}
        self.forces: list = []
        self.outputs: dict[str, Output] = {}
        self.states: dict[str, ExtraState] = {}
        self.initial: dict[str, float] = {}
        self.air = None  # mbs.environment.Air: what the aerodynamics reads of the air (None: still air)
        self.dependent: dict[str, Callable] = {}

    def add_state(self, name: str, initial: float = 0.0, unit: str = "", description: str = "") -> None:
        """Declare an extra first-order state ``z`` (appended after ``s`` and ``u``)."""
        if name in self.states:
            raise ValueError(f"duplicate state name {name!r}")
        if not np.isfinite(initial):
            raise ValueError(f"state {name!r}: initial value {initial} is not finite")
        self.states[name] = ExtraState(name, float(initial), unit, description)

    def add_dependent(self, coordinate: str, fn: Callable) -> None:
        """Make the one-axis coordinate ``coordinate`` (e.g. ``"tail_hub.azimuth"``) a function of
        the others: ``fn(q, t, p) -> SX``, ``q[name]`` the model's other coordinates (those
        declared dependent before it included), ``t`` (s), ``p[name]`` the parameters. It and
        its rate leave the state; the equations of motion hold in the remaining coordinates
        (:mod:`mbs.dynamics._dependent`): a gear between two rotors, a rotor's cyclic pitch
        following its azimuth."""
        if coordinate in self.dependent:
            raise ValueError(f"coordinate {coordinate!r} is made dependent twice")
        self.dependent[coordinate] = fn

    def add_parameter(self, name: str, default: float, unit: str = "", description: str = "",
                      control: bool = False, low: float = -np.inf, high: float = np.inf) -> None:
        """Declare a named run-time parameter, readable in joints and forces as ``p[name]``."""
        if name in self.parameters:
            raise ValueError(f"duplicate parameter name {name!r}")
        if not (np.isfinite(default) and low <= default <= high):
            raise ValueError(f"parameter {name!r}: default {default} is not finite or outside "
                             f"[{low}, {high}]")
        self.parameters[name] = Parameter(name, float(default), unit, description, control,
                                          float(low), float(high))

    def add_output(self, name: str, fn: Callable, unit: str = "", description: str = "") -> None:
        """Declare a named output ``fn(state) -> SX`` (see :class:`mbs.forces.State`)."""
        if name in self.outputs:
            raise ValueError(f"duplicate output name {name!r}")
        self.outputs[name] = Output(name, fn, unit, description)

    def add_body(self, name: str, parent: str, joint: Joint, mass: float, com=(0, 0, 0),
                 inertia=None, at=(0, 0, 0), frame=None, shape: dict | None = None, physical: bool = True) -> Body:
        """Add a body; see :class:`Body` for units and frames. Returns the body. ``physical=False``
        accepts an inertia that violates the triangle inequality (an airframe left when a
        whole-aircraft inertia is published inconsistently with the rotor's own)."""
        if name in self.bodies or name == WORLD:
            raise ValueError(f"duplicate body name {name!r}")
        if not isinstance(joint, Joint):
            raise ValueError(f"body {name!r}: joint must be a Joint, got {joint!r}")
        if not (np.isfinite(mass) and mass > 0):
            raise ValueError(f"body {name!r}: mass {mass} kg must be positive and finite")
        inertia = np.eye(3) * mass * 1e-2 if inertia is None else inertia
        body = Body(name, parent, joint, float(mass), _vector(name, "com", com, (3,)),
                    check_inertia(name, inertia, physical), _vector(name, "at", at, (3,)),
                    check_rotation(name, np.eye(3) if frame is None else frame), shape or {})
        self.bodies[name] = body
        self._add_hinge_springs(body)
        return body

    def _add_hinge_springs(self, body: Body) -> None:
        from mbs.forces import SpringDamper
        for j in leaf_joints(body.joint):
            if isinstance(j, OneAxis) and (j.stiffness or j.damping):
                self.add_force(SpringDamper(f"{body.name}.{j.name}", j.stiffness, j.damping, j.rest))

    def add_force(self, element) -> None:
        """Add a force element (see :mod:`mbs.forces`)."""
        names = [f.name for f in self.forces]
        if element.name in names:
            raise ValueError(f"duplicate force element name {element.name!r}")
        self.forces.append(element)

    def set_initial(self, **values: float) -> None:
        """Initial coordinate values by name, e.g. ``set_initial(**{"blade1.flap": 0.05})``."""
        self.initial.update(values)

    # -- topology -------------------------------------------------------------------

    def order(self) -> list[Body]:
        """Bodies depth-first from the world (parents before children).

        Raises ValueError for an unknown parent or a cycle.
        """
        children: dict[str, list[str]] = {}
        for b in self.bodies.values():
            if b.parent != WORLD and b.parent not in self.bodies:
                raise ValueError(f"body {b.name!r}: unknown parent {b.parent!r}")
            children.setdefault(b.parent, []).append(b.name)
        out: list[Body] = []
        stack = list(reversed(children.get(WORLD, [])))
        while stack:
            name = stack.pop()
            out.append(self.bodies[name])
            stack.extend(reversed(children.get(name, [])))
        if len(out) != len(self.bodies):
            cyc = sorted(set(self.bodies) - {b.name for b in out})
            raise ValueError(f"bodies {cyc} form a cycle (not reachable from the world)")
        return out

    def depth(self, name: str) -> int:
        d = 0
        while name != WORLD:
            name, d = self.bodies[name].parent, d + 1
        return d
