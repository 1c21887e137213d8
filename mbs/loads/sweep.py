"""Rotor loads over a speed sweep: the periodic trim and the loads at every speed, with the
model built and compiled once."""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from mbs.loads.analysis import RotorLoads, rotor_loads


@dataclass
class LoadsSweep:
    """``points``: the loads at the speeds that trimmed, in order; ``failed``: (speed, reason)
    of the others; ``setup_s``: building the evaluators; ``wall_s``: the whole sweep (s)."""

    scene: str
    points: list[RotorLoads]
    failed: list[tuple[float, str]] = field(default_factory=list)
    setup_s: float = 0.0
    wall_s: float = 0.0

    def rows(self) -> list[dict]:
        """One row per speed: the ``N_b``/rev amplitudes of the main-rotor hub loads and the
        mean powers; failed speeds with their reason."""
        out = [_row(p) for p in self.points] + [{"speed": v, "status": "failed", "message": m} for v, m in self.failed]
        return sorted(out, key=lambda r: r["speed"])


def _row(p: RotorLoads) -> dict:
    hub = {f"{r['output']}.{p.n_blades}/rev": r[f"{p.n_blades}/rev"] for r in p.hub_rows("main_rotor")}
    power = {r["output"]: r["mean"] for r in p.power_rows()}
    return {"speed": p.speed, "status": "ok", "thrust": p.thrust, **hub, **power, "wall_s": p.wall_s}


def speed_sweep(scene, speeds, steps_per_rev: int | None = None, backend: str = "compiled",
                progress=None) -> LoadsSweep:
    """:func:`mbs.loads.analysis.rotor_loads` of ``scene`` at each of ``speeds`` (m/s)."""
    from mbs.analysis.trim import evaluators
    from mbs.loads.analysis import check_scene

    start = time.perf_counter()
    sc = check_scene(scene)
    system, stepper = evaluators(sc, "rk4", backend)
    res = LoadsSweep(sc.name, [], setup_s=time.perf_counter() - start)
    for k, v in enumerate(np.asarray(speeds, dtype=float)):
        try:
            res.points.append(rotor_loads(sc, float(v), steps_per_rev, backend, system, stepper))
        except ValueError as exc:
            res.failed.append((float(v), str(exc)))
        if progress:
            progress(k + 1, len(speeds))
    res.wall_s = time.perf_counter() - start
    return res
