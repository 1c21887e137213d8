"""Inputs of a run: values set once (``heli simulate --set NAME=VALUE``) and input tables
(``heli simulate --inputs FILE``).

An input table is the FMU demo's format (:func:`fmu.hosts.pitch_schedule`), which is fmpy's:
a CSV file whose first column is ``time`` (s) and whose other columns are named after the
scene's run-time parameters (the controls ``collective``, ``lateral_cyclic``,
``longitudinal_cyclic``, ``tail_collective`` in rad, or any other parameter, in its unit).
Between two rows of different times the values change linearly, as fmpy interpolates them; a
time written twice is a jump (the second row holds from that time on); after the last row its
values hold. Each fixed step of the run holds the values at its start (right-continuous at a
jump), so the run equals one with the same values held step by step, and an FMU driven by
fmpy with the table at a communication step equal to the integration step. A jump between two
step starts therefore acts at the next step start (:func:`late_switches` names them).

:func:`run_held` applies a table through the generated fixed-step driver, one driver call per
stretch of steps with the same held values.
"""
from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mbs.envelope import SPEED_RANGE  # the initial forward speed that --set speed=V accepts, m/s

SPEED = "speed"


@dataclass
class InputTable:
    """Rows of an input table: ``time`` (m,) s, non-decreasing (a time at most twice: a jump),
    ``values`` (m, k) of the parameters ``names``; ``path`` the file it came from."""

    time: np.ndarray
    names: list[str]
    values: np.ndarray
    path: str = ""
    line_numbers: list[int] | None = None  # of the rows in the file (for messages)

    def line(self, i: int) -> int:
        """The file's line number of row ``i``."""
        return self.line_numbers[i] if self.line_numbers else i + 2

    def at(self, t: np.ndarray) -> np.ndarray:
        """Held values (n, k) at the step starts ``t`` (n,) s: linear between rows, the later row at a jump."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        i = np.searchsorted(self.time, t * (1 + 1e-12) + 1e-15, side="right") - 1
        i = np.clip(i, 0, len(self.time) - 1)
        j = np.minimum(i + 1, len(self.time) - 1)
        span = self.time[j] - self.time[i]
        w = np.where(span > 0, (t - self.time[i]) / np.where(span > 0, span, 1.0), 0.0)
        w = np.clip(w, 0.0, 1.0)[:, None]
        return self.values[i] + w * (self.values[j] - self.values[i])  # exact where the table is flat

    def rows(self) -> list[dict]:
        """The table as ``[{"time": t, name: value, ...}, ...]`` (the FMU demo's ``schedule`` in run.json)."""
        return [{"time": float(t), **dict(zip(self.names, map(float, v)))} for t, v in zip(self.time, self.values)]

    def summary(self) -> dict:
        return {"file": self.path, "columns": self.names, "interpolation": INTERPOLATION, "rows": self.rows()}


INTERPOLATION = ("linear between rows (a time written twice is a jump), each step holding the values at its start, "
                 "as fmpy drives an FMU whose communication step is the integration step")


# -- reading ------------------------------------------------------------------------------------------

def read_table(path: str | Path) -> InputTable:
    """The input table in the CSV file ``path``; ValueError naming the file, line and column of
    the first problem."""
    path = Path(path)
    lines = _lines(path)
    names = [n.strip() for n in next(csv.reader([lines[0]]))]
    _check_header(path, names)
    numbers = [k + 2 for k, line in enumerate(lines[1:]) if line.strip()]
    rows = [_row(path, k, names, lines[k - 1]) for k in numbers]
    if not rows:
        raise ValueError(f"{path}: no rows after the header (give a row at time 0)")
    table = InputTable(np.array(rows)[:, 0], names[1:], np.array(rows)[:, 1:], str(path), numbers)
    _check_times(table)
    return table


def _lines(path: Path) -> list[str]:
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise ValueError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ValueError(f"{path} is a folder; give a CSV file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path} cannot be read as text: {getattr(exc, 'strerror', None) or exc}") from None
    lines = text.splitlines()
    if not lines or not lines[0].strip():
        raise ValueError(f"{path} is empty: expected a header 'time,NAME,...' and rows")
    return lines


def _check_header(path: Path, names: list[str]) -> None:
    if names[0] != "time":
        hint = next((f"; separate the columns with commas, not {c!r}" for c in ";\t" if c in names[0]), "")
        raise ValueError(f"{path}: the first column must be 'time' (s), not {names[0]!r}{hint}")
    if len(names) < 2:
        raise ValueError(f"{path}: no input columns after 'time'")
    seen = {n for n in names if names.count(n) > 1 or not n}
    if seen:
        raise ValueError(f"{path}: column {sorted(seen)[0]!r} is named twice or empty")


def _row(path: Path, line_no: int, names: list[str], line: str) -> list[float]:
    fields = next(csv.reader([line]))
    if len(fields) != len(names):
        raise ValueError(f"{path}: line {line_no} has {len(fields)} values for {len(names)} columns")
    out = []
    for name, text in zip(names, fields):
        try:
            value = float(text)
        except ValueError:
            raise ValueError(f"{path}: line {line_no}, column {name!r}: {text.strip()!r} is not a number") from None
        if not math.isfinite(value):
            raise ValueError(f"{path}: line {line_no}, column {name!r}: {text.strip()} is not a finite number")
        out.append(value)
    return out


def _check_times(table: InputTable) -> None:
    path, t = table.path, table.time
    if t[0] > 0:
        raise ValueError(f"{path}: the first row is at time {t[0]:g} s; the run starts at 0 s (give a row at time 0)")
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        k = back[0]
        raise ValueError(f"{path}: line {table.line(k + 1)}: time {t[k + 1]:g} s is before the previous row's "
                         f"{t[k]:g} s")
    triple = np.flatnonzero((np.diff(t)[:-1] == 0) & (np.diff(t)[1:] == 0))
    if triple.size:
        raise ValueError(f"{path}: time {t[triple[0]]:g} s is written three times (twice is a jump; more is ambiguous)")


# -- checks against the model -------------------------------------------------------------------------

def check_settings(settings: dict[str, float], parameters: dict, scene: str, free: bool) -> None:
    """Refuse (ValueError naming it) a ``--set`` name that is neither a parameter of the model
    (``parameters``: name -> ``{"low", "high", "unit"}``) nor ``speed``, a value outside the
    parameter's range, and ``speed`` on a scene without a free fuselage."""
    known = [*parameters, *([SPEED] if free else [])]
    for name, value in settings.items():
        if name == SPEED:
            _check_speed(value, scene, free)
        else:
            _check_value(f"--set {name}={value:g}", name, value, parameters, scene, known)


CONSTANT_IN_A_RUN = {
    "omega": "the driven hubs turn at azimuth = omega t with no rotor acceleration modelled, so a rotor speed that "
             "changes during a run would give a wrong azimuth (a ramp turns the rotor too slowly, a step jumps it)",
}
"""Parameters that must keep one value through a run (an input table may not change them): why."""


def check_table(table: InputTable, parameters: dict, scene: str, settings: dict[str, float]) -> None:
    """Refuse a column that is not a parameter (or is also ``--set``), one that changes a
    parameter of :data:`CONSTANT_IN_A_RUN`, and a value outside its range."""
    where = f"--inputs {table.path}"
    for k, name in enumerate(table.names):
        if name == SPEED:
            raise ValueError(f"{where}: column 'speed': the forward speed is an initial condition, not an input; "
                             "set it with --set speed=V")
        if name in settings:
            raise ValueError(f"{where}: column {name!r} is also given by --set {name}=...; give it in one place")
        if name in CONSTANT_IN_A_RUN and name in parameters:
            values = table.values[:, k]
            change = np.flatnonzero(values != values[0])
            what = (f"changes from {values[0]:g} to {values[change[0]]:g} (line {table.line(int(change[0]))}), but"
                    if change.size else "is an input table column, but it sets the run's step and revolutions and")
            raise ValueError(f"{where}: column {name!r} {what} {CONSTANT_IN_A_RUN[name]}; give one value with --set "
                             f"{name}=VALUE, or one run per value with 'heli sweep simulate {scene} --param "
                             f"{name}=LO:HI:N'")
        for i, value in enumerate(table.values[:, k]):
            _check_value(f"{where}: line {table.line(i)}", name, float(value), parameters, scene, list(parameters))


def _check_value(where: str, name: str, value: float, parameters: dict, scene: str, known: list[str]) -> None:
    if name not in parameters:
        from mbs.models.helicopter.environment import hint

        raise ValueError(f"{where}: {name!r} is not a parameter of scene {scene!r}{hint(name)} (settable: "
                         f"{', '.join(known) or 'none'})")
    q = parameters[name]
    low, high, unit = q.get("low", -math.inf), q.get("high", math.inf), q.get("unit", "")
    if not low <= value <= high:
        hint = (f" (angles are in rad: {value:g} deg would be {math.radians(value):.4g} rad)"
                if unit == "rad" and low <= math.radians(value) <= high else
                f" (rotor speeds are in rad/s: {value:g} rpm would be {value * math.pi / 30:.4g} rad/s)"
                if unit == "rad/s" and low <= value * math.pi / 30 <= high else "")
        raise ValueError(f"{where}: {name} = {value:g} {unit} is outside its range [{low:g}, {high:g}] {unit}"
                         .replace("  ", " ").rstrip() + hint)


def _check_speed(value: float, scene: str, free: bool) -> None:
    if not free:
        raise ValueError(f"--set speed={value:g}: scene {scene!r} has no free fuselage, so no flight speed "
                         "(speed applies to scenes that fly: forward-flight, hover, structural)")
    low, high = SPEED_RANGE
    if not low <= value <= high:
        raise ValueError(f"--set speed={value:g}: the initial forward speed must lie in [{low:g}, {high:g}] m/s")


def late_switches(table: InputTable, h: float, stop: float) -> list[tuple[float, float]]:
    """``(written, applied)`` times (s) of the jumps of ``table`` before ``stop`` that fall between
    two step starts (steps of ``h`` s from 0): each acts at the next step start."""
    t = table.time
    jumps = t[1:][(np.diff(t) == 0) & (t[1:] > 0) & (t[1:] < stop)]
    out = []
    for tj in np.unique(jumps):
        k = tj / h
        if abs(k - round(k)) > 1e-9 * max(1.0, k):
            out.append((float(tj), math.ceil(k) * h))
    return out


# -- the initial forward speed --------------------------------------------------------------------------

def forward_speed_direction(info, x0: np.ndarray) -> tuple[list[int], np.ndarray] | None:
    """``(velocity indices, direction)`` of the free fuselage: body-axis components of level
    flight along the x axis of the ground at the attitude of ``x0`` (``R(q0)^T e_x``), the
    FMU's ``initial_forward_speed``; None without a free body."""
    body = next((b for b in info.bodies if b["joint"] == "FreeJoint"), None)
    if body is None:
        return None
    w, x, y, z = (x0[info.state_names.index(n)] for n in body["q_names"][3:7])
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    first_row = np.array([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)])
    return [info.state_names.index(n) for n in body["v_names"][:3]], first_row


def with_forward_speed(info, x0: np.ndarray, speed: float) -> np.ndarray:
    """``x0`` with the free fuselage flying level at ``speed`` (m/s) at its initial attitude."""
    found = forward_speed_direction(info, x0)
    if found is None:
        raise ValueError(f"speed = {speed:g} m/s: model {info.name!r} has no free fuselage")
    index, direction = found
    x = np.array(x0, dtype=float)
    x[index] = speed * direction
    return x


def initial_speed(info, x0: np.ndarray) -> float | None:
    """The forward speed (m/s) of the free fuselage in ``x0``, None without one."""
    found = forward_speed_direction(info, x0)
    return None if found is None else float(found[1] @ np.asarray(x0)[found[0]])


# -- running ----------------------------------------------------------------------------------------

def held_rows(system, p: np.ndarray, table: InputTable, times: np.ndarray) -> np.ndarray:
    """Parameter vectors (n, np) in force over steps starting at ``times`` (n,) s."""
    index = [system.info.param_names.index(n) for n in table.names]
    out = np.repeat(np.asarray(p, dtype=float)[None, :], len(times), axis=0)
    out[:, index] = table.at(times)
    return out


def stretch_starts(table: InputTable, h: float, n: int) -> np.ndarray:
    """First steps of the stretches of equal held inputs among ``n`` steps of ``h`` s from 0:
    step 0, the first step at or after each row's time, and every step where the table ramps."""
    k = np.ceil(table.time / h - 1e-9).astype(np.int64)
    starts = [np.array([0]), k]
    ramps = np.flatnonzero((np.diff(table.time) > 0) & np.any(np.diff(table.values, axis=0) != 0, axis=1))
    starts += [np.arange(k[i], k[i + 1]) for i in ramps]
    out = np.unique(np.concatenate(starts))
    return out[(out >= 0) & (out < n)]


def run_held(system, x0, h: float, n: int, p: np.ndarray, table: InputTable, every: int = 1,
             method: str = "rk4", progress=None, compensated: bool = True):
    """``n`` fixed steps of ``h`` s from ``x0`` at ``t = 0`` with the inputs of ``table`` held over
    each step (parameters ``p`` otherwise), rows every ``every`` steps and at the end as
    :meth:`mbs.System.run` records them; one driver call per stretch of equal inputs.

    Returns ``(trajectory, params)``: a :class:`mbs.backends.system.Trajectory` and the
    parameters (rows, np) in force from each recorded row on (the last row: those of the last step).
    """
    from mbs.backends.system import Result, Trajectory

    starts = stretch_starts(table, h, n)
    held = held_rows(system, p, table, starts * h)
    x, rows, steps = np.asarray(x0, dtype=float), [np.asarray(x0, dtype=float)[None, :]], [0]
    wall, nfev, result, message = 0.0, system.nfev, Result.successful, Result.successful.value
    for a, b, pk in zip(starts, np.r_[starts[1:], n], held):
        for c, d, e in _pieces(int(a), int(b), every):
            report = (lambda k, m, c=c: progress(c + k, n)) if progress else None
            traj = system.run(x, c * h, h, d - c, every=e, p=pk, method=method, progress=report,
                              compensated=compensated)
            wall, nfev, x = wall + traj.wall_s, traj.nfev, traj.x[-1]
            k = c + np.r_[0, np.minimum(np.arange(1, len(traj.x)) * e, d - c)]
            keep = [i for i in range(1, len(k)) if k[i] % every == 0 or k[i] == n or not traj.ok]
            rows.append(traj.x[keep])
            steps += [int(k[i]) for i in keep]
            if not traj.ok:
                result = traj.result
                message = re.sub(r"step (\d+)\)", lambda m, c=c: f"step {c + int(m.group(1))})", traj.message)
                break
        if result is not Result.successful:
            break
    steps = np.array(steps)
    traj = Trajectory(steps * h, np.concatenate(rows), result, message, nfev, wall, system.info)
    return traj, held_rows(system, p, table, np.minimum(steps, n - 1) * h)


def _pieces(a: int, b: int, every: int) -> list[tuple[int, int, int]]:
    """Driver calls ``(first step, end step, every)`` covering steps ``a`` to ``b`` so that the
    rows fall on multiples of ``every`` (and at ``b``)."""
    first = -(-a // every) * every if a % every else a
    if first == a:
        return [(a, b, every)]
    if first >= b:
        return [(a, b, b - a)]
    return [(a, first, first - a), (first, b, every)]
