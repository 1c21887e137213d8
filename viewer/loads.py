"""Hub-load arrows: the force and the moment the main rotor exerts on the airframe at its hub
(the model's outputs ``main_rotor.hub.force_*`` and ``moment_*``, in the airframe's body
axes), drawn from the hub centre in the airframe's frame, as long as the load is large.

Each arrow is a node ``<airframe>/hub_loads/<kind>`` turned so that its y axis (three.js's
cylinder axis) points along the load, with a shaft (child ``shaft``: a unit cylinder
stretched to the arrow's length by its scale) and a head (child ``head``, a cone at the
shaft's end). The page's player moves them like the body nodes, from tracks of position,
quaternion and scale at the key times. The moment arrow follows the right-hand rule.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from viewer import kinematics as kin

KINDS = {"force": ("#e0301e", "N", "kN"), "moment": ("#1f5fd6", "N m", "kN m")}
"""Arrow kind -> colour, unit of the output, unit of the legend."""
LONGEST = 1.5  # m: the largest load of the run
RADIUS, HEAD = 0.03, 0.15  # m: shaft radius, head length
HUB = "main_hub"


@dataclass
class HubArrows:
    """The arrows of one run: ``frame`` the body whose frame holds them (the hub's parent, or
    "world"); ``anchor`` (3,) m the hub centre in that frame; ``vectors[kind]`` (k, 3) the
    load at the key times (N, N m; body axes); ``per_metre[kind]`` the load of 1 m of arrow."""

    frame: str
    anchor: np.ndarray
    vectors: dict[str, np.ndarray]
    per_metre: dict[str, float]

    def legend(self) -> str:
        """e.g. ``hub loads on the airframe: force 1 m = 13.6 kN, moment 1 m = 5.2 kN m``."""
        parts = [f"{k} 1 m = {self.per_metre[k] * 1e-3:.3g} {KINDS[k][2]}" for k in self.vectors]
        return "main-rotor hub loads on the airframe: " + ", ".join(parts) + " (moment: right-hand rule)"


def output_names(kind: str) -> list[str]:
    return [f"main_rotor.hub.{kind}_{c}" for c in "xyz"]


def hub_arrows(rec, times: np.ndarray) -> HubArrows | None:
    """The arrows of the recording ``rec`` at ``times`` (s), or None when its model has no
    main-rotor hub loads."""
    info = rec.info
    names = info.output_names
    if HUB not in info.body_names or not all(n in names for k in KINDS for n in output_names(k)):
        return None
    rows = np.array([rec.system.outputs(rec.state_at(float(t)), float(t), rec.params_at(float(t))) for t in times])
    vectors = {k: rows[:, [names.index(n) for n in output_names(k)]] for k in KINDS}
    per_metre = {k: max(float(np.linalg.norm(v, axis=1).max()), 1e-9) / LONGEST for k, v in vectors.items()}
    hub = info.bodies[info.body_names.index(HUB)]
    return HubArrows(hub["parent"], np.array(hub["at"], dtype=float), vectors, per_metre)


def tracks(frame_path: str, arrows: HubArrows) -> list[dict]:
    """Node tracks (path, positions (k, 3) m, quaternions (k, 4) xyzw, scales (k, 3)) of the
    arrows' nodes; ``frame_path``: the meshcat path of the frame holding them."""
    out = []
    for kind, v in arrows.vectors.items():
        length = np.maximum(np.linalg.norm(v, axis=1) / arrows.per_metre[kind], 1e-6)
        turn = np.array([kin.align_y(u) if np.linalg.norm(u) > 0 else np.eye(3) for u in v])
        base = f"{frame_path}/hub_loads/{kind}"
        k, one, zero = len(v), np.ones(len(v)), np.zeros(len(v))
        out += [_track(base, np.tile(arrows.anchor, (k, 1)), kin.quaternions_xyzw(turn), np.ones((k, 3))),
                _track(f"{base}/shaft", np.c_[zero, length / 2, zero], _still(k), np.c_[one, length, one]),
                _track(f"{base}/head", np.c_[zero, length + HEAD / 2, zero], _still(k), np.ones((k, 3)))]
    return out


def _still(k: int) -> np.ndarray:
    return np.tile([0.0, 0.0, 0.0, 1.0], (k, 1))


def _track(path: str, position: np.ndarray, quaternion: np.ndarray, scale: np.ndarray) -> dict:
    return {"path": path, "position": position, "quaternion": quaternion, "scale": scale}


def commands(frame_path: str, arrows: HubArrows) -> list:
    """meshcat commands creating the arrows' geometry (shaft and head of each kind)."""
    from viewer.scene import _path, color_int, meshcat

    mc = meshcat()
    cmd, g, Path = mc.commands, mc.geometry, mc.path.Path
    out = []
    for kind in arrows.vectors:
        material = g.MeshLambertMaterial(color=color_int(KINDS[kind][0], "arrow"))
        base = f"{frame_path}/hub_loads/{kind}"
        out.append(cmd.SetObject(g.Cylinder(1.0, RADIUS), material, _path(Path, f"{base}/shaft")))
        out.append(cmd.SetObject(g.Cylinder(HEAD, radiusTop=0.0, radiusBottom=2.5 * RADIUS), material,
                                 _path(Path, f"{base}/head")))
    return out
