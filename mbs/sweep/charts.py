"""The charts of a sweep, drawn from its results table (PNG files in the output folder).

trim: controls and attitude (deg) and the rotors' and the engine power (kW) against the first axis (speed), each
alone and the three side by side (``trim_summary.png``); simulate: the envelope
(min to max, and the mean) of each plotted coordinate and output against the first axis;
floquet: frequency (Hz) and ``Re λ`` (1/s) of every mode against the first axis (rotor speed).
Other axes give one line per combination of their values. Failed points are marked with a
cross on the axis.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pyarrow as pa

from mbs.plots import save_figure

CONTROLS = ("collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective")


def write(kind: str, result: pa.Table, names: list[str], out: Path) -> list[Path]:
    """Draw the charts of a ``kind`` sweep into ``out``; returns their paths. Every title names
    the scene and its aircraft (from the sweep's settings stored with ``result``)."""
    from mbs.sweep.table import settings_of

    rows = result.to_pylist()
    if not rows:
        return []
    settings = settings_of(result)
    scene = _scene(settings)
    what = settings.get("scene", "sweep") + (f" of the {scene.aircraft.name}" if scene and scene.aircraft else "")
    if kind == "simulate":
        return _simulate(rows, names, Path(out), what, _units(scene))
    return {"trim": _trim, "floquet": _floquet}[kind](rows, names, Path(out), what)


def _scene(settings: dict):
    """The sweep's scene of its aircraft, or None when the settings do not say."""
    from mbs.sweep.models import scene_of

    try:
        return scene_of(settings["scene"], settings.get("options", {}))
    except (KeyError, ValueError, OSError):
        return None


def _units(scene) -> dict[str, str]:
    """The unit of every column of ``scene``'s runs (empty when unknown)."""
    from mbs.results import column_units

    return column_units(scene.model()) if scene is not None else {}


def _pyplot():
    from mbs.plots import _pyplot

    return _pyplot()


def _groups(rows: list[dict], names: list[str]) -> dict[str, list[dict]]:
    """Rows by the values of every axis but the first (label -> rows in order of the first)."""
    out: dict[str, list[dict]] = {}
    for r in rows:
        label = ", ".join(f"{n} = {r[n]:g}" for n in names[1:])
        out.setdefault(label, []).append(r)
    return out


def _series(rows: list[dict], x: str, y: str, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """``x`` and ``y`` (times ``scale``) of the rows with status ok."""
    ok = [r for r in rows if r["status"] == "ok" and r.get(y) is not None]
    return np.array([r[x] for r in ok], float), np.array([r[y] for r in ok], float) * scale


def _mark_failed(ax, rows: list[dict], x: str) -> None:
    bad = [r[x] for r in rows if r["status"] != "ok"]
    if bad:
        ax.scatter(bad, np.zeros(len(bad)), marker="x", color="red", zorder=5, label="no result")


def _line_chart(rows, names, panels: dict[str, list[str]], scale: float, ylabel: str, path: Path,
                title: str) -> Path:
    """One panel per entry of ``panels`` (title -> columns), each column a line per group."""
    plt = _pyplot()
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.6 * len(panels)), sharex=True, squeeze=False)
    for ax, (panel, cols) in zip(axes[:, 0], panels.items()):
        for label, group in _groups(rows, names).items():
            for c in cols:
                ax.plot(*_series(group, names[0], c, scale), marker="o", ms=3,
                        label=", ".join(s for s in (c if len(cols) > 1 else "", label) if s) or None)
        _mark_failed(ax, rows, names[0])
        ax.set_title(panel, fontsize=9)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[1]:
            ax.legend(fontsize=7)
    axes[-1, 0].set_xlabel(_axis_label(names[0]))
    return save_figure(fig, plt, path, title)


def _axis_label(name: str, units: dict | None = None) -> str:
    known = {"speed": "speed (m/s)", "omega": "rotor speed Ω (rad/s)", "climb_rate": "climb rate (m/s)"}
    unit = (units or {}).get(name, "")
    return known.get(name, f"{name} ({unit})" if unit and unit != "1" else name)


POWER = ("main_rotor.power", "tail_rotor.power", "engine.power")
"""Aerodynamic shaft power of each rotor and the power the engines deliver (:mod:`mbs.loads.engine`)."""


def _trim(rows: list[dict], names: list[str], out: Path, what: str = "trim") -> list[Path]:
    """Controls and attitude (deg) and the rotors' power (kW) against the first axis."""
    controls = [c for c in CONTROLS if any(c in r for r in rows)]
    power = [c for c in POWER if any(r.get(c) is not None for r in rows)]
    deg = 180 / np.pi
    paths = [_line_chart(rows, names, {c: [c] for c in controls}, deg, "deg", out / "trim_controls.png",
                         f"{what}, trimmed: controls"),
             _line_chart(rows, names, {"roll": ["roll"], "pitch": ["pitch"]}, deg, "deg", out / "trim_attitude.png",
                         f"{what}, trimmed: attitude")]
    if power:
        paths.append(_line_chart(rows, names, {"rotor and engine power": power}, 1e-3, "kW", out / "trim_power.png",
                                 f"{what}, trimmed: rotors' aerodynamic shaft power and engine power"))
    return paths + [_trim_summary(rows, names, controls, power, out / "trim_summary.png", what)]


def _trim_summary(rows, names, controls, power, path: Path, what: str = "trim") -> Path:
    """Collectives, cyclics, attitude (deg) and power (kW) side by side, one line per quantity
    (first group)."""
    plt = _pyplot()
    deg = 180 / np.pi
    panels = [("collective pitch (deg)", [c for c in controls if "collective" in c], deg),
              ("cyclic pitch (deg)", [c for c in controls if "cyclic" in c], deg),
              ("attitude (deg)", ["roll", "pitch"], deg), ("rotor and engine power (kW)", power, 1e-3)]
    panels = [p for p in panels if p[1]]
    fig, axes = plt.subplots(1, len(panels), figsize=(3.6 * len(panels), 3.6), squeeze=False)
    group = next(iter(_groups(rows, names).values()))
    for ax, (title, cols, scale) in zip(axes[0], panels):
        for c in cols:
            label = c.split(".")[0] if c.endswith(".power") else c
            ax.plot(*_series(group, names[0], c, scale), marker="o", ms=3, label=label.replace("_", " "))
        _mark_failed(ax, rows, names[0])
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(_axis_label(names[0]))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=2, frameon=False)
    return save_figure(fig, plt, path, f"{what}, trimmed over {_axis_label(names[0])}: controls, attitude and power")


PANELS_PER_PAGE, COLUMNS = 24, 4


def _simulate(rows: list[dict], names: list[str], out: Path, what: str = "simulation",
              units: dict | None = None) -> list[Path]:
    """The envelope of every recorded quantity against the first axis: small multiples, four
    across, each titled with the quantity and its unit (angles in degrees), at most
    :data:`PANELS_PER_PAGE` to a chart (``simulate_envelopes.png``, ``simulate_envelopes_2.png``
    ...)."""
    quantities = list(dict.fromkeys(k[:-4] for r in rows for k in r if k.endswith(".min")))
    pages = [quantities[i:i + PANELS_PER_PAGE] for i in range(0, len(quantities), PANELS_PER_PAGE)]
    return [_envelope_page(rows, names, page, units or {}, out / f"simulate_envelopes{'' if k == 0 else f'_{k + 1}'}.png",
                           f"{what}: min-max envelope and mean of each quantity over the run"
                           + (f" ({k + 1} of {len(pages)})" if len(pages) > 1 else ""))
            for k, page in enumerate(pages)]


def _envelope_page(rows, names, quantities: list[str], units: dict, path: Path, title: str) -> Path:
    plt = _pyplot()
    n_rows = -(-len(quantities) // COLUMNS)
    fig, axes = plt.subplots(n_rows, COLUMNS, figsize=(3.4 * COLUMNS, 2.3 * n_rows + 0.8), sharex=True, squeeze=False)
    for ax, q in zip(axes.flat, quantities):
        unit = units.get(q, "")
        scale, unit = (180 / np.pi, "deg") if unit == "rad" else (180 / np.pi, "deg/s") if unit == "rad/s" \
            else (1.0, unit)
        for label, group in _groups(rows, names).items():
            x, lo = _series(group, names[0], f"{q}.min", scale)
            hi, mean = _series(group, names[0], f"{q}.max", scale)[1], _series(group, names[0], f"{q}.mean", scale)[1]
            ax.fill_between(x, lo, hi, alpha=0.25)
            ax.plot(x, mean, marker="o", ms=2.5, lw=1.0, label=f"mean {label}".strip())
        _mark_failed(ax, rows, names[0])
        ax.set_title(f"{q}" + (f" ({unit})" if unit and unit != "1" else ""), fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    for k, ax in enumerate(axes.flat):
        if k >= len(quantities):
            ax.set_visible(False)
        elif k + COLUMNS >= len(quantities):  # the lowest panel of its column: its x axis labelled
            ax.xaxis.set_tick_params(labelbottom=True)
            ax.set_xlabel(_axis_label(names[0], units), fontsize=8)
    if len(names) > 1 or any(r["status"] != "ok" for r in rows):
        axes[0, 0].legend(fontsize=6)
    return save_figure(fig, plt, path, title)


def _floquet(rows: list[dict], names: list[str], out: Path, what: str = "Floquet") -> list[Path]:
    """Frequency and ``Re λ`` of every mode against the first axis, one colour per mode name."""
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.4), sharex=True)
    by_mode: dict[str, list[tuple[float, float, float]]] = {}
    for r in rows:
        for m, f, re in zip(r.get("mode") or [], r.get("frequency_hz") or [], r.get("real_per_s") or []):
            by_mode.setdefault(m, []).append((r[names[0]], f, re))
    for name, pts in sorted(by_mode.items()):
        x, f, re = (np.array(v) for v in zip(*pts))
        top.scatter(x, f, s=12, label=name)
        bottom.scatter(x, re, s=12)
    bottom.axhline(0.0, color="k", lw=0.8)
    _mark_failed(bottom, rows, names[0])
    top.set_ylabel("frequency (Hz)")
    bottom.set_ylabel("Re λ (1/s), > 0 unstable")
    bottom.set_xlabel(_axis_label(names[0]))
    top.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5), frameon=False)
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    return [save_figure(fig, plt, out / "floquet_modes.png", f"{what}, Floquet analysis: frequency and damping of every mode")]
