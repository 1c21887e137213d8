"""The results table of a run, ``results.csv``: writing it, the units of its columns, and
reading it back with a one-line error for every kind of file it is not.

``results.csv`` is plain CSV: a header of column names, then one row of numbers per recorded
step, with nothing else in it (a units row would break every CSV reader); the unit of each
column is in ``run.json`` under ``"units"`` (column -> unit: ``rad``, ``rad/s``, ``m``,
``m/s``, ``1`` for quaternion components and ratios, ``N``, ``N m``, ``W``, ``J``, ``s``).
"""
from __future__ import annotations

import csv
import json
import warnings
from pathlib import Path

import numpy as np

ENERGY_UNIT = "J"
_HINGE = (("rad",), ("rad/s",))
_SLIDER = (("m",), ("m/s",))
_FREE = (("m",) * 3 + ("1",) * 4, ("m/s",) * 3 + ("rad/s",) * 3)
NOT_RESULTS = "not a results table of 'heli simulate' or 'heli demo'"
RESULTS_DIGEST = "results_sha256"
"""The entry of ``run.json`` holding the SHA-256 of the ``results.csv`` written with it."""


def joint_units(joint) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Units of a joint's position and velocity coordinates (``""`` for a joint type not known here)."""
    kind = type(joint).__name__
    if kind in ("Serial", "LoopJoint"):  # a loop joint's coordinates: those of its independent parts
        parts = [joint_units(j) for j in getattr(joint, "independent", joint.parts)]
        return tuple(u for q, _ in parts for u in q), tuple(u for _, v in parts for u in v)
    if kind == "Modal":  # a flexible body's modal coordinates: tip deflection over length and tip twist
        return ("rad",) * joint.nq, ("rad/s",) * joint.nv
    known = {"Hinge": _HINGE, "Slider": _SLIDER, "FreeJoint": _FREE}
    return known.get(kind, (("",) * joint.nq, ("",) * joint.nv))


def column_units(model) -> dict[str, str]:
    """Unit of every state, output and parameter of ``model`` (a :class:`mbs.Model`), by column name."""
    out = {"time": "s"}
    for body in model.bodies.values():
        q, v = joint_units(body.joint)
        out.update(zip((f"{body.name}.{n}" for n in body.joint.q_names), q))
        out.update(zip((f"{body.name}.{n}" for n in body.joint.v_names), v))
    out.update({n: s.unit or "1" for n, s in model.states.items()})
    out.update({n: o.unit or "1" for n, o in model.outputs.items()})
    out.update({n: q.unit or "1" for n, q in model.parameters.items()})
    return out


def write_csv(columns: dict[str, np.ndarray], path: Path, progress=None, chunk: int = 20000) -> Path:
    """``columns`` (name -> (n,) values) as ``path``: a header row, then the values (17 digits),
    ``chunk`` rows at a time with ``progress(rows written, n)`` after each; written under a
    temporary name and renamed when complete (:mod:`mbs.atomic`)."""
    from mbs import atomic

    table = np.column_stack(list(columns.values()))
    with atomic.replacing(path) as tmp, open(tmp, "w") as f:
        f.write(",".join(columns) + "\n")
        for start in range(0, len(table), chunk):
            np.savetxt(f, table[start:start + chunk], delimiter=",", fmt="%.17g")
            if progress:
                progress(min(start + chunk, len(table)), len(table))
    return Path(path)


def results_path(folder_or_csv: Path) -> Path:
    """``results.csv`` in a folder, or the CSV file itself."""
    path = Path(folder_or_csv)
    csv_path = path / "results.csv" if path.is_dir() else path
    if not csv_path.exists():
        raise FileNotFoundError(f"no results file at {csv_path}")
    return csv_path


def read_results(folder_or_csv: Path) -> tuple[dict[str, np.ndarray], dict]:
    """Columns of a ``results.csv`` and the ``run.json`` beside it (empty if absent); ValueError in
    one line for an empty, foreign (a sweep's or a fan plot's table) or corrupt file."""
    path = results_path(folder_or_csv)
    names = _header(path)
    meta = read_run_json(path.parent / "run.json")
    check_pair(path, meta)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numpy's "input contained no data": said below
            data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except ValueError:
        raise ValueError(_first_bad_line(path, names)) from None
    if data.shape[0] == 0:
        raise ValueError(f"{path} has a header but no rows")
    return {n: data[:, i] for i, n in enumerate(names)}, meta


def check_pair(path: Path, meta: dict) -> None:
    """Refuse a ``results.csv`` (``path``) whose ``run.json`` (``meta``) records the SHA-256 of
    another table: the folder mixes the files of two runs."""
    from mbs import atomic

    recorded = meta.get(RESULTS_DIGEST)
    if recorded and recorded != atomic.sha256(path):
        raise ValueError(f"{path} and the run.json beside it are not of the same run (run.json records the SHA-256 "
                         f"of another results.csv): the folder mixes two runs; run the scene again into it, or give "
                         "the folder where both were written together")


def read_run_json(path: Path) -> dict:
    """The run record ``path`` (empty when absent); ValueError for a file that is not a JSON object."""
    if not path.exists():
        return {}
    try:
        meta = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path} is not valid JSON ({getattr(exc, 'msg', exc)}, line {getattr(exc, 'lineno', '?')})"
                         ) from None
    if not isinstance(meta, dict):
        raise ValueError(f"{path} is not a run record (a JSON object)")
    return meta


def _header(path: Path) -> list[str]:
    try:
        with open(path, newline="") as f:
            first = f.readline()
    except UnicodeDecodeError:
        raise ValueError(f"{path} is not a text table (a binary file, such as a chart); give the folder of a run or "
                         "its results.csv") from None
    except OSError as exc:
        raise ValueError(f"{path} cannot be read: {exc.strerror or exc}") from None
    if path.suffix.lower() == ".json":
        raise ValueError(f"{path} is a run record, not its table; give the folder of the run or its results.csv")
    if not first.strip():
        raise ValueError(f"{path} is empty: {NOT_RESULTS}")
    names = [n.strip() for n in next(csv.reader([first]))]
    if names[0] != "time":
        raise ValueError(f"{path} is {NOT_RESULTS}: its first column is {names[0]!r}, not 'time' (a sweep's or a "
                         "fan plot's table cannot be animated; give the folder of a run)")
    return names


def _first_bad_line(path: Path, names: list[str]) -> str:
    """The first line of ``path`` that is not a row of ``len(names)`` numbers, as a message."""
    with open(path, newline="") as f:
        for k, fields in enumerate(csv.reader(f), start=1):
            if k == 1 or not fields:
                continue
            if len(fields) != len(names):
                return f"{path}: line {k} has {len(fields)} values for {len(names)} columns"
            for name, text in zip(names, fields):
                try:
                    float(text)
                except ValueError:
                    return f"{path}: line {k}, column {name!r}: {text.strip()!r} is not a number"
    return f"{path} is {NOT_RESULTS}: it cannot be read as rows of numbers"
