"""Joint types. Each states only its *relative* kinematics.

A joint maps its minimal coordinates ``q`` (position level, shape ``(nq,)``) and
``v`` (velocity level, shape ``(nv,)``) to the motion of the child body frame
relative to the joint frame fixed in the parent (see :class:`Relative`). The tree
traversal composes these relative motions and forward-mode AD supplies every
Jacobian, so a new joint type is only its ``relative`` method (and ``qdot`` when
``q' != v``); nothing else in the package changes.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import casadi as ca
import numpy as np

from mbs import _rotation as rot

ZERO3 = ca.SX.zeros(3)


@dataclass
class Relative:
    """Relative motion of a child frame in its joint frame.

    position: (3,) child origin in joint-frame components, m.
    rotation: (3, 3) child-frame to joint-frame rotation.
    velocity: (3,) time derivative of ``position`` in joint-frame components, m/s.
    omega: (3,) angular velocity of child relative to joint frame, child-frame components, rad/s.
    """

    position: ca.SX
    rotation: ca.SX
    velocity: ca.SX
    omega: ca.SX


def _unit(axis) -> np.ndarray:
    a = np.asarray(axis, dtype=float).reshape(3)
    n = np.linalg.norm(a)
    if not np.isfinite(n) or n == 0:
        raise ValueError(f"joint axis {tuple(a)} must be a finite non-zero vector")
    return a / n


class Joint:
    """Base class. ``nq``/``nv``: number of position/velocity coordinates."""

    nq: int = 0
    nv: int = 0
    q_names: tuple[str, ...] = ()
    v_names: tuple[str, ...] = ()

    def relative(self, q: ca.SX, v: ca.SX, t: ca.SX, p: "Params") -> Relative:
        raise NotImplementedError

    def qdot(self, q: ca.SX, v: ca.SX) -> ca.SX:
        """Position-coordinate rates ``q' = F(q, v)``; the identity unless overridden."""
        return v

    def project(self, q: ca.SX) -> ca.SX:
        """Map ``q`` back onto its manifold after an integrator step (identity by default)."""
        return q

    def q_default(self) -> np.ndarray:
        return np.zeros(self.nq)


@dataclass
class Fixed(Joint):
    """Rigid attachment at a constant offset ``at`` (m) and rotation ``frame`` (3x3)."""

    at: tuple = (0.0, 0.0, 0.0)
    frame: tuple = ((1.0, 0, 0), (0, 1.0, 0), (0, 0, 1.0))

    def relative(self, q, v, t, p):
        return Relative(ca.DM(self.at), ca.DM(self.frame), ZERO3, ZERO3)


@dataclass
class OneAxis(Joint):
    """A 1-DOF joint along or about a constant unit ``axis`` (joint frame) whose ``stiffness``
    and ``damping`` add a linear spring-damper force element, about :attr:`rest`, when the
    model is built. Subclasses state the relative motion."""

    axis: tuple = (0.0, 0.0, 1.0)
    name: str = "angle"
    stiffness: float = 0.0
    damping: float = 0.0
    nq = 1
    nv = 1

    def __post_init__(self):
        self.axis = tuple(_unit(self.axis))
        self.q_names = (self.name,)
        self.v_names = (self.name + "_rate",)

    @property
    def rest(self) -> float:
        """Coordinate at which the spring is relaxed."""
        return 0.0


@dataclass
class Hinge(OneAxis):
    """Revolute joint about ``axis``, 1 DOF: angle (rad), rate (rad/s); ``stiffness`` in
    N m/rad, ``damping`` in N m s/rad, spring relaxed at ``rest_angle`` (rad)."""

    rest_angle: float = 0.0

    @property
    def rest(self) -> float:
        return self.rest_angle

    def relative(self, q, v, t, p):
        a = ca.DM(self.axis)
        return Relative(ZERO3, rot.axis_angle(self.axis, q[0]), ZERO3, a * v[0])


@dataclass
class Slider(OneAxis):
    """Prismatic joint along ``axis``, 1 DOF: displacement (m), rate (m/s); ``stiffness`` in
    N/m, ``damping`` in N s/m, spring relaxed at ``rest_position`` (m)."""

    axis: tuple = (1.0, 0.0, 0.0)
    name: str = "displacement"
    rest_position: float = 0.0

    @property
    def rest(self) -> float:
        return self.rest_position

    def relative(self, q, v, t, p):
        a = ca.DM(self.axis)
        return Relative(a * q[0], ca.DM.eye(3), a * v[0], ZERO3)


@dataclass
class DrivenHinge(Joint):
    """Revolute joint whose angle is prescribed: ``angle(t, p) -> SX`` (rad), no DOF.

    ``t`` is the time symbol (s) and ``p`` the model's parameters by name. The rate and
    the acceleration follow from forward-mode AD of ``angle`` in time, never by hand.
    """

    axis: tuple = (0.0, 0.0, 1.0)
    angle: Callable = field(default=lambda t, p: 0 * t)
    name: str = "driven"

    def __post_init__(self):
        self.axis = tuple(_unit(self.axis))

    def relative(self, q, v, t, p):
        theta = self.angle(t, p)
        rate = ca.jtimes(theta, t, ca.SX(1.0))
        return Relative(ZERO3, rot.axis_angle(self.axis, theta), ZERO3, ca.DM(self.axis) * rate)


class FreeJoint(Joint):
    """Six-DOF joint: ``q = (x, y, z, qw, qx, qy, qz)``, ``v = (body velocity, body angular velocity)``.

    Position in m (joint frame), quaternion scalar first; velocities in child-body
    components, m/s and rad/s. The rotation uses ``q / |q|`` so the kinematics never
    depend on the quaternion norm, and :meth:`project` renormalises after each step.
    """

    nq = 7
    nv = 6
    q_names = ("x", "y", "z", "qw", "qx", "qy", "qz")
    v_names = ("u", "v", "w", "p", "q", "r")

    def relative(self, q, v, t, p):
        r = rot.quat_to_matrix(q[3:7])
        return Relative(q[0:3], r, ca.mtimes(r, v[0:3]), v[3:6])

    def qdot(self, q, v):
        r = rot.quat_to_matrix(q[3:7])
        return ca.vertcat(ca.mtimes(r, v[0:3]), rot.quat_rate(q[3:7], v[3:6]))

    def project(self, q):
        return ca.vertcat(q[0:3], q[3:7] / ca.norm_2(q[3:7]))

    def q_default(self):
        return np.array([0, 0, 0, 1.0, 0, 0, 0])


class Params:
    """Read-only view of the model parameters as symbols: ``p["omega"]``."""

    def __init__(self, names: list[str], sym: ca.SX):
        self._index = {n: i for i, n in enumerate(names)}
        self._sym = sym

    def __getitem__(self, name: str) -> ca.SX:
        if name not in self._index:
            raise KeyError(f"unknown parameter {name!r}; known: {sorted(self._index)}")
        return self._sym[self._index[name]]


def compose(outer: Relative, inner: Relative) -> Relative:
    """Motion of frame C given B in A (``outer``) and C in B (``inner``), expressed like ``outer``.

    The same rule composes a placement with a joint, joints in series, and a body's
    absolute motion with its child's relative motion during the tree traversal.
    """
    lever = ca.mtimes(outer.rotation, inner.position)
    return Relative(
        position=outer.position + lever,
        rotation=ca.mtimes(outer.rotation, inner.rotation),
        velocity=outer.velocity
        + ca.mtimes(outer.rotation, ca.cross(outer.omega, inner.position) + inner.velocity),
        omega=ca.mtimes(inner.rotation.T, outer.omega) + inner.omega,
    )


class Serial(Joint):
    """Joints in series without bodies between them, e.g. ``Serial(pitch, flap, lag)``.

    The paper's flap/lag hinge is such a pair; ``Fixed(at=...)`` parts place hinge offsets.
    Coordinate names are those of the parts and must be unique.
    """

    def __init__(self, *parts: Joint):
        self.parts = parts
        self.nq = sum(j.nq for j in parts)
        self.nv = sum(j.nv for j in parts)
        self.q_names = tuple(n for j in parts for n in j.q_names)
        self.v_names = tuple(n for j in parts for n in j.v_names)
        if len(set(self.q_names)) != len(self.q_names):
            raise ValueError(f"Serial joint has duplicate coordinate names {self.q_names}")

    def _split(self, x, sizes):
        out, i = [], 0
        for n in sizes:
            out.append(x[i:i + n] if n else ca.SX(0, 1))  # a scalar's x[1:1] is not empty in CasADi
            i += n
        return out

    def relative(self, q, v, t, p):
        qs = self._split(q, [j.nq for j in self.parts])
        vs = self._split(v, [j.nv for j in self.parts])
        motion = Fixed().relative(q, v, t, p)
        for j, qj, vj in zip(self.parts, qs, vs):
            motion = compose(motion, j.relative(qj, vj, t, p))
        return motion

    def qdot(self, q, v):
        qs = self._split(q, [j.nq for j in self.parts])
        vs = self._split(v, [j.nv for j in self.parts])
        return ca.vertcat(*[j.qdot(a, b) for j, a, b in zip(self.parts, qs, vs)], ca.SX(0, 1))

    def project(self, q):
        qs = self._split(q, [j.nq for j in self.parts])
        return ca.vertcat(*[j.project(a) for j, a in zip(self.parts, qs)], ca.SX(0, 1))

    def q_default(self):
        return np.concatenate([j.q_default() for j in self.parts] + [np.zeros(0)])
