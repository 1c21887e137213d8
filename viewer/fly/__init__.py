"""Fly it in the browser: one self-contained HTML page holding a scene's model as WebAssembly (the
native FMU's generated C and model core, :mod:`fmu.native.wasm`), its meshcat scene and the
pilot's controls; no server, no network, works from ``file://``.

The model runs in a Web Worker at the fixed RK4 step of ``heli simulate`` (one revolution over the
scene's steps per revolution), in real time or at a chosen time scale, decoupled from the frames
(``web/worker.js``); the page draws the poses, charts, the tip-path plane and the readout
(``web/fly.js``, ``web/charts.js``) and reads the pilot (``web/controls.js``). The inputs flown are
recorded as ``heli simulate``'s ``--inputs`` table, which replays the flight from the same start
(``heli simulate SCENE --start ...``).

Modules: :mod:`.model` (what the page knows of the model), :mod:`.starts` (trims at chosen
speeds), :mod:`.controller` (the hover-hold controller), :mod:`.page` (the HTML),
:mod:`.commands` (``heli fly``), :mod:`.bench` (``heli bench fly``).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from viewer import kinematics as kin
from viewer.fly import controller as hover_hold
from viewer.fly import model as fm
from viewer.fly.page import html_page
from viewer.fly.starts import page_starts

STAND_NOTE = ("{scene}: a rotor on a stand (its fuselage is not free): the pitch controls only; no flight, no "
              "stability augmentation")
NO_INPUTS_NOTE = ("{scene}: {what} with no pitch inputs, so nothing to pilot: watch it run (time scale, pause, reset, "
                  "+1 rev)")


def page_note(scene_name: str, free: bool, inputs: list) -> str:
    """What the page says first: a rotor on a stand, a scene with nothing to pilot, or nothing."""
    if not inputs:
        return NO_INPUTS_NOTE.format(scene=scene_name, what="a free-flying model" if free else "a rotor on a stand")
    return "" if free else STAND_NOTE.format(scene=scene_name)


@dataclass
class FlyPage:
    """What :func:`write_page` wrote: ``path``, ``size`` (bytes), the scene, the starts' labels,
    whether the controller is in, the WebAssembly model's size and the build's seconds."""

    path: Path
    size: int
    scene: str
    starts: list[str]
    controller: bool
    wasm_bytes: int
    build_s: float
    free: bool
    note: str

    def summary(self) -> dict:
        return {"html": str(self.path), "bytes": self.size, "scene": self.scene, "starts": self.starts,
                "controller": self.controller, "wasm_bytes": self.wasm_bytes, "build_s": self.build_s,
                "free_fuselage": self.free, "note": self.note}


def _start_view(system, scene, start: dict, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Node transforms (nb, 4, 4) and the world node (4, 4) at the first start."""
    from viewer.motion import parents_of

    origins, rotations = system.poses(np.array(start["x0"]), 0.0, p)
    local = kin.relative(kin.homogeneous(origins, rotations), parents_of(system.info))
    world = np.eye(4)
    if scene.follow is not None:
        world[:3, 3] = -origins[scene.body_names.index(scene.follow)]
    return local, world


def _params(system, names: list[str], start: dict) -> np.ndarray:
    return system.params({n: v for n, v in zip(names, start["controls"])})


def family(scene_name: str) -> list[str]:
    """The scenes whose models the page's WebAssembly holds: the native FMU's default family
    (forward flight, hover and ground run; two models) for one of them, else the scene alone."""
    from fmu.build import DEFAULT_SCENES

    return list(DEFAULT_SCENES) if scene_name in DEFAULT_SCENES else [scene_name]


def aircraft_argument(aircraft) -> str | None:
    """The ``--aircraft`` that names ``aircraft`` on a command line (None: the Bo105)."""
    if aircraft is None or isinstance(aircraft, str):
        return aircraft
    return aircraft.key if aircraft.packaged else str(aircraft.path)


NO_CONTROLLER = ("stability augmentation is not in this page (left out to write it sooner): 'heli fly {scene}' "
                 "writes the page with the hover-hold controller")


def check(sc, speeds=None) -> None:
    """Refuse, before anything is built, a scene the page cannot fly (no native FMU: not a helicopter
    scene) and ``speeds`` where there is nothing to trim at them (ValueError naming them)."""
    from mbs import scenes
    from mbs.analysis.trim import trimmable

    if sc.aircraft is None:
        flyable = [n for n, s in scenes.all_scenes().items() if s.aircraft is not None]
        raise ValueError(f"scene {sc.name!r} cannot be flown: the page runs the native FMU's model, which is built for "
                         f"the helicopter scenes ({', '.join(flyable)})")
    model = sc.model()
    free = any(type(b.joint).__name__ == "FreeJoint" for b in model.bodies.values())
    if speeds and not (free and trimmable(sc)):
        why = "its fuselage is not free" if not free else "it cannot be trimmed"
        raise ValueError(f"--speeds: scene {sc.name!r} starts from one state ({why}), so there is no trim at a speed "
                         "to choose; leave --speeds out")


def _scene_reals(spec: dict, name: str, vr: dict, controls: list[dict]) -> list[list]:
    """``[value reference, value]`` of each real parameter or input the scene ``name`` starts with
    other than its XML start (the family's primary scene's; e.g. ground-run's initial forward speed
    0 where forward flight's is 10), the pilot's inputs left out (each start sets them)."""
    from fmu.build import scene_start_values

    piloted = {q["name"] for q in controls}
    return [[vr[n], float(v)] for n, v in scene_start_values(spec, name).items()
            if n not in piloted and n != "scene" and isinstance(v, (int, float)) and not isinstance(v, bool)]


def _model_config(sc, system, scene, spec: dict, controls: list[dict]) -> dict:
    """The page's configuration of the model (:mod:`viewer.fly.model`): step, value references, charts,
    readout, bodies and blade tips."""
    info, vr, name = system.info, fm.value_refs(spec), sc.name
    charts, chart_vrs = fm.charts(sc, scene, vr, controls)
    readout, readout_vrs = fm.readout(vr, fm.modelled(info))
    hinge = spec["scenes"][name]["hinge_states"]
    return {"scene": name, "aircraft": info.name, "h": fm.step(sc, system),
            "revolution": sc.revolution(system, system.params()), "steps_per_rev": sc.steps_per_rev,
            "vr": {"scene": vr["scene"], "initial_state": vr.get("initial_state", -1)}, "inputs": controls,
            "scene_reals": _scene_reals(spec, name, vr, controls),
            "hinge": hinge, "hinge_names": [info.state_names[i] for i in hinge], "charts": charts,
            "chart_vrs": chart_vrs, "readout": readout, "readout_vrs": readout_vrs,
            "chart_every": max(1, round(sc.steps_per_rev / fm.CHART_SAMPLES_PER_REV)),
            "history_limit": fm.HISTORY_LIMIT, "tpp_stretch": 5, "stick_reach": fm.STICK_REACH,
            "bodies": fm.bodies(scene), "follow": -1 if scene.follow is None else scene.body_names.index(scene.follow),
            "world": scene.frame_path("world"), "tips": fm.tips(scene), "scales": fm.SCALES,
            "inputs_file": f"{name}-inputs.csv"}


def _pilot(sc, system, spec: dict, speeds, log) -> tuple[list[dict], list[dict]]:
    """The starts and the pilot's inputs (each with the sign that moves the control forward or right,
    measured on the model from the first start)."""
    names = [v["name"] for v in spec["variables"] if v["causality"] == "input"]
    starts = page_starts(sc, system, names, speeds, log)
    free = any(b["joint"] == "FreeJoint" for b in system.info.bodies)
    signs = fm.pilot_signs(system, np.array(starts[0]["x0"]), _params(system, names, starts[0]), fm.step(sc, system),
                           sc.steps_per_rev) if free else {}
    return starts, fm.inputs(spec, sc.name, signs)


def _stability(sc, spec: dict, free: bool, wanted: bool, aircraft, log) -> tuple[dict | None, bytes | None, str]:
    """The hover-hold controller's configuration and WebAssembly, or (None, None, why not)."""
    if not free:
        return None, None, "no stability augmentation on a stand"
    if not wanted:
        return None, None, NO_CONTROLLER.format(scene=sc.name)
    names = [v["name"] for v in spec["variables"] if v["causality"] == "input"]
    return hover_hold.page_controller(sc, fm.value_refs(spec), names, aircraft, log)


def _scene_commands(system, scene, start: dict, names: list[str]) -> list[bytes]:
    """The meshcat commands drawing the scene at the first start."""
    from viewer.export import RecordingWindow
    from viewer.scene import commands

    window = RecordingWindow()
    for command in commands(scene, *_start_view(system, scene, start, _params(system, names, start))):
        window.send(command)
    return window.packed()


def write_page(scene_name: str, out, aircraft=None, speeds=None, flat: bool = False, log=None,
               flags=None, controller: bool = True) -> FlyPage:
    """Write the flight page of ``scene_name`` (of ``aircraft``: a name, file or loaded aircraft,
    default the Bo105) to ``out``: starts at the periodic trims at ``speeds`` (m/s; default
    :data:`viewer.fly.starts.DEFAULT_SPEEDS`) and the scene's own; ``flat``: unlit test colours;
    ``flags``: the WebAssembly's compiler flags (default :data:`fmu.native.wasm.FLAGS`);
    ``controller``: with the hover-hold controller where it applies (its design takes minutes the
    first time)."""
    from fmu.native import wasm
    from mbs import scenes
    from viewer.scene import build_scene

    began = time.perf_counter()
    sc = scenes.get(scene_name, aircraft)
    check(sc, speeds)
    built = wasm.ensure_model(family(scene_name), aircraft, log, flags or wasm.FLAGS)
    system = sc.system("compiled")
    free = any(b["joint"] == "FreeJoint" for b in system.info.bodies)
    scene = build_scene(system.info, flat, True, True)
    starts, controls = _pilot(sc, system, built.spec, speeds, log)
    ctrl, ctrl_wasm, why = _stability(sc, built.spec, free, controller, aircraft, log)
    note = page_note(scene_name, free, [q["name"] for q in controls])
    config = {**_model_config(sc, system, scene, built.spec, controls), "starts": starts, "controller": ctrl,
              "no_controller": why, "free": free, "note": note, "aircraft_arg": aircraft_argument(aircraft)}
    packed = _scene_commands(system, scene, starts[0], [q["name"] for q in controls])
    text = html_page(packed, {"config": config}, built.wasm.read_bytes(), ctrl_wasm,
                     f"fly {scene_name} ({system.info.name})")
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return FlyPage(path, path.stat().st_size, scene_name, [s["label"] for s in starts], ctrl is not None,
                   built.wasm.stat().st_size, time.perf_counter() - began, free, note)
