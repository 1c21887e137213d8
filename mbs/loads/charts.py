"""Charts of rotor loads (PNG): the hub-load harmonics at one speed, the vibratory hub loads
and the power against speed over a sweep, and the spanwise loads of an elastic blade.

Legends sit beside the axes, never over the data; amplitudes are drawn on logarithmic axes
where they span decades (the rotor passes ``N_b``/rev and its multiples; everything else is
orders of magnitude smaller).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mbs.loads.analysis import RotorLoads
from mbs.loads.outputs import COMPONENTS
from mbs.plots import _pyplot, save_figure

FORCES, MOMENTS = COMPONENTS[:3], COMPONENTS[3:]


def hub_harmonics(res: RotorLoads, path: Path, rotor: str = "main_rotor", highest: int = 12) -> Path:
    """Amplitudes of the hub forces (N) and moments (N m) of ``rotor`` per order up to
    ``highest``/rev (main-rotor revolutions), logarithmic, one marker per component."""
    plt = _pyplot()
    keep = (res.orders > 0) & (res.orders <= highest)
    fig, axes = plt.subplots(2, 1, figsize=(8, 5.6), sharex=True)
    for ax, group, unit in zip(axes, (FORCES, MOMENTS), ("N", "N m")):
        for k, c in enumerate(group):
            a = np.abs(res.amplitudes[keep, res.column(f"{rotor}.hub.{c}")])
            ax.semilogy(res.orders[keep], np.maximum(a, 1e-16), "o", ms=3 + k, mfc="none", label=c.replace("_", " "))
        for m in range(res.n_blades, highest + 1, res.n_blades):
            ax.axvline(m, color="0.8", lw=0.8, zorder=0)
        ax.set_ylabel(f"amplitude ({unit})")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5), frameon=False)
    axes[-1].set_xlabel("order (per main-rotor revolution); grey lines: multiples of the blade count")
    return save_figure(fig, plt, path, f"{res.title}: {rotor.replace('_', '-')} hub loads on the "
                 "airframe (body axes), harmonics")


def vibratory(points: list[RotorLoads], path: Path, failed: list[float] = ()) -> Path:
    """Over a speed sweep: the ``N_b``/rev amplitude of the main-rotor hub forces (N) and
    moments (N m) in body axes, and the mean powers (kW): the rotors' aerodynamic and shaft
    power and the engine power. ``failed``: speeds without a trim (crosses on the axis)."""
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(8, 8.4), sharex=True)
    v = np.array([p.speed for p in points])
    nb = points[0].n_blades if points else 4
    for ax, group, unit in zip(axes[:2], (FORCES, MOMENTS), ("N", "N m")):
        for c in group:
            ax.plot(v, [p.harmonic(f"main_rotor.hub.{c}", nb) for p in points], "o-", ms=3, label=c.replace("_", " "))
        ax.set_ylabel(f"{nb}/rev amplitude ({unit})")
    keys = [k for k in ("main_rotor.power", "main_rotor.shaft_power", "tail_rotor.shaft_power", "engine.power")
            if points and k in points[0].names]
    for k in keys:
        axes[2].plot(v, [p.mean(k) * 1e-3 for p in points], "o-", ms=3, label=k.replace("_", " "))
    axes[2].set_ylabel("mean power (kW)")
    for ax in axes:
        if len(failed):
            ax.scatter(failed, np.zeros(len(failed)), marker="x", color="red", label="no trim")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5), frameon=False)
    axes[-1].set_xlabel("speed (m/s)")
    name = (points[0].scene + (f" of the {points[0].aircraft}" if points[0].aircraft else "")) if points else "no trim"
    return save_figure(fig, plt, path, f"{name}: vibratory main-rotor hub loads and power against speed")


def spanwise(res: RotorLoads, path: Path, blade: str = "blade1") -> Path:
    """Blade loads along the span (one point per segment joint): the mean and the 1/rev
    amplitude of the flap and lag bending moments and the torsion (N m) against radius (m)."""
    plt = _pyplot()
    rows = res.span_rows(blade)
    r = [row["radius"] for row in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharex=True)
    for what in ("flap", "lag", "torsion"):
        axes[0].plot(r, [row[f"{what}_mean"] for row in rows], "o-", ms=3, label=what)
        axes[1].plot(r, [row[f"{what}_1/rev"] for row in rows], "o-", ms=3, label=what)
    for ax, label in zip(axes, ("mean moment (N m)", "1/rev amplitude (N m)")):
        ax.set_xlabel("radius of the segment joint (m)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return save_figure(fig, plt, path, f"{res.title}: {blade} loads along the span (rotating frame)")
