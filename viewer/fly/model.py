"""What the flight page knows of its model (``window.__flyData.config``): the step, the FMU's
value references of the inputs and of what the charts and the readout show, the bodies of the 3D
view and the blade tips of the tip-path plane, the starts, the pilot's controls.

Value references and ranges are the native FMU's (its plan, :func:`fmu.native.build.native_spec`),
so that the page sets and reads the WebAssembly model exactly as a master sets and reads the FMU.
"""
from __future__ import annotations

import math

import numpy as np

from viewer.motion import parents_of
from viewer.scene import Scene

SCALES = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, "max"]
"""Time scales offered: simulated seconds per second of wall time; "max": as fast as it can."""
HISTORY_LIMIT = 200_000
"""Steps whose hinge angles the page keeps (for the tests and the record; 1.6 MB per 10 000 steps of the Bo105)."""
CHART_SAMPLES_PER_REV = 36
STICK_REACH = 0.1
"""Largest deflection of a cyclic or the pedals from its trim (keys, gamepad, on-screen stick), as a
part of the input's range: for the Bo105's cyclics 0.017-0.027 rad."""
ROLES = {"collective": "collective", "longitudinal_cyclic": "longitudinal", "lateral_cyclic": "lateral",
         "tail_collective": "pedals"}
KEYS = {"collective": "W / S", "longitudinal": "\u2191 / \u2193 (forward / back)", "lateral": "\u2192 / \u2190",
        "pedals": "D / A (right / left)"}
LABELS = {"collective": "collective", "longitudinal": "longitudinal cyclic", "lateral": "lateral cyclic",
          "pedals": "pedals (tail-rotor collective)"}
FLIGHT_SPAN_S = 20.0
HINGE_SPAN_REVS = 3


def value_refs(spec: dict) -> dict[str, int]:
    """Variable name -> value reference (the FMU's FMI 2.0 ones)."""
    return {v["name"]: k for k, v in enumerate(spec["variables"])}


def step(scene, system) -> float:
    """The fixed step (s): one revolution at the scene's steps per revolution, as ``heli simulate``'s."""
    return scene.revolution(system, system.params()) / scene.steps_per_rev


def inputs(spec: dict, scene_name: str, signs: dict[str, float]) -> list[dict]:
    """The model's inputs (the FMU's): value reference, range (rad) in the scene, the pilot's role,
    label and keys, and the sign of the input that moves the control forward, right or up."""
    ranges, out = spec["scenes"][scene_name]["ranges"], []
    for k, v in enumerate(spec["variables"]):
        if v["causality"] != "input":
            continue
        role = ROLES.get(v["name"])
        low, high = ranges.get(v["name"], [v.get("min"), v.get("max")])
        out.append({"name": v["name"], "vr": k, "low": low, "high": high, "role": role,
                    "label": LABELS.get(role, v["name"]), "keys": KEYS.get(role), "sign": signs.get(v["name"], 1.0)})
    return out


def bodies(scene: Scene) -> list[dict]:
    """Each body's meshcat path and parent index (-1: the world)."""
    parents = parents_of(scene.info)
    return [{"name": n, "path": scene.paths[n], "parent": parents[i]} for i, n in enumerate(scene.body_names)]


def tips(scene: Scene) -> list[dict]:
    """The main-rotor blade tips: body index, tip point (m, blade frame), the index of the body whose
    frame shows the tip-path plane (-1: the world) and the blade's colour."""
    names = scene.body_names
    out = []
    for blade in scene.traced:
        frame = scene.trace_frames[blade]
        out.append({"body": names.index(blade), "point": [float(c) for c in scene.tip_point(blade)],
                    "frame": -1 if frame == "world" else names.index(frame), "color": f"#{scene.colors[blade]:06x}"})
    return out


PALETTE = ["#d62728", "#2ca02c", "#1f77b4", "#222222", "#9467bd"]


def modelled(info) -> set[str]:
    """The variables the scene's own model computes (the family's primary scene may have more: an
    FMU gives 0 for the others): its states and outputs, and a free fuselage's Euler angles."""
    free = [b["name"] for b in info.bodies if b["joint"] == "FreeJoint"]
    return {*info.state_names, *info.output_names, *(f"{b}.{a}" for b in free for a in ("roll", "pitch", "yaw"))}


def _series(scene: Scene, names: list[str], vr: dict, chart_vrs: list[int]) -> list[dict]:
    """Chart series of the variables ``names`` the model has: a blade's in its colour, others from a palette."""
    out = []
    known = modelled(scene.info)
    for k, name in enumerate(names):
        if name not in vr or name not in known:
            continue
        body, _, what = name.partition(".")
        blade = body in scene.colors and body in scene.traced
        chart_vrs.append(vr[name])
        out.append({"name": name, "label": body if blade else what if body == "fuselage" else body.replace("_", " "),
                    "index": len(chart_vrs) - 1,
                    "color": f"#{scene.colors[body]:06x}" if blade else PALETTE[k % len(PALETTE)]})
    return out


def charts(sc, scene: Scene, vr: dict, controls: list[dict]) -> tuple[list[dict], list[int]]:
    """The chart panels (hinge angles of each blade, attitude, speed, rotor thrust, the controls) and
    the value references they read, in order."""
    chart_vrs: list[int] = []
    panels = []
    for title, names in sc.plots.items():
        series = _series(scene, names, vr, chart_vrs)
        if series:
            panels.append({"title": title.replace("(rad)", "(deg)"), "series": series,
                           "scale": 180 / math.pi if "(rad)" in title else 1, "revs": HINGE_SPAN_REVS})
    flight = [("attitude (deg)", ["fuselage.roll", "fuselage.pitch", "fuselage.yaw"], 180 / math.pi),
              ("velocity, body axes (m/s)", ["fuselage.u", "fuselage.v", "fuselage.w"], 1),
              ("rotor thrust (kN)", ["main_rotor.thrust", "tail_rotor.thrust"], 1e-3)]
    for title, names, scale in flight:
        series = _series(scene, names, vr, chart_vrs)
        if series:
            panels.append({"title": title, "series": series, "scale": scale, "seconds": FLIGHT_SPAN_S})
    inputs_panel = [{"name": q["name"], "label": q["label"], "input": i, "color": PALETTE[i % len(PALETTE)]}
                    for i, q in enumerate(controls)]
    if inputs_panel:
        panels.append({"title": "pilot's inputs, as flown (deg)", "series": inputs_panel, "scale": 180 / math.pi,
                       "seconds": FLIGHT_SPAN_S})
    return panels, chart_vrs


def readout(vr: dict, known: set[str]) -> tuple[list[dict], list[int]]:
    """The readout beside time and revolutions: azimuth, speed, attitude, height (those the model has)."""
    items = [("main_rotor.azimuth", "azimuth", 180 / math.pi, 360, 1, "\u00b0"),
             ("fuselage.u", "u", 1, None, 2, " m/s"),
             ("fuselage.roll", "roll", 180 / math.pi, None, 2, "\u00b0"),
             ("fuselage.pitch", "pitch", 180 / math.pi, None, 2, "\u00b0"),
             ("fuselage.yaw", "heading", 180 / math.pi, 360, 1, "\u00b0"),
             ("fuselage.z", "height", -1, None, 2, " m"),
             ("main_rotor.thrust", "thrust", 1e-3, None, 2, " kN")]
    shown = [i for i in items if i[0] in vr and i[0] in known]
    return ([{"name": n, "label": label, "scale": s, "modulo": m, "digits": d, "unit": u}
             for n, label, s, m, d, u in shown], [vr[i[0]] for i in shown])


def pilot_signs(system, x0: np.ndarray, p: np.ndarray, h: float, steps: int) -> dict[str, float]:
    """For each cyclic and the pedals, the sign of the input that moves the aircraft as the control
    moved forward (nose down), right (roll right) and right (yaw right) does: from the body rates
    after ``steps`` steps of ``h`` s with the input raised by 0.01 rad, against the rates without."""
    info = system.info
    rates = [f"fuselage.{c}" for c in "pqr"]
    if not all(r in info.state_names for r in rates):
        return {}
    index = [info.state_names.index(r) for r in rates]
    base = system.run(x0, 0.0, h, steps, every=steps, p=p).x[-1][index]
    out = {}
    for name, axis, forward in (("longitudinal_cyclic", 1, -1.0), ("lateral_cyclic", 0, 1.0), ("tail_collective", 2, 1.0)):
        if name not in info.param_names:
            continue
        q = np.array(p, dtype=float)
        q[info.param_names.index(name)] += 0.01
        moved = system.run(x0, 0.0, h, steps, every=steps, p=q).x[-1][index]
        out[name] = forward * float(np.sign(moved[axis] - base[axis]) or 1.0)
    return out
