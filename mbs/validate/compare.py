"""Side by side: each published point against the model's value at the same speed, in the
published unit: difference (ours - published), ratio (ours / published) and whether the
difference is within the series' tolerance."""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from mbs.validate.quantities import converter, derivative_value, trim_value


@dataclass
class Row:
    """One published point and the model's value (both in ``unit``); ``within`` None when the
    series has no tolerance, False when the model has no value there (``problem`` says why);
    ``ratio`` NaN where the published value is within the series' absolute tolerance of zero."""

    kind: str
    quantity: str
    unit: str
    speed: float
    ours: float
    published: float
    uncertainty: float
    difference: float
    ratio: float
    within: bool | None
    source: str
    problem: str = ""
    condition: str = ""  # the point's mass, altitude and CG where the data give them ("2100 kg, 1500 m")

    def summary(self) -> dict:
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in asdict(self).items()}


def rows(series, model) -> list[Row]:
    """The rows of one :class:`mbs.validate.data.Series` against the model's points."""
    convert = None
    out = []
    echoed = series.shown_conditions or [describe_condition(*c) for _, *c in series.conditions()]
    for (speed, *condition), shown, pub, unc, said in zip(series.conditions(), series.shown_speed, series.value,
                                                           series.uncertainty, echoed):
        point = model.at(speed, *condition)
        value, problem = math.nan, point.problem
        if point.ok:
            si, si_unit = _value(series, point)
            convert = convert or converter(si_unit, series.unit, f"{series.kind} {series.quantity}")
            value = series.ours_factor * convert(si)
        row = _row(series, float(shown), value, float(pub), float(unc), problem)
        row.condition = said
        out.append(row)
    return out


def describe_condition(mass: float | None, altitude: float | None, cg_x: float | None = None) -> str:
    """``"2100 kg, 1500 m, CG +0.076 m"`` of a point's given mass, altitude and CG forward of the
    aircraft file's ("" without them)."""
    return ", ".join(t for t in (None if mass is None else f"{mass:.6g} kg",
                                 None if altitude is None else f"{altitude:.6g} m",
                                 None if cg_x is None else f"CG {cg_x:+.4g} m") if t)


def _value(series, point) -> tuple[float, str]:
    if series.kind == "trim":
        return trim_value(point.trim, series.quantity)
    return derivative_value(point.derivatives, series.quantity)


def _row(series, speed: float, ours: float, pub: float, unc: float, problem: str) -> Row:
    diff = ours - pub
    floor = series.tolerance.absolute if series.tolerance and series.tolerance.absolute else 0.0
    ratio = ours / pub if abs(pub) > floor else math.nan  # within its tolerance of zero a ratio means nothing
    within = None if series.tolerance is None else (not problem and series.tolerance.within(ours, pub))
    return Row(series.kind, series.quantity, series.unit, speed, ours, pub, unc, diff, ratio, within, series.source,
               problem)


def counts(all_rows: list[Row]) -> dict[str, int]:
    """How many rows were checked (have a tolerance), are within it, and have no model value."""
    checked = [r for r in all_rows if r.within is not None]
    return {"rows": len(all_rows), "checked": len(checked), "within": sum(bool(r.within) for r in checked),
            "no_model_value": sum(bool(r.problem) for r in all_rows)}
