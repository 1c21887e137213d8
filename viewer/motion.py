"""Body poses along a trajectory, resampled so that no joint turns too far between keys.

A :class:`Recording` is what the viewer animates: a runnable model (``system``), the
recorded times ``t`` (n,) in s, states ``x`` (n, nx) and parameters ``p``. It comes from a
finished :class:`mbs.simulate.Simulation` or from a results folder (``results.csv`` plus
``run.json``). :func:`motion` picks the keyframes and evaluates the core's body poses there.

Keyframe rule: between consecutive keys every body turns by less than ``max_step`` (rad)
relative to its parent, so that three.js, which interpolates rotations the short way
round, shows the true sense of rotation. The turn is estimated from the poses and from the
relative angular velocity (a joint may have turned more than a full circle between two
recorded rows); intervals that turn too far are split, with states interpolated linearly
in time (quaternions renormalised by the model's ``project``).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from viewer import kinematics as kin

DEFAULT_MAX_STEP = np.radians(60.0)
MAX_KEYS = 200_000
"""More keyframes than this: the motion turns too fast between recorded rows to be shown (a diverged run)."""


@dataclass
class Recording:
    """A trajectory of one model: ``t`` (n,) s, ``x`` (n, nx) states, ``p`` (np,) parameters;
    ``P`` (n, np), if given, holds parameters that change during the run (e.g. pitch inputs
    recorded from an FMU), each row held until the next."""

    system: object
    t: np.ndarray
    x: np.ndarray
    p: np.ndarray
    name: str = ""
    revolution: float | None = None
    P: np.ndarray | None = None
    plots: dict | None = None  # the scene's hinge-angle panels (title -> names)
    scene: object = None  # the :class:`mbs.scenes.Scene` it is a run of, when known

    @property
    def info(self):
        return self.system.info

    def state_at(self, t: float) -> np.ndarray:
        """State at time ``t`` (s), linear between recorded rows, quaternions renormalised."""
        tol = 1e-12 * max(1.0, abs(t))
        if not self.t[0] - tol <= t <= self.t[-1] + tol:
            raise ValueError(f"time {t} s is outside the recording [{self.t[0]}, {self.t[-1]}] s")
        i = int(np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, len(self.t) - 2)) if len(self.t) > 1 else 0
        if len(self.t) == 1 or t == self.t[i]:
            return self.x[i].copy()
        w = (t - self.t[i]) / (self.t[i + 1] - self.t[i])
        return self.system.project((1 - w) * self.x[i] + w * self.x[i + 1])

    def params_at(self, t: float) -> np.ndarray:
        """Parameters in force at time ``t`` (s)."""
        if self.P is None:
            return self.p
        return self.P[int(np.clip(np.searchsorted(self.t, t + 1e-12 * max(1.0, abs(t)), side="right") - 1, 0, len(self.t) - 1))]


def from_simulation(sim) -> Recording:
    """Recording of a :class:`mbs.simulate.Simulation` (float32 runs are evaluated in float64)."""
    system = sim.system
    if system.dtype != np.float64:
        system = sim.scene.system("vm")
    return _checked(Recording(system, sim.traj.t, sim.traj.x, sim.params, sim.scene.name,
                              sim.scene.revolution(system, sim.params), plots=sim.scene.plots, scene=sim.scene))


def from_results(path: str | Path, backend: str = "vm", aircraft=None) -> Recording:
    """Recording of a results folder or ``results.csv`` written by :func:`mbs.simulate.write`.

    Everything that can be wrong with the files is found before the model is built (one-line
    ValueError): a file that is no run's table, a run that stopped (diverged), a non-finite
    value. The scene recorded in ``run.json`` (its aircraft and aerodynamics switches too:
    :func:`mbs.simulate.scene_of_run`) is rebuilt with ``backend`` ("vm" or "compiled"); its
    parameters are taken from ``run.json``, or row by row from columns of the same name
    (inputs that change during the run). ``aircraft``: the run's aircraft file where it is now,
    when it has moved (:func:`mbs.simulate.scene_of_run`).
    """
    from mbs.results import read_results
    from mbs.simulate import scene_of_run

    cols, meta = read_results(Path(path))
    where = Path(path) / "run.json" if Path(path).is_dir() else Path(path).parent / "run.json"
    _check_run(path, cols, meta)
    scene = scene_of_run(meta, str(where), aircraft)
    system = scene.system(backend)
    names = system.info.state_names
    missing = [n for n in ["time", *names] if n not in cols]
    if missing:
        raise ValueError(f"{path}: results of scene {meta['scene']!r} lack the columns {missing}")
    known = system.info.param_names
    p = system.params({k: v for k, v in (meta.get("parameters") or {}).items() if k in known})
    varying = [n for n in known if n in cols and np.ptp(cols[n]) > 1e-12 * max(1.0, np.abs(cols[n]).max())]
    P = None
    if varying:
        P = np.array([system.params(p, **{n: cols[n][i] for n in varying}) for i in range(len(cols["time"]))])
    x = np.column_stack([cols[n] for n in names])
    return _checked(Recording(system, cols["time"], x, p, scene.name, scene.revolution(system, p), P, scene.plots,
                              scene))


def _check_run(path, cols: dict, meta: dict) -> None:
    """Refuse, before any work, a run that stopped before its end and a non-finite value."""
    if "scene" not in meta:
        raise ValueError(f"no run.json with a scene name next to {path}: cannot tell which model to show")
    if meta.get("result", "successful") != "successful":
        raise ValueError(f"{path}: the run stopped before its end ({meta.get('message', meta['result'])}); its last "
                         "rows are no motion to show: run it again with a smaller step (--steps-per-rev)")
    for name, values in cols.items():
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            t = cols["time"][bad[0]]
            raise ValueError(f"{path}: column {name!r} is {values[bad[0]]} at t = {t:.6g} s (the run diverged?); "
                             "nothing after that can be shown")
    t = cols["time"]
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        raise ValueError(f"{path}: time does not increase at t = {t[back[0] + 1]:.6g} s (line {back[0] + 3})")


def as_recording(source, backend: str = "vm") -> Recording:
    """A :class:`Recording` from a Recording, a Simulation or a results path."""
    if isinstance(source, Recording):
        return source
    if isinstance(source, (str, Path)):
        return from_results(source, backend)
    if hasattr(source, "traj") and hasattr(source, "scene"):
        return from_simulation(source)
    raise TypeError(f"cannot show {type(source).__name__}: pass a Simulation, a results path or a Recording")


def _checked(rec: Recording) -> Recording:
    rec.t, rec.x = np.asarray(rec.t, dtype=float), np.asarray(rec.x, dtype=float)
    if rec.t.ndim != 1 or len(rec.t) == 0 or rec.x.shape != (len(rec.t), rec.info.nx):
        raise ValueError(f"recording shapes t {rec.t.shape}, x {rec.x.shape} do not match "
                         f"(n,) and (n, {rec.info.nx})")
    if not np.all(np.isfinite(rec.x)):
        i, j = np.argwhere(~np.isfinite(rec.x))[0]
        raise ValueError(f"state {rec.info.state_names[j]!r} is {rec.x[i, j]} at t = {rec.t[i]} s")
    if np.any(np.diff(rec.t) <= 0):
        raise ValueError("recorded times must increase strictly")
    if rec.P is not None and rec.P.shape != (len(rec.t), len(rec.info.param_names)):
        raise ValueError(f"per-row parameters have shape {rec.P.shape}, expected ({len(rec.t)}, {len(rec.info.param_names)})")
    return rec


@dataclass
class Motion:
    """Keyframes: times ``t`` (k,) s; per body origins (k, nb, 3) m and rotations
    body->world (k, nb, 3, 3) in the world frame (NED); ``local`` (k, nb, 4, 4) each body
    relative to its parent (the world for root bodies); ``parents`` (nb,) with -1 = world."""

    recording: Recording
    t: np.ndarray
    origins: np.ndarray
    rotations: np.ndarray
    local: np.ndarray
    parents: list[int]

    @property
    def body_names(self) -> list[str]:
        return self.recording.info.body_names

    def max_key_angle(self) -> np.ndarray:
        """Largest turn (rad) of each body relative to its parent between two keys, (nb,)."""
        if len(self.t) < 2:
            return np.zeros(len(self.parents))
        return kin.key_angles(self.local).max(axis=0)


def parents_of(info) -> list[int]:
    """Parent index of every body (-1: the world); parents precede children."""
    names = info.body_names
    out = []
    for b in info.bodies:
        out.append(-1 if b["parent"] == "world" else names.index(b["parent"]))
    return out


def key_times(rec: Recording, revs: float | None = 1.0, start: float | None = None, every: int = 1) -> np.ndarray:
    """The recorded times shown: ``revs`` main-rotor revolutions (None: all) from ``start``
    (s; default: the last ``revs`` revolutions), every ``every``-th row plus the last."""
    if every < 1:
        raise ValueError(f"every = {every} must be >= 1")
    t0, t1 = rec.t[0], rec.t[-1]
    if revs is not None:
        if not (np.isfinite(revs) and revs > 0):
            raise ValueError(f"revs = {revs} must be positive")
        span = revs * (rec.revolution or (t1 - t0))
        start = max(t0, t1 - span) if start is None else start
        t1 = min(t1, start + span)
    start = t0 if start is None else start
    if not t0 - 1e-12 <= start <= rec.t[-1]:
        raise ValueError(f"--start {start:g} s is outside the run, {t0:g} to {rec.t[-1]:.6g} s; give a time within it")
    rows = np.flatnonzero((rec.t >= start - 1e-12) & (rec.t <= t1 + 1e-12))
    if len(rows) < 2 and len(rec.t) > 1 and revs is not None:
        need = 2 * float(np.max(np.diff(rec.t))) / (rec.revolution or (rec.t[-1] - t0))
        raise ValueError(f"--revs {revs:g} shows less than one step between recorded rows ({np.max(np.diff(rec.t)):.3g} "
                         f"s apart); give --revs {need:.3g} or more, or 0 for the whole run")
    if len(rows) == 0:
        return np.array([start])
    keep = rows[::every]
    if keep[-1] != rows[-1]:
        keep = np.r_[keep, rows[-1]]
    return rec.t[keep]


def motion(source, revs: float | None = 1.0, start: float | None = None, every: int = 1,
           max_step: float = DEFAULT_MAX_STEP, backend: str = "vm") -> Motion:
    """Keyframes of ``source`` (Simulation, results path or Recording); see :func:`key_times`.

    Intervals in which any body would turn by ``max_step`` (rad, < pi/2) or more relative
    to its parent are split until none does.
    """
    if not 0 < max_step < np.pi / 2:
        raise ValueError(f"max_step = {max_step} rad must lie in (0, pi/2)")
    rec = as_recording(source, backend)
    t = key_times(rec, revs, start, every)
    parents = parents_of(rec.info)
    cache: dict[float, tuple] = {}
    for _ in range(30):
        frames = [cache.setdefault(float(ti), _frame(rec, float(ti), parents)) for ti in t]
        local = np.array([f[2] for f in frames])
        steps = _turn_estimates(t, local, np.array([f[3] for f in frames]))
        if not np.any(steps >= max_step):
            origins, rotations = np.array([f[0] for f in frames]), np.array([f[1] for f in frames])
            return Motion(rec, t, origins, rotations, local, parents)
        parts = np.ceil(np.minimum(steps, 1e12) / (0.95 * max_step))
        if parts.sum() > MAX_KEYS:
            i = int(np.argmax(parts))
            raise ValueError(f"between t = {t[i]:.6g} and {t[i + 1]:.6g} s a joint turns by {steps[i]:.3g} rad: too "
                             "fast to show between recorded rows (did the run diverge? check it with heli simulate, or "
                             "record every step)")
        t = _split(t, parts.astype(int))
    raise RuntimeError("could not resample the trajectory below the keyframe angle limit")


def _frame(rec: Recording, t: float, parents: list[int]):
    """Poses, local transforms and relative angular speeds (rad/s) of all bodies at ``t``."""
    x = rec.state_at(t)
    p = rec.params_at(t)
    origins, rotations = rec.system.poses(x, t, p)
    local = kin.relative(kin.homogeneous(origins, rotations), parents)
    V = rec.system.kinematics(x, t, p)[0].reshape(-1, 6)
    omega = V[:, 3:]  # body components
    rel = omega.copy()
    for i, p in enumerate(parents):
        if p >= 0:
            rel[i] -= rotations[i].T @ rotations[p] @ omega[p]
    return origins, rotations, local, np.linalg.norm(rel, axis=1)


def _turn_estimates(t: np.ndarray, local: np.ndarray, speed: np.ndarray) -> np.ndarray:
    """Per interval the largest turn (rad) of any body: the pose angle or speed * dt."""
    if len(t) < 2:
        return np.zeros(0)
    dt = np.diff(t)[:, None]
    rate = np.maximum(speed[:-1], speed[1:]) * dt
    return np.max(np.maximum(kin.key_angles(local), rate), axis=1)


def _split(t: np.ndarray, parts: np.ndarray) -> np.ndarray:
    """``t`` with interval i divided into ``parts[i]`` equal sub-intervals."""
    pieces = [np.linspace(a, b, max(n, 1), endpoint=False) for a, b, n in zip(t[:-1], t[1:], parts)]
    return np.concatenate(pieces + [t[-1:]])
