"""Plots a rotorcraft engineer looks at: hinge angles and inputs over time, energy error.

Every time axis reads in seconds (below) and main-rotor revolutions (above); legends sit to
the right of the axes, never over the data; the lines of one panel differ in colour and dash
and are drawn with the later ones on top, so that lines that coincide (two cyclic inputs at
the same trim value, four blades at the same flap) all stay visible.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mbs import atomic

DASHES = ("-", "--", "-.", ":")


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, plt, path: Path, title: str) -> Path:
    """Title ``fig``, write it to ``path`` (folders made) and close it; returns the path."""
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
    return path


def _revolutions_axis(ax, revolution: float) -> None:
    """Main-rotor revolutions on the top edge of ``ax`` (whose x is time in s)."""
    top = ax.secondary_xaxis("top", functions=(lambda t: t / revolution, lambda r: r * revolution))
    top.set_xlabel("main-rotor revolutions", fontsize=8)
    top.tick_params(labelsize=8)


def time_panels(t: np.ndarray, revolution: float, columns: dict, panels: dict[str, list[str]], path: Path,
                title: str, events: list[float] = ()) -> Path:
    """One panel per entry of ``panels`` (label -> column names) against time ``t`` (s).

    Columns of a panel labelled ``(rad)`` are drawn in degrees. ``revolution``: the
    main-rotor revolution (s) for the top axis; ``events``: times (s) marked by dotted lines
    in every panel (e.g. input switches). Writes ``path`` (PNG) and returns it.
    """
    plt = _pyplot()
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 1.9 * len(panels) + 1.0), sharex=True, squeeze=False,
                             layout="constrained")
    for ax, (label, names) in zip(axes[:, 0], panels.items()):
        scale = np.degrees if "(rad)" in label else np.asarray
        for k, name in enumerate(names):
            ax.plot(t, scale(columns[name]), lw=1.6 - 0.3 * (k % 4), ls=DASHES[k % 4], label=name, zorder=2 + k)
        for e in events:
            ax.axvline(e, color="grey", lw=0.8, ls=":", zorder=1)
        ax.set_ylabel(label.replace("(rad)", "(deg)"), fontsize=8)
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.005, 1.0), frameon=False, handlelength=2.8)
    _revolutions_axis(axes[0, 0], revolution)
    axes[-1, 0].set_xlabel("time (s)", fontsize=8)
    axes[-1, 0].set_xlim(t[0], t[-1])
    fig.suptitle(title, fontsize=10)
    atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
    return Path(path)


def hinge_angles(sim, path: Path, title: str | None = None) -> Path:
    """One panel per entry of ``scene.plots`` (the paper's Fig. 2 layout), in degrees."""
    panels = sim.scene.plots or {"states": sim.system.info.q_names[:4]}
    start = {"periodic trim": ", from its periodic trim", "scene": ""}.get(sim.start.get("from"), "")
    return time_panels(sim.traj.t, sim.scene.revolution(sim.system, sim.params), sim.columns(), panels, path,
                       title or f"{sim.title()}{start}: hinge angles ({sim.method}, {sim.steps_per_rev} steps/rev)")


def energy_error(sims: list, path: Path, title: str | None = None, log: bool = False) -> Path:
    """Relative total-energy error over time, one line per run (the paper's Fig. 3).

    ``log``: plot ``|E - E0|/|E0|`` on a log axis with the square roots of the precisions
    (the paper's reference level) as dotted lines; otherwise ``(E - E0)/E0`` linearly.
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(10, 4.0), layout="constrained")
    for k, sim in enumerate(sims):
        e = sim.energy[:, -1]
        err = e / e[0] - 1
        label = (f"{sim.system.dtype}{'' if sim.compensated else ', plain summation'} "
                 f"(max {sim.max_rel_energy_error:.1e})")
        ax.plot(sim.traj.t, np.abs(err) if log else err, lw=1.0, ls=DASHES[k % 4], label=label)
    if log:
        ax.set_yscale("log")
        for dt, ls in zip(sorted({str(s.system.dtype) for s in sims}), (":", "--")):
            level = np.sqrt(np.finfo(dt).eps)
            ax.axhline(level, ls=ls, color="grey", lw=1, label=f"√eps({dt}) = {level:.1e}")
    _revolutions_axis(ax, sims[0].scene.revolution(sims[0].system, sims[0].params))
    ax.set_xlabel("time (s)")
    ax.set_ylabel("|E − E0| / |E0|" if log else "relative energy error (E − E0)/E0")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.005, 1.0), frameon=False)
    ax.set_title(title or f"{sims[0].title()}: relative total-energy error, {sims[0].method}, "
                          f"{sims[0].steps_per_rev} steps/rev", fontsize=10)
    atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
    return Path(path)
