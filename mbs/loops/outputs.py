"""Each loop's closure as named outputs: ``<loop>.closure_margin`` (>= 0 where it closes) and,
for a link, ``<loop>.length_error`` (m) measured on the tree's own body motions."""
from __future__ import annotations

import casadi as ca

from mbs.loops.joint import LoopJoint
from mbs.loops.link import LinkLoop
from mbs.tree import WORLD, Model

MARGIN = "closure_margin"
"""Suffix of the outputs :mod:`mbs.backends.closure` reads to name a loop that cannot close."""


def loops_of(model: Model) -> dict[str, LoopJoint]:
    """Body name -> its loop joint, for every body of ``model`` attached by one."""
    return {name: b.joint for name, b in model.bodies.items() if isinstance(b.joint, LoopJoint)}


def joint_coordinates(state, body: str, joint) -> ca.SX:
    """The joint's independent coordinates (nq,) from the symbolic state."""
    return ca.vertcat(*[state.q(f"{body}.{n}") for n in joint.q_names], ca.SX(0, 1))


def anchor_in_world(model: Model, state, body: str, anchor) -> ca.SX:
    """A point given in the joint frame of ``body`` (3,) in world components (m)."""
    b = model.bodies[body]
    if b.parent == WORLD:
        return ca.DM(b.at) + ca.mtimes(ca.DM(b.frame), anchor)
    parent = state.body(b.parent)
    return parent.position + ca.mtimes(parent.rotation, ca.DM(b.at) + ca.mtimes(ca.DM(b.frame), anchor))


def link_length_error(model: Model, state, body: str, joint) -> ca.SX:
    """``|point - anchor| - length`` (m) of a :class:`LinkLoop` from the body's motion in the tree."""
    loop = joint.loop if isinstance(joint.loop, LinkLoop) else joint.loop.loop
    if loop.inboard:
        q = joint_coordinates(state, body, joint)
        return loop.residual(joint, joint.merge(q, joint.loop.solve(joint, q, state.t, state.p)), state.t, state.p)
    tip = state.point_position(body, ca.DM(loop._r))
    return ca.norm_2(tip - anchor_in_world(model, state, body, loop.anchor(state.t, state.p))) - loop.length


def add_loop_outputs(model: Model) -> list[str]:
    """Declare ``<loop>.closure_margin`` for every loop of ``model`` and ``<loop>.length_error``
    for every link loop; returns the names."""
    names = []
    for body, joint in loops_of(model).items():
        loop = joint.loop
        model.add_output(f"{loop.name}.{MARGIN}",
                         lambda s, b=body, j=joint: j.loop.margin(j, joint_coordinates(s, b, j), s.t, s.p), "1",
                         f"closure margin of loop {loop.name} (>= 0 where it closes; 0 at a dead point)")
        names.append(f"{loop.name}.{MARGIN}")
        if isinstance(getattr(loop, "loop", loop), LinkLoop):
            model.add_output(f"{loop.name}.length_error", lambda s, b=body, j=joint: link_length_error(model, s, b, j),
                             "m", f"link length of loop {loop.name} in the tree's motion minus its length")
            names.append(f"{loop.name}.length_error")
    return names
