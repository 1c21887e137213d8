"""The same tree in Pinocchio (an independent engine), for tests and benchmarks.

Supports hinges (any axis), free joints and ``Serial`` joints whose intermediate frames
become massless Pinocchio bodies. Joints are added depth-first: Pinocchio's CRBA is wrong
for breadth-first insertion (ABA is not affected, but we keep one rule).
"""
from __future__ import annotations

import numpy as np

from mbs.joints import Fixed, FreeJoint, Hinge
from mbs.tree import Model, leaf_joints


def _pin():
    try:
        import pinocchio
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("Pinocchio is needed here: pip install pin") from exc
    return pinocchio


def _joint_model(pin, j):
    if isinstance(j, Hinge):
        return pin.JointModelRevoluteUnaligned(np.array(j.axis))
    if isinstance(j, FreeJoint):
        return pin.JointModelFreeFlyer()
    raise NotImplementedError(f"no Pinocchio counterpart for {type(j).__name__}")


def to_pinocchio(model: Model):
    """Return ``(pin_model, q_map)``; ``q_map`` converts our ``s`` to Pinocchio's ``q``."""
    pin = _pin()
    pm = pin.Model()
    pm.gravity.linear = np.array(model.gravity, dtype=float)
    frame_of = {"world": 0}
    for b in model.order():
        parent, placement = frame_of[b.parent], pin.SE3(b.frame, b.at)
        moving = [j for j in leaf_joints(b.joint) if not isinstance(j, Fixed)]
        if not moving:
            raise NotImplementedError(f"body {b.name!r} has no degree of freedom")
        for j in leaf_joints(b.joint):
            if isinstance(j, Fixed):
                placement = placement * pin.SE3(np.array(j.frame, dtype=float), np.array(j.at, dtype=float))
                continue
            parent = pm.addJoint(parent, _joint_model(pin, j), placement, f"{b.name}.{id(j)}")
            placement = pin.SE3.Identity()
        inertia = pin.Inertia(b.mass, b.com, b.inertia)
        pm.appendBodyToJoint(parent, inertia.se3Action(placement) if placement != pin.SE3.Identity()
                             else inertia, pin.SE3.Identity())
        frame_of[b.name] = parent
    return pm, _q_converter(model)


def _q_converter(model: Model):
    perm = []
    for b in model.order():
        for j in leaf_joints(b.joint):
            start = len(perm)
            if isinstance(j, FreeJoint):
                perm += [start + i for i in (0, 1, 2, 4, 5, 6, 3)]
            else:
                perm += [start + i for i in range(j.nq)]
    perm = np.array(perm, dtype=int)
    return lambda s: np.asarray(s)[perm]


def pinocchio_accelerations(model: Model, x: np.ndarray, tau: np.ndarray | None = None) -> np.ndarray:
    """Joint accelerations ``u'`` from Pinocchio's ABA at our state ``x = (s, u)``."""
    pin = _pin()
    pm, conv = to_pinocchio(model)
    data = pm.createData()
    nq = pm.nq
    q, v = conv(x[:nq]), np.asarray(x[nq:nq + pm.nv], dtype=float)
    q = q.copy()
    return pin.aba(pm, data, q, v, np.zeros(pm.nv) if tau is None else tau)
