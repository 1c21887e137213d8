"""Fan plot: Floquet frequency and damping of every mode against a swept parameter (rotor speed).

Each point of the sweep is a full Floquet analysis (:mod:`mbs.analysis.floquet`): the periodic
solution at that parameter value, then the monodromy over the period from forward-mode AD
through the generated fixed-step driver. For a rotor without tail rotor the period is one
revolution, also for an isotropic rotor whose equations are time-invariant in multi-blade
coordinates (ground resonance): the monodromy is always taken over the whole revolution, never
over ``1/N`` revolution with the blades relabelled. Frequencies are read in the fixed frame
(multi-blade coordinates, :mod:`mbs.analysis.multiblade`) unless asked for in the rotating one;
the multipliers and damping do not depend on that choice.

A point that fails (no periodic solution, a parameter outside its range) is kept with its
status and the sweep goes on. The unstable bands (largest multiplier modulus above 1 + 1e-6) are
located between sweep points and their edges refined by Brent's method on that modulus, each
evaluation again a Floquet analysis.
"""
from __future__ import annotations

import csv
import re
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mbs import atomic
from mbs.analysis.floquet import Floquet, analyse, coordinate_functions
from mbs.analysis.period import periodic_scene
from mbs.analysis.shooting import TrimLayout

UNSTABLE = 1e-6  # a multiplier modulus above 1 + UNSTABLE is unstable: neutral modes of undamped
# models reach 1 + 2e-9 by truncation and round-off; the threshold moves band edges by a few 1e-6
CSV_COLUMNS = ("parameter", "value", "omega_rad_s", "mode", "real_per_s", "imag_rad_s", "frequency_hz", "per_rev",
               "damping_ratio", "multiplier_modulus", "status")


class WithParameters:
    """A :class:`mbs.System` whose default parameter values are replaced by ``values``
    (name -> value); everything else is the wrapped system's."""

    def __init__(self, system, **values: float):
        self._system, self._values = system, values

    def params(self, p=None, **named: float) -> np.ndarray:
        if p is None or isinstance(p, dict):
            return self._system.params({**self._values, **(p or {})}, **named)
        return self._system.params(p, **named)

    def __getattr__(self, name: str):
        return getattr(self._system, name)


@dataclass
class SweepPoint:
    """One parameter value: its Floquet analysis, or ``None`` with ``status`` saying why not;
    ``names``: fixed-frame mode names (one per mode) when read in multi-blade coordinates."""

    value: float
    status: str
    floquet: Floquet | None = None
    names: list[str] = field(default_factory=list)
    wall_s: float = 0.0

    @property
    def growth(self) -> float:
        """Largest ``Re λ`` (1/s), NaN when the point failed."""
        return max(m.exponent.real for m in self.floquet.modes) if self.floquet else float("nan")

    def margin(self, tol: float = UNSTABLE) -> float:
        """Largest multiplier modulus minus ``1 + tol`` (> 0: unstable), NaN when the point failed."""
        if not self.floquet:
            return float("nan")
        return max(abs(m.multiplier) for m in self.floquet.modes) - 1 - tol

    @property
    def unstable(self) -> bool:
        return bool(self.margin() > 0)


def parse_sweep(spec: str) -> tuple[str, np.ndarray]:
    """``"omega=LO:HI:N"`` -> ``("omega", N values from LO to HI)``."""
    try:
        name, rng = spec.split("=", 1)
        lo, hi, n = rng.split(":")
        values = np.linspace(float(lo), float(hi), int(n))
    except ValueError:
        raise ValueError(f"sweep {spec!r}: expected NAME=LO:HI:N, e.g. omega=20:60:30") from None
    if len(values) < 1 or not np.all(np.isfinite(values)):
        raise ValueError(f"sweep {spec!r}: need N >= 1 finite values")
    if len(values) == 1 and float(lo) != float(hi):
        raise ValueError(f"sweep {spec!r}: N = 1 gives {lo} only, never {hi}; give N >= 2")
    return name.strip(), values


def parse_settings(items: list[str] | None) -> dict[str, float]:
    """``["lag_damping=50", ...]`` -> ``{"lag_damping": 50.0}``."""
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if "," in value and "=" in value:
            raise ValueError(f"setting {item!r}: one NAME=VALUE per --set; repeat --set for each name")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            unit = re.fullmatch(r"\s*[-+.\d]+(?:e[-+]?\d+)?\s*([a-zA-Z/°]+)\s*", value)
            hint = f" (without the unit {unit.group(1)!r}: values are in SI units, m/s, rad, rad/s)" if unit else ""
            raise ValueError(f"setting {item!r}: expected NAME=VALUE with a number{hint}") from None
        if not sep:
            raise ValueError(f"setting {item!r}: expected NAME=VALUE")
    return out


class FanPlotAnalysis:
    """Floquet analyses of one scene at changing run-time parameters, on one system and stepper.

    scene: a scene name or a :class:`mbs.scenes.Scene`; settings: fixed parameter values
    (name -> value); fixed_frame: read frequencies in multi-blade coordinates; method,
    steps_per_rev, backend: as :func:`mbs.analysis.floquet.floquet`.
    """

    def __init__(self, scene, settings: dict[str, float] | None = None, method: str = "rk4",
                 steps_per_rev: int | None = None, backend: str = "compiled", fixed_frame: bool = True):
        from mbs import scenes
        from mbs.analysis.floquet import check_scene
        from mbs.analysis.monodromy import TangentStepper

        self.scene = periodic_scene(scenes.get(scene) if isinstance(scene, str) else scene)
        check_scene(self.scene)
        self.system = self.scene.system(backend)
        self.settings = dict(settings or {})
        self.system.params(self.settings)  # unknown names, values outside their ranges
        self.stepper = TangentStepper(self.scene.model(), method, backend)
        self.method, self.steps_per_rev, self.fixed_frame = method, steps_per_rev, fixed_frame
        self.names = coordinate_functions(TrimLayout.of(self.system.info), self.system.info.nx)[0]

    def at(self, **values: float) -> SweepPoint:
        """The Floquet analysis with ``values`` (name -> value) on top of the settings."""
        from mbs.analysis.trim import periodic_solution

        start, value = time.perf_counter(), next(iter(values.values()), float("nan"))
        try:
            system = WithParameters(self.system, **{**self.settings, **values})
            sol = periodic_solution(self.scene, None, method=self.method, steps_per_rev=self.steps_per_rev,
                                    system=system, stepper=self.stepper)
            if not sol.converged:
                return SweepPoint(value, f"no periodic solution: {sol.reason}", wall_s=time.perf_counter() - start)
            res = analyse(sol, system, self.stepper, frame=self._frame(sol.period.omega))
        except (ValueError, RuntimeError, np.linalg.LinAlgError) as exc:
            return SweepPoint(value, f"failed: {exc}", wall_s=time.perf_counter() - start)
        return SweepPoint(value, "ok", res, self._names(res), time.perf_counter() - start)

    def _frame(self, omega: float):
        from mbs.analysis.multiblade import transform

        return transform(self.names, omega) if self.fixed_frame else None

    def _names(self, res: Floquet) -> list[str]:
        from mbs.analysis.floquet import fixed_frame_names

        return fixed_frame_names(res) if self.fixed_frame else [m.name for m in res.modes]


def sweep(analysis: FanPlotAnalysis, parameter: str, values, progress=None) -> list[SweepPoint]:
    """One :class:`SweepPoint` per value of ``parameter``; failures are kept as points."""
    known = analysis.system.info.param_names
    if parameter not in known:
        raise ValueError(f"cannot sweep {parameter!r}: not a run-time parameter of {analysis.scene.name!r}; "
                         f"known: {', '.join(known)}")
    points = []
    for k, v in enumerate(values):
        points.append(analysis.at(**{parameter: float(v)}))
        if progress:
            progress(k + 1, len(values))
    return points


def unstable_bands(points: list[SweepPoint], analyse=None, tol: float = UNSTABLE,
                   xtol: float = 1e-6) -> list[tuple[float, float]]:
    """Parameter intervals ``(low, high)`` where the largest multiplier modulus exceeds
    ``1 + tol``. An edge between two points is refined by Brent's method on the margin of
    ``analyse(value) ->`` :class:`SweepPoint` when given (to ``xtol`` relative), otherwise
    linearly interpolated; an unstable end of the sweep is its own edge."""
    ok = [p for p in points if p.floquet]
    unstable = [p.margin(tol) > 0 for p in ok]
    bands, low = [], ok[0].value if ok and unstable[0] else None
    for k in range(len(ok) - 1):
        if unstable[k] != unstable[k + 1]:
            edge = _edge(ok[k], ok[k + 1], analyse, tol, xtol)
            if unstable[k + 1]:
                low = edge
            else:
                bands.append((low, edge))
    if low is not None and unstable[-1]:
        bands.append((low, ok[-1].value))
    return bands


def _edge(a: SweepPoint, b: SweepPoint, analyse, tol: float, xtol: float) -> float:
    """Where the stability margin crosses zero between the points ``a`` and ``b``."""
    if analyse is not None:
        from scipy.optimize import brentq

        margin = lambda v: _finite(analyse(v).margin(tol))  # noqa: E731
        try:
            return float(brentq(margin, a.value, b.value, xtol=xtol * max(abs(a.value), 1.0)))
        except ValueError:  # a failed evaluation: interpolate instead
            pass
    ma, mb = a.margin(tol), b.margin(tol)
    return float(a.value + (b.value - a.value) * ma / (ma - mb))


def _finite(x: float) -> float:
    if not np.isfinite(x):
        raise ValueError("no Floquet result")
    return x


def rows(points: list[SweepPoint], parameter: str) -> list[dict]:
    """CSV rows: one per mode of each point; a failed point is one row with its status."""
    out = []
    for p in points:
        if not p.floquet:
            out.append({"parameter": parameter, "value": p.value, "status": p.status})
        for m, name in zip(p.floquet.modes if p.floquet else [], p.names):
            out.append({"parameter": parameter, "value": p.value, **_mode_row(m, name)})
    return out


def _mode_row(m, name: str) -> dict:
    """The CSV fields of one mode: rad/s, 1/s, Hz, per rev."""
    unstable = abs(m.multiplier) > 1 + UNSTABLE
    return {"omega_rad_s": m.omega, "mode": name, "real_per_s": m.exponent.real, "imag_rad_s": m.exponent.imag,
            "frequency_hz": m.frequency_hz, "per_rev": m.per_rev,
            "damping_ratio": "" if np.isnan(m.damping_ratio) else m.damping_ratio,
            "multiplier_modulus": abs(m.multiplier), "status": "unstable" if unstable else "ok"}


def write_csv(table: list[dict], path: Path) -> Path:
    """Write the rows of :func:`rows` (columns :data:`CSV_COLUMNS`)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic.replacing(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, CSV_COLUMNS, restval="")
        w.writeheader()
        w.writerows(table)
    return path


def figure(points: list[SweepPoint], parameter: str, bands: list[tuple[float, float]], path: Path,
           title: str = "") -> Path:
    """The fan plot: fixed-frame (or rotating-frame) frequency in Hz and ``Re λ`` in 1/s of every
    mode against the swept parameter, one colour per mode name, unstable points ringed in red,
    unstable bands shaded, the legend to the right of the panels."""
    from mbs.plots import _pyplot

    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9.5, 6.6), sharex=True)
    _scatter(top, bottom, points)
    _references(top, bottom, points, parameter, bands)
    top.set_ylabel("frequency (Hz)")
    bottom.set_ylabel("Re λ (1/s), > 0 unstable")
    bottom.set_xlabel("rotor speed Ω (rad/s)" if parameter == "omega" else parameter)
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    handles, labels = top.get_legend_handles_labels()
    fig.legend(handles, labels, loc="center left", bbox_to_anchor=(0.75, 0.5), fontsize=8, frameon=False)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0, 0, 0.75, 0.96))
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
    return path


def _scatter(top, bottom, points: list[SweepPoint]) -> None:
    """One colour per mode name in both panels; unstable points ringed."""
    by_name: dict[str, list[tuple[float, float, float, bool]]] = {}
    for p in points:
        for m, name in zip(p.floquet.modes if p.floquet else [], p.names):
            by_name.setdefault(name, []).append((p.value, m.frequency_hz, m.exponent.real,
                                                 abs(m.multiplier) > 1 + UNSTABLE))
    colours = _colours(len(by_name))
    for (name, pts), c in zip(sorted(by_name.items()), colours):
        x, f, re, bad = (np.array(v) for v in zip(*pts))
        top.scatter(x, f, s=14, color=c, label=name)
        bottom.scatter(x, re, s=14, color=c)
        for ax, y in ((top, f), (bottom, re)):
            ax.scatter(x[bad], y[bad], s=70, facecolors="none", edgecolors="red", linewidths=1.2)
    failed = [p.value for p in points if not p.floquet]
    if failed:
        bottom.scatter(failed, np.zeros(len(failed)), marker="x", color="k", label="no result")


def _colours(n: int) -> list:
    from matplotlib import colormaps

    cmap = colormaps["tab10" if n <= 10 else "tab20"]
    return [cmap(i % cmap.N) for i in range(n)]


def _references(top, bottom, points: list[SweepPoint], parameter: str, bands) -> None:
    """Zero growth line, the 1/rev line (rotor-speed sweeps), the unstable bands shaded."""
    bottom.axhline(0.0, color="k", lw=0.8)
    x = np.array([p.value for p in points])
    if parameter == "omega":
        top.plot(x, x / (2 * np.pi), color="0.6", lw=0.8, ls="--", label="1/rev")
    for k, (lo, hi) in enumerate(bands):
        for ax in (top, bottom):
            ax.axvspan(lo, hi, color="red", alpha=0.08, label="unstable band" if k == 0 and ax is top else None)
    top.scatter([], [], s=70, facecolors="none", edgecolors="red", label="unstable mode")
