"""What a local loop states (:class:`Loop`) and the configuration it is assembled in (:class:`Assembly`)."""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

NOT_CLOSED = ca.SX(np.nan)
"""The value of a dependent coordinate where its loop cannot close: the state turns non-finite,
the run stops with that status and :mod:`mbs.backends.closure` names the loop and the time."""


@dataclass(frozen=True)
class Assembly:
    """A configuration in which a loop is known to close: ``coordinates`` of the joint's
    independent parts by name (rad or m; the others 0), the ``anchor`` (3,) there in the
    joint frame (m) and the dependent ``angle`` (rad) the loop must give there. It fixes the
    branch of a closed-form solution and is checked when the loop is built."""

    angle: float
    anchor: tuple
    coordinates: dict = field(default_factory=dict)


class Loop:
    """A local closed loop of one :class:`mbs.loops.LoopJoint`: closure equations
    ``g(q_all, t, p) = 0`` (:meth:`residual`, one per dependent coordinate) that fix the
    joint's ``dependent`` parts (names) from its independent coordinates ``q``, the time
    ``t`` and the parameters ``p``.

    Subclasses give :meth:`solve` (the dependent coordinates, NaN where the loop cannot
    close) and :meth:`margin` (>= 0 exactly where it closes, dimensionless)."""

    name: str
    dependent: tuple[str, ...]

    def bind(self, joint) -> None:
        """Check the loop against its joint and precompute (called by the joint)."""

    def residual(self, joint, q_all: ca.SX, t, p) -> ca.SX:
        raise NotImplementedError

    def solve(self, joint, q: ca.SX, t, p) -> ca.SX:
        raise NotImplementedError

    def margin(self, joint, q: ca.SX, t, p) -> ca.SX:
        raise NotImplementedError


def closed(value: ca.SX, margin: ca.SX) -> ca.SX:
    """``value`` where ``margin >= 0``, NaN elsewhere (and where the margin is NaN)."""
    return ca.if_else(margin >= 0, value, NOT_CLOSED)
