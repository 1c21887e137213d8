"""One self-contained HTML file: meshcat's viewer script inlined, the scene and the
animation embedded as msgpack commands that run synchronously on load. No server, no
network: it works from ``file://``. ``window.__viewerReady`` becomes true once every command
has run; ``window.__viewerInfo`` describes the page (body paths, clip duration, slow)."""
from __future__ import annotations

import base64
import html
import json
import uuid
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from viewer import animation as anim
from viewer import scene as sc
from viewer.motion import Motion, motion


class RecordingWindow:
    """Stands in for meshcat's server connection: keeps the lowered commands, the last
    one per (type, path, property), the animation last (as the server's scene tree does)."""

    def __init__(self):
        self.commands: dict[tuple, dict] = {}
        self.animation: dict | None = None

    def send(self, command) -> None:
        data = command if isinstance(command, dict) else command.lower()
        if data["type"] == "set_animation":
            self.animation = data
            return
        if data["type"] == "set_object":
            _stable_uuids(data)
        self.commands[(data["type"], data["path"], data.get("property"))] = data

    def packed(self) -> list[bytes]:
        umsgpack = _umsgpack()
        out = [umsgpack.packb(c) for c in self.commands.values()]
        if self.animation is not None:  # three.js stores keys in float32 anyway
            out.append(umsgpack.packb(self.animation, force_float_precision="single"))
        return out


def _umsgpack():
    import umsgpack

    return umsgpack


def _stable_uuids(data: dict) -> None:
    """Replace meshcat's time-and-host based uuids by ones derived from the path."""
    mapping = {}
    for field in ("geometries", "materials"):
        for item in data["object"].get(field, []):
            mapping[item["uuid"]] = str(uuid.uuid5(uuid.NAMESPACE_URL, f"{data['path']}#{field}"))
            item["uuid"] = mapping[item["uuid"]]
    obj = data["object"]["object"]
    for key in ("geometry", "material"):
        obj[key] = mapping.get(obj[key], obj[key])
    obj["uuid"] = str(uuid.uuid5(uuid.NAMESPACE_URL, data["path"]))


@dataclass
class Export:
    """What :func:`export_html` wrote: ``path``, ``size`` (bytes), ``keys`` (number of
    keyframes), ``duration`` (clip s), ``sim_time`` (t_0, t_1) s, ``max_key_angle_deg``."""

    path: Path
    size: int
    keys: int
    duration: float
    sim_time: tuple[float, float]
    slow: float
    max_key_angle_deg: float
    motion: Motion
    scene: sc.Scene

    def summary(self) -> dict:
        return {"html": str(self.path), "bytes": self.size, "keys": self.keys, "duration_s": self.duration,
                "sim_time_s": list(self.sim_time), "slow": self.slow, "max_key_angle_deg": self.max_key_angle_deg,
                "scene": self.motion.recording.name, "bodies": self.scene.body_names}


def record(scene: sc.Scene, mo: Motion, slow: float = 10.0) -> RecordingWindow:
    """The commands of ``scene`` animated along ``mo`` (first key drawn statically)."""
    window = RecordingWindow()
    traces = anim.tip_paths(scene, mo) if scene.traced else {}
    world0 = anim.world_transforms(scene, mo)[0]
    for command in sc.commands(scene, mo.local[0], world0, traces):
        window.send(command)
    window.send(anim.lower(anim.keyframes(scene, mo, slow)))
    return window


def export_html(source, path: str | Path, revs: float | None = 1.0, start: float | None = None, every: int = 1,
                slow: float = 10.0, flat: bool = False, trace=True, follow=True, backend: str = "vm",
                title: str | None = None) -> Export:
    """Write the animated scene of ``source`` (a Simulation, a results folder or csv, or a
    :class:`viewer.motion.Recording`) to the HTML file ``path``.

    revs: main-rotor revolutions shown (None: all; default the last one), from ``start``
    (s) if given; every: keep every n-th recorded row (keys are added back where a joint
    would turn 60 deg or more); slow: slow-motion factor; flat: unlit test colours without
    background, grid and axes; trace: tip paths (see :func:`viewer.scene.build_scene`);
    follow: keep the free root body at the origin.
    """
    mo = motion(source, revs, start, every, backend=backend)
    scene = sc.build_scene(mo.recording.info, flat, trace, follow)
    window = record(scene, mo, slow)
    name = mo.recording.name or mo.recording.info.name
    info = {"model": mo.recording.info.name, "scene": name, "slow": slow, "t0": float(mo.t[0]),
            "t1": float(mo.t[-1]), "duration": float((mo.t[-1] - mo.t[0]) * slow), "keys": len(mo.t),
            "bodies": scene.paths, "world": sc.WORLD}
    label = (f"{name}: t = {mo.t[0]:.4g} to {mo.t[-1]:.4g} s, {slow:g} times slower than real time "
             f"(Open Controls, Animations: play, pause, time, timeScale)")
    text = page(window.packed(), info, title or f"{name} (rotor-mbs viewer)", label)
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text, encoding="utf-8")
    return Export(out, out.stat().st_size, len(mo.t), info["duration"], (info["t0"], info["t1"]), slow,
                  float(np.degrees(mo.max_key_angle().max(initial=0.0))), mo, scene)


def viewer_script() -> str:
    """meshcat's bundled viewer (three.js r132 and helpers), minified."""
    mc = sc.meshcat()
    return (Path(mc.viewer_assets_path()) / "dist" / "main.min.js").read_text(encoding="utf-8")


def _notice() -> str:
    """Names and licences of the inlined third-party code (from meshcat's licence list)."""
    mc = sc.meshcat()
    listing = Path(mc.viewer_assets_path()) / "dist" / "main.min.js.THIRD_PARTY_LICENSES.json"
    try:
        items = json.loads(listing.read_text())
        names = ", ".join(f"{i['name']} {i['version']} ({i['license']})" for i in items)
    except (OSError, ValueError, KeyError):
        names = "three.js and helpers"
    return (f"Contains the MeshCat viewer of meshcat-python 0.3.2 (MIT licence), bundling {names}; "
            "the licence texts ship with the meshcat Python package (viewer/dist).")


def page(packed: list[bytes], info: dict, title: str, label: str) -> str:
    """The HTML text: viewer script, commands (base64 msgpack) and the ready flag."""
    cmds = ",\n".join(json.dumps(base64.b64encode(b).decode("ascii")) for b in packed)
    script = viewer_script().replace("</script", "<\\/script")
    return f"""<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{html.escape(title)}</title>
<!-- {html.escape(_notice()).replace("--", "- -")} -->
<style>
body {{ margin: 0; }}
#meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
#viewer-label {{ position: absolute; left: 8px; bottom: 6px; font: 12px sans-serif; color: #fff;
  text-shadow: 0 0 3px #000; pointer-events: none; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
<div id="viewer-label">{html.escape(label)}</div>
<script>
{script}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
window.__viewerInfo = {json.dumps(info)};
(function () {{
  var commands = [
{cmds}
  ];
  for (var i = 0; i < commands.length; i++) {{
    var text = atob(commands[i]);
    var bytes = new Uint8Array(text.length);
    for (var j = 0; j < text.length; j++) bytes[j] = text.charCodeAt(j);
    viewer.handle_command_bytearray(bytes);
  }}
  window.__viewerReady = true;
}})();
</script>
</body>
</html>
"""


def commands_in(path: str | Path) -> list[dict]:
    """The meshcat commands embedded in an exported page, decoded (for checks and tools)."""
    import re

    text = Path(path).read_text(encoding="utf-8")
    block = re.search(r"var commands = \[\n(.*?)\n  \];", text, re.S)
    if block is None:
        raise ValueError(f"{path} is not a page written by export_html")
    umsgpack = _umsgpack()
    return [umsgpack.unpackb(base64.b64decode(json.loads(s))) for s in block.group(1).split(",\n")]
