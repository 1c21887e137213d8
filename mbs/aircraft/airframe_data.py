"""Airframe aerodynamic tables of the aircraft file, as a report prints them, brought to the model.

A component table (``[fuselage_aero] lift_alpha``, ``yaw_beta``, ``drag_alpha_beta`` ...) is
read with its unit deciding what it is: an area or volume (``ft^2``, ``m^3``: per dynamic
pressure, ``D/q``), a force or moment (``lbf``, ``N m``: loads at ``reference_speed``) or ``-``
(coefficients on ``reference_area`` and, for moments, ``reference_length``). Each becomes SI
per dynamic pressure once (:func:`per_q`), about the reference point from the CG
(:func:`reference_point`); :func:`converted` lists every such conversion with its source for
``heli aircraft check``.
"""
from __future__ import annotations

import numpy as np

from mbs.aircraft import stations, units

FORMS = {(2, 0, 0, 0): "per_q", (3, 0, 0, 0): "per_q", (1, 1, -2, 0): "load", (2, 1, -2, 0): "load",
         (0, 0, 0, 0): "coefficient"}
FORCE_DIMS, MOMENT_DIMS = {(2, 0, 0, 0), (1, 1, -2, 0)}, {(3, 0, 0, 0), (2, 1, -2, 0)}


def read_series(value, unit: str, spec) -> list[float]:
    """Breakpoints: at least two strictly increasing numbers, in SI."""
    return _increasing(value, unit, spec.unit)


def _increasing(value, unit: str, target: str) -> list[float]:
    factor = units.factor_to(str(unit), target)
    if not (isinstance(value, list) and len(value) >= 2 and all(_is_number(v) for v in value)):
        raise ValueError("must be a list of at least two numbers (the breakpoints)")
    out = [float(v) * factor for v in value]
    bad = next((i for i in range(1, len(out)) if out[i] <= out[i - 1]), None)
    if bad is not None:
        raise ValueError(f"breakpoints must increase: {value[bad]!r} follows {value[bad - 1]!r}")
    return out


def read_curve(value, unit: str, spec) -> list[float]:
    """Values on breakpoints given elsewhere: at least two numbers, in SI."""
    if "," in str(unit) or (isinstance(value, list) and any(isinstance(v, list) for v in value)):
        raise ValueError(f"must be one list of numbers in one unit, one per breakpoint, not rows in {unit!r}: a table "
                         "in two variables is not taken here (a stabilator's incidence is a curve in airspeed; its "
                         "dependence on the collective, linear, is collective_gain about collective_reference)")
    factor = units.factor_to(str(unit), spec.unit)
    if not (isinstance(value, list) and len(value) >= 2 and all(_is_number(v) for v in value)):
        raise ValueError("must be a list of at least two numbers (one per breakpoint)")
    return [float(v) * factor for v in value]


def read_lookup(value, unit: str, spec) -> dict:
    """A component table (a list, or a list of rows) with its form: ``{"form", "unit", "values"}``
    (values in SI of that form: m², m³, N, N m or a pure number). A curve digitised at its own
    angles is rows ``[angle, value]`` with two units (``"deg, ft^2"``): it adds ``"breakpoints"``
    (rad) and needs no shared ``alpha`` or ``beta``."""
    if "," in str(unit):
        return read_curve_points(value, str(unit), spec)
    moment = spec.unit.startswith("m^3")
    allowed = MOMENT_DIMS if moment else FORCE_DIMS
    have = units.reading(str(unit), allowed)
    if have.dims not in allowed | {(0, 0, 0, 0)} or have.per_rev:
        want = "a volume (M/q), a moment at reference_speed or -" if moment else \
            "an area (D/q), a force at reference_speed or -"
        raise ValueError(f"unit {unit!r} is {have.describe()}; give {want}")
    rows = value if isinstance(value, list) and value and isinstance(value[0], list) else None
    flat = [v for r in rows for v in r] if rows is not None else value
    if not (isinstance(flat, list) and flat and all(_is_number(v) for v in flat)):
        raise ValueError("must be a list of numbers (one per breakpoint) or a list of rows (alpha x beta)")
    if rows is not None and len({len(r) for r in rows}) != 1:
        raise ValueError("rows of different lengths: a two-argument table has one row per alpha, one column per beta")
    scaled = (np.asarray(rows if rows is not None else value, dtype=float) * have.factor).tolist()
    return {"form": FORMS[have.dims], "unit": str(unit), "values": scaled}


def read_curve_points(value, unit: str, spec) -> dict:
    """Rows ``[angle, value]`` of a one-argument table at its own angles, ``unit`` ``"<angle>,
    <value>"``: :func:`read_lookup`'s table with ``"breakpoints"`` (rad, increasing)."""
    texts = [u.strip() for u in unit.split(",")]
    if len(texts) == 3:
        return read_grid_points(value, texts, spec)
    if len(texts) != 2:
        raise ValueError(f"unit {unit!r}: a curve at its own angles takes two units, the angle's and the "
                         "values' (e.g. \"deg, ft^2\"); a table in alpha and beta on its own grid three (\"deg, deg, "
                         "ft^2\")")
    if not (isinstance(value, list) and len(value) >= 2 and all(isinstance(r, list) and len(r) == 2 for r in value)):
        raise ValueError("with two units, value must be rows [angle, value] (at least two), a curve at its own "
                         "angles; give one unit for values on the section's breakpoints")
    angle = _increasing([r[0] for r in value], texts[0], "rad")
    table = read_lookup([r[1] for r in value], texts[1], spec)
    return {**table, "unit": unit, "breakpoints": angle}


def read_grid_points(value, texts: list[str], spec) -> dict:
    """A table in alpha and beta on its own grid, printed as a report prints it: a first row
    ``[nan, beta_1, beta_2 ...]`` (the corner empty), then rows ``[alpha_i, value_i1, value_i2 ...]``;
    ``texts`` the units of alpha, beta and the values. :func:`read_lookup`'s table with
    ``"breakpoints"`` ``(alpha, beta)`` (rad)."""
    shape = "a first row [nan, beta...] and rows [alpha, values...]"
    if not (isinstance(value, list) and len(value) >= 3 and all(isinstance(r, list) for r in value)
            and len({len(r) for r in value}) == 1 and len(value[0]) >= 3):
        raise ValueError(f"with three units, value must be {shape} (at least two of each, rows of one length)")
    corner = value[0][0]
    if not (isinstance(corner, float) and np.isnan(corner)):
        raise ValueError(f"the first row's first cell is {corner!r}; write nan there (the corner of the printed "
                         f"table): {shape}")
    beta = _increasing(value[0][1:], texts[1], "rad")
    alpha = _increasing([r[0] for r in value[1:]], texts[0], "rad")
    table = read_lookup([r[1:] for r in value[1:]], texts[2], spec)
    return {**table, "unit": ", ".join(texts), "breakpoints": (alpha, beta)}


def read_polynomial(value, unit: str, spec) -> dict:
    """A one-argument component table printed as a law in its angle, ``c_0 + c_1 x + c_2 x² ...``
    (``M/q = XM1 + XM2 α``), with one unit per coefficient (``ft^3, ft^3/rad``): the form of
    ``c_0``'s unit, each ``c_k`` in SI per radian to the k. Returns ``{"form", "unit",
    "coefficients"}``; :func:`at_breakpoints` gives the values once the breakpoints are read."""
    texts = [u.strip() for u in str(unit).split(",")]
    if not (isinstance(value, list) and value and all(_is_number(v) for v in value)):
        raise ValueError("law = \"polynomial\": value must be the list of coefficients c_0, c_1 ... of the angle")
    if len(texts) != len(value):
        raise ValueError(f"law = \"polynomial\": {len(value)} coefficients but {len(texts)} units; give one unit per "
                         "coefficient, e.g. unit = \"ft^3, ft^3/rad\"")
    base = read_lookup([float(value[0])], texts[0], spec)
    dims = units.reading(texts[0], MOMENT_DIMS if spec.unit.startswith("m^3") else FORCE_DIMS).dims
    coefficients = [base["values"][0]]
    for k, (c, text) in enumerate(zip(value[1:], texts[1:]), start=1):
        want = (*dims[:3], dims[3] - k)
        have = units.reading(text, [want])
        if have.dims != want:
            raise ValueError(f"unit {text!r} of c_{k} is {have.describe()}; give c_0's unit per angle^{k} "
                             f"(e.g. {texts[0]}/rad{'' if k == 1 else f'^{k}'})")
        coefficients.append(float(c) * have.factor)
    return {"form": base["form"], "unit": str(unit), "coefficients": coefficients}


def read_expression(value, unit: str, spec, angle: str) -> dict:
    """A one-argument component table printed as a law in its ``angle`` (rad), ``value`` the law's
    text (:mod:`mbs.aircraft.laws`), ``unit`` its value's (read as :func:`read_lookup` reads one
    value): ``{"form", "unit", "expression", "factor"}``; :func:`at_breakpoints` values it."""
    from mbs.aircraft import laws

    laws.parse(value, angle)
    base = read_lookup([1.0], unit, spec)
    return {"form": base["form"], "unit": str(unit), "expression": value, "factor": base["values"][0], "angle": angle}


def at_breakpoints(table: dict, breakpoints) -> dict:
    """``table`` of :func:`read_polynomial` or :func:`read_expression` with its ``values`` at
    ``breakpoints`` (rad)."""
    x = np.asarray(breakpoints, dtype=float)
    if "expression" in table:
        from mbs.aircraft import laws

        with np.errstate(all="ignore"):
            values = table["factor"] * laws.value(laws.parse(table["expression"], table["angle"]), table["angle"], x)
        bad = ~np.isfinite(values)
        if bad.any():
            raise ValueError(f"the law {table['expression']!r} is not finite at {table['angle']} = "
                             f"{np.degrees(x[bad][0]):.6g} deg, a breakpoint; write it so that it is")
        return {**table, "values": values.tolist()}
    return {**table, "values": np.polynomial.polynomial.polyval(x, table["coefficients"]).tolist()}


def read_schedule(value, unit: str, spec) -> dict:
    """A schedule in collective and airspeed as printed: a first row ``[nan, airspeeds...]``, then
    rows ``[collective, values...]``; ``unit`` that of the collective (an angle, or ``-`` for a
    fraction of the lever's travel), the airspeed and the values. ``{"collective" (rad, or the
    fraction), "lever" (bool), "airspeed" (m/s), "values" (rad, rows by collective)}``."""
    texts = [u.strip() for u in str(unit).split(",")]
    shape = "a first row [nan, airspeeds...] and rows [collective, incidences...]"
    if len(texts) != 3:
        raise ValueError(f"give three units: the collective's (deg, or - for a fraction of the lever's travel), the "
                         f"airspeed's and the incidence's, e.g. unit = \"-, kt, deg\"; value is {shape}")
    if not (isinstance(value, list) and len(value) >= 3 and all(isinstance(r, list) for r in value)
            and len({len(r) for r in value}) == 1 and len(value[0]) >= 3):
        raise ValueError(f"value must be {shape} (at least two of each, rows of one length)")
    if not (isinstance(value[0][0], float) and np.isnan(value[0][0])):
        raise ValueError(f"the first row's first cell is {value[0][0]!r}; write nan there (the corner): {shape}")
    cells = [(i, j, c) for i, r in enumerate(value) for j, c in enumerate(r) if (i, j) != (0, 0)]
    bad = next(((i, j, c) for i, j, c in cells if not _is_number(c)), None)
    if bad is not None:
        where = "the airspeed row" if bad[0] == 0 else "a collective" if bad[1] == 0 else "an incidence"
        raise ValueError(f"row {bad[0] + 1}, column {bad[1] + 1} ({where}) is {bad[2]!r}: every cell but the corner "
                         "must be a finite number")
    collective_unit = units.parse(texts[0])
    if collective_unit.dims == (0, 0, 0, 0) and collective_unit.factor != 1.0:
        raise ValueError(f"the collective's unit {texts[0]!r}: give - for a fraction of the lever's travel (0 to 1), "
                         "or an angle (deg) for the blades' collective")
    lever = collective_unit.dims == (0, 0, 0, 0)
    collective = [float(r[0]) for r in value[1:]] if lever else _increasing([r[0] for r in value[1:]], texts[0], "rad")
    if lever and (np.any(np.diff(collective) <= 0) or min(collective) < 0 or max(collective) > 1):
        raise ValueError("the collective lever's fractions must increase within 0 to 1")
    airspeed = _increasing(value[0][1:], texts[1], "m/s")
    values = np.asarray([r[1:] for r in value[1:]], dtype=float) * units.factor_to(texts[2], "rad")
    return {"collective": collective, "lever": bool(lever), "airspeed": airspeed, "values": values.tolist(),
            "unit": str(unit)}


READERS = {"series": read_series, "curve": read_curve, "lookup": read_lookup, "schedule": read_schedule}


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v)


COMPONENTS = {"body": ("X", "Y", "Z", "L", "M", "N"), "stability": ("drag", "side", "lift", "roll", "pitch", "yaw")}
COMPONENTS["wind"] = COMPONENTS["stability"]
ARGUMENTS = ("alpha", "beta", "alpha_beta")


def given(fa: dict) -> dict[str, dict]:
    """The component tables the section gives: ``"lift_alpha" -> {"form", "unit", "values"}``."""
    return {k: v for k, v in fa.items() if isinstance(v, dict) and "form" in v}


def table_problems(values: dict) -> list[str]:
    """Problems of ``[fuselage_aero]`` tables: names of the stated axes, lengths against the
    breakpoints, the reference point, the reference speed, area and length the forms need."""
    fa = values["fuselage_aero"]
    if fa.get("model") != "tables":
        return []
    out, tables = [], given(fa)
    names = COMPONENTS[fa["axes"]]
    if not tables:
        out.append("fuselage_aero: model = \"tables\" but no table given (e.g. lift_alpha, drag_alpha)")
    for key, table in tables.items():
        name, _, arg = key.partition("_")
        if name not in names:
            out.append(f"fuselage_aero.{key}: {name} is not a component in {fa['axes']} axes "
                       f"({', '.join(names)})")
        out += _shape_problems(fa, key, arg, np.asarray(table["values"]), table.get("breakpoints"))
        out += _form_problems(fa, key, table["form"], names.index(name) >= 3 if name in names else False)
    if not len(fa["reference_point"]) and not (len(fa["reference_station"]) and len(fa["cg_station"])):
        out.append("fuselage_aero.reference_point: missing; give the point the moments are about (x, y, z from "
                   "the CG), or reference_station and cg_station")
    if len(fa["reference_point"]) and len(fa["reference_station"]):
        out.append("fuselage_aero.reference_station: give the reference point once (reference_point or stations)")
    return out


def _shape_problems(fa: dict, key: str, arg: str, values: np.ndarray, own=None) -> list[str]:
    if own is not None:
        if (arg == "alpha_beta") == isinstance(own, tuple):
            return []
        return [f"fuselage_aero.{key}: rows [angle, value] make a curve in one angle; give a table in alpha and beta "
                "as a first row [nan, beta...] and rows [alpha, values...] with three units (\"deg, deg, ft^2\")"
                if arg == "alpha_beta" else
                f"fuselage_aero.{key}: a table on an alpha x beta grid (three units) is for {key.partition('_')[0]}"
                "_alpha_beta; a curve in one angle is rows [angle, value] with two units"]
    want = tuple(len(fa[a]) for a in arg.split("_") if a in ("alpha", "beta"))
    missing = [a for a in ("alpha", "beta") if a in arg and len(fa[a]) < 2]
    if missing:
        return [f"fuselage_aero.{key}: needs the breakpoints fuselage_aero.{missing[0]}"]
    if values.shape != want:
        return [f"fuselage_aero.{key}: {' x '.join(map(str, values.shape))} values for "
                f"{' x '.join(map(str, want))} breakpoints ({arg.replace('_', ' x ')})"]
    return []


def _form_problems(fa: dict, key: str, form: str, moment: bool) -> list[str]:
    if form == "per_q":  # its dimension was checked when the entry was read
        return []
    if form == "load":
        return [] if fa["reference_speed"] > 0 else [f"fuselage_aero.{key}: loads at a speed need "
                                                     "fuselage_aero.reference_speed"]
    need = ["reference_area"] + (["reference_length"] if moment else [])
    return [f"fuselage_aero.{key}: coefficients need fuselage_aero.{n}" for n in need if fa[n] <= 0]


def has_horizontal_tail(values: dict) -> bool:
    """Whether the file gives a ``[horizontal_tail]`` (left out: the aircraft has none)."""
    return "area" in (values.get("horizontal_tail") or {})


def has_stabilator(values: dict) -> bool:
    """Whether the file gives a ``[stabilator]`` (its defaults alone do not make one)."""
    st = values.get("stabilator") or {}
    return "airspeed" in st or bool(st.get("incidence_table"))


def schedule_collective(values: dict) -> list[float]:
    """A two-variable stabilator schedule's collective breakpoints as the model's blade collective
    (rad): as given, or the lever's fractions through the rigging (ValueError without one, or when
    the blades' collective follows another pilot control too)."""
    from mbs.aircraft import rigging

    table = values["stabilator"]["incidence_table"]
    if not table["lever"]:
        return list(table["collective"])
    rig = rigging.rigging(values)
    if rig is None:
        raise ValueError("stabilator.incidence_table: its collective is a fraction of the lever's travel (unit -), "
                         "which needs the file's [controls] rigging; give the blades' collective (deg) instead")
    if np.any(rig.matrix()[0, 1:] != 0):
        raise ValueError("stabilator.incidence_table: the blades' collective follows other pilot controls than the "
                         "lever in [controls], so a lever fraction does not give it; give the blades' collective (deg)")
    low, high = rig.travel[0]
    neutral = dict(zip(rigging.PILOT, (0.0, 0.0, 0.0, 0.0)))
    return [rig.blade({**neutral, "collective_lever": low + f * (high - low)})["collective"] for f in table["collective"]]


def tail_problems(values: dict) -> list[str]:
    """Interference tables and the stabilator's schedule against their breakpoints and stops."""
    out = []
    for section, arg, flow in (("horizontal_tail", "alpha", "downwash"), ("vertical_fin", "beta", "sidewash")):
        sec, key = values[section], f"interference_{arg}"
        for name in ("q_ratio", flow):
            if len(sec[name]) and len(sec[name]) != len(sec[key]):
                out.append(f"{section}.{name}: {len(sec[name])} values for {len(sec[key])} breakpoints "
                           f"({section}.{key})")
        if len(sec[key]) and not (len(sec["q_ratio"]) or len(sec[flow])):
            out.append(f"{section}.{key}: breakpoints without tables (q_ratio, {flow})")
        if any(q <= 0 for q in sec["q_ratio"]):
            out.append(f"{section}.q_ratio: dynamic-pressure ratios must be positive")
    st = values.get("stabilator") or {}
    if has_stabilator(values) and not has_horizontal_tail(values):
        out.append("stabilator: schedules a horizontal tail's incidence, and the file has no [horizontal_tail]: give "
                   "its area, x, z, lift_slope, alpha_stall, cd0 and chord")
    if st.get("incidence_table"):
        return out + _table_schedule_problems(values)
    if has_stabilator(values):
        if len(st["incidence"]) != len(st["airspeed"]):
            out.append(f"stabilator.incidence: {len(st['incidence'])} values for {len(st['airspeed'])} airspeeds")
        if st["incidence_min"] >= st["incidence_max"]:
            out.append("stabilator.incidence_max: must exceed incidence_min")
        outside = [i for i in st["incidence"] if not st["incidence_min"] <= i <= st["incidence_max"]]
        if outside:
            out.append(f"stabilator.incidence: {np.degrees(outside[0]):.4g} deg lies beyond the stops "
                       f"[{np.degrees(st['incidence_min']):.4g}, {np.degrees(st['incidence_max']):.4g}] deg")
    return out


def _table_schedule_problems(values: dict) -> list[str]:
    """A two-variable schedule: its collective read as the blades', no collective gain beside it,
    its incidences within the stops."""
    st, out = values["stabilator"], []
    try:
        collective = schedule_collective(values)
    except ValueError as exc:
        return [str(exc)]
    if np.any(np.diff(collective) <= 0):
        out.append("stabilator.incidence_table: the blades' collective of the lever's fractions does not increase "
                   "(check the rigging's collective gain)")
    if st["collective_gain"]:
        out.append("stabilator.collective_gain: the incidence_table carries the collective already; leave the gain out")
    values_ = np.asarray(st["incidence_table"]["values"])
    outside = values_[(values_ < st["incidence_min"]) | (values_ > st["incidence_max"])]
    if outside.size:
        out.append(f"stabilator.incidence_table: {np.degrees(outside[0]):.4g} deg lies beyond the stops "
                   f"[{np.degrees(st['incidence_min']):.4g}, {np.degrees(st['incidence_max']):.4g}] deg")
    return out


def reference_point(d) -> np.ndarray:
    """The moments' reference point (3,) (m, body axes from the CG) of the aircraft data ``d``:
    as given, or from the stations ``reference_station`` and ``cg_station``
    (:func:`mbs.aircraft.stations.position`, counted as the file's ``[conventions]`` say)."""
    fa = d["fuselage_aero"]
    if len(fa["reference_point"]):
        return np.asarray(fa["reference_point"], dtype=float)
    return np.asarray(stations.position("xyz", fa["reference_station"], fa["cg_station"], d.get("conventions", {})))


def scale(fa: dict, key: str, rho: float) -> float:
    """The factor taking the table ``key`` to SI per dynamic pressure (m², m³)."""
    form, moment = fa[key]["form"], key.split("_")[0] in ("roll", "pitch", "yaw", "L", "M", "N")
    if form == "per_q":
        return 1.0
    if form == "load":
        return 1.0 / (0.5 * rho * fa["reference_speed"] ** 2)
    return fa["reference_area"] * (fa["reference_length"] if moment else 1.0)


def fuselage_table(d):
    """The :class:`mbs.aero.airframe_tables.AirframeTable` of ``d["fuselage_aero"]``."""
    from mbs.aero.airframe_tables import AirframeTable

    fa, rho = d["fuselage_aero"], d["environment"]["rho"]
    names, parts = COMPONENTS[fa["axes"]], {}
    for key, table in given(fa).items():
        name, _, arg = key.partition("_")
        parts.setdefault(names.index(name), []).append((arg, scale(fa, key, rho) * np.asarray(table["values"]),
                                                        table.get("breakpoints")))
    grid = {a: np.asarray(fa[a]) if len(fa[a]) else None for a in ("alpha", "beta")}
    return AirframeTable(fa["axes"], tuple(reference_point(d)), grid["alpha"], grid["beta"], parts,
                         beta_sign(fa))


def beta_sign(fa: dict) -> float:
    """-1 for fuselage tables printed with the wind from port at positive sideslip, else 1."""
    return -1.0 if fa.get("sideslip_positive") == "wind from port" else 1.0


def drag_area(d) -> float:
    """Fuselage drag per dynamic pressure (m²) at zero angle of attack and sideslip: of its tables,
    or of its polynomials' constant ``X`` at their reference speed."""
    fa = d["fuselage_aero"]
    if fa["model"] != "tables":
        return -fa["X"][0] / (0.5 * d["environment"]["rho"] * fa["v_ref"] ** 2)
    force, _ = fuselage_table(d).body_per_q(0.0, 0.0)
    return -float(force.full()[0, 0])


def converted(data) -> list[tuple]:
    """Rows ``(entry, value, unit, how, source)`` of every value the program converted."""
    fa = data["fuselage_aero"]
    if fa.get("model") != "tables":
        return []
    meta, rho, rows = data.meta["fuselage_aero"], data["environment"]["rho"], []
    if not len(fa["reference_point"]):
        sign = stations.signs(data.get("conventions", {}))
        formula = ", ".join(f"{'-' if sign[a] < 0 else ''}({n} - {n}_cg)" for a, n in zip("xyz", ("FS", "BL", "WL")))
        rows.append(("fuselage_aero.reference_station", reference_point(data).round(6).tolist(), "m",
                     f"x, y, z from the CG: {formula}", meta["reference_station"]["source"]))
    if beta_sign(fa) < 0:
        rows.append(("fuselage_aero.sideslip_positive", "wind from port", "-", "the tables read at -beta (beta = "
                     "asin(v / V), positive with the wind from starboard)", meta["sideslip_positive"]["source"]))
    for key, table in given(fa).items():
        factor = scale(fa, key, rho)
        law = (f"the polynomial {meta[key]['value']} {table['unit']} in {key.partition('_')[2]} (rad) at its "
               "breakpoints; ") if "coefficients" in table else ""
        if "expression" in table:
            law = f"the law {table['expression']!r} {table['unit']} in {table['angle']} (rad) at its breakpoints; "
        if "breakpoints" in table:
            own = table["breakpoints"] if isinstance(table["breakpoints"], tuple) else (table["breakpoints"],)
            law = "at its own " + " and ".join(f"{a} {[float(f'{b:.6g}') for b in grid]}" for a, grid in
                                               zip(key.partition("_")[2].split("_"), own)) + " rad; "
        unit = "m^3" if key.split("_")[0] in ("roll", "pitch", "yaw", "L", "M", "N") else "m^2"
        how = law + {"per_q": f"per dynamic pressure, from {table['unit'].rpartition(',')[2].strip()}",
                     "load": f"loads in {table['unit']}{_pound_force(table['unit'])} at {fa['reference_speed']:.4g} "
                             f"m/s over q = {1 / factor:.6g} Pa",
                     "coefficient": f"coefficients times {factor:.6g} {unit}"}[table["form"]]
        values = np.asarray(table["values"]) * factor
        rows.append((f"fuselage_aero.{key}", [float(f"{v:.9g}") for v in values.ravel()], unit, how,
                     meta[key]["source"]))
    force, moment = fuselage_table(data).body_per_q(0.0, 0.0)
    rows.append(("fuselage_aero (alpha = beta = 0)", np.round(np.concatenate([force.full().ravel(),
                                                                              moment.full().ravel()]), 6).tolist(),
                 "m^2, m^3", f"X, Y, Z per q and L, M, N per q about the CG, body axes, from {fa['axes']} axes about "
                 f"the reference point {np.round(reference_point(data), 4).tolist()} m", "DER"))
    return rows


def _pound_force(unit: str) -> str:
    """What the check says of a load table's unit read with ``lb`` as the pound-force."""
    first = unit.split(",")[0]  # a polynomial's c_0
    return "" if units.parse(first).dims in FORCE_DIMS | MOMENT_DIMS else " (lb as pound-force)"


def stabilator_schedule(d):
    """The :class:`mbs.aero.empennage.Schedule` of the file's ``[stabilator]``, or None."""
    from mbs.aero.empennage import Schedule

    if not has_stabilator(d):
        return None
    st = d["stabilator"]
    if st.get("incidence_table"):
        table = st["incidence_table"]
        return Schedule(tuple(table["airspeed"]), tuple(map(tuple, table["values"])), 0.0, 0.0, st["pitch_rate_gain"],
                        st["incidence_min"], st["incidence_max"], st["cyclic_gain"],
                        tuple(schedule_collective(d)))
    return Schedule(tuple(st["airspeed"]), tuple(st["incidence"]), st["collective_gain"], st["collective_reference"],
                    st["pitch_rate_gain"], st["incidence_min"], st["incidence_max"], st["cyclic_gain"])


def interference_tables(d, section: str):
    """The :class:`mbs.aero.empennage.Interference` of ``section`` ("horizontal_tail" or
    "vertical_fin"), or None where the file gives none."""
    from mbs.aero.empennage import Interference

    sec, lateral = d[section], section == "vertical_fin"
    key, flow = ("interference_beta", "sidewash") if lateral else ("interference_alpha", "downwash")
    if not len(sec[key]):
        return None
    return Interference(tuple(sec[key]), tuple(sec["q_ratio"]) if len(sec["q_ratio"]) else None,
                        tuple(sec[flow]) if len(sec[flow]) else None, lateral)


def tables_from_polynomials(fa: dict, step_deg: float = 5.0, limit_deg: float = 90.0) -> str:
    """The ``[fuselage_aero]`` section of tables sampling a file's Padfield polynomials ``fa``
    (their angles clipped as the model clips them) every ``step_deg`` over ±``limit_deg``: body
    axes about the CG, loads at the polynomials' ``v_ref``."""
    from mbs.aero.sections import soft_clip

    grid = np.arange(-limit_deg, limit_deg + step_deg / 2, step_deg)
    clipped = [float(soft_clip(a, fa["angle_limit"])) for a in np.radians(grid)]

    def entry(key: str, unit: str) -> str:
        values = [round(float(np.polyval(fa[key[0]][::-1], a)), 9) for a in clipped]
        return f'{key} = {{ value = {values}, unit = "{unit}", source = "polynomials sampled" }}'

    return "\n".join([
        "[fuselage_aero]", 'model = { value = "tables", unit = "-", source = "polynomials sampled" }',
        'axes = { value = "body", unit = "-", source = "polynomials sampled" }',
        'reference_point = { value = [0.0, 0.0, 0.0], unit = "m", source = "polynomials sampled" }',
        f'alpha = {{ value = {grid.tolist()}, unit = "deg", source = "polynomials sampled" }}',
        f'beta = {{ value = {grid.tolist()}, unit = "deg", source = "polynomials sampled" }}',
        f'reference_speed = {{ value = {fa["v_ref"]}, unit = "m/s", source = "polynomials sampled" }}',
        entry("X_alpha", "N"), entry("Z_alpha", "N"), entry("M_alpha", "N m"), entry("Y_beta", "N"),
        entry("N_beta", "N m"), ""])
