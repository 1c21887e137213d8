"""The joint assembly that carries a local loop: :class:`LoopJoint`.

A loop joint is a :class:`mbs.joints.Serial` chain of parts between a parent body and a child
body (massless links inside, as Modelica's joint assemblies), some of whose one-axis parts are
*dependent*: their coordinates are not states but the solution of the loop's closure equations,
functions of the joint's own independent coordinates, the time and the parameters. The states
stay the tree's; the tree, the AD and the dynamics see an ordinary joint whose relative motion
is a function of ``(q, v, t, p)``.

Rates of the dependent coordinates are one forward-mode directional derivative of their
solution along ``(q', 1)`` (``q'`` the independent coordinates' rates): linear in ``v`` as a
joint's velocity must be. Their accelerations, and every Jacobian, come from the AD of the
tree through the same expression (:mod:`mbs.loops`).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.joints import Joint, OneAxis, Serial


class LoopJoint(Serial):
    """``LoopJoint(*parts, loop=...)``: the parts in series, those named in
    ``loop.dependent`` (one-axis parts: :class:`mbs.joints.Hinge` or
    :class:`mbs.joints.Slider`, without spring or damper) solved by ``loop``
    (a :class:`mbs.loops.Loop`). Coordinates ``q`` (nq,) and rates ``v`` (nv,) are those
    of the other parts, in their order."""

    def __init__(self, *parts: Joint, loop):
        super().__init__(*parts)
        names = [getattr(j, "name", None) for j in parts]
        for name in loop.dependent:
            if names.count(name) != 1:
                raise ValueError(f"loop {loop.name!r}: dependent part {name!r} is not exactly one part of the joint "
                                 f"(parts: {', '.join(str(n) for n in names)})")
            part = parts[names.index(name)]
            if not isinstance(part, OneAxis) or part.stiffness or part.damping:
                raise ValueError(f"loop {loop.name!r}: dependent part {name!r} must be a hinge or slider without "
                                 "spring or damper (its coordinate is not a state)")
        self.loop = loop
        self.dependent = [names.index(n) for n in loop.dependent]
        self.independent = [j for i, j in enumerate(parts) if i not in self.dependent]
        self.nq = sum(j.nq for j in self.independent)
        self.nv = sum(j.nv for j in self.independent)
        self.q_names = tuple(n for j in self.independent for n in j.q_names)
        self.v_names = tuple(n for j in self.independent for n in j.v_names)
        loop.bind(self)

    # -- the dependent coordinates ----------------------------------------------------------
    def merge(self, q: ca.SX, dependent: ca.SX) -> ca.SX:
        """All parts' coordinates in series order from the independent ``q`` (nq,) and the
        dependent ones (n_dependent,), (nq + n_dependent,)."""
        out, i, k = [], 0, 0
        for n, part in enumerate(self.parts):
            if n in self.dependent:
                out.append(dependent[k])
                k += 1
            elif part.nq:
                out.append(q[i:i + part.nq])
                i += part.nq
        return ca.vertcat(*out, ca.SX(0, 1))

    def full(self, q: ca.SX, v: ca.SX, t: ca.SX, p) -> tuple[ca.SX, ca.SX]:
        """Coordinates and rates of every part, the dependent ones solved by the loop and
        their rates by forward-mode AD along ``(q', 1)``: ``(q_all, v_all)``. ``q``, ``t`` must
        be symbols (the state's and the time's, as in the tree traversal)."""
        solved = self.loop.solve(self, q, t, p)
        rates = ca.jtimes(solved, ca.vertcat(q, t), ca.vertcat(self.qdot(q, v), 1))
        return self.merge(q, solved), self.merge(v, rates)

    # -- the Joint interface ----------------------------------------------------------------
    def relative(self, q, v, t, p):
        q_all, v_all = self.full(q, v, t, p)
        return Serial.relative(self, q_all, v_all, t, p)

    def _split(self, x, sizes):
        """Consecutive pieces of ``x`` of ``sizes`` (an empty piece is a 0x1 column, also of a 1x1 ``x``)."""
        out, i = [], 0
        for n in sizes:
            out.append(x[i:i + n] if n else ca.SX(0, 1))
            i += n
        return out

    def _independent_split(self, x, size: str):
        return self._split(x, [getattr(j, size) for j in self.independent])

    def qdot(self, q, v):
        qs, vs = self._independent_split(q, "nq"), self._independent_split(v, "nv")
        return ca.vertcat(*[j.qdot(a, b) for j, a, b in zip(self.independent, qs, vs)], ca.SX(0, 1))

    def project(self, q):
        qs = self._independent_split(q, "nq")
        return ca.vertcat(*[j.project(a) for j, a in zip(self.independent, qs)], ca.SX(0, 1))

    def q_default(self):
        return np.concatenate([j.q_default() for j in self.independent] + [np.zeros(0)])

    # -- geometry for the loops ---------------------------------------------------------------
    def frame_before(self, index: int, q_all: ca.SX, t, p):
        """The motion of the frame in front of part ``index`` relative to the joint frame (the
        parts before it composed with their coordinates ``q_all``)."""
        from mbs.joints import Fixed, compose

        sizes = [j.nq for j in self.parts]
        qs = self._split(q_all, sizes)
        motion = Fixed().relative(q_all, q_all, t, p)
        zero = [ca.SX.zeros(j.nv) for j in self.parts]
        for j, qj, vj in list(zip(self.parts, qs, zero))[:index]:
            motion = compose(motion, j.relative(qj, vj, t, p))
        return motion
