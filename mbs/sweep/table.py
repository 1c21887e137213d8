"""The results table of a sweep: one row per point, written as Parquet and CSV.

Columns: the inputs (axis values, SI units), the outputs of the sweep kind, ``status``
(``ok``, ``failed``: the model gave no result, ``error``: the task itself was lost),
``message`` and ``wall_s`` (the point's computing time, s). Rows are sorted by their inputs
(first axis first), so the table does not depend on the order in which points finished.
The sweep's settings are kept in the Parquet file's metadata (key ``mbs.sweep``) and checked
when a sweep resumes into the same folder.
"""
from __future__ import annotations

import json
from pathlib import Path

import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from mbs import atomic
from mbs.sweep.grid import key

PARQUET, CSV = "results.parquet", "results.csv"
META_KEY = b"mbs.sweep"
FINISHED = ("ok", "failed")
"""Statuses of points that are not computed again on resume (``error`` rows are)."""


def build(rows: list[dict], names: list[str], settings: dict) -> pa.Table:
    """The table of ``rows`` sorted by the inputs ``names``, with ``settings`` as metadata."""
    rows = sorted(rows, key=lambda r: key(r, names))
    table = pa.table({c: [r.get(c) for r in rows] for c in columns(rows, names)})
    return table.replace_schema_metadata({META_KEY: json.dumps(settings, sort_keys=True).encode()})


def columns(rows: list[dict], names: list[str]) -> list[str]:
    """Column order: the inputs, the outputs as they first appear, then status, message, wall time."""
    tail = ["status", "message", "wall_s"]
    seen = dict.fromkeys(k for r in rows for k in r if k not in names and k not in tail)
    return [*names, *seen, *tail]


def settings_of(table: pa.Table) -> dict:
    """The sweep settings stored with ``table`` (empty when there are none)."""
    raw = (table.schema.metadata or {}).get(META_KEY)
    return json.loads(raw) if raw else {}


def read(out: Path) -> pa.Table | None:
    """The table in the folder ``out``, or None when there is none."""
    path = Path(out) / PARQUET
    return pq.read_table(path) if path.exists() else None


def finished(table: pa.Table | None, names: list[str]) -> dict[tuple, dict]:
    """Rows of ``table`` whose points need no computing again, by point key."""
    if table is None:
        return {}
    return {key(r, names): r for r in table.to_pylist() if r.get("status") in FINISHED}


def check_settings(table: pa.Table | None, settings: dict, out: Path) -> None:
    """Refuse to resume into ``out`` when its table was made with other settings."""
    old = _flat_settings(settings_of(table)) if table is not None else {}
    new = _flat_settings(settings)
    diff = {k: (old.get(k), v) for k, v in new.items() if old and old.get(k) != v}
    if diff:
        what = "; ".join(f"{k}: {a!r} there, {b!r} now" for k, (a, b) in diff.items())
        raise ValueError(f"--out {out} holds a different sweep ({what}); use another folder")


def _flat_settings(settings: dict) -> dict:
    """``{"options": {"tol": 1e-10}}`` -> ``{"tol": 1e-10}``: each setting by its own name."""
    return {**{k: v for k, v in settings.items() if k != "options"}, **settings.get("options", {})}


def write(table: pa.Table, out: Path) -> list[Path]:
    """Write ``results.parquet`` and ``results.csv`` into ``out`` (each replaced atomically)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / PARQUET, out / CSV]
    atomic.write(paths[0], lambda p: pq.write_table(table, p))
    atomic.write(paths[1], lambda p: pacsv.write_csv(_flat(table), p))
    return paths


def _flat(table: pa.Table) -> pa.Table:
    """``table`` with list columns (Floquet modes) as JSON text, which CSV can hold."""
    for i, f in enumerate(table.schema):
        if pa.types.is_list(f.type) or pa.types.is_large_list(f.type):
            text = pa.array([json.dumps(v) if v is not None else None for v in table.column(i).to_pylist()])
            table = table.set_column(i, f.name, text)
    return table
