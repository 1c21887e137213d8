"""The chart and table of one Floquet analysis (``heli floquet SCENE --out DIR``).

Left panel: the characteristic exponents in the complex plane, ``Re λ`` (1/s, on a scale that
is linear within ±0.1 1/s and logarithmic beyond, so the slow body modes and the fast inflow
modes both show) against the frequency (Hz, with the multiples of the rotor speed on the right
axis), one colour per mode group (the group with the largest share of the mode's energy), the
oscillating and the unstable modes named, the unstable half-plane ``Re λ > 0`` shaded. Right
panel: the multipliers over the whole period on the unit circle, the outside (unstable)
shaded. The legend sits below the panels, outside the data.

Table: one row per mode (one per conjugate pair): name, group, ``Re λ`` (1/s), ``Im λ``
(rad/s), frequency (Hz), frequency per rev, damping ratio, multiplier modulus.
"""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from mbs import atomic
from mbs.analysis.floquet import GROUPS, Floquet

CSV_COLUMNS = ("mode", "group", "real_per_s", "imag_rad_s", "frequency_hz", "per_rev", "damping_ratio",
               "multiplier_modulus")
GROUP_COLOURS = {"body": "tab:blue", "flap": "tab:orange", "lag": "tab:green", "inflow": "tab:purple",
                 "tail rotor": "tab:brown", "stabilizer bar": "tab:gray"}
UNSTABLE_SHADE = {"color": "tab:red", "alpha": 0.08, "lw": 0}


def rows(res: Floquet) -> list[dict]:
    """The table: one dict per mode with the fields of :data:`CSV_COLUMNS` (SI units; a neutral
    root's damping ratio, undefined, left empty)."""
    return [{"mode": m.name, "group": m.group, "real_per_s": m.exponent.real, "imag_rad_s": m.exponent.imag,
             "frequency_hz": m.frequency_hz, "per_rev": m.per_rev,
             "damping_ratio": "" if np.isnan(m.damping_ratio) else m.damping_ratio,
             "multiplier_modulus": abs(m.multiplier)} for m in res.modes]


def write_csv(res: Floquet, path: Path) -> Path:
    """Write :func:`rows` of ``res`` to ``path`` (floats at full precision)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic.replacing(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, CSV_COLUMNS)
        w.writeheader()
        w.writerows(rows(res))
    return path


def figure(res: Floquet, path: Path, of: str = "") -> Path:
    """Draw the two panels of ``res`` into the PNG ``path``; ``of`` names the aircraft in the
    title (`` of the MBB Bo105``)."""
    from mbs.plots import _pyplot

    plt = _pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(12.5, 5.4), gridspec_kw={"width_ratios": [1.45, 1]})
    _exponents(left, res)
    _multipliers(right, res)
    handles = [left.scatter([], [], s=36, color=GROUP_COLOURS[g], label=g) for g in _groups(res)]
    handles.append(left.scatter([], [], s=90, facecolors="none", edgecolors="tab:red", label="unstable"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), frameon=False, fontsize=9,
               title="mode group (largest share of the energy)", title_fontsize=9)
    fig.suptitle(_title(res, of), fontsize=11)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
    return path


def _groups(res: Floquet) -> list[str]:
    """The groups present, in the order of :data:`mbs.analysis.floquet.GROUPS`."""
    present = {m.group for m in res.modes}
    return [g for g in GROUPS if g in present]


def _title(res: Floquet, of: str = "") -> str:
    growth = max((m.exponent.real for m in res.modes), default=0.0)
    verdict = "stable" if res.stable else f"UNSTABLE (largest Re λ = {growth:+.3g} 1/s)"
    frame = "fixed-frame" if res.frame.startswith("fixed") else "rotating-frame"
    return (f"{res.scene}{of} at {res.speed:g} m/s: Floquet exponents and multipliers over {res.period_revs} "
            f"revolutions ({frame} frequencies): {verdict}")


LINEAR_WITHIN = 0.1  # 1/s: the exponent axis is linear within ±LINEAR_WITHIN, logarithmic beyond


def _exponents(ax, res: Floquet) -> None:
    """``Re λ`` (1/s) against frequency (Hz); unstable half-plane shaded; modes named."""
    re = np.array([m.exponent.real for m in res.modes])
    hz = np.array([m.frequency_hz for m in res.modes])
    left = min(-1.0, 1.6 * float(re.min(initial=0.0)))
    right = max(1.0, 3.0 * float(re.max(initial=0.0)))
    ax.set_xscale("symlog", linthresh=LINEAR_WITHIN)
    ax.axvspan(0.0, right, **UNSTABLE_SHADE)
    ax.axvline(0.0, color="k", lw=0.8)
    for m, x, y in zip(res.modes, re, hz):
        ax.scatter(x, y, s=36, color=GROUP_COLOURS[m.group], zorder=3)
        if abs(m.multiplier) > 1 + 1e-6:
            ax.scatter(x, y, s=90, facecolors="none", edgecolors="tab:red", linewidths=1.3, zorder=4)
    ax.set_xlim(left, right)
    ax.set_ylim(-0.03 * max(1.0, float(hz.max(initial=1.0))), 1.08 * max(1.0, float(hz.max(initial=1.0))))
    ax.set_xlabel(f"Re λ (1/s): < 0 decays, > 0 grows (linear within ±{LINEAR_WITHIN:g})")
    ax.set_ylabel("frequency (Hz)")
    ax.text(0.985, 0.98, "unstable", transform=ax.transAxes, ha="right", va="top", color="tab:red", fontsize=9)
    ax.grid(alpha=0.3)
    _per_rev_axis(ax, res)
    _label_modes(ax, res, re, hz)


def _label_modes(ax, res: Floquet, re: np.ndarray, hz: np.ndarray) -> None:
    """Name the oscillating and the unstable modes next to their points: right of the point,
    else left, else higher up, wherever the label clears those already placed (pixels)."""
    ax.figure.canvas.draw()
    placed: list[tuple[float, float, float]] = []  # left, right, middle height of each label
    for k in np.argsort(hz):
        m = res.modes[k]
        if hz[k] <= 0 and abs(m.multiplier) <= 1 + 1e-6:
            continue
        px, py = ax.transData.transform((re[k], hz[k]))
        width = 5.2 * len(m.name)
        for dx, dy in ((6, 3), (-6, 3), (8, 14), (-8, 14), (8, -12), (8, 25), (8, 36)):
            box = (px + dx, px + dx + width) if dx > 0 else (px + dx - width, px + dx)
            if not any(box[0] < hi and lo < box[1] and abs(py + dy - y) < 10 for lo, hi, y in placed):
                break
        placed.append((*box, py + dy))
        leader = {"arrowstyle": "-", "color": "0.6", "lw": 0.6, "shrinkA": 0, "shrinkB": 3} if dy != 3 else None
        ax.annotate(m.name, (re[k], hz[k]), xytext=(dx, dy), textcoords="offset points", fontsize=7.5,
                    color="0.2", ha="left" if dx > 0 else "right", va="center", arrowprops=leader)


def _per_rev_axis(ax, res: Floquet) -> None:
    """A right-hand axis in multiples of the main-rotor speed."""
    if not res.modes:
        return
    rev_hz = abs(res.modes[0].omega) / (2 * np.pi)
    sec = ax.secondary_yaxis("right", functions=(lambda f: f / rev_hz, lambda r: r * rev_hz))
    sec.set_ylabel("per rev")


def _multipliers(ax, res: Floquet) -> None:
    """The multipliers of the whole period and their conjugates on the unit circle."""
    import matplotlib.patches as mpatches

    mu = np.array([m.multiplier for m in res.modes])
    reach = max(1.15, float(np.abs(mu).max(initial=1.0)) * 1.08)
    ax.add_patch(mpatches.Rectangle((-reach, -reach), 2 * reach, 2 * reach, **UNSTABLE_SHADE))
    ax.add_patch(mpatches.Circle((0, 0), 1.0, facecolor="white", edgecolor="k", lw=0.9))
    for m, z in zip(res.modes, mu):
        c = GROUP_COLOURS[m.group]
        ax.scatter([z.real, z.real], [z.imag, -z.imag], s=30, color=c, zorder=3)
        if abs(z) > 1 + 1e-6:
            ax.scatter([z.real], [z.imag], s=90, facecolors="none", edgecolors="tab:red", linewidths=1.3, zorder=4)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_aspect("equal")
    ax.set_xlabel("Re μ")
    ax.set_ylabel("Im μ")
    ax.set_title(f"multipliers μ over the period ({res.period_revs} rev), outside the circle unstable",
                 fontsize=9)
