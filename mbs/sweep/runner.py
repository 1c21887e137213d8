"""Run a sweep: build the model in the client, submit the missing points, collect the rows.

:func:`run` is the one entry point (``heli sweep ...`` and :mod:`mbs.sweep` call it). With
``workers=0`` the points run in a plain loop in this process (no Dask); otherwise each point
is one Dask task. A lost worker's tasks are retried by Dask on the others; a task that still
fails becomes an ``error`` row and the sweep goes on. The table is saved every few seconds
while the sweep runs and when it stops, so an interrupted sweep resumes where it stopped.
"""
from __future__ import annotations

import json
import time
import uuid
from pathlib import Path
from typing import Callable, Iterator

import numpy as np
import pyarrow as pa

from mbs.sweep import grid, models, table
from mbs.sweep.tasks import Task, run_task, warm

SAVE_EVERY_S = 5.0
RUN_KEY = b"mbs.sweep.run"


def run(kind: str, scene: str, axes: dict[str, np.ndarray], options: dict | None = None,
        out: str | Path | None = None, workers: int | None = None, scheduler: str | None = None,
        client=None, progress: Callable[[int, int], None] | None = None) -> pa.Table:
    """Sweep ``kind`` (``trim``, ``simulate``, ``floquet``) of ``scene`` over the grid ``axes``
    (name -> values, SI units) and return the results table (a :class:`pyarrow.Table`).

    options: fixed settings of every point (method, steps_per_rev, backend, ...); out: the
    folder of the table and charts, whose finished points are not computed again; workers,
    scheduler, client: where to run (:func:`mbs.sweep.cluster.connect`; ``workers=0``: a plain
    loop here); progress: ``progress(done, total)`` after each point.
    """
    start, options, names = time.perf_counter(), dict(options or {}), list(axes)
    if workers is not None and workers < 0:
        raise ValueError(f"--workers {workers} must be >= 0 (0: a plain loop, no Dask)")
    settings = {"kind": kind, "scene": scene, "axes": names, "options": options}
    models.check_axes(kind, scene, options, names)  # on the symbolic model: before anything is compiled
    old = table.read(out) if out else None
    if out:  # before anything is compiled: a resumed sweep must be the same sweep
        table.check_settings(old, settings, Path(out))
    models.loaded(kind, scene, options)  # compiled here, once, before any task
    rows = table.finished(old, names)
    todo = [Task(kind, scene, p, options, _cache()) for p in grid.points(axes) if grid.key(p, names) not in rows]
    reused = len(rows)
    new = _collect(todo, rows, names, settings, out, workers, scheduler, client, progress)
    result = table.build(list(rows.values()), names, settings)
    info = {"computed": new, "reused": reused, "wall_s": time.perf_counter() - start}
    result = result.replace_schema_metadata({**result.schema.metadata, RUN_KEY: json.dumps(info).encode()})
    if out:
        _write_all(kind, result, names, Path(out))
    return result


def run_info(result: pa.Table) -> dict:
    """What the run that made ``result`` did: points ``computed`` and ``reused``, ``wall_s`` (s)."""
    return json.loads((result.schema.metadata or {}).get(RUN_KEY, b"{}"))


def _cache() -> str:
    from mbs.backends.compiled import cache_dir

    return str(cache_dir())


def _write_all(kind: str, result: pa.Table, names: list[str], out: Path) -> list[Path]:
    from mbs.sweep import charts

    return table.write(result, out) + charts.write(kind, result, names, out)


def _collect(todo: list[Task], rows: dict, names: list[str], settings: dict, out, workers, scheduler, client,
             progress) -> int:
    """Compute ``todo`` into ``rows`` (by point key), saving the table now and then; the count."""
    done, last_save = 0, time.perf_counter()
    stream = _serial(todo) if workers == 0 else _distributed(todo, workers, scheduler, client)
    try:
        for row in stream:
            rows[grid.key(row, names)] = row
            done += 1
            if progress:
                progress(done, len(todo))
            if out and time.perf_counter() - last_save > SAVE_EVERY_S:
                table.write(table.build(list(rows.values()), names, settings), Path(out))
                last_save = time.perf_counter()
    finally:
        if out and done:
            table.write(table.build(list(rows.values()), names, settings), Path(out))
    return done


def _serial(todo: list[Task]) -> Iterator[dict]:
    """The rows of ``todo`` computed one after the other in this process."""
    for task in todo:
        try:
            yield run_task(task)
        except Exception as exc:  # an unexpected failure of one point: recorded, the sweep goes on
            yield error_row(task, exc)


def _distributed(todo: list[Task], workers, scheduler, client) -> Iterator[dict]:
    """The rows of ``todo`` as their Dask tasks finish (in completion order)."""
    from distributed import as_completed

    from mbs.sweep.cluster import connect

    if not todo:
        return
    with connect(workers, scheduler, client) as c:
        c.run(warm, todo[0].kind, todo[0].scene, todo[0].options, todo[0].cache_dir)
        token = uuid.uuid4().hex[:8]
        futures = {c.submit(run_task, t, key=f"sweep-{t.kind}-{token}-{i}", pure=False): t
                   for i, t in enumerate(todo)}
        for fut in as_completed(futures):
            yield _row(fut, futures[fut])
            fut.release()


def _row(fut, task: Task) -> dict:
    """The row a finished future holds, or an ``error`` row when its task was lost."""
    try:
        return fut.result()
    except Exception as exc:
        return error_row(task, exc)


def error_row(task: Task, exc: BaseException) -> dict:
    """The row of a point whose task failed unexpectedly (computed again on resume)."""
    return {**task.inputs, "status": "error", "message": f"{type(exc).__name__}: {exc}", "wall_s": float("nan")}
