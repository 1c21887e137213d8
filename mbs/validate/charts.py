"""Charts of a validation: trims against speed, each derivative against speed, and the root locus
of the eigenvalues against speed; the model's values and the published ones on the same axes,
the published points with their uncertainty, the tolerance as a band about them, and the
data's conventions printed under each chart."""
from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np

from mbs.plots import _pyplot

COLUMNS = 3


def write_all(res, folder: Path) -> list[Path]:
    """Every chart of ``res`` (:class:`mbs.validate.runner.Result`) into ``folder``."""
    out = []
    for kind, name in (("trim", "trims.png"), ("derivative", "derivatives.png")):
        blocks = [(s, rows) for s, rows in res.blocks if s.kind == kind]
        if blocks:
            out.append(series_chart(blocks, res, folder / name, kind))
    if res.pairs:
        out.append(root_locus(res, folder / "root_locus.png"))
    return out


def _grid(plt, n: int):
    cols = min(COLUMNS, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(max(4.2 * cols, 8.0), 2.9 * rows + 1.2), squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat)


def panels(blocks) -> list[list[tuple]]:
    """The series of ``blocks`` grouped by what they publish (quantity, unit and the model's
    factor), in the order each first appears: one panel each."""
    out: dict[tuple, list] = {}
    for s, rows in blocks:
        out.setdefault((s.quantity, s.unit, s.ours_factor), []).append((s, rows))
    return list(out.values())


MARKERS = "osD^v<>"


def series_chart(blocks, res, path: Path, kind: str) -> Path:
    """One panel per published quantity: the published points of each source (with uncertainty
    bars and the tolerance band) and the model's values at their speeds."""
    plt = _pyplot()
    groups = panels(blocks)
    fig, axes = _grid(plt, len(groups))
    v = res.validation
    speeds = [r.speed for _, rows in blocks for r in rows]
    pad = 0.03 * (max(speeds) - min(speeds)) or 1.0
    for ax, group in zip(axes, groups):
        sources = list(dict.fromkeys(s.source.split()[0] for s, _ in group))  # one marker per source
        for s, rows in group:
            _published(ax, s, rows, MARKERS[sources.index(s.source.split()[0]) % len(MARKERS)])
        s = group[0][0]
        _model(ax, [r for _, rows in group for r in rows], "" if s.ours_factor == 1 else f" × {s.ours_factor:g}")
        ax.set_title(f"{s.quantity}", fontsize=9)
        ax.set_xlim(min(speeds) - pad, max(speeds) + pad)  # one speed axis for every panel
        ax.set_xlabel(f"speed ({v.speed_unit})", fontsize=8)
        ax.set_ylabel(s.unit, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        _legend(ax)
    return _save(fig, plt, path, f"{v.title}: {kind}s, model against published", v)


def _legend(ax) -> None:
    """The panel's legend, an entry once (two series of one source draw the same two)."""
    handles, labels = ax.get_legend_handles_labels()
    entries = dict(zip(labels, handles))
    ax.legend(list(entries.values()), list(entries), fontsize=6, loc="best")


def _model(ax, rows, factor: str) -> None:
    """The model's values of a panel: a line through its speeds, or, when the points have flight
    conditions of their own (several at one speed), a cross at each point."""
    if any(r.condition for r in rows):
        ax.plot([r.speed for r in rows], [r.ours for r in rows], "x", color="tab:red", ms=5,
                label=f"model{factor} (at each point's condition)")
        return
    ours = sorted({r.speed: r.ours for r in rows}.items())
    ax.plot([x for x, _ in ours], [y for _, y in ours], "-", marker=".", color="tab:red", lw=1.3, label=f"model{factor}")


def _published(ax, s, rows, marker: str) -> None:
    """One source's points of a panel: uncertainty bars and its tolerance band."""
    speed = np.array([r.speed for r in rows])
    pub = np.array([r.published for r in rows])
    order = np.argsort(speed)
    if s.tolerance is not None and s.tolerance.bound is not None:  # a limit: its side, marked by the point's shape
        marker = "v" if s.tolerance.bound == "upper" else "^"
    elif s.tolerance is not None:
        half = s.tolerance.absolute if s.tolerance.absolute is not None else s.tolerance.relative * np.abs(pub)
        label = f"tolerance {s.tolerance.describe(s.unit)}"
        if len(speed) > 1:
            ax.fill_between(speed[order], (pub - half)[order], (pub + half)[order], color="0.88", lw=0, label=label)
        else:  # a band needs two speeds: a single point's tolerance as a bar
            ax.vlines(speed, pub - half, pub + half, color="0.82", lw=7, label=label)
    bound = "" if s.tolerance is None or s.tolerance.bound is None else f", {s.tolerance.bound} bound"
    ax.errorbar(speed, pub, yerr=np.array([r.uncertainty for r in rows]), fmt=marker, ms=3.5, color="k",
                mfc="white", capsize=2, lw=0.8, label=f"published ({s.source.split()[0]}{bound})")


def root_locus(res, path: Path) -> Path:
    """Published and model eigenvalues in the complex plane, coloured by speed; lines join each
    published eigenvalue to the model's paired with it; the model's other eigenvalues at the
    published speeds as dots."""
    from matplotlib import colormaps

    plt = _pyplot()
    v = res.validation
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(12.5, 6.2))
    speeds = sorted({p.speed for p in res.pairs})
    cmap = colormaps["viridis"]
    color = {s: cmap(k / max(len(speeds) - 1, 1)) for k, s in enumerate(speeds)}
    others = _model_eigenvalues(res, set(speeds))
    for a in (ax, zoom):
        for s, z in others:
            a.plot(z.real, z.imag, ".", color=color[s], ms=3, alpha=0.6)
        for p in res.pairs:
            c = color[p.speed]
            a.plot([p.published.real, p.ours.real], [p.published.imag, p.ours.imag], "-", color=c, lw=0.5, alpha=0.6)
            a.plot(p.published.real, p.published.imag, "o", mfc="white", mec=c, ms=6)
            a.plot(p.ours.real, p.ours.imag, "x" if p.within else "s", color=c, ms=6 if p.within else 5)
        a.axvline(0, color="k", lw=0.7)
        a.axhline(0, color="k", lw=0.4)
        a.grid(alpha=0.3)
        a.set_xlabel("Re λ (1/s)")
        a.set_ylabel("Im λ (rad/s)")
    slow = [z for p in res.pairs for z in (p.published, p.ours) if abs(z) < 1.5]
    if slow:
        zoom.set_xlim(min(z.real for z in slow) - 0.1, max(max(z.real for z in slow), 0) + 0.1)
        zoom.set_ylim(min(z.imag for z in slow) - 0.1, max(z.imag for z in slow) + 0.1)
    zoom.set_title("near the origin (|λ| < 1.5)", fontsize=9)
    handles = [plt.Line2D([], [], ls="", marker="o", mfc="white", mec="k", label="published"),
               plt.Line2D([], [], ls="", marker="x", color="k", label="model, within tolerance"),
               plt.Line2D([], [], ls="", marker="s", color="k", label="model, outside"),
               plt.Line2D([], [], ls="", marker=".", color="k", label="model, not paired"),
               *[plt.Line2D([], [], ls="", marker="o", color=color[s], label=f"{s:g} {v.speed_unit}") for s in speeds]]
    ax.legend(handles=handles, fontsize=7, loc="best")
    return _save(fig, plt, path, f"{v.title}: root locus against speed", v)


def _model_eigenvalues(res, speeds: set) -> list[tuple[float, complex]]:
    """``(published speed, eigenvalue)`` of every model eigenvalue at the published speeds that
    no published one is paired with."""
    from mbs.validate.eigen import model_eigenvalues

    paired = {(p.speed, p.ours) for p in res.pairs}
    out = []
    for e in res.validation.eigenvalues:
        point = res.model.at(e.speed, altitude=e.altitude)
        if e.shown_speed in speeds and point.ok and point.derivatives is not None:
            out += [(e.shown_speed, z) for z in model_eigenvalues(point.derivatives)[0]
                    if (e.shown_speed, complex(z)) not in paired]
    return out


def _save(fig, plt, path: Path, title: str, v) -> Path:
    """Title ``fig``, print the data's conventions under it, write it to ``path`` and close it."""
    text = " | ".join(f"{k}: {t}" for k, t in v.conventions.items())
    lines = textwrap.wrap("Conventions of the published data — " + text, 200) if text else []
    height = fig.get_size_inches()[1]
    bottom = (0.1 + 0.09 * len(lines)) / height
    fig.text(0.01, 0.01, "\n".join(lines), fontsize=5.5, va="bottom", ha="left", color="0.3")
    heading = textwrap.wrap(title, int(fig.get_size_inches()[0] * 12))
    fig.suptitle("\n".join(heading), fontsize=10)
    fig.tight_layout(rect=(0, bottom, 1, 1 - (0.15 + 0.2 * len(heading)) / height))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
