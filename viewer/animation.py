"""meshcat animation of a :class:`viewer.motion.Motion` on a :class:`viewer.scene.Scene`.

Every body node gets a position and a quaternion track of its transform relative to its
parent (tracks that never change are left out: the node keeps its static transform); the
world node gets the followed body's negated position. Clip time = (t - t_0) * ``slow``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from viewer import kinematics as kin
from viewer.motion import Motion
from viewer.scene import WORLD, Scene


@dataclass
class Keyframes:
    """Per animated node (meshcat path): clip times (k,) s, positions (k, 3) m and
    quaternions (k, 4) three.js order (x, y, z, w), with constant tracks marked."""

    times: np.ndarray
    nodes: dict[str, tuple[np.ndarray, np.ndarray]]
    slow: float


def world_transforms(scene: Scene, mo: Motion) -> np.ndarray:
    """World-node transforms (k, 4, 4): minus the followed body's origin (or identity)."""
    out = np.tile(np.eye(4), (len(mo.t), 1, 1))
    if scene.follow is not None:
        out[:, :3, 3] = -mo.origins[:, scene.body_names.index(scene.follow)]
    return out


def keyframes(scene: Scene, mo: Motion, slow: float = 10.0) -> Keyframes:
    """Track data of the animation; ``slow`` > 0 stretches time (10: ten times slower)."""
    if not (np.isfinite(slow) and slow > 0):
        raise ValueError(f"slow = {slow} must be positive and finite")
    nodes = {WORLD: (world_transforms(scene, mo)[:, :3, 3], np.tile([0.0, 0, 0, 1], (len(mo.t), 1)))}
    quats = kin.quaternions_xyzw(mo.local[:, :, :3, :3])
    for i, name in enumerate(scene.body_names):
        nodes[scene.paths[name]] = (mo.local[:, i, :3, 3], quats[:, i])
    return Keyframes((mo.t - mo.t[0]) * slow, nodes, float(slow))


def lower(kf: Keyframes, repetitions: int = 1_000_000, play: bool = True) -> dict:
    """The ``set_animation`` command as meshcat's viewer expects it (plain Python types)."""
    anims = []
    for path, (pos, quat) in kf.nodes.items():
        tracks = [_track(".position", "vector3", kf.times, pos), _track(".quaternion", "quaternion", kf.times, quat)]
        tracks = [t for t in tracks if t is not None]
        if tracks:
            anims.append({"path": path, "clip": {"fps": 1, "name": "default", "tracks": tracks}})
    return {"type": "set_animation", "path": "", "animations": anims,
            "options": {"play": bool(play), "repetitions": int(repetitions)}}


def _track(name: str, kind: str, times: np.ndarray, values: np.ndarray) -> dict | None:
    if len(times) < 2 or np.abs(values - values[0]).max() < 1e-9:
        return None
    return {"name": name, "type": kind,
            "keys": [{"time": float(t), "value": [float(v) for v in row]} for t, row in zip(times, values)]}


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
