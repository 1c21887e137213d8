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
    """Draw the charts of a ``kind`` sweep into ``out``; returns their paths."""
    rows = result.to_pylist()
    if not rows:
        return []
    return {"trim": _trim, "simulate": _simulate, "floquet": _floquet}[kind](rows, names, Path(out))


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


def _axis_label(name: str) -> str:
    return {"speed": "speed (m/s)", "omega": "rotor speed Ω (rad/s)", "climb_rate": "climb rate (m/s)"}.get(name, name)


POWER = ("main_rotor.power", "tail_rotor.power", "engine.power")
"""Aerodynamic shaft power of each rotor and the power the engines deliver (:mod:`mbs.loads.engine`)."""


def _trim(rows: list[dict], names: list[str], out: Path) -> list[Path]:
    """Controls and attitude (deg) and the rotors' power (kW) against the first axis."""
    controls = [c for c in CONTROLS if any(c in r for r in rows)]
    power = [c for c in POWER if any(r.get(c) is not None for r in rows)]
    deg = 180 / np.pi
    paths = [_line_chart(rows, names, {c: [c] for c in controls}, deg, "deg", out / "trim_controls.png",
                         "trim: controls"),
             _line_chart(rows, names, {"roll": ["roll"], "pitch": ["pitch"]}, deg, "deg", out / "trim_attitude.png",
                         "trim: attitude")]
    if power:
        paths.append(_line_chart(rows, names, {"rotor and engine power": power}, 1e-3, "kW", out / "trim_power.png",
                                 "trim: rotors' aerodynamic shaft power and engine power"))
    return paths + [_trim_summary(rows, names, controls, power, out / "trim_summary.png")]


def _trim_summary(rows, names, controls, power, path: Path) -> Path:
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
    return save_figure(fig, plt, path, "trim over speed: controls, attitude and power")


def _simulate(rows: list[dict], names: list[str], out: Path) -> list[Path]:
    """The envelope of every recorded quantity against the first axis."""
    quantities = list(dict.fromkeys(k[:-4] for r in rows for k in r if k.endswith(".min")))
    if not quantities:
        return []
    plt = _pyplot()
    fig, axes = plt.subplots(len(quantities), 1, figsize=(8, 2.2 * len(quantities)), sharex=True, squeeze=False)
    for ax, q in zip(axes[:, 0], quantities):
        for label, group in _groups(rows, names).items():
            x, lo = _series(group, names[0], f"{q}.min")
            hi, mean = _series(group, names[0], f"{q}.max")[1], _series(group, names[0], f"{q}.mean")[1]
            ax.fill_between(x, lo, hi, alpha=0.25)
            ax.plot(x, mean, marker="o", ms=3, label=f"mean {label}".strip())
        _mark_failed(ax, rows, names[0])
        ax.set_ylabel(q, fontsize=8)
        ax.grid(alpha=0.3)
    if len(names) > 1 or any(r["status"] != "ok" for r in rows):
        axes[0, 0].legend(fontsize=7)
    axes[-1, 0].set_xlabel(_axis_label(names[0]))
    return [save_figure(fig, plt, out / "simulate_envelopes.png", "simulation: min-max envelope and mean")]


def _floquet(rows: list[dict], names: list[str], out: Path) -> list[Path]:
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
    return [save_figure(fig, plt, out / "floquet_modes.png", "Floquet: frequency and damping of every mode")]
