"""The validation as text (a table per published series, the eigenvalue pairs, the verdict) and
as plain data (JSON)."""
from __future__ import annotations

import math
import re

import numpy as np

from mbs.validate.data import ADVANCE_RATIO, EigenTolerance

MARK = {True: "ok", False: "OUT", None: ""}


def lines(res) -> list[str]:
    """The human-readable report of :func:`mbs.validate.runner.validate`."""
    v = res.validation
    cited = v.cited_sources()
    out = [f"{v.title}", f"  data: {v.path}", f"  model: {res.model.aircraft or 'default aircraft'}, scene {v.scene}; "
           f"{_count(len(res.model.points), 'flight condition')} in {res.model.wall_s:.1f} s",
           *[f"  convention, {k}: {t}" for k, t in v.conventions.items()],
           *([f"  model's controls: {res.model.controls}"] if res.model.controls else []),
           *([f"  speeds: advance ratios mu = V / (Omega R) of the aircraft file's tip speed Omega R = "
              f"{v.per_unit:.5g} m/s"] if v.speed_unit in ADVANCE_RATIO else []),
           *[f"  source {k}: {t}" + ("" if k in cited else " (cited by no series)") for k, t in v.sources.items()]]
    out += problem_lines(res)
    out += warning_lines(res)
    for s, rows in res.blocks:
        out += series_lines(s, rows, v)
    if res.pairs:
        out += eigen_lines(res.pairs, v.eigen_tolerance or EigenTolerance(), v.speed_unit)
    return out + verdict_lines(res)


def problem_lines(res) -> list[str]:
    """Each point the model could not give, with its reason, at its speed and condition as the data
    give them."""
    from mbs.validate.data import condition_key

    v = res.validation
    factor = v.per_unit
    shown = {condition_key(*c): (r.speed, r.condition) for s, rows in res.blocks
             for c, r in zip(s.conditions(), rows)}
    out = []
    for key, p in res.model.points.items():
        if not p.ok:
            speed, condition = shown.get(key, (p.speed / factor, p.condition))
            out.append(f"  at {speed:.6g} {v.speed_unit}{', ' + condition if condition else ''}: {p.problem}")
    return out


def series_lines(s, rows, v) -> list[str]:
    tol = f"tolerance {s.tolerance.describe(s.unit)}" if s.tolerance else "no tolerance (shown, not checked)"
    head = [f"{s.kind} {s.quantity} [{s.unit}]: {tol}; source {s.source}"]
    if s.ours_factor != 1.0:
        head.append(f"  model's value times {s.ours_factor:g}: {s.note}")
    elif s.note:
        head.append(f"  note: {s.note}")
    given = [what for what, x in (("its mass (a weight added at the CG)", s.mass), ("ISA altitude", s.altitude),
                                  ("CG", s.cg_x if s.cg_x is not None else s.cg_station)) if x is not None]
    if given:
        head.append(f"  each point at {' and '.join(given)} as published")
    w = max(10, len(f"speed {v.speed_unit}"))
    head.append(f"  {'speed ' + v.speed_unit:>{w}s} {'ours':>11s} {'published':>11s} {'±':>8s} {'ours-pub':>11s} "
                f"{'ours/pub':>9s}")
    return head + [_row_line(r, w) for r in rows]


def _row_line(r, w: int = 10) -> str:
    at = f"  ({r.condition})" if r.condition else ""
    unc = f"{r.uncertainty:8.2g}" if r.uncertainty else f"{'—':>8s}"  # not stated, not exact
    if r.problem:  # its reason is said once above the tables
        return f"  {r.speed:{w}.4g} {'—':>11s} {r.published:+11.4g} {unc}  {r.problem.split(':')[0]} (said above){at}"
    ratio = f"{r.ratio:9.3f}" if math.isfinite(r.ratio) else " " * 9
    return (f"  {r.speed:{w}.4g} {r.ours:+11.4g} {r.published:+11.4g} {unc} {r.difference:+11.4g} "
            f"{ratio} {MARK[r.within]:3s}{at}").rstrip()


def eigen_lines(pairs, tol: EigenTolerance, speed_unit: str) -> list[str]:
    w = max(10, len(f"speed {speed_unit}"))
    out = [f"eigenvalues (1/s, rad/s), each published one paired with the nearest of the model's: same stability "
           f"(|Re| <= {tol.neutral:g} 1/s neutral) and within {100 * tol.frequency:g} % the frequency |Im| of a "
           f"published oscillation (|Im| >= {tol.min_frequency:g} rad/s) or the rate |λ| of a published subsidence",
           f"  {'speed ' + speed_unit:>{w}s} {'published':>20s} {'ours':>20s} {'mode (ours)':22s} {'ratio':>7s} measure"]
    for p in pairs:
        ratio = f"{p.ratio:7.3f}" if p.ratio is not None else " " * 7
        verdict = "ok" if p.within else ("OUT: stability" if not p.same_stability else f"OUT: {p.measure}")
        out.append(f"  {p.speed:{w}.4g} {_z(p.published):>20s} {_z(p.ours):>20s} {p.mode:22s} {ratio} {p.measure:9s} "
                   f"{verdict}")
    return out


def _z(z: complex) -> str:
    return f"{z.real:+.4f}{z.imag:+.4f}i" if z.imag else f"{z.real:+.4f}"


def verdict_lines(res) -> list[str]:
    c = res.counts()
    out = []
    for kind in ("trim", "derivative"):
        k = c[kind]
        if k["rows"]:
            out.append(f"{kind}s: {k['within']} of {_count(k['checked'], 'checked point')} within tolerance "
                       f"({_count(k['rows'], 'point')}, {k['no_model_value']} without a model value)")
    if res.pairs:
        e = c["eigenvalues"]
        out.append(f"eigenvalues: {e['within']} of {e['pairs']} within tolerance, {e['same_stability']} of the same "
                   "stability")
    if not res.pairs and not any(c[kind]["checked"] for kind in ("trim", "derivative")):
        out.append("nothing checked: no series gives a tolerance, so its values are shown, not judged")
    else:
        out.append("all within tolerance" if res.all_within else "NOT all within tolerance")
    return out


NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")
LISTED_SPEEDS = 4
"""A warning given at more points than this is listed with their count and speed range."""


def warnings(res) -> dict[str, tuple[list[str], list[float]]]:
    """Each kind of warning of the model's trims and derivatives (:func:`mbs.analysis.trim_checks.warnings`,
    the derivatives' own), its figures aside: its texts and the speeds (m/s) of the points that gave it."""
    out: dict[str, tuple[list[str], list[float]]] = {}
    for p in sorted(res.model.points.values(), key=lambda p: p.speed):
        found = [*getattr(p.trim, "warnings", []), *getattr(p.derivatives, "warnings", [])]
        for text in dict.fromkeys(found):
            texts, speeds = out.setdefault(NUMBER.sub("#", text), ([], []))
            texts.append(text)
            speeds.append(p.speed)
    return out


FILE_WARNINGS = ("aircraft.inertia:",)
"""Warnings the trims carry of the aircraft file itself (its inertias): said once, not per point."""


def warning_lines(res) -> list[str]:
    """One line per kind of warning, at the speeds (in the data's unit) of the points that gave it;
    where its figures differ from point to point, those of the slowest."""
    v = res.validation
    factor = v.per_unit
    found = warnings(res).values()
    out = [f"  warning of the aircraft file: {texts[0]}" for texts, _ in found if texts[0].startswith(FILE_WARNINGS)]
    for texts, speeds in found:
        if texts[0].startswith(FILE_WARNINGS):
            continue
        shown = [x / factor for x in speeds]
        distinct = sorted(set(round(x, 9) for x in shown))  # points of several conditions at one speed: once
        at = (", ".join(f"{x:.4g}" for x in distinct) + (f" ({len(shown)} points)" if len(shown) > len(distinct) else "")
              if len(distinct) <= LISTED_SPEEDS else f"{len(shown)} points, {min(shown):.4g} to {max(shown):.4g}")
        figures = "" if len(set(texts)) == 1 else f" (the figures at {shown[0]:.4g} {v.speed_unit})"
        out.append(f"  warning at {at} {v.speed_unit}{figures}: {texts[0]}")
    return out


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def worst(rows, relative: bool) -> dict[str, float]:
    """For each quantity the largest |difference| (or |ratio - 1|) of its rows with a model value."""
    out: dict[str, float] = {}
    for r in rows:
        if r.problem:
            continue
        err = abs(r.ratio - 1.0) if relative else abs(r.difference)
        if math.isfinite(err):
            out[r.quantity] = max(out.get(r.quantity, 0.0), err)
    return out


def summary(res) -> dict:
    """Plain-data form (JSON)."""
    v = res.validation
    return {"title": v.title, "data": str(v.path), "aircraft": res.model.aircraft, "scene": v.scene,
            "speed_unit": v.speed_unit, "conventions": v.conventions, "sources": v.sources,
            "uncited_sources": sorted(set(v.sources) - v.cited_sources()),
            "series": [{"kind": s.kind, "quantity": s.quantity, "unit": s.unit, "source": s.source, "note": s.note,
                        "ours_factor": s.ours_factor,
                        "tolerance": None if s.tolerance is None else vars(s.tolerance)} for s in v.series],
            "rows": [r.summary() for r in res.rows], "eigenvalues": [p.summary() for p in res.pairs],
            "model": {"speeds_m_s": sorted({p.speed for p in res.model.points.values()}),
                      "points": [_point_summary(k) for k in sorted(res.model.points, key=_point_order)],
                      "wall_s": res.model.wall_s,
                      "controls": res.model.controls,
                      "problems": {str(p.speed): p.problem for p in res.model.points.values() if not p.ok}},
            "warnings": [{"texts": texts, "speeds_m_s": speeds} for texts, speeds in warnings(res).values()],
            "counts": res.counts(), "all_within": res.all_within,
            "worst": {"trim_abs": worst([r for r in res.rows if r.kind == "trim"], False),
                      "derivative_rel": worst([r for r in res.rows if r.kind == "derivative"], True),
                      "eigen_size_rel": _eigen_worst(res.pairs)}}


def _point_order(key) -> tuple:
    """A model point's key (a speed alone, or with its mass, altitude and CG) in an order that
    mixes both (the file's conditions, given as None, first)."""
    speed, *rest = key if isinstance(key, tuple) else (key, None, None, None)
    return (speed, *((x is not None, x or 0.0) for x in rest))


def _point_summary(key) -> dict:
    speed, mass, altitude, cg_x = key if isinstance(key, tuple) else (key, None, None, None)
    return {"speed_m_s": speed, "mass_kg": mass, "altitude_m": altitude, "cg_x_m": cg_x}


def _eigen_worst(pairs) -> float | None:
    errs = [abs(p.ratio - 1.0) for p in pairs if p.ratio is not None]
    return float(np.max(errs)) if errs else None
