"""Parameter sweeps as Dask tasks: trims over speed, simulations over parameters, Floquet
analyses over rotor speed.

Each point is one task; the compiled model is built once by the caller and loaded from the
compiled-model cache by every worker. The result is one table (a :class:`pyarrow.Table`; call
``.to_pandas()`` for a DataFrame when pandas is installed), also written as Parquet and CSV
with the sweep's charts when ``out`` is given; a sweep into an existing ``out`` computes only
the points not already there.

Modules: :mod:`~mbs.sweep.grid` (ranges and points), :mod:`~mbs.sweep.models` (building and
loading the models), :mod:`~mbs.sweep.tasks` (one point), :mod:`~mbs.sweep.cluster` (the Dask
client), :mod:`~mbs.sweep.runner` (submitting and collecting), :mod:`~mbs.sweep.table`
(Parquet/CSV), :mod:`~mbs.sweep.charts`, :mod:`~mbs.sweep.commands` (``heli sweep``).
"""
from __future__ import annotations

import numpy as np

from mbs.sweep.runner import run, run_info

__all__ = ["floquet_sweep", "run", "run_info", "simulate_sweep", "trim_sweep"]


def trim_sweep(scene: str, speeds, params: dict | None = None, **kwargs):
    """Trims of ``scene`` at every ``speeds`` (m/s) and combination of ``params`` (name ->
    values of run-time parameters, or ``climb_rate`` in m/s); keyword arguments: those of
    :func:`run` (``options``, ``out``, ``workers``, ``scheduler``, ``client``, ``progress``)."""
    return run("trim", scene, {"speed": np.atleast_1d(speeds), **(params or {})}, **kwargs)


def simulate_sweep(scene: str, params: dict, **kwargs):
    """Simulations of ``scene`` at every combination of ``params`` (name -> values of run-time
    parameters); ``options={"revs": R}`` sets the length; keywords as :func:`run`."""
    return run("simulate", scene, dict(params), **kwargs)


def floquet_sweep(scene: str, omegas, params: dict | None = None, **kwargs):
    """Floquet analyses of ``scene`` at every rotor speed in ``omegas`` (rad/s) and combination
    of ``params``; keywords as :func:`run`."""
    return run("floquet", scene, {"omega": np.atleast_1d(omegas), **(params or {})}, **kwargs)
