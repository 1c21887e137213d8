"""The meshcat scene of a model: one node per body, nested as in the tree.

Paths (meshcat's ``/meshcat`` prefix included)::

    /meshcat/model                      fixed: 180 deg about x (world NED -> meshcat z up)
    /meshcat/model/world                the world frame; moved by -r(t) of the followed body
    /meshcat/model/world/fuselage       body transform relative to its parent
    /meshcat/model/world/fuselage/main_hub/blade1   ...
    <body>/shape/<k>                    fixed offset of geometry part k (box or cylinder)
    <frame>/tip_path/<blade>            tip-path trace of a blade, in its hub's parent frame

Geometry comes from ``info.bodies[i]["shape"]`` (body frame, m): a box ``size`` or a
cylinder ``radius``, ``length``, ``axis``; an ``offset`` and an optional ``color``; or a
``parts`` list of such dicts. Bodies without a colour get one from a palette: the root body
light grey, inner bodies (hubs, seesaw) dark grey, leaves (blades) distinct colours.
"""
from __future__ import annotations

import re
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from viewer import kinematics as kin

ROOT = "/meshcat/model"
WORLD = ROOT + "/world"
RESERVED = ("shape", "tip_path", "hub_loads")
LEAF_COLORS = ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
               "#393b79", "#ad494a", "#31a354"]
"""Distinct colours of the leaves and of the main-rotor blades (the first four those the
helicopter model gives its blades)."""
BLADE = re.compile(r"blade(\d+)(?:[_:].*)?")
ROOT_COLOR, INNER_COLOR = "#c8ccd2", "#50565e"


def meshcat():
    """The meshcat package, imported without its pyzmq deprecation warning."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        import meshcat as mc
        import meshcat.animation  # noqa: F401
    return mc


def color_int(text: str, where: str) -> int:
    """``"#rrggbb"`` -> 0xrrggbb; ValueError naming ``where`` otherwise."""
    if not isinstance(text, str) or not re.fullmatch(r"#[0-9a-fA-F]{6}", text):
        raise ValueError(f"{where}: colour {text!r} is not of the form '#rrggbb'")
    return int(text[1:], 16)


def tint(color: int, amount: float = 0.5) -> int:
    """``color`` blended towards white by ``amount`` (0..1)."""
    rgb = np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255], dtype=float)
    r, g, b = np.rint(rgb + amount * (255 - rgb)).astype(int)
    return int(r << 16 | g << 8 | b)


@dataclass
class Part:
    """One solid: ``kind`` "box" (``size`` (3,)) or "cylinder" (``radius``, ``length``,
    ``axis``); ``transform`` (4, 4) places it in the body frame; ``color`` 0xrrggbb."""

    kind: str
    dims: tuple
    transform: np.ndarray
    color: int


@dataclass
class Scene:
    """Scene description of a model: ``paths[body]`` is the meshcat path of its node,
    ``parts[body]`` its geometry, ``colors[body]`` its main colour (0xrrggbb); ``traced``
    the blades whose tips are traced and ``trace_frames[blade]`` the body (or "world")
    whose frame holds the trace. ``flat``: unlit colours, no background, grid or axes."""

    info: object
    paths: dict[str, str]
    parts: dict[str, list[Part]]
    colors: dict[str, int]
    flat: bool = False
    traced: list[str] = field(default_factory=list)
    trace_frames: dict[str, str] = field(default_factory=dict)
    follow: str | None = None
    extent: float = 1.0

    @property
    def body_names(self) -> list[str]:
        return self.info.body_names

    def frame_path(self, body: str) -> str:
        return WORLD if body == "world" else self.paths[body]

    def tip_point(self, blade: str) -> np.ndarray:
        """The blade tip in the blade frame (m): the outermost point of its shape along x."""
        best = None
        for part in self.parts[blade]:
            half = _half_extent_x(part)
            tip = part.transform[:3, 3] + np.array([half, 0.0, 0.0])
            if best is None or tip[0] > best[0]:
                best = tip
        return best


def _half_extent_x(part: Part) -> float:
    """Half of the part's extent along the body x axis."""
    R = part.transform[:3, :3]
    if part.kind == "box":
        return float(np.abs(R[0]) @ np.asarray(part.dims) / 2)
    radius, length = part.dims
    axis = R[:, 1]
    return float(abs(axis[0]) * length / 2 + radius * np.sqrt(max(0.0, 1 - axis[0] ** 2)))


def _parts_of(body: dict) -> list[dict]:
    shape = body.get("shape") or {}
    if not isinstance(shape, dict):
        raise ValueError(f"body {body['name']!r}: shape must be a dict, got {type(shape).__name__}")
    if "parts" in shape:
        return list(shape["parts"])
    return [shape] if shape else []


def _positive(values, what: str) -> tuple:
    arr = np.asarray(values, dtype=float).ravel()
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        raise ValueError(f"{what} must be positive and finite, got {list(arr)}")
    return tuple(float(v) for v in arr)


def _part(spec: dict, name: str, color: int) -> Part:
    where = f"body {name!r}"
    offset = np.asarray(spec.get("offset", [0.0, 0.0, 0.0]), dtype=float)
    if offset.shape != (3,) or not np.all(np.isfinite(offset)):
        raise ValueError(f"{where}: shape offset must be 3 finite numbers, got {spec.get('offset')}")
    if "color" in spec:
        color = color_int(spec["color"], where)
    kind = spec.get("kind")
    if kind == "box":
        size = _positive(spec.get("size", []), f"{where}: box size")
        if len(size) != 3:
            raise ValueError(f"{where}: box size must have 3 entries, got {spec.get('size')}")
        return Part("box", size, kin.homogeneous(offset, np.eye(3)), color)
    if kind == "cylinder":
        radius, length = _positive([spec.get("radius", 0), spec.get("length", 0)], f"{where}: cylinder radius, length")
        axis = np.asarray(spec.get("axis", [0, 0, 1]), dtype=float)
        if axis.shape != (3,) or not np.linalg.norm(axis) > 0:
            raise ValueError(f"{where}: cylinder axis must be a non-zero 3-vector, got {spec.get('axis')}")
        return Part("cylinder", (radius, length), kin.homogeneous(offset, kin.align_y(axis)), color)
    raise ValueError(f"{where}: unknown shape kind {kind!r} (use 'box' or 'cylinder')")


def _default_colors(info, parents: list[int]) -> dict[str, int]:
    has_child = {p for p in parents if p >= 0}
    out, leaf = {}, 0
    for i, b in enumerate(info.bodies):
        if parents[i] < 0:
            out[b["name"]] = color_int(ROOT_COLOR, "palette")
        elif i in has_child:
            out[b["name"]] = color_int(INNER_COLOR, "palette")
        else:
            out[b["name"]] = color_int(LEAF_COLORS[leaf % len(LEAF_COLORS)], "palette")
            leaf += 1
    return out


def default_traced(info) -> list[str]:
    """Main-rotor blades: the bodies called ``blade<k>``; for a flexible blade (no shape of its
    own, :mod:`mbs.flexible`) its outermost section with a shape, whose tip is the blade's."""
    out = []
    for b in info.bodies:
        if re.fullmatch(r"blade\d+", b["name"]):
            sections = [c["name"] for c in info.bodies if c["parent"] == b["name"] and c["joint"] == "Section"
                        and c.get("shape")]
            out.append(sections[-1] if not b.get("shape") and sections else b["name"])
    return out


def build_scene(info, flat: bool = False, trace=True, follow: str | None | bool = True) -> Scene:
    """Scene of a model described by ``info`` (:class:`mbs.backends.info.ModelInfo`).

    trace: True (main-rotor blades ``blade<k>``), False, or a list of body names whose tips
    are traced. follow: True (the first free root body, if any), False/None, or a body
    name: the world is shifted so that this body's origin stays at the meshcat origin.
    """
    from viewer.motion import parents_of

    parents = parents_of(info)
    names = info.body_names
    for n in names:
        if n in RESERVED or "/" in n or not n:
            raise ValueError(f"body name {n!r} cannot be shown (reserved names: {RESERVED}; no '/')")
    paths: dict[str, str] = {}
    for i, n in enumerate(names):
        paths[n] = (WORLD if parents[i] < 0 else paths[names[parents[i]]]) + "/" + n
    defaults = _default_colors(info, parents)
    parts = {b["name"]: [_part(s, b["name"], defaults[b["name"]]) for s in _parts_of(b)] for b in info.bodies}
    _distinct_blades(parts)
    colors = {n: (parts[n][0].color if parts[n] else defaults[n]) for n in names}
    traced = _traced(info, parents, parts, trace)
    frames = {b: _trace_frame(names, parents, b, info) for b in traced}
    return Scene(info, paths, parts, colors, flat, traced, frames, _follow(info, parents, follow),
                 _extent(info, parents, parts))


def _distinct_blades(parts: dict[str, list[Part]]) -> None:
    """Give the main-rotor blades distinct colours when the model repeats its few (a five-bladed
    rotor's fifth blade had the first one's): every part of blade ``k`` (its segments and
    sections too) that has another blade's colour takes ``LEAF_COLORS[k - 1]``."""
    first: dict[int, int] = {}
    for name, body_parts in parts.items():
        m = BLADE.fullmatch(name)
        if m and body_parts and name == f"blade{m.group(1)}":
            first[int(m.group(1))] = body_parts[0].color
    if len(set(first.values())) == len(first):
        return
    for name, body_parts in parts.items():
        m = BLADE.fullmatch(name)
        if m and int(m.group(1)) in first:
            k = int(m.group(1))
            new = color_int(LEAF_COLORS[(k - 1) % len(LEAF_COLORS)], "palette")
            parts[name] = [replace(p, color=new) if p.color == first[k] else p for p in body_parts]


def _traced(info, parents, parts, trace) -> list[str]:
    names = info.body_names
    chosen = default_traced(info) if trace is True else list(trace or [])
    for b in chosen:
        if b not in names:
            raise ValueError(f"cannot trace unknown body {b!r}; bodies: {names}")
        if not parts[b]:
            raise ValueError(f"cannot trace body {b!r}: it has no shape, so no tip")
    return chosen


def _trace_frame(names, parents, blade: str, info=None) -> str:
    i = names.index(blade)
    if info is not None and info.bodies[i]["joint"] == "Section":  # a flexible blade's section: its blade's hub
        i = parents[i]
    hub = parents[i]
    if hub < 0 or parents[hub] < 0:
        return "world"
    return names[parents[hub]]


def _follow(info, parents, follow) -> str | None:
    if follow is True:
        roots = [b["name"] for i, b in enumerate(info.bodies) if parents[i] < 0 and b["joint"] == "FreeJoint"]
        return roots[0] if roots else None
    if follow in (False, None):
        return None
    if follow not in info.body_names:
        raise ValueError(f"cannot follow unknown body {follow!r}; bodies: {info.body_names}")
    return follow


def _extent(info, parents, parts) -> float:
    """A rough radius (m) of the model around the root: joint offsets plus part reach."""
    reach = np.zeros(len(parents))
    best = 0.5
    for i, b in enumerate(info.bodies):
        base = (reach[parents[i]] if parents[i] >= 0 else 0.0) + float(np.linalg.norm(b.get("at", [0, 0, 0])))
        reach[i] = base
        for part in parts[b["name"]]:
            size = np.asarray(part.dims if part.kind == "box" else (2 * part.dims[0], part.dims[1], 2 * part.dims[0]))
            best = max(best, base + float(np.linalg.norm(part.transform[:3, 3]) + np.linalg.norm(size) / 2))
    return best


# -- meshcat commands ---------------------------------------------------------------------

def commands(scene: Scene, local0: np.ndarray, world0: np.ndarray, traces: dict[str, np.ndarray] | None = None) -> list:
    """meshcat command objects drawing ``scene`` at its first key: ``local0`` (nb, 4, 4)
    node transforms, ``world0`` (4, 4) the world node; ``traces[blade]`` (n, 3) tip points
    in the trace frame (m)."""
    mc = meshcat()
    cmd, g = mc.commands, mc.geometry
    Path = mc.path.Path
    out = [cmd.SetTransform(kin.rotation_x(np.pi), _path(Path, ROOT)),
           cmd.SetTransform(np.asarray(world0, dtype=float), _path(Path, WORLD))]
    for i, name in enumerate(scene.body_names):
        out.append(cmd.SetTransform(np.asarray(local0[i], dtype=float), _path(Path, scene.paths[name])))
        for k, part in enumerate(scene.parts[name]):
            p = f"{scene.paths[name]}/shape/{k}"
            geometry = g.Box(list(part.dims)) if part.kind == "box" else g.Cylinder(part.dims[1], part.dims[0])
            out.append(cmd.SetObject(geometry, _material(g, part.color, scene.flat), _path(Path, p)))
            out.append(cmd.SetTransform(part.transform, _path(Path, p)))
    for blade, points in (traces or {}).items():
        p = f"{scene.frame_path(scene.trace_frames[blade])}/tip_path/{blade}"
        line = g.Line(g.PointsGeometry(np.asarray(points, dtype=np.float32).T),
                      g.LineBasicMaterial(color=tint(scene.colors[blade])))
        out.append(cmd.SetObject(line, path=_path(Path, p)))
    return out + _view(scene, cmd, Path, max(scene.extent, posed_extent(scene, local0)))


def posed_extent(scene: Scene, local0: np.ndarray) -> float:
    """The model's radius (m) about the root at the pose ``local0`` (nb, 4, 4): every part's
    reach from the origin of the root body, through the actual joint transforms (a flexible blade's sections
    sit along the span through their joints' motion, not their ``at`` offsets, which
    :attr:`Scene.extent` reads)."""
    names, world = scene.body_names, {}
    best = 0.5
    for i, name in enumerate(names):
        parent = scene.paths[name].rsplit("/", 1)[0]
        above = next((world[n] for n in names[:i] if scene.paths[n] == parent), np.eye(4))
        world[name] = above @ np.asarray(local0[i], dtype=float)
        if parent == WORLD:  # about the root's own origin, wherever it has flown
            world[name][:3, 3] = 0.0
        for part in scene.parts[name]:
            size = np.asarray(part.dims if part.kind == "box" else (2 * part.dims[0], part.dims[1], 2 * part.dims[0]))
            centre = (world[name] @ part.transform)[:3, 3]
            best = max(best, float(np.linalg.norm(centre) + np.linalg.norm(size) / 2))
    return best


def _material(g, color: int, flat: bool):
    return g.MeshBasicMaterial(color=color) if flat else g.MeshLambertMaterial(color=color)


def _path(Path, text: str):
    return Path(tuple(text.strip("/").split("/")))


def _view(scene: Scene, cmd, Path, extent: float | None = None) -> list:
    """Camera above and behind-left of the model, ``extent`` (m, default the scene's) away in
    proportion; in flat mode no background, grid, axes."""
    d = 1.35 * (extent or scene.extent)
    world = np.array([-0.55, 0.65, 0.85]) * d  # meshcat frame (z up): from the left rear, above
    out = [cmd.SetProperty("position", [float(world[0]), float(world[2]), float(-world[1])],
                           _path(Path, "/Cameras/default/rotated/<object>"))]
    if scene.flat:
        out += [cmd.SetProperty("visible", False, _path(Path, f"/{n}")) for n in ("Background", "Grid", "Axes")]
    return out
