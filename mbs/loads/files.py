"""The loads' files: the period's time series and the harmonics of every output (CSV), the
sweep's table (CSV), and the charts (:mod:`mbs.loads.charts`)."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from mbs import atomic
from mbs.loads import charts
from mbs.loads.analysis import RotorLoads


def _table(path: Path, header: list[str], columns: list[np.ndarray]) -> Path:
    return atomic.write(path, lambda tmp: np.savetxt(tmp, np.column_stack(columns), delimiter=",",
                                                    header=",".join(header), comments="", fmt="%.17g"))


def period_csv(res: RotorLoads, path: Path) -> Path:
    """``time`` (s), ``azimuth`` (rad, main rotor) and every output over the period."""
    azimuth = 2 * np.pi * res.t / res.revolution
    return _table(path, ["time", "azimuth", *res.names], [res.t, azimuth, *res.values.T])


def harmonics_csv(res: RotorLoads, path: Path) -> Path:
    """One row per order (per main-rotor revolution): the amplitude of every output (its
    unit; order 0: the mean, signed)."""
    amp = np.abs(res.amplitudes)
    amp[0] = res.amplitudes[0].real
    return _table(path, ["order", *res.names], [res.orders, *amp.T])


def sweep_csv(rows: list[dict], path: Path) -> Path:
    """The sweep's rows (:meth:`mbs.loads.sweep.LoadsSweep.rows`), blanks where a value is missing."""
    keys = list(dict.fromkeys(k for r in rows for k in r))
    with atomic.replacing(path) as tmp, tmp.open("w", newline="") as f:
        w = csv.DictWriter(f, keys)
        w.writeheader()
        w.writerows(rows)
    return path


def write(res: RotorLoads, out: Path) -> list[Path]:
    """The files of one speed in ``out``: ``loads_<scene>.csv``, ``harmonics_<scene>.csv``, the
    hub-load harmonics of each rotor and, for elastic blades, the spanwise loads (PNG)."""
    stem = f"{res.scene}_{res.speed:g}ms"
    paths = [period_csv(res, out / f"loads_{stem}.csv"), harmonics_csv(res, out / f"harmonics_{stem}.csv")]
    for rotor in ("main_rotor", "tail_rotor"):
        if f"{rotor}.hub.force_x" in res.names:
            paths.append(charts.hub_harmonics(res, out / f"hub_harmonics_{rotor}_{stem}.png", rotor,
                                              highest=12 if rotor == "main_rotor" else 24))
    if len(res.stations) > res.n_blades:
        paths.append(charts.spanwise(res, out / f"spanwise_{stem}.png"))
    return paths
