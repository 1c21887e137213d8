"""Keyframes that the page's player interpolates, and the same time-to-pose mapping in numpy.

Per body node (meshcat path): positions (k, 3) m and quaternions (k, 4) in three.js order
(x, y, z, w) of its transform relative to its parent, at the key times ``t`` (k,) s of the
simulation. Between keys a position is linear in time and a quaternion spherical-linear
(slerp, the short way: neighbouring keys have a non-negative dot product). The page's script
(``web/player.js``) and :func:`local_at` implement this same mapping, so a page can be
checked against Python at any time.

The world node is moved by minus the followed body's origin at the current time ("follow"
camera) or at the first key ("fixed" camera).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from viewer import kinematics as kin
from viewer.motion import Motion
from viewer.scene import Scene

SLERP_LINEAR_ABOVE = 0.9995  # cos of the angle below which slerp falls back to normalised lerp


@dataclass
class Keyframes:
    """Key times ``t`` (k,) s; ``nodes[path] = (positions (k, 3) m, quaternions (k, 4) xyzw)``
    (a track that never changes may be a single row); ``follow`` (k, 3) m: the followed
    body's origin in the world frame, or None."""

    t: np.ndarray
    nodes: dict[str, tuple[np.ndarray, np.ndarray]]
    follow: np.ndarray | None


def keyframes(scene: Scene, mo: Motion) -> Keyframes:
    """The body-node tracks of ``mo`` on ``scene``."""
    quats = kin.quaternions_xyzw(mo.local[:, :, :3, :3])
    nodes = {scene.paths[name]: (mo.local[:, i, :3, 3], quats[:, i]) for i, name in enumerate(scene.body_names)}
    follow = None if scene.follow is None else mo.origins[:, scene.body_names.index(scene.follow)]
    return Keyframes(np.asarray(mo.t, dtype=float), nodes, follow)


def interval(times: np.ndarray, t: float) -> tuple[int, float]:
    """Key index i and weight w in [0, 1] with t = (1 - w) t_i + w t_{i+1}; t clamped to the keys."""
    if len(times) < 2:
        return 0, 0.0
    t = min(max(t, times[0]), times[-1])
    i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    return i, float((t - times[i]) / (times[i + 1] - times[i]))


def lerp(values: np.ndarray, i: int, w: float) -> np.ndarray:
    """Row i of ``values`` (k, n) moved by w towards row i + 1 (a single row is constant)."""
    if len(values) == 1 or w == 0.0:
        return np.array(values[min(i, len(values) - 1)], dtype=float)
    return (1 - w) * values[i].astype(float) + w * values[i + 1].astype(float)


def slerp(quats: np.ndarray, i: int, w: float) -> np.ndarray:
    """Unit quaternion between rows i and i + 1 of ``quats`` (k, 4) at weight w, the short way."""
    if len(quats) == 1 or w == 0.0:
        return np.array(quats[min(i, len(quats) - 1)], dtype=float)
    a, b = quats[i].astype(float), quats[i + 1].astype(float)
    d = float(a @ b)
    if d < 0:
        b, d = -b, -d
    if d > SLERP_LINEAR_ABOVE:
        q = a + w * (b - a)
        return q / np.linalg.norm(q)
    theta = np.arccos(d)
    return (np.sin((1 - w) * theta) * a + np.sin(w * theta) * b) / np.sin(theta)


def local_at(kf: Keyframes, t: float) -> dict[str, np.ndarray]:
    """Node transforms (4, 4) relative to their parents at time ``t`` (s), per path."""
    i, w = interval(kf.t, t)
    out = {}
    for path, (pos, quat) in kf.nodes.items():
        R = kin.rotations_xyzw(slerp(quat, i, w))
        out[path] = kin.homogeneous(lerp(pos, i, w), R)
    return out


def world_at(kf: Keyframes, t: float, follow: bool = True) -> np.ndarray:
    """World-node transform (4, 4) at ``t`` (s): minus the followed origin now, or at the first key."""
    out = np.eye(4)
    if kf.follow is not None:
        i, w = interval(kf.t, t) if follow else (0, 0.0)
        out[:3, 3] = -lerp(kf.follow, i, w)
    return out


def tip_paths(scene: Scene, mo: Motion) -> dict[str, np.ndarray]:
    """Tip positions (k, 3) m of each traced blade in its trace frame (the hub's parent)."""
    absolute = kin.homogeneous(mo.origins, mo.rotations)
    out = {}
    for blade in scene.traced:
        i = scene.body_names.index(blade)
        tip = np.r_[scene.tip_point(blade), 1.0]
        world = absolute[:, i] @ tip
        frame = scene.trace_frames[blade]
        if frame != "world":
            world = np.einsum("kij,kj->ki", kin.inverse(absolute[:, scene.body_names.index(frame)]), world)
        out[blade] = world[:, :3]
    return out
