"""The data document a page's scripts read (``window.__viewerData``): key times and node tracks,
the followed origin, the azimuth, the trace lines and the plot, with every array stored as
base64 of little-endian float32 ("f4") or float64 ("f8") values.

Times, the followed origin and the azimuth are float64 (a seek to a key time lands exactly on
it; the aircraft may be far from the origin); node tracks and plot values float32. A track
that never changes is stored as one row.
"""
from __future__ import annotations

import base64

import numpy as np

from viewer.animation import Keyframes
from viewer.scene import Scene
from viewer.series import Panel

INPUT_COLORS = ["#000000", "#9467bd", "#8c564b", "#17becf", "#bcbd22", "#7f7f7f"]


def encode(values, dtype: str = "f4") -> dict:
    """An array as ``{"dtype", "shape", "b64"}``; dtype "f4" or "f8"."""
    arr = np.ascontiguousarray(values, dtype="<" + dtype)
    return {"dtype": dtype, "shape": list(arr.shape), "b64": base64.b64encode(arr.tobytes()).decode("ascii")}


def decode(obj: dict) -> np.ndarray:
    """The array stored by :func:`encode` (float64 copy)."""
    raw = np.frombuffer(base64.b64decode(obj["b64"]), dtype="<" + obj["dtype"])
    return raw.reshape(obj["shape"]).astype(float)


def track(values: np.ndarray, tol: float = 1e-9) -> dict:
    """A node track (k, n) as float32; one row if it never moves by more than ``tol``."""
    constant = len(values) < 2 or np.abs(values - values[0]).max() < tol
    return encode(values[:1] if constant else values)


def hex_color(color: int) -> str:
    return f"#{color:06x}"


def series_color(scene: Scene, name: str, k: int) -> str:
    """The colour of the body a series belongs to (e.g. blade2.flap: blade2), else a palette colour."""
    body = name.split(".", 1)[0]
    return hex_color(scene.colors[body]) if body in scene.colors else INPUT_COLORS[k % len(INPUT_COLORS)]


def plot_data(scene: Scene, times: np.ndarray, panels: list[Panel]) -> dict:
    """The plot's rows ``times`` (n,) s and panels."""
    out = []
    for panel in panels:
        series = [{"name": n, "color": series_color(scene, n, k), "values": encode(panel.values[:, k])}
                  for k, n in enumerate(panel.names)]
        out.append({"title": panel.title, "series": series})
    return {"t": encode(times, "f8"), "panels": out}


def document(scene: Scene, kf: Keyframes, plot: dict, azimuth: np.ndarray | None, revolution: float | None,
             speed: float, follow: bool, arrows: list[dict] | None = None) -> dict:
    """Everything the player needs; ``speed`` is the initial playback rate (1 = real time);
    ``arrows``: node tracks with a scale (:func:`viewer.loads.tracks`)."""
    traces = [f"{scene.frame_path(scene.trace_frames[b])}/tip_path/{b}/<object>" for b in scene.traced]
    return {"t": encode(kf.t, "f8"),
            "nodes": [{"path": p, "position": track(pos), "quaternion": track(q)} for p, (pos, q) in kf.nodes.items()],
            "world": scene.frame_path("world"),
            "follow": None if kf.follow is None else encode(kf.follow, "f8"),
            "camera": "follow" if follow and kf.follow is not None else "fixed",
            "azimuth": None if azimuth is None else encode(azimuth, "f8"),
            "revolution": revolution, "speed": speed, "traces": traces, "plot": plot,
            "arrows": [{"path": a["path"], **{k: track(a[k]) for k in ("position", "quaternion", "scale")}}
                       for a in arrows or []]}


def keyframes_of(doc: dict) -> Keyframes:
    """The :class:`Keyframes` stored in a document (a constant track keeps its single row)."""
    nodes = {node["path"]: (decode(node["position"]), decode(node["quaternion"])) for node in doc["nodes"]}
    follow = None if doc["follow"] is None else decode(doc["follow"])
    return Keyframes(decode(doc["t"]), nodes, follow)
