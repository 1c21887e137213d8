"""Plots a rotorcraft engineer looks at: hinge angles over revolutions, energy error."""
from __future__ import annotations

from pathlib import Path

import numpy as np


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _revs(sim) -> np.ndarray:
    return sim.traj.t / sim.scene.revolution(sim.system, sim.params)


def hinge_angles(sim, path: Path, title: str | None = None) -> Path:
    """One panel per entry of ``scene.plots`` (the paper's Fig. 2 layout), in degrees."""
    plt = _pyplot()
    cols = sim.columns()
    panels = sim.scene.plots or {"states": sim.system.info.q_names[:4]}
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.4 * len(panels) + 0.6), sharex=True, squeeze=False)
    revs = _revs(sim)
    for ax, (label, names) in zip(axes[:, 0], panels.items()):
        for name in names:
            ax.plot(revs, np.degrees(cols[name]), lw=1.0, label=name)
        ax.set_ylabel(label.replace("(rad)", "(deg)"))
        ax.grid(alpha=0.3)
        if len(names) > 1:
            ax.legend(fontsize=7, ncol=min(len(names), 4), loc="upper right")
    axes[-1, 0].set_xlabel("main-rotor revolutions")
    fig.suptitle(title or f"{sim.scene.name}: hinge angles", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def energy_error(sims: list, path: Path, title: str | None = None, log: bool = False) -> Path:
    """Relative total-energy error over revolutions, one line per run (the paper's Fig. 3).

    ``log``: plot ``|E - E0|/|E0|`` on a log axis with the square roots of the precisions
    (the paper's reference level) as dotted lines; otherwise ``(E - E0)/E0`` linearly.
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.8))
    for sim in sims:
        e = sim.energy[:, -1]
        err = e / e[0] - 1
        label = (f"{sim.system.dtype}{'' if sim.compensated else ', plain summation'} "
                 f"(max {sim.max_rel_energy_error:.1e})")
        ax.plot(_revs(sim), np.abs(err) if log else err, lw=1.0, label=label)
    if log:
        ax.set_yscale("log")
        for dt, ls in zip(sorted({str(s.system.dtype) for s in sims}), (":", "--")):
            level = np.sqrt(np.finfo(dt).eps)
            ax.axhline(level, ls=ls, color="grey", lw=1, label=f"√eps({dt}) = {level:.1e}")
    ax.set_xlabel("main-rotor revolutions")
    ax.set_ylabel("|E − E0| / |E0|" if log else "relative energy error (E − E0)/E0")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="lower right" if log else "best")
    ax.set_title(title or f"{sims[0].scene.name}: relative total-energy error, RK4", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)
