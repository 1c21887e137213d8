"""The swashplate and the pitch links of a swashplate scene, drawn.

Each pitch link is a rod from its lower ball on the rotating plate to its upper ball on the
pitch horn; the plate is a disc through the lower balls. Both points come from the model's own
loop geometry (:func:`mbs.models.helicopter.swashplate.pitch_links`: the link's anchor and
its point on the pitch hinge side, functions of the blade's flap and lag, its pitch, the rotor
azimuth and the controls), evaluated at the key times in each blade's joint frame and carried
into the hub's frame (a node under the hub, which turns with it). A rigid link keeps its length
exactly. Like the hub-load arrows (:mod:`viewer.loads`), every node is a track of position,
quaternion and scale that the page's player moves.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from viewer import kinematics as kin

HUB = "main_hub"
ROD, DISC = 0.012, 0.02  # m: pitch-link radius, plate thickness
COLORS = {"link": "#e8a317", "plate": "#8a94a0"}


@dataclass
class Mechanism:
    """The mechanism at the key times, in the hub's frame (m): ``lower[blade]`` and
    ``upper[blade]`` (k, 3) the balls of each link; the plate's ``centre`` (k, 3), unit
    ``normal`` (k, 3) and ``radius``."""

    lower: dict[str, np.ndarray]
    upper: dict[str, np.ndarray]
    centre: np.ndarray
    normal: np.ndarray
    radius: float


def mechanism(rec, times: np.ndarray) -> Mechanism | None:
    """The swashplate and links of the recording ``rec`` (its scene a swashplate scene) at
    ``times`` (s), or None when it has none."""
    scene = getattr(rec, "scene", None)
    if scene is None or scene.aircraft is None or HUB not in rec.info.body_names:
        return None
    from mbs.models.helicopter.config import config_of
    from mbs.models.helicopter.swashplate import pitch_links

    cfg = config_of(scene)
    if not cfg.swashplate:
        return None
    model = scene.model()
    d = scene.aircraft.data
    links = pitch_links(model, d, cfg)
    points = _points_function(links, list(model.parameters))
    info = rec.info
    lower, upper = {}, {}
    for link, f in zip(links, points):
        body = info.bodies[info.body_names.index(link.blade)]
        at, frame = np.asarray(body["at"], dtype=float), np.asarray(body["frame"], dtype=float)
        rows = [_balls(rec, info, link, f, float(t)) for t in times]
        lower[link.blade] = np.array([at + frame @ lo for lo, _ in rows])
        upper[link.blade] = np.array([at + frame @ up for _, up in rows])
    centre, normal = _plate(np.stack(list(lower.values()), axis=1))
    return Mechanism(lower, upper, centre, normal, float(d["swashplate"]["plate_radius"]))


def _points_function(links, parameter_names: list[str]) -> list[ca.Function]:
    """For each link: ``(q (nq,), pitch, t, p (np,)) -> (lower ball, upper ball)`` in its joint frame."""
    from mbs.joints import Params

    p = ca.SX.sym("p", len(parameter_names))
    params, t, pitch = Params(parameter_names, p), ca.SX.sym("t"), ca.SX.sym("pitch")
    out = []
    for link in links:
        q = ca.SX.sym("q", link.joint.nq)
        loop = link.link
        up = loop.point_in_joint(link.joint, link.joint.merge(q, pitch), t, params)
        out.append(ca.Function(f"{link.blade}_balls", [q, pitch, t, p], [loop.anchor(t, params), up]))
    return out


def _balls(rec, info, link, f: ca.Function, t: float) -> tuple[np.ndarray, np.ndarray]:
    x, p = rec.state_at(t), rec.params_at(t)
    q = [x[info.state_names.index(f"{link.blade}.{n}")] for n in link.joint.q_names]
    pitch = rec.system.outputs(x, t, p)[info.output_names.index(f"{link.blade}.pitch")]
    lo, up = f(q, pitch, t, p)
    return np.asarray(lo, dtype=float).ravel(), np.asarray(up, dtype=float).ravel()


def _plate(balls: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre (k, 3) and unit normal (k, 3), pointing up the shaft, of the plane through the
    lower balls (k, nb, 3) of equally spaced blades (two blades: the plane square to the shaft
    through them)."""
    centre = balls.mean(axis=1)
    if balls.shape[1] < 3:
        return centre, np.tile([0.0, 0.0, 1.0], (len(balls), 1))
    normal = np.array([np.linalg.svd(b - c)[2][-1] for b, c in zip(balls, centre)])
    return centre, normal * np.sign(normal[:, 2:3] + 1e-300)


def tracks(hub_path: str, mech: Mechanism) -> list[dict]:
    """Node tracks (path, positions (k, 3), quaternions (k, 4) xyzw, scales (k, 3)) of the
    links (a unit rod along y stretched to the link) and the plate, under the hub's node."""
    out = []
    for blade, lo in mech.lower.items():
        along = mech.upper[blade] - lo
        length = np.linalg.norm(along, axis=1)
        turn = np.array([kin.align_y(u) for u in along])
        out.append({"path": f"{hub_path}/swashplate/{blade}", "position": lo + along / 2,
                    "quaternion": kin.quaternions_xyzw(turn), "scale": np.c_[np.ones(len(lo)), length,
                                                                             np.ones(len(lo))]})
    turn = np.array([kin.align_y(n) for n in mech.normal])
    out.append({"path": f"{hub_path}/swashplate/plate", "position": mech.centre,
                "quaternion": kin.quaternions_xyzw(turn), "scale": np.ones((len(mech.centre), 3))})
    return out


def commands(hub_path: str, mech: Mechanism) -> list:
    """meshcat commands creating the links' rods and the plate's disc."""
    from viewer.scene import _path, color_int, meshcat

    mc = meshcat()
    cmd, g, Path = mc.commands, mc.geometry, mc.path.Path
    rod = g.MeshLambertMaterial(color=color_int(COLORS["link"], "pitch link"))
    out = [cmd.SetObject(g.Cylinder(1.0, ROD), rod, _path(Path, f"{hub_path}/swashplate/{blade}"))
           for blade in mech.lower]
    plate = g.MeshLambertMaterial(color=color_int(COLORS["plate"], "swashplate"), opacity=0.85, transparent=True)
    out.append(cmd.SetObject(g.Cylinder(DISC, mech.radius * 1.15), plate, _path(Path, f"{hub_path}/swashplate/plate")))
    return out
