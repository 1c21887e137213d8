"""One self-contained HTML file: meshcat's viewer script inlined, the scene embedded as msgpack
commands that run synchronously on load, the keyframes and plot data as a data document read
by the page's own player (see :mod:`viewer.page`). No server, no network: it works from
``file://``. ``window.__viewerReady`` becomes true once the scene is drawn and the player
has started; ``window.__viewerInfo`` describes the page (body paths, times, stride).

The page is kept under ``max_bytes``: when the rows of the run would not fit, every n-th
row is shown (keys are added back where a joint would turn 60 deg or more).
"""
from __future__ import annotations

import base64
import json
import re
import uuid
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from viewer import animation as anim
from viewer import loads as hub_loads
from viewer import pack
from viewer import scene as sc
from viewer import series
from viewer import swashplate as swash
from viewer.motion import Motion, as_recording, key_times, motion
from viewer.page import html_page

DEFAULT_MAX_BYTES = 5_000_000


class RecordingWindow:
    """Stands in for meshcat's server connection: keeps the lowered commands, the last
    one per (type, path, property), as the server's scene tree does."""

    def __init__(self):
        self.commands: dict[tuple, dict] = {}

    def send(self, command) -> None:
        data = command if isinstance(command, dict) else command.lower()
        if data["type"] == "set_object":
            _stable_uuids(data)
        self.commands[(data["type"], data["path"], data.get("property"))] = data

    def packed(self) -> list[bytes]:
        umsgpack = _umsgpack()
        return [umsgpack.packb(c) for c in self.commands.values()]


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
    keyframes), ``duration`` (s of playback at the initial speed), ``sim_time`` (t_0, t_1) s,
    ``every`` (row stride used), ``plot_rows``, ``max_key_angle_deg``."""

    path: Path
    size: int
    keys: int
    duration: float
    sim_time: tuple[float, float]
    slow: float
    every: int
    plot_rows: int
    max_key_angle_deg: float
    motion: Motion
    scene: sc.Scene

    def summary(self) -> dict:
        return {"html": str(self.path), "bytes": self.size, "keys": self.keys, "duration_s": self.duration,
                "sim_time_s": list(self.sim_time), "slow": self.slow, "every": self.every,
                "plot_rows": self.plot_rows, "max_key_angle_deg": self.max_key_angle_deg,
                "scene": self.motion.recording.name, "bodies": self.scene.body_names}


def record(scene: sc.Scene, mo: Motion, arrows: hub_loads.HubArrows | None = None,
           mech: swash.Mechanism | None = None) -> RecordingWindow:
    """The commands drawing ``scene`` at the first key of ``mo`` (with the tip-path lines, the
    hub-load ``arrows`` and the swashplate ``mech``)."""
    window = RecordingWindow()
    traces = anim.tip_paths(scene, mo) if scene.traced else {}
    world0 = anim.world_at(anim.keyframes(scene, mo), float(mo.t[0]))
    for command in sc.commands(scene, mo.local[0], world0, traces):
        window.send(command)
    for command in hub_loads.commands(scene.frame_path(arrows.frame), arrows) if arrows else []:
        window.send(command)
    for command in swash.commands(scene.paths[swash.HUB], mech) if mech else []:
        window.send(command)
    return window


def document(scene: sc.Scene, mo: Motion, slow: float, follow: bool,
             arrows: hub_loads.HubArrows | None = None, mech: swash.Mechanism | None = None) -> tuple[dict, int]:
    """The page's data document for ``mo`` (with the hub-load ``arrows`` and the swashplate
    ``mech``) and the number of plot rows."""
    rec = mo.recording
    rows = series.plot_rows(rec, float(mo.t[0]), float(mo.t[-1]))
    plot = pack.plot_data(scene, rec.t[rows], series.panels(rec, rows))
    tracks = (hub_loads.tracks(scene.frame_path(arrows.frame), arrows) if arrows else []) + \
        (swash.tracks(scene.paths[swash.HUB], mech) if mech else [])
    doc = pack.document(scene, anim.keyframes(scene, mo), plot, series.azimuth(rec, mo.t), rec.revolution,
                        1.0 / slow, follow, tracks)
    return doc, len(rows)


def first_stride(rec, scene: sc.Scene, revs, start, every: int, max_bytes: float) -> int:
    """A row stride (>= ``every``) whose page should fit ``max_bytes``, estimated from the
    number of rows and bodies (base64 float32 tracks, float64 times)."""
    room = max_bytes - len(html_page([], {}, {}, "", "").encode("utf-8"))
    if not room > 0:
        raise ValueError(f"max_bytes = {max_bytes:.0f} leaves no room for data beside the viewer script")
    per_key = 4 / 3 * (28 * len(scene.body_names) + 12 * len(scene.traced) + 40)
    rows = len(key_times(rec, revs, start, every)) * every
    return max(every, int(np.ceil(rows * per_key / room)))


def fitted(rec, scene: sc.Scene, revs, start, every: int, max_bytes: float, render) -> tuple[Motion, str, int]:
    """The motion, page text (``render(mo, every)``) and stride of the first page that fits
    ``max_bytes``, thinning the rows from an estimated stride on."""
    every = first_stride(rec, scene, revs, start, every, max_bytes)
    for _ in range(8):
        mo = motion(rec, revs, start, every)
        text = render(mo, every)
        size = len(text.encode("utf-8"))
        if size <= max_bytes:
            return mo, text, every
        if len(mo.t) < 3:
            break
        every = max(every + 1, int(np.ceil(every * size / max_bytes)))
    raise ValueError(f"cannot fit {rec.name or rec.info.name} into max_bytes = {max_bytes:.0f}: the page from 1 row "
                     f"in {every} has {size} bytes (keys stay at most 60 deg of joint turn apart)")


def export_html(source, path: str | Path, revs: float | None = None, start: float | None = None, every: int = 1,
                slow: float = 10.0, flat: bool = False, trace=True, follow=True, backend: str = "vm",
                title: str | None = None, max_bytes: float = DEFAULT_MAX_BYTES, loads: bool = True) -> Export:
    """Write the scene of ``source`` (a Simulation, a results folder or csv, or a
    :class:`viewer.motion.Recording`) to the HTML file ``path``: 3D view, plot and controls.

    revs: main-rotor revolutions shown (default None: the whole run), from ``start`` (s) if
    given, else the last ones; every: keep every n-th recorded row at least (keys are added
    back where a joint would turn 60 deg or more); slow: the page starts playing 1/slow of real
    time; flat: unlit test colours without background, grid and axes; trace: tip paths (see
    :func:`viewer.scene.build_scene`), drawn over the last revolution; follow: the camera
    starts following the free root body (False: fixed; the page has a toggle); max_bytes:
    the page's size limit (rows are thinned to fit); loads: the main rotor's hub force and
    moment as arrows at the hub, when the model has them (:mod:`viewer.loads`).
    """
    if not (np.isfinite(slow) and slow > 0):
        raise ValueError(f"slow = {slow} must be positive and finite")
    rec = as_recording(source, backend)
    scene = sc.build_scene(rec.info, flat, trace, True if follow in (False, None) else follow)
    name = rec.name or rec.info.name
    plot_rows = []

    def render(mo: Motion, stride: int) -> str:
        arrows = hub_loads.hub_arrows(rec, mo.t) if loads else None
        mech = swash.mechanism(rec, mo.t)
        doc, rows = document(scene, mo, slow, bool(follow), arrows, mech)
        plot_rows[:] = [rows]
        info = {"model": rec.info.name, "scene": name, "slow": slow, "t0": float(mo.t[0]), "t1": float(mo.t[-1]),
                "keys": len(mo.t), "every": stride, "bodies": scene.paths, "world": sc.WORLD,
                "arrows": arrows.per_metre if arrows else None}
        label = f"{name}: t = {mo.t[0]:.4g} to {mo.t[-1]:.4g} s" + (f", every {stride} rows" if stride > 1 else "")
        label += f"; {arrows.legend()}" if arrows else ""
        return html_page(record(scene, mo, arrows, mech).packed(), info, doc, title or f"{name} (rotor-mbs viewer)",
                         label)

    mo, text, every = fitted(rec, scene, revs, start, every, max_bytes, render)
    out = Path(path)
    from mbs import atomic

    atomic.write_text(out, text)
    return Export(out, out.stat().st_size, len(mo.t), float((mo.t[-1] - mo.t[0]) * slow), (float(mo.t[0]), float(mo.t[-1])),
                  slow, every, plot_rows[0], float(np.degrees(mo.max_key_angle().max(initial=0.0))), mo, scene)


def _embedded(path: str | Path, pattern: str, what: str) -> str:
    text = Path(path).read_text(encoding="utf-8")
    block = re.search(pattern, text, re.S)
    if block is None:
        raise ValueError(f"{path} is not a page written by export_html (no {what})")
    return block.group(1)


def commands_in(path: str | Path) -> list[dict]:
    """The meshcat commands embedded in an exported page, decoded (for checks and tools)."""
    block = _embedded(path, r"var commands = \[\n(.*?)\n  \];", "scene commands")
    umsgpack = _umsgpack()
    return [umsgpack.unpackb(base64.b64decode(json.loads(s))) for s in block.split(",\n")]


def data_in(path: str | Path) -> dict:
    """The data document embedded in an exported page (arrays still encoded; see
    :func:`viewer.pack.decode` and :func:`viewer.pack.keyframes_of`)."""
    return json.loads(_embedded(path, r'<script id="viewer-data" type="application/json">(.*?)</script>', "data"))
