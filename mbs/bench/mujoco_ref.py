"""The same tree in MuJoCo (an independent engine), for tests and benchmarks.

:func:`to_mjcf` writes an MJCF document of a :class:`mbs.Model`: one MuJoCo body per body,
hinge joints (several in one body for a ``Serial`` of hinges, which MuJoCo applies in
order, like ``Serial``), a free joint at the root, masses and full inertia tensors, gravity,
no contacts, no geometry. Hinge spring-dampers become joint stiffness and damping; other
force elements have no counterpart and are refused.

State conventions differ only in the free joint: MuJoCo's translational velocity is in
world components, ours in body components, so positions, rates and accelerations are
converted (:class:`MujocoTree`).
"""
from __future__ import annotations

from xml.sax.saxutils import quoteattr

import numpy as np

from mbs.joints import Fixed, FreeJoint, Hinge
from mbs.tree import Model, leaf_joints


def _mujoco():
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("MuJoCo is needed here: pip install mujoco") from exc
    return mujoco


def _num(values) -> str:
    return " ".join(repr(float(v)) for v in np.ravel(values))


def _quat(frame: np.ndarray) -> np.ndarray:
    """Scalar-first unit quaternion of a rotation matrix."""
    q = np.zeros(4)
    _mujoco().mju_mat2Quat(q, np.ascontiguousarray(frame, dtype=float).ravel())
    return q


def _springs(model: Model) -> dict[str, tuple[float, float, float]]:
    from mbs.forces import SpringDamper

    out = {}
    for f in model.forces:
        if not isinstance(f, SpringDamper):
            raise NotImplementedError(f"force element {f.name!r} has no MuJoCo counterpart")
        out[f.coordinate] = (f.stiffness, f.damping, f.rest)
    return out


def _joints_xml(body, springs: dict) -> list[str]:
    """MJCF joint elements of one body (hinges in order, or one free joint)."""
    parts = list(leaf_joints(body.joint))
    if any(isinstance(j, Fixed) for j in parts):
        raise NotImplementedError(f"body {body.name!r}: fixed offsets inside a Serial joint are not supported")
    lines = []
    for j in parts:
        name = f"{body.name}.{j.name}" if isinstance(j, Hinge) else f"{body.name}.free"
        if isinstance(j, FreeJoint):
            if body.parent != "world":
                raise NotImplementedError(f"body {body.name!r}: MuJoCo allows free joints only at the root")
            lines.append(f"<freejoint name={quoteattr(name)}/>")
        elif isinstance(j, Hinge):
            k, c, rest = springs.get(name, (0.0, 0.0, 0.0))
            lines.append(f"<joint name={quoteattr(name)} type=\"hinge\" axis=\"{_num(j.axis)}\" "
                         f"stiffness=\"{k!r}\" springref=\"{rest!r}\" damping=\"{c!r}\"/>")
        else:
            raise NotImplementedError(f"body {body.name!r}: no MuJoCo counterpart for {type(j).__name__}")
    return lines


def _inertial_xml(body) -> str:
    i = body.inertia
    full = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
    return f"<inertial pos=\"{_num(body.com)}\" mass=\"{body.mass!r}\" fullinertia=\"{_num(full)}\"/>"


def to_mjcf(model: Model) -> str:
    """MJCF text of ``model`` (bodies depth-first in the order of ``model.order()``)."""
    springs = _springs(model)
    children: dict[str, list] = {}
    for b in model.order():
        children.setdefault(b.parent, []).append(b)

    def body_xml(b, indent: str) -> list[str]:
        head = (f"{indent}<body name={quoteattr(b.name)} pos=\"{_num(b.at)}\" "
                f"quat=\"{_num(_quat(b.frame))}\">")
        inner = [indent + "  " + s for s in _joints_xml(b, springs) + [_inertial_xml(b)]]
        for c in children.get(b.name, []):
            inner += body_xml(c, indent + "  ")
        return [head, *inner, f"{indent}</body>"]

    lines = [f"<mujoco model={quoteattr(model.name)}>",
             "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>",
             f"  <option gravity=\"{_num(model.gravity)}\"><flag contact=\"disable\"/></option>",
             "  <worldbody>"]
    for b in children.get("world", []):
        lines += body_xml(b, "    ")
    return "\n".join(lines + ["  </worldbody>", "</mujoco>"])


class MujocoTree:
    """A compiled MuJoCo model of ``model`` with state conversion to and from ours.

    ``set_state(x)`` writes our ``x = (s, u)`` into ``data.qpos``/``data.qvel``;
    ``forward()`` is one raw ``mj_forward``, ``step()`` one ``mj_step`` (RK4 after
    ``use_rk4(h)``); ``accelerations(x)`` returns ``u'`` (nv,) in our coordinates.
    """

    def __init__(self, model: Model):
        mj = _mujoco()
        self.mj, self.model = mj, model
        self.m = mj.MjModel.from_xml_string(to_mjcf(model))
        self.d = mj.MjData(self.m)
        self._map(model)

    def _map(self, model: Model) -> None:
        """Index arrays from our ``s``/``u`` entries to MuJoCo's ``qpos``/``qvel``."""
        self.free = []  # (our q start, our v start, mujoco qpos adr, mujoco dof adr, body)
        qi, vi, q_idx, v_idx = 0, 0, [], []
        for b in model.order():
            for j in leaf_joints(b.joint):
                name = f"{b.name}.{j.name}" if isinstance(j, Hinge) else f"{b.name}.free"
                jid = self.mj.mj_name2id(self.m, self.mj.mjtObj.mjOBJ_JOINT, name)
                qa, da = int(self.m.jnt_qposadr[jid]), int(self.m.jnt_dofadr[jid])
                if isinstance(j, FreeJoint):
                    self.free.append((qi, vi, qa, da, b))
                q_idx += range(qa, qa + j.nq)
                v_idx += range(da, da + j.nv)
                qi, vi = qi + j.nq, vi + j.nv
        self.nq, self.nv = qi, vi
        self.q_idx, self.v_idx = np.array(q_idx, int), np.array(v_idx, int)

    def set_state(self, x: np.ndarray) -> None:
        s, u = np.asarray(x[:self.nq], float), np.asarray(x[self.nq:self.nq + self.nv], float)
        qpos, qvel = np.zeros(self.m.nq), np.zeros(self.m.nv)
        qpos[self.q_idx], qvel[self.v_idx] = s, u
        for qi, vi, qa, da, b in self.free:
            quat = s[qi + 3:qi + 7] / np.linalg.norm(s[qi + 3:qi + 7])
            qpos[qa:qa + 3] = b.at + b.frame @ s[qi:qi + 3]
            self.mj.mju_mulQuat(qpos[qa + 3:qa + 7], _quat(b.frame), quat)
            qvel[da:da + 3] = self._rotation(qpos[qa + 3:qa + 7]) @ u[vi:vi + 3]
        self.d.qpos[:], self.d.qvel[:] = qpos, qvel

    def _rotation(self, quat: np.ndarray) -> np.ndarray:
        r = np.zeros(9)
        self.mj.mju_quat2Mat(r, quat)
        return r.reshape(3, 3)

    def forward(self) -> None:
        self.mj.mj_forward(self.m, self.d)

    def use_rk4(self, h: float) -> None:
        """Integrate with MuJoCo's RK4 at the step ``h`` (s) in :meth:`step`."""
        self.m.opt.integrator = self.mj.mjtIntegrator.mjINT_RK4
        self.m.opt.timestep = h

    def step(self) -> None:
        """One raw ``mj_step`` (the state advances)."""
        self.mj.mj_step(self.m, self.d)

    def accelerations(self, x: np.ndarray) -> np.ndarray:
        """Our ``u'`` (nv,) at ``x`` from ``mj_forward``."""
        self.set_state(x)
        self.forward()
        acc = self.d.qacc[self.v_idx].copy()
        for _, vi, qa, da, _ in self.free:
            r, w = self._rotation(self.d.qpos[qa + 3:qa + 7]), self.d.qvel[da + 3:da + 6]
            # world-frame acceleration of the origin -> rate of its body-frame components
            acc[vi:vi + 3] = r.T @ self.d.qacc[da:da + 3] - np.cross(w, r.T @ self.d.qvel[da:da + 3])
        return acc


def mujoco_accelerations(model: Model, x: np.ndarray) -> np.ndarray:
    """Joint accelerations ``u'`` (nv,) from MuJoCo's ``mj_forward`` at our state ``x = (s, u)``."""
    return MujocoTree(model).accelerations(x)
