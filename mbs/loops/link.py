"""A rigid link closing a loop over one revolute part: :class:`LinkLoop`, solved in closed form.

The link joins a point turning with the dependent hinge (a pitch horn, a coupler's end) to an
anchor known in the joint frame (a swashplate's ball, a ground pivot). In the frame in front of
the hinge (axis ``a``, origin on the axis), with the point ``r`` after the hinge and the anchor
``b``, the closure ``|R(a, θ) r - b| = L`` reads

    A cos θ + B sin θ = K,   A = b·r⊥,  B = b·(a × r),  K = (|r|² + |b|² - L²)/2 - (a·r)(a·b)

(``r⊥ = r - (a·r) a``), so ``θ = α ± acos(K/ρ)`` with ``ρ = √(A² + B²)``, ``α = atan2(B, A)``.
The branch and the reference of ``α`` are those of the loop's :class:`Assembly`; the solution is
continuous in the state as long as ``|K/ρ| < 1``: the two branches meet only where the link is
stretched or folded through the hinge axis (``|K| = ρ``, the mechanism's dead point), so the branch
of the assembly is kept along any run that stays closed. Its margin is ``1 - |K|/ρ``; where it is
negative the link cannot reach and the solution is NaN.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import casadi as ca
import numpy as np

from mbs.joints import Fixed, Hinge
from mbs.loops.loop import Assembly, Loop, closed


@dataclass
class LinkLoop(Loop):
    """A rigid link of ``length`` (m) from ``point`` (3,) m, fixed in the frame after the
    dependent hinge called ``hinge`` (after any :class:`mbs.joints.Fixed` parts that follow
    it: the child body's frame), to ``anchor(t, p) -> (3,)`` m in the joint frame.

    ``inboard``: the point turns with the hinge about its axis as the axis lies in the joint
    frame, not carried by the parts before the hinge (a feathering housing inboard of the
    flexure of a hingeless rotor: its horn does not flap or lag). ``assembly``: a configuration
    that closes (:class:`Assembly`)."""

    name: str
    hinge: str
    point: tuple
    length: float
    anchor: Callable
    assembly: Assembly
    inboard: bool = False

    def __post_init__(self):
        self.dependent = (self.hinge,)
        if not (np.isfinite(self.length) and self.length > 0):
            raise ValueError(f"loop {self.name!r}: link length {self.length} m must be positive and finite")

    # -- set-up -------------------------------------------------------------------------------
    def bind(self, joint) -> None:
        index = joint.dependent[0]
        part = joint.parts[index]
        if not isinstance(part, Hinge):
            raise ValueError(f"loop {self.name!r}: its dependent part {self.hinge!r} must be a hinge")
        r = np.asarray(self.point, dtype=float)
        for after in reversed(joint.parts[index + 1:]):
            if not isinstance(after, Fixed):
                raise ValueError(f"loop {self.name!r}: only fixed parts may follow its hinge {self.hinge!r}")
            r = np.asarray(after.at, dtype=float) + np.asarray(after.frame, dtype=float) @ r
        self._index, self._axis, self._r = index, np.asarray(part.axis, dtype=float), r
        self._branch, self._alpha_ref = 1.0, 0.0
        self._assemble(joint)

    def _assemble(self, joint) -> None:
        """Branch and reference angle from the assembly; ValueError when it does not close there."""
        a = self.assembly
        q = np.array([a.coordinates.get(n, 0.0) for n in joint.q_names], dtype=float)
        unknown = sorted(set(a.coordinates) - set(joint.q_names))
        if unknown:
            raise ValueError(f"loop {self.name!r}: assembly coordinates {unknown} are not the joint's "
                             f"({', '.join(joint.q_names)})")
        t = ca.SX.sym("t")
        origin, rotation = self._hinge_frame(joint, joint.merge(ca.SX(ca.DM(q)), ca.SX.zeros(1)), t, None)
        b = ca.mtimes(rotation.T, ca.DM(a.anchor) - origin)
        big_a, big_b, k = np.array(ca.Function("assembly", [t], [ca.vertcat(*self._coefficients(b))])(0.0)).ravel()
        rho = np.hypot(big_a, big_b)
        if not rho > 0 or abs(k) >= rho:
            raise ValueError(f"loop {self.name!r} does not close at its assembly configuration: the link of "
                             f"{self.length} m cannot reach its anchor {list(a.anchor)} m")
        alpha, spread = np.arctan2(big_b, big_a), np.arccos(k / rho)
        miss = [abs(np.angle(np.exp(1j * (alpha + s * spread - a.angle)))) for s in (1.0, -1.0)]
        if min(miss) > 1e-9:
            raise ValueError(f"loop {self.name!r} does not close at its assembly angle {a.angle} rad: its link "
                             f"gives {alpha + spread:.6g} or {alpha - spread:.6g} rad there")
        self._branch = 1.0 if miss[0] <= miss[1] else -1.0
        self._alpha_ref = float(a.angle - self._branch * spread)

    # -- geometry -----------------------------------------------------------------------------
    def _hinge_frame(self, joint, q_all, t, p):
        if self.inboard:
            return ca.DM.zeros(3), ca.DM.eye(3)
        frame = joint.frame_before(self._index, q_all, t, p)
        return frame.position, frame.rotation

    def _hinge_local(self, joint, q, anchor, t, p):
        """The anchor in the frame in front of the hinge (3,)."""
        q_all = joint.merge(q, ca.SX.zeros(1))
        origin, rotation = self._hinge_frame(joint, q_all, t, p)
        return ca.mtimes(rotation.T, anchor - origin)

    def _coefficients(self, b):
        a, r = ca.DM(self._axis), ca.DM(self._r)
        along = float(self._axis @ self._r)
        normal, cross = r - along * a, ca.cross(a, r)
        k = 0.5 * (float(self._r @ self._r) + ca.dot(b, b) - self.length**2) - along * ca.dot(a, b)
        return ca.dot(b, normal), ca.dot(b, cross), k

    def point_in_joint(self, joint, q_all: ca.SX, t, p) -> ca.SX:
        """The link's point on the hinge side (3,) m in the joint frame."""
        origin, rotation = self._hinge_frame(joint, q_all, t, p)
        turn = joint.parts[self._index].relative(q_all[self._q_index(joint)], ca.SX.zeros(1), t, p).rotation
        return origin + ca.mtimes(rotation, ca.mtimes(turn, ca.DM(self._r)))

    def _q_index(self, joint) -> int:
        return sum(j.nq for j in joint.parts[:self._index])

    def arm(self, joint, q: ca.SX, angle: ca.SX, t, p) -> ca.SX:
        """The link's moment arm about the hinge (m), ``-∂ℓ/∂θ`` by AD at the hinge ``angle``:
        a tension ``F`` turns the point side by the moment ``F arm`` about the hinge axis."""
        x = ca.SX.sym("angle")
        length = ca.norm_2(self.point_in_joint(joint, joint.merge(q, x), t, p) - self.anchor(t, p))
        return -ca.substitute(ca.jacobian(length, x), x, angle)

    # -- the loop -----------------------------------------------------------------------------
    def residual(self, joint, q_all, t, p) -> ca.SX:
        """Link-length error ``|point - anchor| - length`` (m), (1,)."""
        gap = self.point_in_joint(joint, q_all, t, p) - self.anchor(t, p)
        return ca.norm_2(gap) - self.length

    def _ratio(self, joint, q, t, p):
        big_a, big_b, k = self._coefficients(self._hinge_local(joint, q, self.anchor(t, p), t, p))
        return big_a, big_b, k / ca.sqrt(big_a**2 + big_b**2)

    def margin(self, joint, q, t, p) -> ca.SX:
        """``1 - |K|/ρ``: 1 with the link square to the hinge's reach, 0 at a dead point, < 0 beyond."""
        return 1 - ca.fabs(self._ratio(joint, q, t, p)[2])

    def solve(self, joint, q, t, p) -> ca.SX:
        """The hinge angle (rad) of the branch of the assembly; NaN where the link cannot reach."""
        big_a, big_b, c = self._ratio(joint, q, t, p)
        ref = self._alpha_ref
        alpha = ref + ca.atan2(big_b * np.cos(ref) - big_a * np.sin(ref), big_a * np.cos(ref) + big_b * np.sin(ref))
        return closed(alpha + self._branch * ca.acos(c), 1 - ca.fabs(c))
